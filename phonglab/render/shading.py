"""Colours for the three interpolation modes, computed by the core.

Each point is shaded with the material of the object it lies on, and, in a
scene with ``shadows``, with the lights its shadow rays reach
(:mod:`~phonglab.render.shadows`), at the points each mode shades:

* **flat** — one colour per triangle: the core shades the triangle's
  centroid with its geometric normal; VTK paints the whole face with it.
* **gouraud** — the core shades every vertex with its normal; VTK
  interpolates the *colours* across each triangle.
* **pixel** — VTK interpolates *positions and normals* per pixel (the
  G-buffer of :mod:`phonglab.render.gbuffer`); the core shades every pixel.

Colours leave the core unclamped, as linear light; they are encoded for the
display only here, at the last step before VTK, with the scene's display
options (:func:`display_rgb8`): linear radiance → ``scene.exposure`` → clip
to [0, 1] → ``scene.display`` transfer curve (sRGB by default, or
``"linear"``) → 8 bits. So a 50 % grey is 188/255 by default, 128 raw.

Every function takes ``mistake=``: None (the default) shades correctly with
:func:`phonglab.scene.shade`; a name from :data:`phonglab.teaching.MISTAKES`
shades with that deliberately wrong variant instead (a lesson's "common
mistake"), through :func:`phonglab.scene.shade`'s ``mistake=``. A mistake that
needs the interpolated, not renormalised, normals gets them in pixel mode
(:attr:`GBuffer.raw_normals`); per vertex and per face the normals are unit
vectors, so that mistake cannot show there (:func:`mistake_note` says so).
"""

from __future__ import annotations

import numpy as np

from phonglab.core.display import display_bytes, display_values
from phonglab.render import shadows
from phonglab.render.gbuffer import GBuffer
from phonglab.render.mesh import face_centroids_normals
from phonglab.render.objects import OBJECT_ARRAY, cell_objects, point_objects

#: what a view can show: one term of the sum, or the whole colour
TERMS = ("color", "ambient", "diffuse", "specular")


def shade(scene, points, normals, mistake: str | None = None, *, scene_plan=None, objects=None, cache=None):
    """The core's shading of ``points`` with ``normals`` under ``scene``.

    A thin wrapper over :func:`phonglab.scene.shade` (which passes the
    scene's materials, lights, eye, model, two-sidedness and plan to the
    core), with the scene's shadows cast here when it has them
    (:func:`phonglab.render.shadows.visibility`).

    Parameters
    ----------
    scene : phonglab.scene.Scene
    points, normals : array_like, shape (..., 3)
    mistake : str or None
        None shades correctly. A name from :data:`phonglab.teaching.MISTAKES`
        shades with that deliberately wrong variant
        (:func:`phonglab.scene.shade` with ``mistake=``).
    scene_plan : phonglab.scene.ScenePlan, optional
        ``plan(scene)`` when the caller has made it already (it is not made
        again); None plans here. The colours are the same either way.
    objects : array_like of int, optional
        The object each point lies on (None: the first).
    cache : tuple, optional
        What the points are (``("vertex",)``, ``("face",)``, or a G-buffer's
        key): their shadows are kept while the objects, lights and bias stay.

    Raises
    ------
    ValueError
        For an unknown mistake name (the message lists the names allowed).
    """
    from phonglab.scene.planner import plan, shade as scene_shade

    seen = None
    if scene.shadows:
        scene_plan = scene_plan or plan(scene)  # once, for the shadows and the shading
        seen = shadows.visibility(scene, points, objects, scene_plan=scene_plan, cache=cache)
    return scene_shade(scene, points, normals, mistake=mistake, scene_plan=scene_plan, objects=objects,
                       visibility=seen)


def get_mistake(name: str):
    """The :class:`phonglab.teaching.Mistake` called ``name`` (ValueError listing the names otherwise)."""
    from phonglab.teaching import get_mistake as lookup

    return lookup(name)


def mistake_names() -> tuple[str, ...]:
    """The names a ``mistake=`` option accepts."""
    from phonglab.teaching import MISTAKES

    return tuple(MISTAKES)


