"""Per-pixel shading: a G-buffer rendered by VTK, shaded by the core.

VTK rasterizes the mesh with a ``vtkValuePass`` in floating-point mode: each
pass writes one component of a point array, interpolated across every
triangle, into a 32-bit float image (pixels the mesh does not cover hold NaN).
Six passes give the interpolated world position and normal of the surface
seen through every pixel; the core then shades each covered pixel with the
normal renormalised, which is Phong *shading* (as opposed to Gouraud's
interpolated colours). The interpolated normals are kept as they came too
(``raw_normals``, shorter than 1 inside a triangle), for the lesson that shows
what forgetting the renormalisation does.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pyvista as pv
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

from phonglab.render._vtk import make_render_window
from phonglab.render.objects import OBJECT_ARRAY

#: name of the point array (normal xyz, position xyz, and the object for a mesh of several) drawn by the value pass
GBUFFER_ARRAY = "phonglab_gbuffer"
#: which faces a G-buffer may leave out: none, the back faces, the front faces
CULLS = (None, "back", "front")


@dataclass(frozen=True)
class GBuffer:
    """What the camera sees through each pixel, top row first.

    Attributes
    ----------
    positions : ndarray, shape (height, width, 3), float32
        World position of the visible surface (NaN where uncovered).
    normals : ndarray, shape (height, width, 3), float32
        Unit normal, interpolated from the point normals and renormalised
        (NaN where uncovered).
    mask : ndarray, shape (height, width), bool
        True where the mesh covers the pixel.
    raw_normals : ndarray, shape (height, width, 3), float32, or None
        The interpolated normal *before* renormalising: a blend of unit
        vectors, shorter than 1 inside a triangle whose vertex normals differ
        (NaN where uncovered). Only a deliberately wrong shading uses it.
    objects : ndarray, shape (height, width), int32, or None
        For a mesh of several objects (:mod:`~phonglab.render.objects`): the
        object seen through each pixel (-1 where uncovered). None: one object.
    """

    positions: np.ndarray
    normals: np.ndarray
    mask: np.ndarray
    raw_normals: np.ndarray | None = None
    objects: np.ndarray | None = None

    @property
    def shape(self) -> tuple[int, int]:
        """(height, width)."""
        return self.mask.shape


class GBufferRenderer:
    """Renders G-buffers of meshes in its own offscreen window.

    The window is kept between calls, so a sequence of frames (a slider
    moving, a sweep) reuses one OpenGL context.
    """

    def __init__(self):
        self._window = make_render_window((64, 64), offscreen=True)
        self._renderer = vtk.vtkRenderer()
        self._window.AddRenderer(self._renderer)
        self._mapper = vtk.vtkPolyDataMapper()
        self._mapper.ScalarVisibilityOn()
        self._actor = vtk.vtkActor()
        self._actor.SetMapper(self._mapper)
        self._actor.GetProperty().LightingOff()
        self._renderer.AddActor(self._actor)
        self._value_pass = vtk.vtkValuePass()
        self._value_pass.SetInputArrayToProcess(vtk.VTK_SCALAR_MODE_USE_POINT_FIELD_DATA, GBUFFER_ARRAY)
        passes = vtk.vtkRenderPassCollection()
        passes.AddItem(self._value_pass)
        sequence = vtk.vtkSequencePass()
        sequence.SetPasses(passes)
        camera_pass = vtk.vtkCameraPass()
        camera_pass.SetDelegatePass(sequence)
        self._renderer.SetPass(camera_pass)
        self._source = None
        self._data = None

    def _use_mesh(self, mesh: pv.PolyData) -> None:
        # one shallow copy per mesh, carrying the normal+position(+object) array
        if mesh is self._source:
            return
        data = pv.PolyData(mesh.points, faces=mesh.faces)
        columns = [np.asarray(mesh.point_data["Normals"], np.float32), np.asarray(mesh.points, np.float32)]
        objects = mesh.point_data.get(OBJECT_ARRAY)
        if objects is not None:  # the same at a triangle's three corners: interpolated, it stays the object's
            columns.append(np.asarray(objects, np.float32)[:, None])
        data.point_data[GBUFFER_ARRAY] = np.hstack(columns)
        self._mapper.SetInputData(data)
        self._source, self._data = mesh, data

    def render(self, mesh: pv.PolyData, camera: vtk.vtkCamera, size: tuple[int, int], *,
               cull: str | None = None) -> GBuffer:
        """The G-buffer of ``mesh`` seen by ``camera`` at ``size`` = (width, height).

        Parameters
        ----------
        mesh : pyvista.PolyData
            A mesh from :func:`~phonglab.render.mesh.build_mesh` (point normals in ``"Normals"``).
        camera : vtkCamera
            Copied; the clipping range is fitted to the mesh.
        size : (int, int)
            Image width and height in pixels.
        cull : {None, "back", "front"}
            None (the default) keeps the nearest surface whichever way it
            faces. ``"back"`` leaves out the faces turned away from the camera
            (the near side of a closed mesh); ``"front"`` leaves out the faces
            turned towards it (the far side, seen from inside). A face's
            side is its winding on screen, as in OpenGL.
        """
        width, height = int(size[0]), int(size[1])
        if cull not in CULLS:
            raise ValueError(f"cull must be one of {', '.join(map(repr, CULLS))}, got {cull!r}")
        prop = self._actor.GetProperty()
        prop.SetBackfaceCulling(cull == "back")
        prop.SetFrontfaceCulling(cull == "front")
        self._use_mesh(mesh)
        self._window.SetSize(width, height)
        own = self._renderer.GetActiveCamera()
        own.DeepCopy(camera)
        own.Modified()  # DeepCopy leaves the modification time: without this, the last camera's matrices stay
        self._renderer.ResetCameraClippingRange()
        planes = []
        # one pass per component: normal x, y, z then position x, y, z (then the object)
        for component in range(self._data.point_data[GBUFFER_ARRAY].shape[1]):
            self._value_pass.SetInputComponentToProcess(component)
            self._window.Render()
            values = vtk_to_numpy(self._value_pass.GetFloatImageDataArray(self._renderer))
            planes.append(np.array(values, dtype=np.float32).reshape(height, width)[::-1])
        normals = np.stack(planes[:3], axis=-1)
        positions = np.stack(planes[3:6], axis=-1)
        # uncovered pixels hold NaN; a zero normal cannot be shaded either
        mask = np.isfinite(planes[0])
        covered = normals[mask]
        length = np.sqrt(np.einsum("ij,ij->i", covered, covered))
        good = length > 0
        if not good.all():
            mask[mask] = good
            covered, length = covered[good], length[good]
        # keep the interpolated normals as they came, then renormalise (Phong shading's key step)
        raw_normals = np.full_like(normals, np.nan)
        raw_normals[mask] = covered
        normals[...] = np.nan
        normals[mask] = covered / length[:, None]
        objects = None
        if len(planes) > 6:
            objects = np.full(mask.shape, -1, np.int32)
            objects[mask] = np.rint(planes[6][mask]).astype(np.int32)
        return GBuffer(positions=positions, normals=normals, mask=mask, raw_normals=raw_normals, objects=objects)

    def close(self) -> None:
        """Release the OpenGL context."""
        self._renderer.SetPass(None)
        self._window.Finalize()
