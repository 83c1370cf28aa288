"""The VTK actors of a view: the shaded mesh's, and the glyphs' (arrows, letters, legend, markers).

Every actor has VTK lighting off and takes its colours from uint8 RGB
arrays; glyphs are not pickable. Actors are made once and reshaped in place
(:meth:`Glyphs.show_arrows` and friends), so a change of scene never adds
one, except a marker slot when the number of lights grows.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pyvista as pv
import vtk

from phonglab.render import framing, glyphs, shading
from phonglab.render import mesh as meshes

#: the VTK camera counts as "at the eye" within this distance; the eye marker is hidden then
EYE_MARKER_MIN_DISTANCE = 0.5
#: the letters sit this far along their arrow, as a fraction of its length
LETTER_AT = 1.12


class Glyph(NamedTuple):
    """One glyph of a view: its polydata (reshaped in place) and the actor drawing it."""

    data: pv.PolyData
    actor: vtk.vtkActor


def overwrite_array(owner, name: str, values: np.ndarray) -> None:
    """Overwrite the named array's values, keeping the same VTK array object."""
    array = owner[name]
    array[...] = values
    owner.GetArray(name).Modified()


def mesh_actor(renderer: vtk.vtkRenderer) -> tuple[vtk.vtkPolyDataMapper, vtk.vtkActor]:
    """The mapper and actor that show a view's shaded mesh (lighting off), added to ``renderer``."""
    mapper = vtk.vtkPolyDataMapper()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().LightingOff()
    renderer.AddActor(actor)
    return mapper, actor


def cull_hidden_faces(actor: vtk.vtkActor, mesh: pv.PolyData, eye) -> None:
    """Leave out the faces turned away from ``eye`` where they cannot be seen, and only there.

    That is an opaque mesh closed and wound outwards (:func:`~phonglab.render.mesh.closed_outward`)
    with the eye outside its bounding box. The picture is the same; the
    faces drawn are half as many, which a browser drawing WebGL in software
    (no GPU) feels: a frame of the 100k-vertex sphere took about a third less.
    """
    lo, hi = np.reshape(mesh.bounds, (3, 2)).T
    outside = bool(np.any((np.asarray(eye, dtype=float) < lo) | (np.asarray(eye, dtype=float) > hi)))
    prop = actor.GetProperty()
    prop.SetBackfaceCulling(outside and prop.GetOpacity() >= 1.0 and meshes.closed_outward(mesh))


def show_mesh(mapper: vtk.vtkPolyDataMapper, mesh: pv.PolyData) -> None:
    """Make ``mapper`` draw ``mesh`` from zeroed uint8 RGB arrays, per point and per cell, sized for it."""
    # lighting is off, so nothing draws with the normals: stop them being the
    # normals attribute (a browser's copy would receive them), keep the array
    mesh.GetPointData().SetActiveAttribute(-1, vtk.vtkDataSetAttributes.NORMALS)
    mesh.point_data[glyphs.COLOR_ARRAY] = np.zeros((mesh.n_points, 3), np.uint8)
    mesh.cell_data[glyphs.COLOR_ARRAY] = np.zeros((mesh.n_cells, 3), np.uint8)
    mesh.point_data.active_scalars_name = glyphs.COLOR_ARRAY
    mesh.cell_data.active_scalars_name = glyphs.COLOR_ARRAY
    mapper.SetInputData(mesh)
    mapper.SetColorModeToDirectScalars()
    mapper.ScalarVisibilityOn()


def colour_mesh(mapper: vtk.vtkPolyDataMapper, mesh: pv.PolyData, scene, term: str, mistake: str | None, *,
                scene_plan=None) -> None:
    """Shade ``mesh`` with the core and write the colours in place: per cell (flat) or per point.

    ``term`` is ``"color"`` or one term; ``mistake`` a common mistake's name or None; ``scene_plan``
    ``plan(scene)`` if the caller has it (None: planned here).
    """
    if scene.interpolation == "flat":
        rgb = shading.face_colors(scene, mesh, (term,), mistake, scene_plan=scene_plan)[term]
        overwrite_array(mesh.cell_data, glyphs.COLOR_ARRAY, rgb)
        mapper.SetScalarModeToUseCellData()
    else:
        # gouraud, and the interactive preview of pixel mode
        rgb = shading.vertex_colors(scene, mesh, (term,), mistake, scene_plan=scene_plan)[term]
        overwrite_array(mesh.point_data, glyphs.COLOR_ARRAY, rgb)
        mapper.SetScalarModeToUsePointData()
    mapper.Modified()


