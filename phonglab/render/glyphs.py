"""Geometry and colours of the arrows N, L, R, V, H, the light and eye markers and the area light's panel.

Every glyph is a triangle mesh carrying its colours as a uint8 RGB point
array (:data:`COLOR_ARRAY`), so it looks the same in VTK and in vtk.js with
lighting switched off. The soft relief on arrows comes from the core too: a
matte material lit by a headlight, computed once per glyph.

Directions point *away from the surface point*: every arrow starts at the
probe point.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pyvista as pv

from phonglab import core
from phonglab.core.display import display_bytes, srgb_decode
from phonglab.render.options import parse_vectors  # noqa: F401  (kept importable here: the view and figures use it)

#: name of the uint8 RGB point array every glyph carries
COLOR_ARRAY = "rgb"

#: the vectors, in drawing order: letter -> (RGB colour 0..255, legend text)
VECTORS = {
    "N": ((86, 180, 233), "normal"),
    "L": ((240, 228, 66), "to the light"),
    "R": ((230, 97, 20), "reflected light"),
    "V": ((0, 190, 140), "to the eye"),
    "H": ((214, 130, 190), "halfway, (L + V)/|L + V|"),
}
EYE_COLOR = (235, 235, 235)
PUPIL_COLOR = (40, 40, 48)

#: length of the arrows N, L, R, V, H as a fraction of the mesh's bounding radius
ARROW_FRACTION = 0.5
#: arrow thickness in world units
SHAFT_RADIUS = 0.018
TIP_RADIUS = 0.05
#: length of an arrow's head as a fraction of the arrow's length
TIP_LENGTH = 0.3
LIGHT_MARKER_SIZE = 0.09
#: thickness of the area light's panel, as a fraction of its longer edge
AREA_PANEL_THICKNESS = 0.03
#: colour of the area light panel's back and sides (RGB 0-255): it emits from its front face only
AREA_PANEL_BACK = (72, 74, 82)




def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def relief(mesh: pv.PolyData | None, base_rgb, view_direction, *, points=None, normals=None) -> np.ndarray:
    """uint8 RGB per point: ``base_rgb`` (0..255) lit by a headlight, computed by the core.

    A matte material (``ka = kd = base``, a touch of specular) under an ambient
    light and a directional light from over the viewer's shoulder; gives glyphs
    a 3D look without VTK lighting. ``base_rgb`` is a colour as shown
    (sRGB): it is decoded to linear light, shaded, and encoded again, so a
    glyph facing the light shows about its chip colour. Without a ``mesh``,
    ``points`` and ``normals`` (arrays of shape (n, 3)) are the mesh's.
    """
    base = tuple(float(c) for c in srgb_decode(np.asarray(base_rgb, dtype=np.float64) / 255.0))
    material = core.Material(ka=base, kd=base, ks=0.2, shininess=24.0)
    v = _unit(view_direction)
    # light from over the viewer's shoulder: the view direction tilted up
    up = np.array([0.0, 1.0, 0.0]) if abs(v[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    towards = _unit(v + 0.6 * _unit(up - (up @ v) * v))
    lights = (core.AmbientLight(intensity=0.5), core.DirectionalLight(direction=tuple(towards), intensity=0.6))
    shading = core.shade(
        np.asarray(points if mesh is None else mesh.points, dtype=np.float64),
        np.asarray(normals if mesh is None else mesh.point_data["Normals"], dtype=np.float64),
        view_direction=tuple(v),
        material=material,
        lights=lights,
    )
    return display_bytes(shading.color, encoding="srgb")


def _with_normals(mesh: pv.PolyData) -> pv.PolyData:
    mesh = mesh.triangulate().compute_normals(
        cell_normals=False, point_normals=True, split_vertices=True, feature_angle=45.0
    )
    return mesh


def _colored(mesh: pv.PolyData, base_rgb, view_direction, shaded: bool = True) -> pv.PolyData:
    mesh = _with_normals(mesh)
    if shaded:
        rgb = relief(mesh, base_rgb, view_direction)
    else:
        rgb = np.tile(np.asarray(base_rgb, dtype=np.uint8), (mesh.n_points, 1))
    out = pv.PolyData(mesh.points, faces=mesh.faces)
    out.point_data[COLOR_ARRAY] = rgb
    return out


def bounding_radius(mesh: pv.PolyData) -> float:
    """The largest distance of a mesh point from the centre of the mesh's bounding box.

    Returns 1.0 for an empty or single-point mesh (the size every mesh is scaled to).
    """
    points = np.asarray(mesh.points, dtype=np.float64)
    if len(points) == 0:
        return 1.0
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    radius = float(np.sqrt(((points - centre) ** 2).sum(axis=1).max()))
    return radius if radius > 0 else 1.0


def arrow_length(mesh: pv.PolyData) -> float:
    """How long the arrows N, L, R, V, H are drawn on ``mesh``: :data:`ARROW_FRACTION` of its bounding radius."""
    return ARROW_FRACTION * bounding_radius(mesh)


def arrow(start, direction, color, view_direction, length: float = ARROW_FRACTION) -> pv.PolyData:
    """An arrow from ``start`` along ``direction``, ``length`` long, coloured ``color``.

    The shaft and head radii are :data:`SHAFT_RADIUS` and :data:`TIP_RADIUS`
    whatever the length (world units; meshes fit about the unit sphere).

    The arrow of each length is built once along +x, with its normals
    (:func:`_arrow_model`); each call turns and moves a copy of its points and
    normals, as ``pv.Arrow`` would turn the built arrow, and shades its relief.
    Building it each time (VTK's arrow source, triangles, normals) cost about
    3.6 ms an arrow, five arrows each time a slider moves a light or the eye.
    """
    points, normals, faces = _arrow_model(float(length))
    turn = arrow_turn(direction)
    points = points @ turn.T + np.asarray(start, dtype=np.float64)
    normals = normals @ turn.T
    out = pv.PolyData(points.astype(np.float32), faces=faces)
    out.point_data[COLOR_ARRAY] = relief(None, color, view_direction, points=points, normals=normals)
    return out


def arrow_turn(direction) -> np.ndarray:
    """The rotation that turns +x onto ``direction``, about the axis ``pv.Arrow`` turns its arrow.

    Its columns are the direction and two unit vectors square to it; the
    second is made from +y (from -x or +x when the direction is +y or -y).
    """
    x = _unit(direction)
    helper = [0.0, 1.0, 0.0]
    if np.allclose(x, [0, 1, 0]):
        helper = [-1.0, 0.0, 0.0]
    elif np.allclose(x, [0, -1, 0]):
        helper = [1.0, 0.0, 0.0]
    z = _unit(np.cross(x, helper))
    return np.column_stack([x, np.cross(z, x), z])


@functools.lru_cache(maxsize=16)
def _arrow_model(length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arrow ``length`` long from the origin along +x: its points, split normals and faces (read-only)."""
    mesh = _with_normals(pv.Arrow(
        start=(0.0, 0.0, 0.0),
        direction=(1.0, 0.0, 0.0),
        tip_length=TIP_LENGTH,
        tip_radius=TIP_RADIUS / length,
        shaft_radius=SHAFT_RADIUS / length,
        tip_resolution=24,
        shaft_resolution=16,
        scale=length,
    ))
    model = (np.array(mesh.points, dtype=np.float64), np.array(mesh.point_data["Normals"], dtype=np.float64),
             np.array(mesh.faces))
    for array in model:
        array.flags.writeable = False
    return model


def _bulb(radius: float, centre, color, *, theta_resolution: int, phi_resolution: int) -> pv.PolyData:
    """A ball of ``radius`` at ``centre`` in the flat colour ``color``: a light's bulb, unshaded (it glows)."""
    points, faces = _ball_model(float(radius), theta_resolution, phi_resolution)
    out = pv.PolyData((points + np.asarray(centre, dtype=np.float64)).astype(np.float32), faces=faces)
    out.point_data[COLOR_ARRAY] = np.tile(np.asarray(color, dtype=np.uint8), (len(points), 1))
    return out


@functools.lru_cache(maxsize=8)
def _ball_model(radius: float, theta_resolution: int, phi_resolution: int) -> tuple[np.ndarray, np.ndarray]:
    """The ball of ``radius`` about the origin as :func:`_colored` shapes it: points and faces (read-only).

    Built once: a lamp's bulb follows its light at every step of a slider.
    """
    mesh = _with_normals(pv.Sphere(radius=radius, theta_resolution=theta_resolution, phi_resolution=phi_resolution))
    model = (np.array(mesh.points, dtype=np.float64), np.array(mesh.faces))
    for array in model:
        array.flags.writeable = False
    return model


#: the marker colour of a light that gives no light (intensity or colour 0): a lamp switched off
OFF_LIGHT_COLOR = (70, 70, 70)


def light_color_255(light) -> tuple[int, int, int]:
    """A marker colour for a light: its (linear) colour, brightened so the largest channel is 1, sRGB-encoded.

    A light that gives no light (intensity 0, or a black colour) is drawn dark grey, switched off.
    """
    c = np.asarray(getattr(light, "color", (1.0, 1.0, 1.0)), dtype=float)
    top = c.max()
    if not top > 0 or not float(getattr(light, "intensity", 1.0)) > 0:
        return OFF_LIGHT_COLOR
    return tuple(int(x) for x in display_bytes(c / top, encoding="srgb"))


def light_marker(light, view_direction, centre=(0.0, 0.0, 0.0)) -> pv.PolyData | None:
    """The marker of a light: a sphere (point), a cone (spot) or three parallel arrows (directional).

    Returns None for an ambient light (it has no place).
    """
    color = light_color_255(light)
    size = LIGHT_MARKER_SIZE
    if isinstance(light, core.SpotLight) and light.cutoff < 180:
        axis = _unit(light.direction)
        half_angle = min(float(light.cutoff), 50.0)
        height = 3.0 * size
        radius = height * math.tan(math.radians(half_angle))
        # apex at the light, opening along the spot's axis
        cone = pv.Cone(
            center=tuple(np.asarray(light.position) + axis * height / 2),
            direction=tuple(-axis),
            height=height,
            radius=radius,
            resolution=32,
            capping=True,
        )
        bulb = _bulb(0.45 * size, light.position, color, theta_resolution=16, phi_resolution=12)
        return _colored(cone, color, view_direction).merge(bulb)
    if isinstance(light, (core.PointLight, core.SpotLight)):
        return _bulb(size, light.position, color, theta_resolution=24, phi_resolution=16)
    if isinstance(light, core.DirectionalLight):
        d = _unit(light.direction)
        centre = np.asarray(centre, dtype=float)
        # three parallel arrows coming in from the light's side
        side = np.cross(d, [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0])
        side = _unit(side)
        up = _unit(np.cross(side, d))
        parts = []
        for offset in (np.zeros(3), 0.22 * side, -0.22 * side):
            tail = centre + 1.75 * d + offset + 0.05 * up
            parts.append(arrow(tail, -d, color, view_direction, length=0.45))
        return parts[0].merge(parts[1]).merge(parts[2])
    return None


def eye_marker(eye, focal_point, view_direction) -> pv.PolyData:
    """An eyeball at ``eye`` with its pupil facing ``focal_point``."""
    eye = np.asarray(eye, dtype=float)
    look = _unit(np.asarray(focal_point, dtype=float) - eye)
    ball = pv.Sphere(radius=0.08, center=tuple(eye), theta_resolution=24, phi_resolution=16)
    pupil = pv.Sphere(radius=0.04, center=tuple(eye + 0.06 * look), theta_resolution=16, phi_resolution=12)
    return _colored(ball, EYE_COLOR, view_direction).merge(_colored(pupil, PUPIL_COLOR, view_direction))


def area_light_panel(light) -> pv.PolyData:
    """A thin box showing a :class:`phonglab.core.AreaLight` where it is.

    The emitting face is the light's rectangle itself (corners
    ``position ± edge_u/2 ± edge_v/2``), flat in the light's colour
    brightened to full (:func:`light_color_255`); the
    box extends :data:`AREA_PANEL_THICKNESS` of the longer edge behind it
    (against the light's normal), and its back and sides are dark grey
    (:data:`AREA_PANEL_BACK`), since the light shines from its front only.

    Returns
    -------
    pyvista.PolyData
        24 points (4 per face, so each face has its own colour), 12 triangles,
        uint8 RGB in the point array ``"rgb"``.
    """
    centre = np.asarray(light.position, dtype=np.float64)
    u = np.asarray(light.edge_u, dtype=np.float64) / 2
    v = np.asarray(light.edge_v, dtype=np.float64) / 2
    depth = -light.normal * AREA_PANEL_THICKNESS * 2 * max(np.linalg.norm(u), np.linalg.norm(v))
    front = [centre - u - v, centre + u - v, centre + u + v, centre - u + v]
    back = [corner + depth for corner in front]
    faces = [front, back[::-1]] + [[front[i], back[i], back[(i + 1) % 4], front[(i + 1) % 4]] for i in range(4)]
    points = np.array([corner for face in faces for corner in face])
    triangles = []
    for f in range(len(faces)):
        a, b, c, d = 4 * f, 4 * f + 1, 4 * f + 2, 4 * f + 3
        triangles += [3, a, b, c, 3, a, c, d]
    panel = pv.PolyData(points, faces=np.array(triangles))
    colours = np.tile(np.asarray(AREA_PANEL_BACK, dtype=np.uint8), (len(points), 1))
    colours[:4] = light_color_255(light)
    panel.point_data[COLOR_ARRAY] = colours
    return panel