def mistake_shows(mistake: str | None, interpolation: str) -> bool:
    """Whether ``mistake`` can change the picture in this interpolation mode.

    A mistake that needs the interpolated, not renormalised, normals shows
    only per pixel: per vertex and per face the normals are unit vectors.
    Every other mistake shows in all three modes (where its bug bites).
    """
    if mistake is None:
        return False
    return interpolation == "pixel" or not get_mistake(mistake).needs_raw_normals


def mistake_note(mistake: str | None, interpolation: str) -> str:
    """A sentence for a caption when ``mistake`` cannot show in this mode, else ``""``."""
    if mistake is None or mistake_shows(mistake, interpolation):
        return ""
    mode = {"flat": "flat (per face)", "gouraud": "Gouraud (per vertex)"}.get(interpolation, interpolation)
    return (f"This mistake shows only with per-pixel shading: with {mode} shading every normal is a unit "
            "vector, so this picture is the correct one (set interpolation = \"pixel\" to see it).")


def term_of(shading, term: str) -> np.ndarray:
    """One term of a core ``Shading``: ``"color"`` (the sum), ``"ambient"``, ``"diffuse"``, ``"specular"``."""
    if term not in TERMS:
        raise ValueError(f"term must be one of {', '.join(TERMS)}, got {term!r}")
    return getattr(shading, term)


def display_rgb8(scene, values) -> np.ndarray:
    """Linear light computed for ``scene`` as the uint8 RGB the display shows.

    The scene's ``exposure`` scales the radiance, which is clipped to [0, 1]
    and encoded with the scene's ``display`` curve
    (:func:`phonglab.core.display.display_bytes`): 0.5 is 188 with ``"srgb"``
    (the default), 128 with ``"linear"``. NaN shows as black.
    """
    return display_bytes(values, encoding=getattr(scene, "display", "srgb"),
                         exposure=getattr(scene, "exposure", 1.0))


def to_rgb8(values) -> np.ndarray:
    """Clip values already meant for the display (a background colour) to [0, 1] and scale them to uint8 RGB.

    Shaded colours are linear light: use :func:`display_rgb8`, which encodes them.
    """
    values = np.asarray(values)
    if values.dtype not in (np.float32, np.float64):
        values = values.astype(np.float64)
    scaled = np.clip(values, 0.0, 1.0) * 255.0
    # NaN would survive the clip; it becomes black
    scaled = np.where(np.isnan(scaled), 0.0, scaled) if np.isnan(scaled).any() else scaled
    return np.rint(scaled).astype(np.uint8)


def vertex_colors(scene, mesh, terms=("color",), mistake: str | None = None, *,
                  scene_plan=None) -> dict[str, np.ndarray]:
    """Gouraud: uint8 RGB per mesh point, for each requested term (with ``mistake``, if given).

    ``scene_plan``: ``plan(scene)`` if the caller has it (see :func:`shade`).
    """
    points, normals, objects = _vertices(mesh)
    shading = shade(scene, points, normals, mistake, scene_plan=scene_plan, objects=objects, cache=("vertex",))
    return {t: display_rgb8(scene, term_of(shading, t)) for t in terms}


#: the last mesh's points, normals and objects as NumPy arrays: (key, arrays); see :func:`_vertices`
_last_vertices: list = [None, None]


def _vertices(mesh):
    """The mesh's points, point normals and point objects, remembered for the last mesh while they stay.

    A slider step re-shades the same vertices: reading them through PyVista
    again cost more than a tenth of a millisecond per step. VTK's modification
    times tell when they changed (the colour arrays the view writes into the
    same point data do not count).
    """
    data = mesh.GetPointData()
    normals, ids = data.GetArray("Normals"), data.GetArray(OBJECT_ARRAY)
    key = (id(mesh), mesh.GetPoints().GetMTime(), normals.GetMTime() if normals is not None else None,
           ids.GetMTime() if ids is not None else None, mesh.n_points)
    if _last_vertices[0] != key:
        _last_vertices[:] = [key, (np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"]),
                                   point_objects(mesh))]
    return _last_vertices[1]


#: the last mesh's face centroids and normals: (key, (centroids, normals)); see :func:`_faces`
_last_faces: list = [None, None]


