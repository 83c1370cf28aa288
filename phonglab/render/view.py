"""SceneView: one VTK renderer and window showing a scene shaded by the core.

What the window holds:

* the mesh of every object (:func:`~phonglab.render.objects.scene_mesh`),
  coloured by the core (RGB scalars, VTK lighting off), each object with its
  own material and, with ``shadows``, the lights its points' shadow rays
  reach: per face (flat) or per vertex (gouraud, and pixel mode's preview);
* arrows N, L, R, V, H at the probe point, in fixed colours, half as long
  as the (smallest) object's bounding radius;
* a marker per light (a sphere for a point light, a cone for a spotlight,
  three parallel arrows for a directional light) and an eye marker (shown
  only when the VTK camera has left the scene's eye);
* the scene's area light, if it has one, as a thin panel whose emitting face
  is drawn flat in the light's colour (:func:`~phonglab.render.glyphs.area_light_panel`);
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

Framing (:mod:`phonglab.render.framing`): the camera stays at the scene's
eye and looks where the scene says; when arrows are shown and a tip (with
the letter beyond it) would leave the window, the view angle is widened just
enough to hold it. Nothing else about the camera changes, and a change of
material never refits it. Once the VTK camera has been moved off the scene's
eye (a browser's camera copied in), the view angle is left as it was set
until the scene's camera is applied again.

SceneView ties together: the actors (:mod:`~phonglab.render.actors`), the
probe and its vectors from the core (:mod:`~phonglab.render.probe`,
:mod:`~phonglab.render.arrows`), the camera check
(:mod:`~phonglab.render.camera`), picking and projecting
(:mod:`~phonglab.render.picking`), per-pixel shading composited with the
glyphs (:mod:`~phonglab.render.pixels`) and PNG writing
(:mod:`~phonglab.render.saving`). What it gives out (picks, projections,
the letters' places, images) is in :mod:`~phonglab.render.view_pictures`.

Directions point *away from the surface point*: every arrow starts at the probe.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np
import pyvista as pv
import vtk

from phonglab.render import actors, framing, glyphs, picking, pixels, shading
from phonglab.render._vtk import make_render_window, set_camera
from phonglab.render.arrows import ProbeArrows
from phonglab.render.camera import CameraState, check_camera
from phonglab.render.objects import scene_mesh, smallest_radius
from phonglab.render.probe import directed_light_index
from phonglab.render.view_pictures import ViewPictures
from phonglab.scene import Scene

#: default background (slate), RGB in [0, 1]
BACKGROUND = (0.13, 0.14, 0.17)
#: what a scene change may need of the glyphs (Scene.changes): the arrows, the light markers, the eye marker
GLYPHS = {"vectors", "markers", "eye"}


def _check_term(term: str) -> None:
    if term not in shading.TERMS:
        raise ValueError(f"term must be one of {', '.join(shading.TERMS)}, got {term!r}")


class ColourArray(NamedTuple):
    """The colours a :class:`SceneView` shows on its mesh (see :meth:`SceneView.colour_array`)."""

    #: the array's name in the mesh's point or cell data
    name: str
    #: ``"point"`` (Gouraud, pixel mode's preview) or ``"cell"`` (flat)
    location: str
    #: uint8 RGB, shape (number of points or cells, 3): the array itself, not a copy
    values: np.ndarray


class SceneView(ViewPictures):
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
        _check_term(term)
        if mistake is not None:
            shading.get_mistake(mistake)  # raises ValueError listing the names allowed
        self.scene = scene
        self.term = term
        self.mistake = mistake
        self.background = tuple(float(c) for c in background)
        self.show_labels = bool(labels)
        self.show_markers = bool(markers)
        self._arrows = ProbeArrows(glyphs.parse_vectors(vectors))
        self._light_index_choice = light_index
        self._gbuffers = pixels.GBufferCache()
        self._keep_view_angle = False  # the camera came from a browser: its view angle is not refitted
        self._stale_glyphs = set()  # glyphs (GLYPHS) a change left to reshape (defer_glyphs)
        self._scene_plan = (None, None)  # (scene, plan(scene)) from update(scene_plan=), used while it shows

        # window, renderer, camera
        self.render_window = make_render_window(size, offscreen=offscreen)
        self.renderer = vtk.vtkRenderer()
        self.renderer.SetBackground(*self.background)
        self.renderer.AutomaticLightCreationOff()
        self.render_window.AddRenderer(self.renderer)
        set_camera(self.renderer.GetActiveCamera(), scene.camera)

        # the shaded mesh: one actor for the whole life of the view
        self._mapper, self._mesh_actor = actors.mesh_actor(self.renderer)
        self._set_mesh(scene_mesh(scene))

        # glyphs: an actor per arrow, per light, the eye and the area light
        self._glyphs = actors.Glyphs(self.renderer, self.size[1], vtk_text=vtk_text)

        # first fill
        self._recolor()
        self._arrows.locate(self.mesh, scene)
        self._update_vectors()
        self._update_markers()
        self._update_eye_marker()

    def _set_mesh(self, mesh: pv.PolyData) -> None:
        """Show a new mesh (geometry changed): colour arrays sized for it."""
        actors.show_mesh(self._mapper, mesh)
        self.mesh = mesh
        self._arrows.length = glyphs.ARROW_FRACTION * smallest_radius(mesh)
        self._gbuffers.clear()
        self._cull()

    def _cull(self) -> None:
        """Hidden faces left out for the camera, where that changes no pixel (fewer for a browser to draw)."""
        actors.cull_hidden_faces(self._mesh_actor, self.mesh, self.renderer.GetActiveCamera().GetPosition())

    # ------------------------------------------------------------------
    # state

    @property
    def light_index(self) -> int | None:
        """Index in ``scene.lights`` of the light the vectors refer to (None: no such light)."""
        return directed_light_index(self.scene.lights, self._light_index_choice)

    @property
    def probe(self) -> tuple[np.ndarray, np.ndarray]:
        """The probe point on the surface and the unit normal there."""
        return self._arrows.point, self._arrows.normal

    @property
    def probe_vectors(self):
        """The core's ``ProbeVectors`` at the probe, or None without a directed light."""
        return self._arrows.vectors

    @property
    def arrow_length(self) -> float:
        """Length of the arrows in world units (half the mesh's bounding radius)."""
        return self._arrows.length

    # ------------------------------------------------------------------
    # updates

    def update(self, scene, *, keep_view_angle: bool = False, defer_glyphs: bool = False, scene_plan=None) -> None:
        """Show ``scene``, recomputing only what differs from the current one.

        The mesh's colour array is overwritten in place; actors are never
        added on a change of material, lights, model or probe.

        Parameters
        ----------
        scene : Scene
        keep_view_angle : bool
            The scene's camera is a browser's (the student turned the view):
            show its view angle as it is, not widened to hold the arrows, until
            a camera comes without this flag (:meth:`reset_camera`, a new scene).
            The core shades for this camera's eye either way.
        defer_glyphs : bool
            Recolour the mesh and compute the vectors at the probe (the
            readout's numbers), but leave the arrows' and markers' shapes for
            later (a drag of the view: the browser gets only the colours until
            it ends). The next :meth:`update` without it, :meth:`refresh_glyphs`
            or a render reshapes them.
        scene_plan : phonglab.scene.ScenePlan, optional
            ``plan(scene)`` when the caller has made it (the app plans for its
            panels): the core's shading uses it instead of planning again.
            The colours are the same either way.
        """
        if scene_plan is not None:
            self._scene_plan = (scene, scene_plan)
        old, self.scene = self.scene, scene
        needs = Scene.changes(old, scene)
        if "camera" in needs:
            self._keep_view_angle = bool(keep_view_angle)
        if not needs:
            return
        if "mesh" in needs:
            self._set_mesh(scene_mesh(scene))
        if "camera" in needs:
            set_camera(self.renderer.GetActiveCamera(), scene.camera)
            self._gbuffers.clear()
            self._cull()
        if "colours" in needs:
            self._recolor()
        if "probe" in needs or ("default probe" in needs and scene.probe is None):
            self._arrows.locate(self.mesh, scene)
        stale = needs.needs & GLYPHS
        if defer_glyphs:
            if "vectors" in stale:
                self._arrows.compute(scene, self.light_index)  # the numbers now, the shapes later
            self._stale_glyphs |= stale
            return
        self._stale_glyphs |= stale
        self.refresh_glyphs()

    def refresh_glyphs(self) -> None:
        """Reshape the arrows and markers that an :meth:`update` with ``defer_glyphs`` left as they were."""
        stale, self._stale_glyphs = self._stale_glyphs, set()
        if "vectors" in stale:
            self._update_vectors()
        if "markers" in stale:
            self._update_markers()
        if "eye" in stale:
            self._update_eye_marker()

    @property
    def glyphs_stale(self) -> bool:
        """True while an :meth:`update` with ``defer_glyphs`` left arrows or markers to reshape."""
        return bool(self._stale_glyphs)

    def set_probe(self, point) -> None:
        """Move the probe to the surface point nearest ``point`` (None: the default probe)."""
        probe = None if point is None else tuple(float(c) for c in point)
        self.scene = dataclasses.replace(self.scene, probe=probe)
        self._arrows.locate(self.mesh, self.scene)
        self._update_vectors()

    def set_term(self, term: str) -> None:
        """Show one term (``"ambient"``, ``"diffuse"``, ``"specular"``) or ``"color"`` (their sum)."""
        _check_term(term)
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
    def glyph_actors(self) -> actors.Glyphs:
        """The glyphs' actors: ``arrows`` and ``letters`` by letter, ``light_markers``, ``eye``, ``area_panel``.

        The same objects for the life of the view, reshaped in place; a glyph
        not shown has its actor's visibility off. ``letters`` (VTK text) is
        empty for a view made with ``vtk_text=False``.
        """
        return self._glyphs

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
        set_camera(self.renderer.GetActiveCamera(), check_camera(eye, focal_point, up, view_angle))
        self._cull()
        self._fit_view_angle()
        self._sync_eye_visibility()

    def reset_camera(self) -> None:
        """Look through the scene's camera again (after :meth:`set_camera`), the view angle refitted."""
        self._keep_view_angle = False
        set_camera(self.renderer.GetActiveCamera(), self.scene.camera)
        self._cull()
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
        return picking.ray_hit(self.mesh, origin, target)

    @staticmethod
    def empty_window(size=(16, 16)) -> vtk.vtkRenderWindow:
        """An offscreen render window with one empty renderer (for a page that has no scene to show)."""
        window = make_render_window(size)
        window.AddRenderer(vtk.vtkRenderer())
        return window

    @property
    def vectors(self) -> str:
        """The letters of the arrows asked for, in drawing order (``""``: none)."""
        return self._arrows.letters

    def set_vectors(self, vectors) -> None:
        """Choose which of N, L, R, V, H are drawn (``"NLRVH"``, ``"N,L"``, None)."""
        self._arrows.letters = glyphs.parse_vectors(vectors)
        self._update_vectors()

    def set_size(self, size) -> None:
        """Resize the window to (width, height) pixels."""
        self.render_window.SetSize(int(size[0]), int(size[1]))
        self._glyphs.set_height(int(size[1]))
        self._update_vectors()  # the letters' stacking offsets are in lines of the new size

    def _recolor(self) -> None:
        """Recompute the mesh colours with the core and write them into the arrays."""
        planned_for, scene_plan = self._scene_plan
        actors.colour_mesh(self._mapper, self.mesh, self.scene, self.term, self.mistake,
                           scene_plan=scene_plan if planned_for is self.scene else None)
        # the material's opacity on the actor too: a browser's copy (vtk.js) blends with it
        opacity = float(self.scene.material.opacity)
        if self._mesh_actor.GetProperty().GetOpacity() != opacity:
            actors.set_opacity(self._mesh_actor, opacity)
            self._cull()  # hidden faces are left out of an opaque mesh only (new colours change no face)

    def _update_vectors(self) -> None:
        """Recompute N, L, R, V, H at the probe and reshape the arrows in place."""
        arrows = self._arrows
        arrows.compute(self.scene, self.light_index)
        self._glyphs.show_arrows(arrows.point, arrows.directions, arrows.letters,
                                 view_direction=self.scene.camera.view_direction, length=arrows.length,
                                 labels=self.show_labels, height=self.size[1])
        self._fit_view_angle()

    # ------------------------------------------------------------------
    # framing the arrows

    def _fit_view_angle(self) -> None:
        """Set the VTK camera's view angle: the scene's, widened if the arrows or light markers would leave the window.

        The camera's position, focal point and up vector are left alone. The
        view angle spans the shorter side of the window (see :meth:`render`).
        A camera moved away from the scene's eye or focal point (set from a
        browser's view, say) keeps the view angle it was given.
        """
        camera = self.renderer.GetActiveCamera()
        width, height = self.render_window.GetSize()
        camera.SetUseHorizontalViewAngle(bool(width < height))
        if self._keep_view_angle:  # a browser's camera, shown as the browser shows it
            return
        letters = self._arrows.shown()
        angle = framing.fitted_view_angle(
            self.scene.camera, camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
            [self._arrows.tip(letter) for letter in letters],
            tip_radius=glyphs.TIP_RADIUS, width=width, height=height,
            reach=framing.label_reach(height, letters) if letters and self.show_labels else 0.0)
        if angle is not None:  # a light's marker near the edge is brought whole into the window, or left out
            framed = []
            for centre, radius in self._glyphs.marker_balls():
                needed = framing.view_angle_for_tips(
                    camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(), [centre],
                    tip_radius=radius, width=width, height=height, reach=0.0)
                framed.append(needed <= framing.MARKER_WIDENING * self.scene.camera.view_angle)
                if framed[-1]:
                    angle = max(angle, needed)
            self._glyphs.frame_markers(framed)
        if angle is not None and camera.GetViewAngle() != angle:
            camera.SetViewAngle(angle)

    def _update_markers(self) -> None:
        """The lights' markers and the area light's panel where the scene puts them."""
        area = self.scene.area_light
        self._glyphs.show_light_markers(self.scene.lights, self.scene.camera.view_direction,
                                        visible=self.show_markers)
        self._glyphs.show_area_panel(area.light if area is not None else None, visible=self.show_markers)
        self._fit_view_angle()

    def _update_eye_marker(self) -> None:
        self._glyphs.show_eye(self.scene.camera, self.renderer.GetActiveCamera(), visible=self.show_markers)

    def _sync_eye_visibility(self) -> None:
        self._glyphs.sync_eye(self.scene.camera, self.renderer.GetActiveCamera(), visible=self.show_markers)

    # ------------------------------------------------------------------
    # rendering

    def render(self) -> None:
        """Render the window (fits the clipping range first).

        The scene's view angle spans the *shorter* side of the window: the
        height of a wide window (VTK's usual vertical angle), the width of a
        tall one, so that a tall panel does not crop the mesh. With arrows
        shown, it is widened if needed to hold them (see the module notes).
        """
        if self._stale_glyphs:
            self.refresh_glyphs()
        self._sync_eye_visibility()
        self._fit_view_angle()
        self.renderer.ResetCameraClippingRange()
        self.render_window.Render()

    def close(self) -> None:
        """Release the OpenGL contexts."""
        self._gbuffers.close()
        self.render_window.Finalize()
