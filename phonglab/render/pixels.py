"""Per-pixel shading for a view: the G-buffer of its mesh, and compositing it with the glyphs by depth.

VTK rasterizes the mesh's positions and interpolated normals into a
G-buffer (:mod:`phonglab.render.gbuffer`); the core shades each pixel
(:func:`phonglab.render.shading.pixel_colors`); the glyphs, drawn by VTK
without the mesh, are then kept wherever they lie in front of it.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
import vtk

from phonglab.render._vtk import eye_distance
from phonglab.render.gbuffer import GBuffer, GBufferRenderer

#: a glyph hides the mesh only where it is nearer by more than this fraction of the distance
DEPTH_SLACK = 1e-4


class GBufferCache:
    """The G-buffer of one mesh, camera and window size, re-rendered only when one of them changes."""

    def __init__(self):
        self._renderer = None
        self._cached = None
        self._culled = {}  # cull -> (key, GBuffer), for the layers of a translucent mesh

    def get(self, mesh: pv.PolyData, camera: vtk.vtkCamera, size, *, cull: str | None = None) -> GBuffer:
        """The G-buffer for ``mesh`` seen through ``camera`` in a window of ``size`` = (width, height).

        ``cull`` (``"back"`` or ``"front"``) leaves out one side's faces
        (:meth:`GBufferRenderer.render`); each kind is cached on its own.
        """
        size = tuple(size)
        key = (id(mesh), size, camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
               camera.GetViewAngle(), camera.GetParallelProjection(), camera.GetParallelScale())
        cached = self._cached if cull is None else self._culled.get(cull)
        if cached is None or cached[0] != key:
            if self._renderer is None:
                self._renderer = GBufferRenderer()
            cached = (key, self._renderer.render(mesh, camera, size, cull=cull))
            if cull is None:
                self._cached = cached
            else:
                self._culled[cull] = cached
        return cached[1]

    def clear(self) -> None:
        """Forget the G-buffers (the mesh or the camera changed)."""
        self._cached = None
        self._culled = {}

    def close(self) -> None:
        """Release the G-buffer's OpenGL context."""
        if self._renderer is not None:
            self._renderer.close()


def composite(overlay: np.ndarray, depth: np.ndarray, gbuffer: GBuffer, shaded: np.ndarray,
              camera: vtk.vtkCamera) -> np.ndarray:
    """The per-pixel shaded mesh in front of or behind the glyphs, by depth.

    Parameters
    ----------
    overlay : ndarray, shape (height, width, 3), uint8
        The window rendered without the mesh (glyphs on the background).
    depth : ndarray, shape (height, width)
        That render's depth buffer, top row first.
    gbuffer : GBuffer
        The mesh's G-buffer for the same camera and size.
    shaded : ndarray, shape (height, width, 3), uint8
        The mesh shaded per pixel.
    camera : vtkCamera
        The camera of both renders.
    """
    mask = gbuffer.mask
    glyph_z = eye_distance(camera, depth[mask])
    eye = np.asarray(camera.GetPosition())
    axis = np.asarray(camera.GetDirectionOfProjection())
    # the mesh wins where it is nearer than any glyph (or where no glyph was drawn)
    mesh_z = (gbuffer.positions[mask] - eye) @ axis
    front = np.zeros_like(mask)
    front[mask] = mesh_z <= glyph_z * (1 + DEPTH_SLACK)
    out = overlay.copy()
    out[front] = shaded[front]
    return out
