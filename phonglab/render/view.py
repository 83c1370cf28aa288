"""SceneView: one VTK renderer and window showing a scene shaded by the core.

What the window holds:

* the mesh, coloured by the core (RGB scalars, VTK lighting off): per face
  (flat) or per vertex (gouraud, and pixel mode's preview);
* arrows N, L, R, V, H at the probe point, in fixed colours, half as long
  as the mesh's bounding radius;
* a marker per light (a sphere for a point light, a cone for a spotlight,
  three parallel arrows for a directional light) and an eye marker (shown
  only when the VTK camera has left the scene's eye);
* the scene's area light, if it has one, as a thin panel whose emitting face
  is drawn flat in the light's colour (:func:`area_light_panel`);
* optionally VTK text: a letter at every arrow tip and a legend (for
  server-side rendering; vtk.js does not draw these, see :meth:`SceneView.legend`).

Every actor has lighting off and carries its colours in a point or cell
array, so the geometry and colours are all a browser needs (trame-vtk's
local view). The mesh keeps its point normals in the ``"Normals"`` array for
the core's shading, but not as VTK's normals attribute, so a browser's copy
is sent without them. :meth:`SceneView.update` changes arrays in place: moving a slider
never adds an actor.

A lesson's common mistake (:data:`phonglab.teaching.MISTAKES`) can be shown
on the mesh: :meth:`SceneView.set_mistake` recolours it in place with the
deliberately wrong shading, and :meth:`SceneView.pixel_image` uses it too;
``set_mistake(None)`` brings back the correct colours.

Framing: the camera stays at the scene's eye and looks where the scene says;
when arrows are shown and a tip (with the letter beyond it) would leave the
window, the view angle is widened just enough to hold it. Nothing else
about the camera changes, and a change of material never refits it. Once
the VTK camera has been moved off the scene's eye (a browser's camera copied
in), the view angle is left as it was set until the scene's camera is
applied again.

Directions point *away from the surface point*: every arrow starts at the probe.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import NamedTuple

import numpy as np
import pyvista as pv
import vtk
from PIL import Image

from phonglab import core
from phonglab.scene import viewer
from phonglab.render import _files, glyphs, shading
from phonglab.render._vtk import eye_distance, make_render_window, read_depth, read_rgb, set_camera
from phonglab.render.annotate import draw_labels, draw_legend, font
from phonglab.render.gbuffer import GBufferRenderer
from phonglab.render.mesh import build_mesh, ray_hit, surface_point

#: default background (slate), RGB in [0, 1]
BACKGROUND = (0.13, 0.14, 0.17)
#: the VTK camera counts as "at the eye" within this distance; the eye marker is hidden then
EYE_MARKER_MIN_DISTANCE = 0.5
#: the widest view angle (degrees) the framing of the arrows may choose
MAX_VIEW_ANGLE = 120.0
#: free border around the arrows and their letters, as a fraction of the window's shorter side
FRAME_PAD = 0.02
#: thickness of the area light's panel, as a fraction of its longer edge
AREA_PANEL_THICKNESS = 0.03
#: colour of the area light panel's back and sides (RGB 0-255): it emits from its front face only
AREA_PANEL_BACK = (72, 74, 82)


def _array_to_vtk_in_place(owner, name: str, values: np.ndarray) -> None:
    """Overwrite the named array's values, keeping the same VTK array object."""
    array = owner[name]
    array[...] = values
    owner.GetArray(name).Modified()


def default_probe(mesh: pv.PolyData, camera) -> tuple[np.ndarray, np.ndarray]:
    """Where the vectors go when a scene gives no probe.

    The first surface point on the ray from the eye through the focal point;
    if that ray misses the mesh (a torus's hole), the surface point nearest
    the eye.
    """
    hit = ray_hit(mesh, camera.eye, camera.focal_point)
    return hit if hit is not None else surface_point(mesh, camera.eye)


def area_light_panel(light) -> pv.PolyData:
    """A thin box showing a :class:`phonglab.core.AreaLight` where it is.

    The emitting face is the light's rectangle itself (corners
    ``position ± edge_u/2 ± edge_v/2``), flat in the light's colour
    brightened to full (:func:`~phonglab.render.glyphs.light_color_255`); the
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
    colours[:4] = glyphs.light_color_255(light)
    panel.point_data[glyphs.COLOR_ARRAY] = colours
    return panel


class ColourArray(NamedTuple):
    """The colours a :class:`SceneView` shows on its mesh (see :meth:`SceneView.colour_array`)."""

    #: the array's name in the mesh's point or cell data
    name: str
    #: ``"point"`` (Gouraud, pixel mode's preview) or ``"cell"`` (flat)
    location: str
    #: uint8 RGB, shape (number of points or cells, 3): the array itself, not a copy
    values: np.ndarray


class CameraState(NamedTuple):
    """Where the view's VTK camera stands and looks (see :meth:`SceneView.camera_state`)."""

    eye: tuple[float, float, float]
    focal_point: tuple[float, float, float]
    up: tuple[float, float, float]
    view_angle: float


