"""The view's camera as plain numbers: its state, and the one check of a camera given from outside.

VTK-free. A camera is an eye point, a focal point it looks at, an up vector
and a view angle in degrees; :func:`check_camera` is where such a camera
(a browser's, say) is validated before a :class:`~phonglab.render.SceneView`
looks through it, and :func:`finite_vector` is the check of one point or
direction that picking uses too.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np


class CameraState(NamedTuple):
    """Where the view's VTK camera stands and looks (see :meth:`phonglab.render.SceneView.camera_state`)."""

    eye: tuple[float, float, float]
    focal_point: tuple[float, float, float]
    up: tuple[float, float, float]
    view_angle: float


def finite_vector(name: str, value) -> np.ndarray:
    """``value`` as a float64 array of shape (3,).

    Raises
    ------
    ValueError
        ``"NAME: must be 3 finite numbers, got VALUE"`` for anything else.
    """
    try:
        v = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        v = None
    if v is None or v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: must be 3 finite numbers, got {value!r}")
    return v


def check_camera(eye, focal_point, up, view_angle) -> CameraState:
    """A camera given from outside, checked: the state to look through.

    Parameters
    ----------
    eye, focal_point, up : 3 finite numbers
    view_angle : float
        Degrees, strictly between 0 and 180.

    Returns
    -------
    CameraState
        The same values as floats (``up`` as given: the camera makes it
        orthogonal to the line of sight).

    Raises
    ------
    ValueError
        For a point or direction that is not 3 finite numbers, an eye on
        the focal point, an up vector along the line of sight, or a view
        angle outside (0, 180) degrees; the message names the field.
    """
    eye = finite_vector("eye", eye)
    focal_point = finite_vector("focal_point", focal_point)
    up = finite_vector("up", up)
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
    # up must leave the line of sight, relative to its own length
    if not np.linalg.norm(np.cross(sight / distance, up)) > 1e-9 * max(1.0, float(np.linalg.norm(up))):
        raise ValueError(f"up: must not point along the line of sight {tuple(sight / distance)}, got {tuple(up)}")
    return CameraState(tuple(float(c) for c in eye), tuple(float(c) for c in focal_point),
                       tuple(float(c) for c in up), angle)


def stands_at(position, focal_point, scene_camera) -> bool:
    """True while a camera at ``position`` looking at ``focal_point`` is the scene's camera.

    Both points must match the scene camera's within a millionth of the
    eye's distance to its focal point (at least 1 unit).
    """
    scale = max(1.0, float(np.linalg.norm(np.subtract(scene_camera.eye, scene_camera.focal_point))))
    return bool(np.allclose(position, scene_camera.eye, rtol=0, atol=1e-6 * scale)
                and np.allclose(focal_point, scene_camera.focal_point, rtol=0, atol=1e-6 * scale))
