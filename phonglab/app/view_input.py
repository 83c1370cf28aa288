"""What the student does in the 3D view: a click that moves the probe or the light, a turn, a new size.

:class:`ViewInput` holds :class:`~phonglab.app.lesson_app.LessonApp`'s
handlers for the view's own events, apart from the lesson and the controls:

* a click (:meth:`ViewInput.on_pick`) moves the probe, or the picked light, to
  the surface point under it;
* a turn (:meth:`ViewInput.on_camera_move` during a drag, :meth:`ViewInput.on_camera`
  at its end) makes the browser's camera the scene's eye
  (:mod:`phonglab.app.eye`): the core re-shades for it and the arrows,
  markers and readout follow, put off behind the colours;
* the view's size in the browser sets the server window's (the per-pixel
  picture, the view angle that holds the arrows).

:func:`guarded` wraps every handler a browser triggers: any failure becomes
a notice on the page, never an exception that reaches the server.
"""

from __future__ import annotations

import functools
import logging

from phonglab.app import address, eye, owned
from phonglab.app import controls as ctl
from phonglab.app.control import finite3
from phonglab.app.timing import Stopwatch, record_lap
from phonglab.scene import SceneError

log = logging.getLogger("phonglab.app.lesson_app")

#: largest side of the server's window (pixel mode image), in pixels
MAX_PIXEL_SIDE = 1600


def guarded(method):
    """Run a browser-triggered method; any failure becomes a notice on the page, never an exception."""

    @functools.wraps(method)
    def run(self, *args, **kwargs):
        try:
            return method(self, *args, **kwargs)
        except Exception as exc:
            log.exception("%s failed", method.__name__)
            self.notify("error", f"Could not {method.__name__.replace('_', ' ')}: {owned.reason(exc)}")
            return None

    return run


