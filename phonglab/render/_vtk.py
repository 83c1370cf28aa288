"""Small VTK helpers shared by the render modules: offscreen windows, buffers.

Nothing here knows about scenes; it only hides the VTK plumbing that every
module would otherwise repeat.
"""

from __future__ import annotations

import contextlib
import os

import numpy as np
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy


def make_render_window(size: tuple[int, int], *, offscreen: bool = True) -> vtk.vtkRenderWindow:
    """A render window of ``size`` = (width, height) pixels, offscreen by default.

    Without a ``DISPLAY`` the EGL window class is used directly: VTK's
    default factory would first try X and log "bad X server connection".
    Multisampling is off: figures are antialiased by supersampling, and the
    G-buffer needs exact, unblended values.
    """
    window = None
    if offscreen and not os.environ.get("DISPLAY"):
        try:
            from vtkmodules.vtkRenderingOpenGL2 import vtkEGLRenderWindow

            window = vtkEGLRenderWindow()
        except ImportError:  # pragma: no cover - VTK built without EGL
            window = None
    if window is None:
        window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1 if offscreen else 0)
    window.SetMultiSamples(0)
    window.SetSize(int(size[0]), int(size[1]))
    return window


@contextlib.contextmanager
def quiet_vtk():
    """Keep VTK's own warnings and error dumps off stderr inside the ``with`` block.

    Used around mesh readers: a malformed file makes VTK print a multi-line
    report before the reader fails; the caller's one-line SceneError is the
    message the user should see.
    """
    was = vtk.vtkObject.GetGlobalWarningDisplay()
    vtk.vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtk.vtkObject.SetGlobalWarningDisplay(was)


def read_rgb(window: vtk.vtkRenderWindow) -> np.ndarray:
    """The window's colour buffer as a (height, width, 3) uint8 array, top row first."""
    width, height = window.GetSize()
    grab = vtk.vtkUnsignedCharArray()
    window.GetRGBACharPixelData(0, 0, width - 1, height - 1, 0, grab)
    rgba = vtk_to_numpy(grab).reshape(height, width, 4)
    return np.ascontiguousarray(rgba[::-1, :, :3])


def read_depth(window: vtk.vtkRenderWindow) -> np.ndarray:
    """The window's depth buffer as a (height, width) float32 array in [0, 1], top row first."""
    width, height = window.GetSize()
    grab = vtk.vtkFloatArray()
    window.GetZbufferData(0, 0, width - 1, height - 1, grab)
    return np.ascontiguousarray(vtk_to_numpy(grab).reshape(height, width)[::-1])


def set_camera(camera: vtk.vtkCamera, scene_camera) -> None:
    """Copy a scene :class:`~phonglab.scene.Camera` into a VTK camera."""
    camera.SetPosition(*scene_camera.eye)
    camera.SetFocalPoint(*scene_camera.focal_point)
    camera.SetViewUp(*scene_camera.up)
    camera.SetViewAngle(scene_camera.view_angle)
    camera.OrthogonalizeViewUp()


@contextlib.contextmanager
def hidden(props):
    """Hide the props (actors) inside the ``with`` block, then give each its visibility back."""
    visible = [p.GetVisibility() for p in props]
    for p in props:
        p.VisibilityOff()
    try:
        yield
    finally:
        for p, v in zip(props, visible):
            p.SetVisibility(v)


def eye_distance(camera: vtk.vtkCamera, depth: np.ndarray) -> np.ndarray:
    """Distance along the view axis for depth-buffer values of a perspective camera.

    Parameters
    ----------
    camera : vtkCamera
        The camera the depth buffer was rendered with (its clipping range).
    depth : ndarray
        Depth-buffer values in [0, 1]; 1 means nothing was drawn.

    Returns
    -------
    ndarray
        Camera-space distance :math:`z_e = 2nf / ((f + n) - z_{ndc}(f - n))`
        with :math:`z_{ndc} = 2d - 1`; ``inf`` where nothing was drawn.
    """
    near, far = camera.GetClippingRange()
    z_ndc = 2.0 * depth.astype(np.float64) - 1.0
    dist = 2.0 * near * far / ((far + near) - z_ndc * (far - near))
    return np.where(depth >= 1.0, np.inf, dist)
