"""The view's camera is the model's eye: a browser's camera becomes the scene's.

When the student turns, zooms or pans the 3D view, the browser sends its
camera (vtk.js ``getCamera()``: ``position``, ``focalPoint``, ``viewUp``,
``viewAngle``). :func:`scene_camera` checks it once, at this boundary, and
makes it the scene's ``camera`` (its eye is the lighting's eye; the
scene's ``infinite_viewer`` setting is kept, so the direction
``(eye - focal_point)`` is the constant view vector of an infinite viewer).
The core then shades for it like for any other scene change.

During a drag the browser sends a camera every frame, faster than the
server can shade a large mesh. :class:`Latest` keeps only the newest camera
and runs one re-shade for it as soon as the server is free: stale cameras
are dropped, never queued. The camera sent when the drag ends is marked
``final``: its re-shade also synchronises the arrows and markers, so the
picture and the numbers are exact for the camera the drag ended at.
"""

from __future__ import annotations

import math
from typing import Callable

from phonglab.app.later import Later
from phonglab.render.camera import stands_at

#: the browser camera's keys and the scene camera fields they set
BROWSER_KEYS = {"position": "camera.eye", "focalPoint": "camera.focal_point", "viewUp": "camera.up",
                "viewAngle": "camera.view_angle"}


def _three(name: str, value) -> list[float]:
    """Three finite floats, or ValueError naming the key, the value and what is allowed."""
    try:
        numbers = [float(c) for c in value]
    except (TypeError, ValueError):
        numbers = []
    if len(numbers) != 3 or not all(math.isfinite(c) for c in numbers):
        raise ValueError(f"camera.{name}: must be 3 finite numbers, got {value!r}")
    return numbers


def camera_settings(camera) -> list[tuple[str, object]]:
    """The scene settings ``(field path, value)`` for a browser's camera.

    Parameters
    ----------
    camera : dict
        ``{"position": [x, y, z], "focalPoint": [...], "viewUp": [...], "viewAngle": degrees}``;
        ``viewAngle`` may be left out (the scene's stays).

    Raises
    ------
    ValueError
        For a camera that is not a dict, or a point or direction that is not
        3 finite numbers, or a view angle that is not a finite number. (Whether
        the camera makes sense, e.g. an eye on the focal point, is checked by
        the scene, which raises SceneError.)
    """
    if not isinstance(camera, dict):
        raise ValueError(f"camera: must be a dict of position, focalPoint, viewUp, got {camera!r}")
    settings = [(BROWSER_KEYS[key], _three(key, camera.get(key))) for key in ("position", "focalPoint", "viewUp")]
    if camera.get("viewAngle") is not None:
        try:
            angle = float(camera["viewAngle"])
        except (TypeError, ValueError):
            angle = math.nan
        if not math.isfinite(angle):
            raise ValueError(f"camera.viewAngle: must be a finite number of degrees, got {camera['viewAngle']!r}")
        settings.append(("camera.view_angle", angle))
    return settings


def scene_camera(scene, camera):
    """``scene`` seen through a browser's ``camera`` (see :func:`camera_settings`), validated.

    Returns the same scene object when the camera is the scene's already.
    """
    moved = scene.replace_many(camera_settings(camera))
    return scene if moved.camera == scene.camera else moved


def _unit_up(eye, focal_point, up):
    """``up`` made perpendicular to the view direction and of length 1 (None where it cannot be)."""
    d = [f - e for f, e in zip(focal_point, eye)]
    dd = sum(c * c for c in d)
    if dd == 0:
        return None
    along = sum(u * c for u, c in zip(up, d)) / dd
    ortho = [u - along * c for u, c in zip(up, d)]
    length = math.sqrt(sum(c * c for c in ortho))
    return None if length == 0 else [c / length for c in ortho]


def same_view(shown, camera, *, tolerance: float = 1e-6) -> bool:
    """Whether a browser's ``camera`` is the view ``shown`` already: the same picture, not a turn.

    vtk.js reports a camera after every interaction, a plain click too, with
    its up vector made perpendicular to the view direction and the view angle
    it draws (the server's, fitted to hold the arrows). A lesson whose
    ``camera.up`` leans on the view direction (lesson 7's ``[0, 0, 1]``) then
    comes back changed in its numbers only. This compares what the picture
    depends on: the eye, the focal point, the up vector's direction across the
    view and the view angle: the points as :func:`~phonglab.render.camera.stands_at`
    compares them, the up vector's direction and the angle within ``tolerance``
    (the angle relative to its degrees).

    Parameters
    ----------
    shown : phonglab.render.camera.CameraState
        The camera the view shows (``eye``, ``focal_point``, ``up``, ``view_angle``).
    camera : dict
        As :func:`camera_settings` takes it; a malformed one is not the same view.
    """
    try:
        settings = dict(camera_settings(camera))
    except ValueError:
        return False
    eye, focal, up = settings["camera.eye"], settings["camera.focal_point"], settings["camera.up"]
    if not stands_at(eye, focal, shown):  # the eye and the focal point, to a millionth of their distance
        return False
    angle = settings.get("camera.view_angle", shown.view_angle)
    if abs(angle - shown.view_angle) > tolerance * max(1.0, abs(shown.view_angle)):
        return False
    mine, theirs = _unit_up(shown.eye, shown.focal_point, shown.up), _unit_up(eye, focal, up)
    return mine is not None and theirs is not None and math.dist(mine, theirs) <= tolerance


class Latest:
    """Run ``apply(camera, final)`` for the newest camera only, once the server is free.

    Parameters
    ----------
    apply : callable
        ``apply(camera, final)``; called from the event loop (or at once
        when there is no running loop, as in scripts and tests).
    later : phonglab.app.later.Later, optional
        The tab's put-off work, where the run waits as the job ``"camera"``
        (a new one when not given).

    Notes
    -----
    :meth:`offer` stores the camera and asks for a run as soon as the loop
    is free. Cameras offered before that run replace each other: only the
    newest is shaded. ``final`` sticks until the run, so a drag's last camera
    is never downgraded to an intermediate one.
    """

    def __init__(self, apply: Callable, later: Later | None = None):
        self._apply = apply
        self._wanted = None
        self._later = Later() if later is None else later
        self._later.add("camera", self.run)
        #: cameras offered and cameras applied (dropped = offered - applied)
        self.offered = 0
        self.applied = 0

    def offer(self, camera, *, final: bool) -> None:
        """The browser's newest camera; ``final`` when the drag has ended."""
        self.offered += 1
        final = bool(final) or bool(self._wanted and self._wanted[1])
        self._wanted = (camera, final)
        self._later.ask("camera")

    def run(self) -> None:
        """Apply the newest camera (nothing when none is waiting)."""
        wanted, self._wanted = self._wanted, None
        if wanted is not None:
            self.applied += 1
            self._apply(*wanted)

    def cancel(self) -> None:
        """Forget a waiting camera."""
        self._later.cancel("camera")
        self._wanted = None