class ViewInput:
    """The view's events for a :class:`~phonglab.app.lesson_app.LessonApp` (a mixin: it uses the app's scene,
    view, state and put-off jobs)."""

    @guarded
    def on_pick(self, event=None, *_, **__) -> None:
        """A click on the view: move the probe to the first surface point under it.

        Not in the accuracy lesson: its panel takes the readout's place, so
        the page offers no probe (nor a light to move) and a click changes nothing.
        """
        if self.accuracy.active:
            return
        try:
            ray = (event or {}).get("ray") if isinstance(event, dict) else None
            if not (isinstance(ray, list) and len(ray) == 2):
                return
            near, far = (finite3(p) for p in ray)
            hit = self.view.ray_hit(near, far)
            if hit is None:
                return
            point = [round(float(c), 6) for c in hit[0]]
            if self.state.pick_target == "light" and self.view.light_index is not None:
                # the light moves onto the line from the focal point through the click
                scene = self.scene
                frame = ctl.Frame.of_camera(self.entry.scene.camera)
                offset = [p - f for p, f in zip(point, scene.camera.focal_point)]
                azimuth, elevation, _ = ctl.place_of(offset, frame)
                elevation = max(-89.0, min(89.0, elevation))
                moved = ctl.move_light(scene, self.view.light_index, frame, azimuth=azimuth, elevation=elevation)
                self._show_scene(moved)
            else:
                self._show_scene(self.scene.replace("probe", point))
        except (ValueError, TypeError, SceneError) as exc:
            self.notify("error", f"Refused a click: {exc}")
        except Exception as exc:
            log.exception("pick")
            self.notify("error", f"Could not pick: {owned.reason(exc)}")

    @guarded
    def on_camera(self, camera=None, *_, **__) -> None:
        """The browser's camera after the student turned, zoomed or panned the view (the drag's end).

        The view's camera is the scene's eye (:mod:`phonglab.app.eye`): the
        core re-shades for it, and the arrows, markers, readout and eye
        controls follow; the picture and numbers are exact for this camera.
        """
        self._cameras.offer(camera, final=True)

    @guarded
    def on_camera_move(self, camera=None, *_, **__) -> None:
        """The browser's camera during a drag: re-shade for the newest one, dropping stale ones."""
        self._cameras.offer(camera, final=False)

    def _apply_camera(self, camera, final: bool) -> None:
        """Make the browser's ``camera`` the scene's and show the re-shaded scene (see :meth:`on_camera`).

        During a drag only the mesh's colours go to the browser (its own
        copy keeps turning smoothly); at the drag's end the arrows and
        markers are synchronised too.
        """
        if self.scene is None or self.view is None:
            return
        clock = Stopwatch()
        # the view as it is shown (a click, a frame without motion, vtk.js's own rounding of it): not a turn
        same = eye.same_view(self.view.camera_state(), camera)
        try:
            scene = self.scene if same else eye.scene_camera(self.scene, camera)
            if scene is not self.scene and scene.probe is None:
                # the default probe stays on the surface point it marks: turning the view moves the eye only
                scene = scene.replace("probe", [round(float(c), 6) for c in self.view.probe[0]])
        except (ValueError, TypeError, SceneError):
            return  # a malformed camera from the browser is ignored
        moved = scene is not self.scene
        try:
            if moved:
                self.scene = scene
                self.view.update(scene, keep_view_angle=True, defer_glyphs=not final, scene_plan=self._planned(scene))
                self._camera_moved = True
                self.options = address.turned(self.options, True)
                if scene.interpolation != "pixel":
                    self._push_colours(change=True)
                record_lap("turn", *clock.split())  # a re-shade (not a camera already shown)
        except Exception as exc:
            log.exception("camera")
            self.notify("error", f"Could not follow the view's camera: {type(exc).__name__}: {exc}")
            return
        if not moved and not (final and self.view.glyphs_stale):
            return  # a camera already shown and synchronised (a click, a frame without motion): nothing to refresh
        # the readout (and at the drag's end the arrows), once the colours have left for the browser
        if final:
            self._later.ask("turn end")
        self._later.ask("panels")

    def _end_turn(self) -> None:
        """The drag's end: the arrows and markers reshaped and synchronised, the per-pixel picture made."""
        if self.scene is None or self.view is None:
            return
        self.view.refresh_glyphs()
        self.html_view.update()
        self._refresh_pixels()

    def _send_camera(self, force: bool = False) -> None:
        """Send the view's camera to the browser when it moved since last sent (or ``force``).

        Its angle is widened to hold the arrows and markers for the window's size
        (:meth:`SceneView.update`): the browser's letters meet the arrows of the core's picture.
        """
        shown = self.view.camera_state()
        if force or shown != self._camera_shown:
            self.html_view.push_camera()
        self._camera_shown = shown

    def _on_view_ready(self) -> None:
        """The page's 3D view is mounted (it waits for the lesson its address names): send it the view's camera."""
        if self.view is not None and self.scene is not None:
            self._send_camera(force=True)

    def _on_view_size(self, view_size=None, **_) -> None:
        """The view's size in the browser: the server window (pixel mode, framing) follows it."""
        try:
            size = (view_size or {}).get("size") or {}
            width, height = int(size.get("width", 0)), int(size.get("height", 0))
        except (AttributeError, TypeError, ValueError):
            return
        if self.view is None or not (64 <= width <= 4096 and 64 <= height <= 4096):
            return
        width, height = min(width, MAX_PIXEL_SIDE), min(height, MAX_PIXEL_SIDE)
        if self.view.size != (width, height):
            self.view.set_size((width, height))
            if self.scene is not None:
                self._send_camera()  # the angle that holds the arrows depends on the window's shape
            if self.scene is not None and self.scene.interpolation == "pixel":
                self._refresh_pixels()
            if self.scene is not None and self.options.get("compare"):  # the comparison fills the view
                self.compare.follow(self.scene, True, self.view.size)
