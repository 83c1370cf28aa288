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

#: name of the 6-component point array (normal xyz, position xyz) drawn by the value pass
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
    """

    positions: np.ndarray
    normals: np.ndarray
    mask: np.ndarray
    raw_normals: np.ndarray | None = None

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
        # one shallow copy per mesh, carrying the normal+position array
        if mesh is self._source:
            return
        data = pv.PolyData(mesh.points, faces=mesh.faces)
        data.point_data[GBUFFER_ARRAY] = np.hstack(
            [np.asarray(mesh.point_data["Normals"], np.float32), np.asarray(mesh.points, np.float32)]
        )
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
        # one pass per component: normal x, y, z then position x, y, z
        for component in range(6):
            self._value_pass.SetInputComponentToProcess(component)
            self._window.Render()
            values = vtk_to_numpy(self._value_pass.GetFloatImageDataArray(self._renderer))
            planes.append(np.array(values, dtype=np.float32).reshape(height, width)[::-1])
        normals = np.stack(planes[:3], axis=-1)
        positions = np.stack(planes[3:], axis=-1)
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
        return GBuffer(positions=positions, normals=normals, mask=mask, raw_normals=raw_normals)

    def close(self) -> None:
        """Release the OpenGL context."""
        self._renderer.SetPass(None)
        self._window.Finalize()