def _faces(mesh):
    """:func:`face_centroids_normals`, remembered for the last mesh while its points, normals and cells stay.

    A turn of the view re-shades the same mesh for every new eye; VTK's
    modification times (a global counter) tell when the geometry changed.
    """
    normals = mesh.GetPointData().GetArray("Normals")
    key = (id(mesh), mesh.GetPoints().GetMTime(), normals.GetMTime() if normals is not None else None,
           mesh.GetPolys().GetMTime(), mesh.n_cells)
    if _last_faces[0] != key:
        _last_faces[:] = [key, face_centroids_normals(mesh)]
    return _last_faces[1]


def face_colors(scene, mesh, terms=("color",), mistake: str | None = None, *,
                scene_plan=None) -> dict[str, np.ndarray]:
    """Flat: uint8 RGB per triangle, shaded at its centroid with its face normal (with ``mistake``, if given).

    ``scene_plan``: ``plan(scene)`` if the caller has it (see :func:`shade`).
    """
    centroids, normals = _faces(mesh)
    shading = shade(scene, centroids, normals, mistake, scene_plan=scene_plan, objects=cell_objects(mesh),
                    cache=("face",))
    return {t: display_rgb8(scene, term_of(shading, t)) for t in terms}


def pixel_colors(scene, gbuffer: GBuffer, background, terms=("color",),
                 mistake: str | None = None, *, scene_plan=None) -> dict[str, np.ndarray]:
    """Per pixel: a (height, width, 3) uint8 image per term, background where uncovered.

    Parameters
    ----------
    scene : phonglab.scene.Scene
    gbuffer : GBuffer
    background : sequence of 3 floats in [0, 1]
        Colour of the pixels the mesh does not cover, as the display shows
        it (not encoded again, so it matches VTK's background).
    terms : sequence of str
    mistake : str or None
        A deliberately wrong shading to use (see :func:`shade`). A mistake
        with ``needs_raw_normals`` is given the interpolated normals as they
        came (:attr:`GBuffer.raw_normals`), so its bug shows.
    scene_plan : phonglab.scene.ScenePlan, optional
        ``plan(scene)`` if the caller has it (see :func:`shade`).
    """
    mask = gbuffer.mask
    shading = _pixel_shading(scene, gbuffer, mistake, scene_plan=scene_plan)
    back = to_rgb8(background)
    out = {}
    for t in terms:
        image = np.empty(mask.shape + (3,), dtype=np.uint8)
        image[...] = back
        image[mask] = display_rgb8(scene, term_of(shading, t))
        out[t] = image
    return out


def _pixel_shading(scene, gbuffer: GBuffer, mistake: str | None, *, scene_plan=None):
    """The core's ``Shading`` of a G-buffer's covered pixels (raw normals for a mistake that needs them)."""
    mask = gbuffer.mask
    normals = gbuffer.normals
    if mistake is not None and get_mistake(mistake).needs_raw_normals:
        # the bug: the interpolated normals, not renormalised
        if gbuffer.raw_normals is None:
            raise ValueError(f"gbuffer: the mistake {mistake!r} needs the raw interpolated normals, "
                             "and this G-buffer has none")
        normals = gbuffer.raw_normals
    objects = None if gbuffer.objects is None else gbuffer.objects[mask]
    return shade(scene, gbuffer.positions[mask], normals[mask], mistake, scene_plan=scene_plan, objects=objects,
                 cache=("pixel", gbuffer))


def pixel_linear(scene, gbuffer: GBuffer, term: str = "color", mistake: str | None = None) -> np.ndarray:
    """Per pixel: the linear light the display will show, before its encoding, for blending.

    The core's colour (or one term) at every covered pixel, times the
    scene's exposure and clipped to [0, 1] (:func:`display_values` with the
    ``"linear"`` curve): what :func:`pixel_colors` encodes, one step earlier.

    Returns
    -------
    ndarray, shape (height, width, 3), float64
        NaN where the G-buffer's mesh does not cover the pixel.
    """
    mask = gbuffer.mask
    out = np.full(mask.shape + (3,), np.nan)
    out[mask] = display_values(term_of(_pixel_shading(scene, gbuffer, mistake), term), encoding="linear",
                               exposure=getattr(scene, "exposure", 1.0))
    return out