def _finite_vector(name: str, value) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        v = None
    if v is None or v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: must be 3 finite numbers, got {value!r}")
    return v


class SceneView:
    """A scene shown in a VTK render window, lit by the core.

    Parameters
    ----------
    scene : phonglab.scene.Scene
    size : (int, int)
        Window width and height in pixels.
    offscreen : bool
        Render offscreen (no display needed; EGL here).
    vectors : str or None
        Which of N, L, R, V, H to draw at the probe (``"NLRVH"``, ``"N,L"``,
        ``""`` or None for none).
    labels : bool
        Letters at the arrow tips and the legend, drawn on :meth:`screenshot`
        images (and as VTK text in the window when ``vtk_text``).
    vtk_text : bool
        Put the letters and legend in the VTK window as text actors (seen in
        server-side rendering). vtk.js cannot show them and trame-vtk's local
        view warns about them: pass False there and show :meth:`legend` in HTML.
    markers : bool
        Show the light and eye markers.
    term : str
        ``"color"`` (the sum), or one term: ``"ambient"``, ``"diffuse"``, ``"specular"``.
    light_index : int or None
        Which light the vectors L, R, H refer to; None picks the first light
        that is not ambient.
    background : 3 floats in [0, 1]
    mistake : str or None
        Shade with this deliberately wrong variant (a name from
        :data:`phonglab.teaching.MISTAKES`) instead of the correct model;
        see :meth:`set_mistake`.

    Attributes
    ----------
    render_window : vtkRenderWindow
    renderer : vtkRenderer
    scene : Scene
        The scene shown now.
    mistake : str or None
        The common mistake the colours show, or None for the correct shading.
    arrow_length : float
        Length of the arrows in world units (half the mesh's bounding radius).
    """

    def __init__(
        self,
        scene,
        *,
        size=(800, 600),
        offscreen: bool = True,
        vectors="NLRVH",
        labels: bool = True,
        vtk_text: bool = True,
        markers: bool = True,
        term: str = "color",
        light_index: int | None = None,
        background=BACKGROUND,
        mistake: str | None = None,
    ):
        if term not in shading.TERMS:
            raise ValueError(f"term must be one of {', '.join(shading.TERMS)}, got {term!r}")
        if mistake is not None:
            shading.get_mistake(mistake)  # raises ValueError listing the names allowed
        self.scene = scene
        self.term = term
        self.mistake = mistake
        self.background = tuple(float(c) for c in background)
        self.show_labels = bool(labels)
        self.show_markers = bool(markers)
        self._letters = glyphs.parse_vectors(vectors)
        self._light_index_choice = light_index
        self._gbuffer_renderer = None
        self._gbuffer_cache = None

        # window, renderer, camera
        self.render_window = make_render_window(size, offscreen=offscreen)
        self.renderer = vtk.vtkRenderer()
        self.renderer.SetBackground(*self.background)
        self.renderer.AutomaticLightCreationOff()
        self.render_window.AddRenderer(self.renderer)
        set_camera(self.renderer.GetActiveCamera(), scene.camera)

        # the shaded mesh: one actor for the whole life of the view
        self._mapper = vtk.vtkPolyDataMapper()
        self._mesh_actor = vtk.vtkActor()
        self._mesh_actor.SetMapper(self._mapper)
        self._mesh_actor.GetProperty().LightingOff()
        self.renderer.AddActor(self._mesh_actor)
        self._set_mesh(build_mesh(scene.geometry))

        # glyphs: an actor per arrow, per light, and the eye
        self._arrows = {}
        self._labels = {}
        for letter in glyphs.VECTORS:
            data = pv.PolyData()
            self._arrows[letter] = (data, self._glyph_actor(data))
            if vtk_text:
                self._labels[letter] = self._label_actor(letter)
        self._light_markers = []
        eye_data = pv.PolyData()
        self._eye = (eye_data, self._glyph_actor(eye_data))
        area_data = pv.PolyData()
        self._area_panel = (area_data, self._glyph_actor(area_data))
        self._directions = {}
        self._legend_actor = self._make_legend_actor() if vtk_text else None

        # first fill
        self._recolor()
        self._locate_probe()
        self._update_vectors()
        self._update_light_markers()
        self._update_eye_marker()
        self._update_area_panel()

    # ------------------------------------------------------------------
    # building blocks

    def _glyph_actor(self, data: pv.PolyData) -> vtk.vtkActor:
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(data)
        mapper.SetColorModeToDirectScalars()
        mapper.SetScalarModeToUsePointData()
        mapper.ScalarVisibilityOn()
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().LightingOff()
        actor.PickableOff()
        self.renderer.AddActor(actor)
        return actor

    def _label_actor(self, letter: str) -> vtk.vtkBillboardTextActor3D:
        actor = vtk.vtkBillboardTextActor3D()
        actor.SetInput(letter)
        prop = actor.GetTextProperty()
        prop.SetColor(*(c / 255 for c in glyphs.VECTORS[letter][0]))
        prop.BoldOn()
        prop.SetFontSize(_letter_font_size(self.render_window.GetSize()[1]))
        prop.SetJustificationToCentered()
        prop.SetVerticalJustificationToCentered()
        actor.PickableOff()
        self.renderer.AddActor(actor)
        return actor

    def _make_legend_actor(self) -> vtk.vtkTextActor:
        actor = vtk.vtkTextActor()
        prop = actor.GetTextProperty()
        prop.SetFontSize(max(10, self.render_window.GetSize()[1] // 38))
        prop.SetColor(0.92, 0.92, 0.92)
        prop.SetBackgroundColor(0.04, 0.04, 0.06)
        prop.SetBackgroundOpacity(0.65)
        actor.SetPosition(8, 8)
        actor.PickableOff()
        self.renderer.AddViewProp(actor)
        return actor

    def _set_mesh(self, mesh: pv.PolyData) -> None:
        """Show a new mesh (geometry changed): colour arrays sized for it."""
        # lighting is off, so nothing draws with the normals: stop them being the
        # normals attribute (a browser's copy would receive them), keep the array
        mesh.GetPointData().SetActiveAttribute(-1, vtk.vtkDataSetAttributes.NORMALS)
        mesh.point_data[glyphs.COLOR_ARRAY] = np.zeros((mesh.n_points, 3), np.uint8)
        mesh.cell_data[glyphs.COLOR_ARRAY] = np.zeros((mesh.n_cells, 3), np.uint8)
        mesh.point_data.active_scalars_name = glyphs.COLOR_ARRAY
        mesh.cell_data.active_scalars_name = glyphs.COLOR_ARRAY
        self.mesh = mesh
        self.arrow_length = glyphs.arrow_length(mesh)
        self._mapper.SetInputData(mesh)
        self._mapper.SetColorModeToDirectScalars()
        self._mapper.ScalarVisibilityOn()
        self._gbuffer_cache = None

    # ------------------------------------------------------------------
    # state

    @property
    def light_index(self) -> int | None:
        """Index in ``scene.lights`` of the light the vectors refer to (None: no such light)."""
        lights = self.scene.lights
        if self._light_index_choice is not None:
            i = self._light_index_choice
            if 0 <= i < len(lights) and not isinstance(lights[i], core.AmbientLight):
                return i
        for i, light in enumerate(lights):
            if not isinstance(light, core.AmbientLight):
                return i
        return None

    @property
    def probe(self) -> tuple[np.ndarray, np.ndarray]:
        """The probe point on the surface and the unit normal there."""
        return self._probe_point, self._probe_normal

    @property
    def probe_vectors(self):
        """The core's ``ProbeVectors`` at the probe, or None without a directed light."""
        return self._vectors

    # ------------------------------------------------------------------
    # updates

    def update(self, scene) -> None:
        """Show ``scene``, recomputing only what differs from the current one.

        The mesh's colour array is overwritten in place; actors are never
        added on a change of material, lights, model or probe.
        """
        old, self.scene = self.scene, scene
        changed = {
            name
            for name in ("geometry", "material", "lights", "camera", "model", "interpolation", "two_sided", "probe",
                         "area_light")
            if getattr(old, name) != getattr(scene, name)
        }
        if not changed:
            return
        if "geometry" in changed:
            self._set_mesh(build_mesh(scene.geometry))
        if "camera" in changed:
            set_camera(self.renderer.GetActiveCamera(), scene.camera)
            self._gbuffer_cache = None
        if changed & {"geometry", "material", "lights", "camera", "model", "interpolation", "two_sided", "area_light"}:
            self._recolor()
        if changed & {"geometry", "probe"} or ("camera" in changed and scene.probe is None):
            self._locate_probe()
        if changed & {"geometry", "probe", "lights", "camera", "two_sided"}:
            self._update_vectors()
        if changed & {"lights", "camera"}:
            self._update_light_markers()
        if "camera" in changed:
            self._update_eye_marker()
        if "area_light" in changed:
            self._update_area_panel()

    def set_probe(self, point) -> None:
        """Move the probe to the surface point nearest ``point`` (None: the default probe)."""
        self.scene = self._with_probe(point)
        self._locate_probe()
        self._update_vectors()

    def _with_probe(self, point):
        probe = None if point is None else tuple(float(c) for c in point)
        return dataclasses.replace(self.scene, probe=probe)

    def set_term(self, term: str) -> None:
        """Show one term (``"ambient"``, ``"diffuse"``, ``"specular"``) or ``"color"`` (their sum)."""
        if term not in shading.TERMS:
            raise ValueError(f"term must be one of {', '.join(shading.TERMS)}, got {term!r}")
        if term != self.term:
            self.term = term
            self._recolor()

    def set_mistake(self, mistake: str | None) -> None:
        """Show a common mistake on the mesh, or the correct shading again (None).

        The mesh's colour array is overwritten in place (no actor is added),
        as :meth:`update` does; :meth:`pixel_image` and :meth:`screenshot`
        use the mistake too. The vectors at the probe stay the correct ones.

        Parameters
        ----------
        mistake : str or None
            A name from :data:`phonglab.teaching.MISTAKES`, or None.

        Raises
        ------
        ValueError
            For an unknown name; the message lists the names allowed and
            the view is left as it was.
        """
        if mistake is not None:
            shading.get_mistake(mistake)  # raises ValueError listing the names allowed
        if mistake != self.mistake:
            self.mistake = mistake
            self._recolor()

    @property
    def mistake_shows(self) -> bool:
        """True when the mistake set can change the picture in the scene's interpolation mode.

        False without a mistake, and for a mistake that needs the raw
        interpolated normals (``needs_raw_normals``) outside pixel mode, where
        every normal is a unit vector and the picture is the correct one.
        """
        return shading.mistake_shows(self.mistake, self.scene.interpolation)

    @property
    def mistake_note(self) -> str:
        """A sentence to show when the mistake set cannot show in this mode, else ``""``."""
        return shading.mistake_note(self.mistake, self.scene.interpolation)

    # ------------------------------------------------------------------
    # what a front end (the web app) needs to know and set

    @property
    def mesh_actor(self) -> vtk.vtkActor:
        """The actor of the shaded mesh (the same actor for the life of the view).

        Its mapper's input is the polydata shown, which holds the colour
        arrays (:meth:`colour_array`).
        """
        return self._mesh_actor

    def colour_array(self) -> ColourArray:
        """The colours the mesh shows now, in the array VTK draws them from.

        Per cell in flat mode, per point otherwise. The values are the array
        itself: the view overwrites them in place on every change of
        material, lights, model, term or mistake.
        """
        location = "cell" if self.scene.interpolation == "flat" else "point"
        fields = self.mesh.cell_data if location == "cell" else self.mesh.point_data
        return ColourArray(glyphs.COLOR_ARRAY, location, fields[glyphs.COLOR_ARRAY])

    @property
    def size(self) -> tuple[int, int]:
        """The window's (width, height) in pixels."""
        width, height = self.render_window.GetSize()
        return int(width), int(height)

    def camera_state(self) -> CameraState:
        """Where the VTK camera is now (the scene's camera, or one set by :meth:`set_camera`)."""
        camera = self.renderer.GetActiveCamera()
        return CameraState(
            eye=tuple(float(c) for c in camera.GetPosition()),
            focal_point=tuple(float(c) for c in camera.GetFocalPoint()),
            up=tuple(float(c) for c in camera.GetViewUp()),
            view_angle=float(camera.GetViewAngle()),
        )

    def set_camera(self, eye, focal_point, up=(0.0, 1.0, 0.0), view_angle: float = 30.0) -> None:
        """Look from ``eye`` at ``focal_point`` (a browser's camera, say); lighting keeps the scene's eye.

        Only the picture changes (the window, :meth:`pixel_image`,
        :meth:`screenshot`): the core still shades for the scene's camera.
        A camera away from the scene's keeps ``view_angle`` as given (the
        arrows do not refit it); :meth:`reset_camera` goes back.

        Raises
        ------
        ValueError
            For a point or direction that is not 3 finite numbers, an eye on
            the focal point, an up vector along the line of sight, or a view
            angle outside (0, 180) degrees; the camera stays as it was.
        """
        eye = _finite_vector("eye", eye)
        focal_point = _finite_vector("focal_point", focal_point)
        up = _finite_vector("up", up)
        try:
            angle = float(view_angle)
        except (TypeError, ValueError):
            angle = math.nan
        if not 0.0 < angle < 180.0:
            raise ValueError(f"view_angle: must be a number of degrees between 0 and 180, got {view_angle!r}")
        sight = focal_point - eye
        distance = float(np.linalg.norm(sight))
        if not distance > 0.0:
            raise ValueError(f"focal_point: must differ from the eye {tuple(eye)}, got {tuple(focal_point)}")
        if not np.linalg.norm(np.cross(sight / distance, up)) > 1e-9 * max(1.0, float(np.linalg.norm(up))):
            raise ValueError(f"up: must not point along the line of sight {tuple(sight / distance)}, got {tuple(up)}")
        camera = self.renderer.GetActiveCamera()
        camera.SetPosition(*eye)
        camera.SetFocalPoint(*focal_point)
        camera.SetViewUp(*up)
        camera.SetViewAngle(angle)
        camera.OrthogonalizeViewUp()
        self._fit_view_angle()
        self._sync_eye_visibility()

    def reset_camera(self) -> None:
        """Look through the scene's camera again (after :meth:`set_camera`), the view angle refitted."""
        set_camera(self.renderer.GetActiveCamera(), self.scene.camera)
        self._fit_view_angle()
        self._sync_eye_visibility()

    def ray_hit(self, origin, target):
        """The first mesh point on the ray from ``origin`` through ``target`` (a click's ray).

        Returns
        -------
        (point, normal) or None
            ndarrays of shape (3,); None when the ray misses the mesh.

        Raises
        ------
        ValueError
            When ``origin`` or ``target`` is not 3 finite numbers.
        """
        return ray_hit(self.mesh, _finite_vector("origin", origin), _finite_vector("target", target))

    @staticmethod
    def empty_window(size=(16, 16)) -> vtk.vtkRenderWindow:
        """An offscreen render window with one empty renderer (for a page that has no scene to show)."""
        window = make_render_window(size)
        window.AddRenderer(vtk.vtkRenderer())
        return window

    def set_vectors(self, vectors) -> None:
        """Choose which of N, L, R, V, H are drawn (``"NLRVH"``, ``"N,L"``, None)."""
        self._letters = glyphs.parse_vectors(vectors)
        self._update_vectors()

    def set_size(self, size) -> None:
        """Resize the window to (width, height) pixels."""
        self.render_window.SetSize(int(size[0]), int(size[1]))
        for actor in self._labels.values():
            actor.GetTextProperty().SetFontSize(_letter_font_size(int(size[1])))
        if self._legend_actor is not None:
            self._legend_actor.GetTextProperty().SetFontSize(max(10, int(size[1]) // 38))
        self._update_vectors()  # the letters' stacking offsets are in lines of the new size

    def _recolor(self) -> None:
        """Recompute the mesh colours with the core and write them into the arrays."""
        mesh, scene = self.mesh, self.scene
        if scene.interpolation == "flat":
            rgb = shading.face_colors(scene, mesh, (self.term,), self.mistake)[self.term]
            _array_to_vtk_in_place(mesh.cell_data, glyphs.COLOR_ARRAY, rgb)
            self._mapper.SetScalarModeToUseCellData()
        else:
            # gouraud, and the interactive preview of pixel mode
            rgb = shading.vertex_colors(scene, mesh, (self.term,), self.mistake)[self.term]
            _array_to_vtk_in_place(mesh.point_data, glyphs.COLOR_ARRAY, rgb)
            self._mapper.SetScalarModeToUsePointData()
        self._mapper.Modified()

    def _locate_probe(self) -> None:
        if self.scene.probe is None:
            point, normal = default_probe(self.mesh, self.scene.camera)
        else:
            point, normal = surface_point(self.mesh, self.scene.probe)
        self._probe_point, self._probe_normal = point, normal

    def _update_vectors(self) -> None:
        """Recompute N, L, R, V, H at the probe and reshape the arrows in place."""
        index = self.light_index
        point, normal = self._probe_point, self._probe_normal
        if index is not None:
            self._vectors = core.vectors(
                point, normal, light=self.scene.lights[index], two_sided=self.scene.two_sided, **viewer(self.scene)
            )
            directions = {"N": self._vectors.n, "L": self._vectors.l, "R": self._vectors.r,
                          "V": self._vectors.v, "H": self._vectors.h}
        else:
            self._vectors = None
            camera = self.scene.camera
            v = np.asarray(camera.eye) - point if not camera.infinite_viewer else np.asarray(camera.view_direction)
            v = v / np.linalg.norm(v)
            n = -normal if (self.scene.two_sided and normal @ v < 0) else normal
            directions = {"N": n, "V": v}
        view_direction = self.scene.camera.view_direction
        offsets = label_offsets([letter for letter in self._arrows if letter in self._letters and letter in directions],
                                directions)
        line = _letter_font_size(self.render_window.GetSize()[1]) + 2
        for letter, (data, actor) in self._arrows.items():
            shown = letter in self._letters and letter in directions
            if shown:
                data.ShallowCopy(glyphs.arrow(point, directions[letter], glyphs.VECTORS[letter][0], view_direction,
                                              length=self.arrow_length))
                data.Modified()
                tip = point + directions[letter] * self.arrow_length * 1.12
                if letter in self._labels:
                    self._labels[letter].SetPosition(*tip)
                    # letters of arrows that (nearly) coincide are stacked, not drawn on each other
                    self._labels[letter].SetDisplayOffset(0, -offsets[letter] * line)
            actor.SetVisibility(bool(shown))
            if letter in self._labels:
                self._labels[letter].SetVisibility(bool(shown and self.show_labels))
        self._directions = directions
        entries = [f"{letter}  {glyphs.VECTORS[letter][1]}" for letter in self._letters if letter in directions]
        if self._legend_actor is not None:
            self._legend_actor.SetInput("\n".join(entries))
            self._legend_actor.SetVisibility(bool(entries) and self.show_labels)
        self._fit_view_angle()

    # ------------------------------------------------------------------
    # framing the arrows

    def _shown_letters(self) -> list[str]:
        return [letter for letter in self._letters if letter in self._directions]

    def _fit_view_angle(self) -> None:
        """Set the VTK camera's view angle: the scene's, widened if the arrows would leave the window.

        The camera's position, focal point and up vector are left alone. The
        view angle spans the shorter side of the window (see :meth:`render`).
        A camera moved away from the scene's eye or focal point (set from a
        browser's view, say) keeps the view angle it was given.
        """
        camera = self.renderer.GetActiveCamera()
        width, height = self.render_window.GetSize()
        camera.SetUseHorizontalViewAngle(bool(width < height))
        if not self._camera_is_the_scenes(camera):
            return  # turned by someone else (a browser's camera): its view angle is theirs
        angle = float(self.scene.camera.view_angle)
        if self._shown_letters():
            angle = max(angle, self._angle_for_arrows(camera, width, height))
        if camera.GetViewAngle() != angle:
            camera.SetViewAngle(angle)

    def _camera_is_the_scenes(self, camera) -> bool:
        """True while the VTK camera stands at the scene's eye and looks at its focal point."""
        scene_camera = self.scene.camera
        scale = max(1.0, float(np.linalg.norm(np.subtract(scene_camera.eye, scene_camera.focal_point))))
        return bool(np.allclose(camera.GetPosition(), scene_camera.eye, rtol=0, atol=1e-6 * scale)
                    and np.allclose(camera.GetFocalPoint(), scene_camera.focal_point, rtol=0, atol=1e-6 * scale))

    def _angle_for_arrows(self, camera, width: int, height: int) -> float:
        """The smallest view angle (degrees) that shows the arrows' tips with their letters.

        Each tip is taken as a small ball (the arrow head's radius) around
        it. Seen from the eye, a ball at screen-axis offset ``c`` and depth
        ``z`` with radius ``ρ`` spans the angles
        :math:`\\arctan(c / z) \\pm \\arcsin(\\rho / \\sqrt{c^2 + z^2})` along that
        axis; the window must hold those spans plus, in pixels, the letters
        drawn beyond the tips and a free border.
        """
        eye = np.asarray(camera.GetPosition(), dtype=float)
        forward = np.asarray(camera.GetFocalPoint(), dtype=float) - eye
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, camera.GetViewUp())
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        head = glyphs.TIP_RADIUS

        def reach(c: float, depth: float, radius: float) -> float | None:
            # largest |tan| of a ball's span along one screen axis; None when the ball is not in front of the eye
            distance = math.hypot(c, depth)
            if depth <= 0 or distance <= radius:
                return None
            centre, half = math.atan2(c, depth), math.asin(radius / distance)
            if abs(centre) + half >= math.pi / 2:
                return None
            return max(abs(math.tan(centre - half)), abs(math.tan(centre + half)))

        tan_x = tan_y = 0.0
        for letter in self._shown_letters():
            tip = self._probe_point + self._directions[letter] * self.arrow_length - eye
            depth = float(tip @ forward)
            rx, ry = reach(float(tip @ right), depth, head), reach(float(tip @ up), depth, head)
            if rx is None or ry is None:
                return MAX_VIEW_ANGLE
            tan_x, tan_y = max(tan_x, rx), max(tan_y, ry)
        # the letters beyond the tips and a free border, as fractions of the half window
        border = (self._label_reach(height) if self.show_labels else 0.0) + FRAME_PAD * min(width, height)
        keep_x = max(0.5, 1.0 - border / (width / 2))
        keep_y = max(0.5, 1.0 - border / (height / 2))
        aspect = width / height
        if width < height:
            # the view angle spans the width
            half_tan = max(tan_x / keep_x, tan_y * aspect / keep_y)
        else:
            half_tan = max(tan_y / keep_y, tan_x / (aspect * keep_x))
        return min(MAX_VIEW_ANGLE, math.degrees(2.0 * math.atan(half_tan)))

    def _label_reach(self, height: int) -> float:
        """How far (pixels) a letter drawn by :func:`~phonglab.render.annotate.draw_labels` reaches past its tip."""
        size, offset, half = _label_metrics(height, self._shown_letters() or ["N"])
        return offset + half + max(1, size // 10) + 2.0

    def vector_marks(self) -> dict[str, tuple[tuple[float, float], tuple[float, float, float, float]]]:
        """Where each shown arrow's tip and letter land on an image of the current window.

        Returns
        -------
        dict
            letter -> ``((x, y), (left, top, right, bottom))``: the projected
            tip and the box of its letter as
            :func:`~phonglab.render.annotate.draw_labels` places it (before
            any nudging), in image pixels with row 0 at the top.
        """
        self._fit_view_angle()
        self.renderer.ResetCameraClippingRange()
        width, height = self.render_window.GetSize()
        letters = self._shown_letters()
        size, offset, half = _label_metrics(height, letters or ["N"])
        base = np.asarray(self._to_image(self._probe_point, height))
        marks = {}
        for letter in letters:
            tip = np.asarray(self._to_image(self._probe_point + self._directions[letter] * self.arrow_length, height))
            d = tip - base
            norm = np.linalg.norm(d)
            d = d / norm if norm > 1e-9 else np.array([0.0, -1.0])
            centre = tip + d * offset
            box = (centre[0] - half, centre[1] - half, centre[0] + half, centre[1] + half)
            marks[letter] = ((float(tip[0]), float(tip[1])), tuple(float(v) for v in box))
        return marks

    def _update_light_markers(self) -> None:
        """One marker per light; actors are reused, added only if the number of lights grows."""
        view_direction = self.scene.camera.view_direction
        lights = self.scene.lights
        while len(self._light_markers) < len(lights):
            data = pv.PolyData()
            self._light_markers.append((data, self._glyph_actor(data)))
        for i, (data, actor) in enumerate(self._light_markers):
            marker = glyphs.light_marker(lights[i], view_direction) if i < len(lights) else None
            if marker is not None:
                data.ShallowCopy(marker)
                data.Modified()
            actor.SetVisibility(marker is not None and self.show_markers)

    def _update_area_panel(self) -> None:
        """The area light's panel where the scene puts it (hidden without an area light)."""
        data, actor = self._area_panel
        area = self.scene.area_light
        if area is not None:
            data.ShallowCopy(area_light_panel(area.light))
            data.Modified()
        actor.SetVisibility(bool(area is not None and self.show_markers))

    def _update_eye_marker(self) -> None:
        camera = self.scene.camera
        data, actor = self._eye
        data.ShallowCopy(glyphs.eye_marker(camera.eye, camera.focal_point, camera.view_direction))
        data.Modified()
        self._sync_eye_visibility()

    def _sync_eye_visibility(self) -> None:
        # the eye marker would fill the screen when the VTK camera sits at the eye
        at_eye = np.linalg.norm(
            np.asarray(self.renderer.GetActiveCamera().GetPosition()) - np.asarray(self.scene.camera.eye)
        )
        self._eye[1].SetVisibility(bool(self.show_markers and at_eye > EYE_MARKER_MIN_DISTANCE))

    # ------------------------------------------------------------------
    # rendering

    def render(self) -> None:
        """Render the window (fits the clipping range first).

        The scene's view angle spans the *shorter* side of the window: the
        height of a wide window (VTK's usual vertical angle), the width of a
        tall one, so that a tall panel does not crop the mesh. With arrows
        shown, it is widened if needed to hold them (see the module notes).
        """
        self._sync_eye_visibility()
        self._fit_view_angle()
        self.renderer.ResetCameraClippingRange()
        self.render_window.Render()

    def pick(self, display_x: float, display_y: float):
        """The mesh point under a display position, or None.

        Parameters
        ----------
        display_x, display_y : float
            VTK display coordinates: pixels from the window's *bottom-left* corner.

        Returns
        -------
        ndarray of shape (3,) or None
            The picked world point on the mesh (glyphs are not pickable).
        """
        picker = vtk.vtkCellPicker()
        picker.SetTolerance(0.0005)
        picker.PickFromListOn()
        picker.AddPickList(self._mesh_actor)
        self.renderer.ResetCameraClippingRange()
        if not picker.Pick(float(display_x), float(display_y), 0.0, self.renderer):
            return None
        if picker.GetCellId() < 0:
            return None
        return np.asarray(picker.GetPickPosition(), dtype=np.float64)

    def _gbuffer(self):
        """The G-buffer for the current mesh, VTK camera and window size (cached)."""
        camera = self.renderer.GetActiveCamera()
        size = tuple(self.render_window.GetSize())
        key = (id(self.mesh), size, camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
               camera.GetViewAngle(), camera.GetParallelProjection(), camera.GetParallelScale())
        if self._gbuffer_cache is None or self._gbuffer_cache[0] != key:
            if self._gbuffer_renderer is None:
                self._gbuffer_renderer = GBufferRenderer()
            self._gbuffer_cache = (key, self._gbuffer_renderer.render(self.mesh, camera, size))
        return self._gbuffer_cache[1]

    def pixel_image(self, term: str | None = None) -> np.ndarray:
        """The mesh shaded per pixel by the core, on the background (no glyphs).

        With a mistake set (:meth:`set_mistake`) the pixels are shaded with
        it; a mistake with ``needs_raw_normals`` gets the interpolated normals
        as they came, not renormalised, so its bug shows here.

        Parameters
        ----------
        term : str, optional
            ``"color"``, ``"ambient"``, ``"diffuse"`` or ``"specular"``; the view's term by default.

        Returns
        -------
        ndarray, shape (height, width, 3), uint8
            For the current VTK camera and window size, top row first.
        """
        term = term or self.term
        return shading.pixel_colors(self.scene, self._gbuffer(), self.background, (term,), self.mistake)[term]

    def annotate(self, image: np.ndarray, *, legend: bool = True) -> np.ndarray:
        """Draw the letters at the arrow tips (and the legend) on a rendered image.

        Parameters
        ----------
        image : ndarray, shape (height, width, 3), uint8
            A render of this view at its current camera and size.
        legend : bool
            Also draw the legend box.
        """
        if not self.show_labels:
            return image
        height = image.shape[0]
        labels, entries = [], []
        point = self._probe_point
        for letter in self._letters:
            if letter not in self._directions:
                continue
            tip = point + self._directions[letter] * self.arrow_length
            x, y = self._to_image(tip, height)
            bx, by = self._to_image(point, height)
            labels.append((letter, (x, y), (x - bx, y - by), glyphs.VECTORS[letter][0]))
            entries.append((letter, glyphs.VECTORS[letter][1], glyphs.VECTORS[letter][0]))
        image = draw_labels(image, labels)
        return draw_legend(image, entries) if legend else image

    def _to_image(self, world, height: int) -> tuple[float, float]:
        self.renderer.SetWorldPoint(float(world[0]), float(world[1]), float(world[2]), 1.0)
        self.renderer.WorldToDisplay()
        x, y, _ = self.renderer.GetDisplayPoint()
        return x, height - 1 - y

    def screenshot(self, path=None, *, annotate: bool = True) -> np.ndarray:
        """Render and return the image, optionally saving it as PNG.

        In pixel mode the per-pixel shaded mesh is composited with the glyphs
        by depth. Labels and the legend are drawn on the image (not by VTK).

        Parameters
        ----------
        path : str or path-like, optional
            Where to write a PNG (written to a temporary file, then renamed).
        annotate : bool
            Draw the vector letters and the legend.

        Returns
        -------
        ndarray, shape (height, width, 3), uint8
        """
        text_actors = list(self._labels.values()) + ([self._legend_actor] if self._legend_actor else [])
        visible = [a.GetVisibility() for a in text_actors]
        for a in text_actors:
            a.VisibilityOff()
        pixel_mode = self.scene.interpolation == "pixel"
        try:
            if pixel_mode:
                self._mesh_actor.VisibilityOff()
            self.render()
            image = read_rgb(self.render_window)
            if pixel_mode:
                depth = read_depth(self.render_window)
                image = self._composite(image, depth)
        finally:
            self._mesh_actor.VisibilityOn()
            for a, v in zip(text_actors, visible):
                a.SetVisibility(v)
        if annotate:
            image = self.annotate(image)
        if path is not None:
            save_png(image, path)
        return image

    def _composite(self, overlay: np.ndarray, depth: np.ndarray) -> np.ndarray:
        """Per-pixel shaded mesh in front of or behind the glyphs, by depth."""
        camera = self.renderer.GetActiveCamera()
        gbuffer = self._gbuffer()
        shaded = self.pixel_image()
        mask = gbuffer.mask
        glyph_z = eye_distance(camera, depth[mask])
        eye = np.asarray(camera.GetPosition())
        axis = np.asarray(camera.GetDirectionOfProjection())
        # the mesh wins where it is nearer than any glyph (or where no glyph was drawn)
        mesh_z = (gbuffer.positions[mask] - eye) @ axis
        front = np.zeros_like(mask)
        front[mask] = mesh_z <= glyph_z * (1 + 1e-4)
        out = overlay.copy()
        out[front] = shaded[front]
        return out

    def legend(self) -> list[tuple[str, str, str]]:
        """The vectors shown, for a legend drawn elsewhere (HTML): (letter, meaning, "#rrggbb")."""
        return [
            (letter, glyphs.VECTORS[letter][1], "#%02x%02x%02x" % glyphs.VECTORS[letter][0])
            for letter in self._letters
            if letter in self._directions
        ]

    def close(self) -> None:
        """Release the OpenGL contexts."""
        if self._gbuffer_renderer is not None:
            self._gbuffer_renderer.close()
        self.render_window.Finalize()


@functools.lru_cache(maxsize=64)
def _letter_metrics(height: int, letters: str) -> tuple[int, float, float]:
    size = max(12, round(height / 24))
    fnt = font(size, bold=True)
    # draw_labels: half-extent of the letter from its anchor, and the centre's distance from the tip
    extent = max(max(fnt.getbbox(letter, anchor="mm")[2:]) for letter in letters)
    return size, 0.45 * size + 0.6 * extent, float(extent)


def _letter_font_size(height: int) -> int:
    """Font size (pixels) of the VTK text letters at the arrow tips in a window this tall."""
    return max(12, height // 24)


#: Arrows closer than this angle (degrees) have their letters stacked.
LABEL_STACK_DEGREES = 10.0


def label_offsets(letters, directions) -> dict[str, int]:
    """How many lines down to shift each letter so nearly coinciding arrows stay readable.

    Each letter moves one line below every earlier letter whose arrow lies
    within :data:`LABEL_STACK_DEGREES` of its own (e.g. N, L, R, V and H all
    coincide when the light and the eye are straight above the point).
    """
    cos_limit = np.cos(np.radians(LABEL_STACK_DEGREES))
    offsets: dict[str, int] = {}
    for i, letter in enumerate(letters):
        d = np.asarray(directions[letter], float)
        taken = {offsets[other] for other in letters[:i]
                 if float(np.dot(d, np.asarray(directions[other], float))) >= cos_limit}
        offsets[letter] = next(k for k in range(len(letters) + 1) if k not in taken)
    return offsets


def _label_metrics(height: int, letters) -> tuple[int, float, float]:
    """For letters drawn on an image ``height`` pixels tall: (font size, centre beyond the tip, half extent)."""
    return _letter_metrics(int(height), "".join(sorted(letters)))


def save_png(image: np.ndarray, path) -> None:
    """Write an RGB image as PNG, whole or not at all (temporary file, then rename)."""
    _files.write_atomically(path, lambda tmp: Image.fromarray(np.asarray(image, dtype=np.uint8)).save(tmp, format="PNG"))