def set_opacity(actor: vtk.vtkActor, opacity: float) -> None:
    """Give the mesh's actor the material's opacity (a browser's vtk.js copy draws with it).

    Images do not rely on VTK's blending: :mod:`~phonglab.render.translucency`
    composites the mesh's layers in linear light.
    """
    prop = actor.GetProperty()
    if prop.GetOpacity() != float(opacity):
        prop.SetOpacity(float(opacity))


def legend_font_size(height: int) -> int:
    """Font size (pixels) of the VTK legend in a window this tall."""
    return max(10, int(height) // 38)


def _glyph(renderer: vtk.vtkRenderer) -> Glyph:
    data = pv.PolyData()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(data)
    mapper.SetColorModeToDirectScalars()
    mapper.SetScalarModeToUsePointData()
    mapper.ScalarVisibilityOn()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().LightingOff()
    actor.PickableOff()
    renderer.AddActor(actor)
    return Glyph(data, actor)


def _letter_actor(renderer: vtk.vtkRenderer, letter: str, height: int) -> vtk.vtkBillboardTextActor3D:
    actor = vtk.vtkBillboardTextActor3D()
    actor.SetInput(letter)
    prop = actor.GetTextProperty()
    prop.SetColor(*(c / 255 for c in glyphs.VECTORS[letter][0]))
    prop.BoldOn()
    prop.SetFontSize(framing.letter_font_size(height))
    prop.SetJustificationToCentered()
    prop.SetVerticalJustificationToCentered()
    actor.PickableOff()
    renderer.AddActor(actor)
    return actor


def _legend_actor(renderer: vtk.vtkRenderer, height: int) -> vtk.vtkTextActor:
    actor = vtk.vtkTextActor()
    prop = actor.GetTextProperty()
    prop.SetFontSize(legend_font_size(height))
    prop.SetColor(0.92, 0.92, 0.92)
    prop.SetBackgroundColor(0.04, 0.04, 0.06)
    prop.SetBackgroundOpacity(0.65)
    actor.SetPosition(8, 8)
    actor.PickableOff()
    renderer.AddViewProp(actor)
    return actor


def _reshape(glyph: Glyph, polydata: pv.PolyData) -> None:
    glyph.data.ShallowCopy(polydata)
    glyph.data.Modified()


class Glyphs:
    """A view's glyph actors, made once on ``renderer``.

    Parameters
    ----------
    renderer : vtkRenderer
    height : int
        The window's height in pixels (sets the font sizes).
    vtk_text : bool
        Also make VTK text actors: a letter per arrow and the legend.

    Attributes
    ----------
    arrows : dict
        letter -> :class:`Glyph`, for every letter of N, L, R, V, H.
    letters : dict
        letter -> vtkBillboardTextActor3D (empty without ``vtk_text``).
    legend : vtkTextActor or None
    light_markers : list of Glyph
        One slot per light seen so far.
    eye, area_panel : Glyph
    """

    def __init__(self, renderer: vtk.vtkRenderer, height: int, *, vtk_text: bool):
        self._renderer = renderer
        self.arrows: dict[str, Glyph] = {}
        self.letters: dict[str, vtk.vtkBillboardTextActor3D] = {}
        for letter in glyphs.VECTORS:
            self.arrows[letter] = _glyph(renderer)
            if vtk_text:
                self.letters[letter] = _letter_actor(renderer, letter, height)
        self.light_markers: list[Glyph] = []
        self._markers_wanted: set = set()  # the light markers and area panel the scene shows (ids of their actors)
        self.eye = _glyph(renderer)
        self.area_panel = _glyph(renderer)
        self.legend = _legend_actor(renderer, height) if vtk_text else None

    def text_actors(self) -> list:
        """The VTK text actors (letters and legend), to hide them from an image that draws its own."""
        return list(self.letters.values()) + ([self.legend] if self.legend else [])

    def set_height(self, height: int) -> None:
        """Font sizes for a window ``height`` pixels tall."""
        for actor in self.letters.values():
            actor.GetTextProperty().SetFontSize(framing.letter_font_size(height))
        if self.legend is not None:
            self.legend.GetTextProperty().SetFontSize(legend_font_size(height))

    def show_arrows(self, point, directions, letters, *, view_direction, length: float, labels: bool,
                    height: int) -> None:
        """Reshape the arrows at ``point`` along ``directions`` and place their letters; hide the others.

        Parameters
        ----------
        point : 3 floats
            The probe, where every arrow starts.
        directions : dict
            letter -> unit direction, for the vectors that exist (N and V only without a directed light).
        letters : str
            The letters asked for; an arrow is shown when its letter is asked for and has a direction.
        view_direction : 3 floats
            The camera's, for the arrows' relief shading.
        length : float
            The arrows' length in world units.
        labels : bool
            Show the VTK letters and legend.
        height : int
            The window's height in pixels: stacked letters are a line of its font apart.
        """
        shown_letters = [letter for letter in self.arrows if letter in letters and letter in directions]
        offsets = framing.label_offsets(shown_letters, directions)
        line = framing.letter_font_size(height) + 2
        for letter, glyph in self.arrows.items():
            shown = letter in letters and letter in directions
            if shown:
                _reshape(glyph, glyphs.arrow(point, directions[letter], glyphs.VECTORS[letter][0], view_direction,
                                             length=length))
                if letter in self.letters:
                    self.letters[letter].SetPosition(*(point + directions[letter] * length * LETTER_AT))
                    # letters of arrows that (nearly) coincide are stacked, not drawn on each other
                    self.letters[letter].SetDisplayOffset(0, -offsets[letter] * line)
            glyph.actor.SetVisibility(bool(shown))
            if letter in self.letters:
                self.letters[letter].SetVisibility(bool(shown and labels))
        entries = [f"{letter}  {glyphs.VECTORS[letter][1]}" for letter in letters if letter in directions]
        if self.legend is not None:
            self.legend.SetInput("\n".join(entries))
            self.legend.SetVisibility(bool(entries) and labels)

    def show_light_markers(self, lights, view_direction, *, visible: bool) -> None:
        """One marker per light (none for an ambient light); slots are reused, added only if the lights grow."""
        while len(self.light_markers) < len(lights):
            self.light_markers.append(_glyph(self._renderer))
        for i, glyph in enumerate(self.light_markers):
            marker = glyphs.light_marker(lights[i], view_direction) if i < len(lights) else None
            if marker is not None:
                _reshape(glyph, marker)
            self._show_marker(glyph, marker is not None and visible)

    def _show_marker(self, glyph: Glyph, wanted: bool) -> None:
        if wanted:
            self._markers_wanted.add(id(glyph.actor))
        else:
            self._markers_wanted.discard(id(glyph.actor))
        glyph.actor.SetVisibility(wanted)

    def _wanted_markers(self) -> list[Glyph]:
        return [g for g in [*self.light_markers, self.area_panel] if id(g.actor) in self._markers_wanted]

    def marker_balls(self) -> list[tuple[np.ndarray, float]]:
        """``(centre, radius)`` of a ball around each light marker and area panel the scene shows, in world units.

        In the order :meth:`frame_markers` takes; a marker left out of the picture by it is counted too.
        """
        balls = []
        for glyph in self._wanted_markers():
            x0, x1, y0, y1, z0, z1 = glyph.actor.GetBounds()
            low, high = np.array([x0, y0, z0]), np.array([x1, y1, z1])
            balls.append(((low + high) / 2, float(np.linalg.norm(high - low)) / 2))
        return balls

    def frame_markers(self, framed) -> None:
        """Show the markers of :meth:`marker_balls` whose entry in ``framed`` is true; leave the others out.

        A marker the view angle cannot take in whole is left out of the
        picture: a piece of one at the window's edge looks like a fault.
        """
        for glyph, whole in zip(self._wanted_markers(), framed):
            glyph.actor.SetVisibility(bool(whole))

    def show_area_panel(self, area_light, *, visible: bool) -> None:
        """The area light's panel where it is (hidden for None)."""
        if area_light is not None:
            _reshape(self.area_panel, glyphs.area_light_panel(area_light))
        self._show_marker(self.area_panel, bool(area_light is not None and visible))

    def show_eye(self, scene_camera, vtk_camera, *, visible: bool) -> None:
        """Reshape the eye marker at the scene camera's eye, then :meth:`sync_eye`."""
        _reshape(self.eye, glyphs.eye_marker(scene_camera.eye, scene_camera.focal_point, scene_camera.view_direction))
        self.sync_eye(scene_camera, vtk_camera, visible=visible)

    def sync_eye(self, scene_camera, vtk_camera, *, visible: bool) -> None:
        """Show the eye marker only while the VTK camera is away from the scene's eye."""
        # the eye marker would fill the screen when the VTK camera sits at the eye
        at_eye = np.linalg.norm(np.asarray(vtk_camera.GetPosition()) - np.asarray(scene_camera.eye))
        self.eye.actor.SetVisibility(bool(visible and at_eye > EYE_MARKER_MIN_DISTANCE))
