"""Between the screen and the world: picking a mesh point, following a ray, projecting to pixels.

Display coordinates are VTK's (pixels from the window's *bottom-left*
corner); image coordinates have row 0 at the top, as in a screenshot.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
import vtk

from phonglab.render import mesh as meshes
from phonglab.render.camera import finite_vector

#: how close (a fraction of the window's diagonal) a click must come to the mesh to pick it
PICK_TOLERANCE = 0.0005


def pick(renderer: vtk.vtkRenderer, actor: vtk.vtkActor, display_x: float, display_y: float):
    """The point of ``actor`` under a display position, or None.

    Only ``actor`` is considered (glyphs are never picked).

    Returns
    -------
    ndarray of shape (3,) or None
    """
    picker = vtk.vtkCellPicker()
    picker.SetTolerance(PICK_TOLERANCE)
    picker.PickFromListOn()
    picker.AddPickList(actor)
    renderer.ResetCameraClippingRange()
    if not picker.Pick(float(display_x), float(display_y), 0.0, renderer):
        return None
    if picker.GetCellId() < 0:
        return None
    return np.asarray(picker.GetPickPosition(), dtype=np.float64)


def ray_hit(mesh: pv.PolyData, origin, target):
    """The first point of ``mesh`` on the ray from ``origin`` through ``target``, with its normal, or None.

    Raises
    ------
    ValueError
        When ``origin`` or ``target`` is not 3 finite numbers.
    """
    return meshes.ray_hit(mesh, finite_vector("origin", origin), finite_vector("target", target))


def hidden_tips(mesh: pv.PolyData, origin, tips: dict) -> set:
    """The keys of ``tips`` (name -> point) that ``mesh`` hides from ``origin``: one ray to each."""
    origin = np.asarray(origin, dtype=float)
    hidden = set()
    for name, tip in tips.items():
        tip = np.asarray(tip, dtype=float)
        hit = ray_hit(mesh, origin, tip)
        if hit is not None and np.linalg.norm(hit[0] - origin) < float(np.linalg.norm(tip - origin)) * (1 - 1e-4):
            hidden.add(name)
    return hidden


def to_image(renderer: vtk.vtkRenderer, world, height: int) -> tuple[float, float]:
    """Where a world point lands on an image ``height`` pixels tall of the renderer's window (row 0 at the top)."""
    renderer.SetWorldPoint(float(world[0]), float(world[1]), float(world[2]), 1.0)
    renderer.WorldToDisplay()
    x, y, _ = renderer.GetDisplayPoint()
    return x, height - 1 - y
