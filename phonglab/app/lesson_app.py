"""The lesson page: one trame app per browser tab.

:class:`LessonApp` shows a lesson's text (Markdown with MathML), the scene in
a ``VtkLocalView`` (the render layer's :class:`~phonglab.render.SceneView`:
colours from the core, lighting off), the controls the lesson asks for plus
all the others, the numbers at the probe point, and the planner's verdict.

What happens on a change:

1. the browser sets a control's state key; :meth:`LessonApp._on_control`
   checks the value (:class:`~phonglab.app.controls.Control`) and builds the
   new scene, or refuses it with a visible notice and keeps the old scene;
2. the view is updated (:meth:`SceneView.update`, which redoes what
   :meth:`Scene.changes` says the change needs); if only colours changed,
   the new colour bytes alone go to the browser (:mod:`phonglab.app.client`),
   otherwise the local view is synchronised;
3. the readout, the planner's verdict and the other widgets follow, a
   moment later (:class:`~phonglab.app.later.Later`: every put-off job of a
   tab, the newest camera of a drag included, waits there).

The accuracy lesson (``NN-accuracy.md``) also gets the panel of
:mod:`phonglab.app.accuracy_panel` below the view: the accuracy plot and the
error images of a picked method and mesh, computed in worker processes.

Nothing a browser sends can stop the server: every handler catches its
errors and reports them on the page.
"""

from __future__ import annotations

import functools
import logging
from dataclasses import dataclass, field
from pathlib import Path

from trame.app import TrameApp

from phonglab.app import controls as ctl
from phonglab.app.control import ControlError, finite3, format_value
from phonglab.app import eye, owned, page, sync, text
from phonglab.app.accuracy_panel import AccuracyPanel
from phonglab.app.check_question import CheckPanel
from phonglab.app.compare_panel import ComparePanel
from phonglab.app.student_code import StudentCodePanel
from phonglab.app import client
from phonglab.app import address
from phonglab.app import download
from phonglab.app.client import MODULE, color_payload
from phonglab.app.readout import probe_readout
from phonglab.app.later import Later
from phonglab.app.pixel_picture import PixelPicture
from phonglab.app.timing import Stopwatch, record_lap
from phonglab.render import SceneView, pixel_job
from phonglab.render.translucency import translucent
from phonglab.scene import Scene, SceneError, load_lesson, load_scene, plan
from phonglab.scene.loader import lesson_files

log = logging.getLogger(__name__)

#: size of the server-side image in pixel mode (width, height)
PIXEL_SIZE = (960, 720)
#: largest side of the server's window (pixel mode image), in pixels
MAX_PIXEL_SIDE = 1600
#: seconds between sending a view update and refreshing the panels (lets the update leave first)
PANEL_DELAY = 0.004


def _guarded(method):
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


# the lesson list: titles, numbers and problems as the scene layer reads them
from phonglab.scene.lessons import Entry, catalog, load_entry  # noqa: E402,F401


class LessonApp(TrameApp):
    """The lesson page for one browser tab.

    Parameters
    ----------
    server : trame server or name
    target : path
        A lessons folder, a lesson file or a scene file.
    export_dir : path or None
        Where the export buttons also keep a copy of each figure on the
        server; None (the default): the figures go to the browser only.
    """

    def __init__(self, server=None, *, target, export_dir=None, allow_student_code=False):
        super().__init__(server)
        self.server.enable_module(MODULE)
        self.export_dir = Path(export_dir) if export_dir is not None else None
        self.entries, first = catalog(target)
        self.index = None
        self.entry = None
        self.scene = None
        self.options = {"term": "color"}
        self.view = None  # SceneView, created with the first good scene
        self.controls = ctl.ControlSet(ctl.Frame())  # the open lesson's controls
        self._watched = set()  # state keys with a change handler
        self._notice_serial = 0
        self._busy = False  # a control's change is being applied
        self._view_ms = (0.0, 0.0)  # wall and CPU ms of a control's update before its deferred panels
        self._camera_moved = False
        self._camera_shown = None  # the view's camera as last sent to the browser
        self._plan = (None, None)  # (scene, plan(scene)): planned once for the view's shading and the panels
        self._pushed = (None, None)  # the last colour push and its colours (a turn sends only what changed)
        self.state[client.SHOWN_KEY] = None  # the hash of the pushed colours the browser shows (it sets it)
        # the work put off until the view's update has left for the browser, in this order:
        # the newest camera (as soon as the loop is free), then the drag's end, then the panels
        self._later = Later(self._job_failed)
        self._cameras = eye.Latest(self._apply_camera, self._later)  # the browser's newest camera, shaded when free
        self._later.add("turn end", self._end_turn, delay=PANEL_DELAY)
        self._later.add("panels", self._deferred_panels, delay=PANEL_DELAY)
        self.address = address.ViewAddress()  # the settings in the page's address
        self.state.trame__title = "phonglab — the Phong illumination model"
        self._init_state()
        self.accuracy = AccuracyPanel(self.state, self.notify)
        self.check = CheckPanel(self.state)
        self.compare = ComparePanel(self.state)  # Phong beside Cook–Torrance, made in a worker
        self.student_code = StudentCodePanel(self.state, allow_student_code)
        self.exports = download.Exports(self.state, self.notify)  # figures made in a worker process
        self.pictures = PixelPicture(self.state, self.notify)  # the per-pixel picture, made in a thread
        self.state.change("view_size")(self._on_view_size)
        self.state.change(address.REQUEST_KEY)(self._on_address)
        # the lesson's mistake is the server's: a browser's write is undone
        self._mistake = None
        self.state.change("mistake")(owned.keep_server_value(self.state, "mistake", lambda: self._mistake))
        # cheaper full synchronisations (after trame-vtk has set up this session)
        sync.install()
        self.ctrl.on_server_ready.add(lambda **_: sync.install())
        # one SceneView for the whole session, built from the first good scene
        good = [e for e in self.entries if e.ok]
        if good:
            start = self.entries[first] if self.entries[first].ok else good[0]
            self.view = SceneView(start.scene, size=PIXEL_SIZE, labels=False, vtk_text=False)
        window = self.view.render_window if self.view is not None else SceneView.empty_window()
        self.ui, self.html_view = page.build_page(self.server, window, page.Handlers(
            open_lesson=self._open_from_list,
            reset_lesson=self.reset_lesson,
            export_figure=self.export_figure,
            apply_experiment=self.apply_experiment,
            pick=self.on_pick,
            camera=self.on_camera,
            check_answer=self.check.submit,
            student_code=self.student_code.submit if allow_student_code else None,
            camera_move=self.on_camera_move,
            view_ready=self._on_view_ready,
        ))
        self.open_lesson(first)

    # ------------------------------------------------------------------
    # state

    def _init_state(self):
        s = self.state
        s.update(page.initial_state())
        s.lessons = [
            {"index": i, "number": e.number, "title": e.title, "ok": e.ok, "problems": len(e.errors)}
            for i, e in enumerate(self.entries)
        ]

    def notify(self, kind: str, message: str) -> None:
        """Show a message above the controls (kind: "error", "success", "info")."""
        self._notice_serial += 1
        self.state.notice = {"kind": kind, "text": owned.short(message), "serial": self._notice_serial}

    # ------------------------------------------------------------------
    # lessons

    @_guarded
    def open_lesson(self, index=None, *_, **__) -> None:
        """Show lesson ``index`` of the list (its errors, if it has any)."""
        try:
            index = int(index)
            if not 0 <= index < len(self.entries):
                raise IndexError
        except (TypeError, ValueError, IndexError):
            self.notify("error", f"no such lesson: {index!r}")
            return
        entry = self.entries[index]
        self.index, self.entry = index, entry
        s = self.state
        s.lesson_index = index
        s.lesson_title = entry.title
        s.lesson_number = entry.number
        s[address.QUERY_KEY] = address.query_for(entry)  # the address bar follows the lesson
        s.show_answer = False
        s.notice = None
        self.check.open(entry.lesson if entry.ok else None)
        if not entry.ok:
            s.lesson_errors = entry.errors or ["this file has no scene"]
            s.lesson_html = ""
            s.lesson_goal_html = ""
            s.experiments = []
            s.question_html = s.answer_html = ""
            self._mistake = None
            s.mistake, s.mistake_note = None, ""
            s.has_view = self.view is not None
            self._later.cancel("panels")  # a refresh for the previous lesson's scene
            self.controls = ctl.ControlSet(ctl.Frame())
            page.build_controls(self.server, [])
            self.accuracy.open(None, None)
            return
        s.lesson_errors = []
        lesson = entry.lesson
        s.has_model_control = bool(lesson and "model" in lesson.controls)
        s.lesson_goal_html = text.inline(lesson.goal) if lesson and lesson.goal else ""
        s.lesson_html = text.render_markdown(text.strip_title(lesson.body, lesson.title)) if lesson else ""
        s.experiments = [
            {"index": i, "label": text.inline(x.label), "text": text.inline(x.text) if x.text else ""}
            for i, x in enumerate(lesson.experiments)
        ] if lesson else []
        s.question_html = text.inline(lesson.question) if lesson and lesson.question else ""
        s.answer_html = text.render_markdown(lesson.answer) if lesson and lesson.answer else ""
        self._mistake = s.mistake = self._mistake_info()
        extra = {"view__compare": ctl.COMPARE_SWITCH}
        if self._mistake and self._mistake.get("available"):
            extra["view__mistake"] = ctl.MISTAKE_SWITCH
        self.controls = ctl.ControlSet(ctl.Frame.of_camera(entry.scene.camera),
                                       lesson.controls if lesson else (), extra)
        self.options = {"term": "color"}
        self.accuracy.open(entry, entry.scene)
        self._show_scene(entry.scene, new_lesson=True)

    @_guarded
    def reset_lesson(self, *_, **__) -> None:
        """Go back to the lesson's own scene."""
        if self.entry is not None and self.entry.ok:
            self.options = {"term": "color"}
            self._show_scene(self.entry.scene, new_lesson=True)
            self.notify("info", "Back to the lesson's settings.")

    @_guarded
    def apply_experiment(self, index=None, *_, **__) -> None:
        """Apply an experiment's settings to the current scene."""
        lesson = self.entry.lesson if self.entry else None
        try:
            experiment = lesson.experiments[int(index)]
        except (AttributeError, TypeError, ValueError, IndexError):
            self.notify("error", f"no such experiment: {index!r}")
            return
        try:
            scene = self.scene.replace_many(experiment.settings)
        except SceneError as exc:
            self.notify("error", f"experiment {experiment.label!r} could not be applied: {exc}")
            return
        self._show_scene(scene)
        self.notify("info", f"Applied: {experiment.label}")

    # ------------------------------------------------------------------
    # the scene on screen

    def _show_scene(self, scene, *, new_lesson=False, colours_only=False, defer_panels=False,
                    turned=False) -> None:
        """Make ``scene`` the one on screen and refresh everything that depends on it.

        With ``defer_panels`` the readout, verdict and widgets are refreshed a
        moment later, so the view's update leaves for the browser first.
        ``turned``: the scene's camera is a view turned by the mouse (an
        address's ``view.turned``), shown with its view angle as it is.
        """
        old = self.scene
        self.scene = scene
        if old is None or old.camera != scene.camera:  # the view angle is the camera's, or widened
            self.options = address.turned(self.options, turned)
            self._camera_moved = self._camera_moved or turned
        if turned:
            self.view.update(scene, keep_view_angle=True)
        else:
            self.view.update(scene)
        if new_lesson and self._camera_moved:
            # the browser turned the view: back to the lesson's camera
            self.view.reset_camera()
            self._camera_moved = False
        self.view.set_term(self.options["term"])
        self._paint_mistake()
        self.state.has_view = True
        if colours_only:
            self._push_colours()
        else:
            self.html_view.update()
            self._pushed = (None, None)  # the browser's colours now come from this synchronisation
            self._send_camera(force=new_lesson or (old is not None and "camera" in Scene.changes(old, scene)))
        self._refresh_pixels()
        if defer_panels:
            self._later.ask("panels")
        else:
            self._refresh_panels()

    def _deferred_panels(self) -> None:
        """The refresh :meth:`_show_scene` put off; records the update's server time."""
        clock = Stopwatch()
        try:
            if self.scene is not None:
                self._refresh_panels()
                self.state.flush()
        except Exception as exc:
            log.exception("refreshing the panels")
            self.notify("error", f"Could not refresh the panels: {owned.reason(exc)}")
            self.state.flush()
        finally:
            (wall, cpu), (spent_wall, spent_cpu) = clock.split(), self._view_ms
            self._view_ms = (0.0, 0.0)
            record_lap("view", spent_wall + wall, spent_cpu + cpu)

    def _paint_mistake(self) -> None:
        """Show the lesson's common mistake in the view when the switch is on, else the correct shading.

        The view recolours its mesh (and shades its pixel image) with the
        mistake; where the mistake cannot show in the current interpolation
        mode, the page says so (``mistake_note``).
        """
        info = self._mistake  # never the state: a browser may have written it
        wanted = bool(info and info.get("available") and self.options.get("mistake"))
        self.view.set_mistake(info["name"] if wanted else None)
        self.state.mistake_note = self.view.mistake_note

    def _mistake_info(self) -> dict | None:
        """The lesson's common mistake for the page, or None."""
        name = self.entry.lesson.mistake if self.entry and self.entry.lesson else None
        if not name:
            return None
        from phonglab.teaching import get_mistake

        try:
            m = get_mistake(name)
        except ValueError as exc:
            return {"name": name, "title": name, "looks_like": str(exc), "wrong": "", "right": "",
                    "available": False}
        return {"name": name, "title": m.title, "looks_like": m.looks_like, "wrong": m.wrong, "right": m.right,
                "available": True}

    def _push_colours(self, change: bool = False) -> None:
        """Send only the mesh's new colours to the browser (with ``change``, only the rows that changed)."""
        colours = self.view.colour_array()
        payload = color_payload(self.view.mesh_actor.GetMapper(), colours.values,
                                name=colours.name, location=colours.location,
                                vtk_array=getattr(colours.values, "VTKObject", None))
        previous, base_values = self._pushed
        if change and previous is not None and self.state[client.SHOWN_KEY] == previous.get("hash"):
            # the browser shows the last push: the rows that changed are enough
            payload = client.color_change(payload, previous, colours.values, base_values)
        self._pushed = (payload, colours.values.copy())
        self.state.view_colors = payload
        self.state.flush()

    def _refresh_pixels(self) -> None:
        """In pixel mode, the core's per-pixel image (from the scene's camera) over the view."""
        pixel = self.scene.interpolation == "pixel"
        # a translucent mesh is blended in linear light by the server (vtk.js would blend encoded colours)
        pixel = pixel or translucent(self.scene)
        self.state.pixel_mode = pixel
        self.state.pixel_hint = ("Per-pixel shading by the core" if self.scene.interpolation == "pixel"
                                 else "Translucent: blended by the core in linear light")
        if not pixel:
            self.pictures.drop()  # a picture still being made is not shown
            self.state.pixel_src = ""
            return
        # the VTK part here, the NumPy part and the PNG in a thread; the newest scene's picture comes last,
        # and the readout and letters for its eye with it
        self.pictures.request(lambda: pixel_job.prepare(self.view, annotate=True), along=self._probe_panels)

    def _planned(self, scene):
        """``plan(scene)``, made once per scene shown (the view's shading and the panels share it)."""
        if self._plan[0] is not scene:
            self._plan = (scene, plan(scene))
        return self._plan[1]

    def _refresh_panels(self) -> None:
        """The verdict, the readout, the accuracy panel and the controls, for the scene on screen."""
        scene = self.scene
        s = self.state
        # planner verdict, planned once and shared with the readout (and the view's shading)
        verdict = self._planned(scene)
        s.plan_computed = [{"effect": e, "reason": r} for e, r in verdict.computed]
        s.plan_skipped = [{"effect": e, "reason": r} for e, r in verdict.skipped]
        # probe readout and vector legend; over the core's picture they come with it (_refresh_pixels)
        if not s.pixel_mode:
            s.update(self._probe_panels())
        self.accuracy.follow(scene)
        self.compare.follow(scene, bool(self.options.get("compare")), self.view.size if self.view else None)
        # controls: drawn again only when their set changes; their values follow every scene
        rebuilt = self.controls.update(scene)
        values = self._sync_control_values()
        # the address bar: the lesson and the settings that differ from the lesson's
        s[address.QUERY_KEY] = self.address.query(self.entry, scene, self.options, self.controls, values)
        if rebuilt:
            s.control_labels = {c.key: text.inline(c.label) for c in self.controls.widgets}
            page.build_controls(self.server, self.controls.chosen, self.controls.widgets)
            for key in self.controls.by_key:
                if key not in self._watched:
                    self._watched.add(key)
                    s.change(key)(self._watcher(key))

    def _probe_panels(self) -> dict:
        """The readout, the legend and the letters' tips for the scene and eye the view has now."""
        scene = self.scene
        point, normal = self.view.probe
        camera = self.view.camera_state()
        legend = [{"letter": l, "meaning": m, "color": c} for l, m, c in self.view.legend()]
        return {
            "readout": probe_readout(scene, point, normal, self.view.light_index, mistake=self.view.mistake),
            "legend": legend,
            "arrow_tips": client.arrow_tips(self.view.arrow_tips(), legend, hidden=self.view.hidden_letters()),
            # the camera the tips and readout are for (and, in pixel mode, the picture that comes with them)
            "arrow_camera": {"position": list(camera.eye), "view_angle": camera.view_angle},
        }

    def _sync_control_values(self) -> dict:
        """Write every control's value for the current scene into the state; returns them (state key -> value)."""
        shown = {}
        values = self.controls.values(self.scene, self.options)
        for key, value in values.items():
            control = self.controls.by_key[key]
            # never echo a browser's own value back with rounding noise: a slider
            # being dragged would jump back to an older position
            if not control.same(self.state[key], value):
                self.state[key] = value
            if control.kind == "slider":
                shown[key] = format_value(control, value)
        if shown != self.state.control_values:
            self.state.control_values = shown
        return values

    # ------------------------------------------------------------------
    # browser input

    def _watcher(self, key):
        def on_change(**_):
            self._on_control(key, self.state[key])

        return on_change

    def _on_control(self, key, value) -> None:
        control = self.controls.by_key.get(key)
        if control is None or self.scene is None or self._busy:
            return
        try:
            current = control.read(self.scene, self.options)
            if control.same(value, current):
                return
            clock = Stopwatch()
            self._busy = True
            try:
                scene, options = control.apply(self.scene, value, self.options)
            except ControlError as exc:
                self.notify("error", f"Refused: {exc}. The previous value stays.")
                self.state[key] = current
                return
            colours_only = Scene.changes(self.scene, scene).colours_only and scene.interpolation != "pixel"
            self.options = options
            self._show_scene(scene, colours_only=colours_only, defer_panels=True)
            if isinstance(self.state.notice, dict) and self.state.notice.get("kind") == "error":
                self.state.notice = None
            self.state.flush()
            self._view_ms = tuple(a + b for a, b in zip(self._view_ms, clock.split()))
        except Exception as exc:  # the server stays up whatever arrives
            log.exception("control %s", key)
            self.notify("error", f"Could not apply {key}: {owned.reason(exc)}")
        finally:
            self._busy = False

    @_guarded
    def on_pick(self, event=None, *_, **__) -> None:
        """A click on the view: move the probe to the first surface point under it."""
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

    @_guarded
    def on_camera(self, camera=None, *_, **__) -> None:
        """The browser's camera after the student turned, zoomed or panned the view (the drag's end).

        The view's camera is the scene's eye (:mod:`phonglab.app.eye`): the
        core re-shades for it, and the arrows, markers, readout and eye
        controls follow; the picture and numbers are exact for this camera.
        """
        self._cameras.offer(camera, final=True)

    @_guarded
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
        try:
            scene = eye.scene_camera(self.scene, camera)
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

    def _job_failed(self, name: str, exc: Exception) -> None:
        """A put-off job raised: said on the page; the server and the other jobs go on."""
        log.error("%s failed", name, exc_info=exc)
        what = {"panels": "refresh the panels"}.get(name, "follow the view's camera")
        self.notify("error", f"Could not {what}: {type(exc).__name__}: {exc}")
        self.state.flush()

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

    @_guarded
    def export_figure(self, kind="render", *_, **__) -> None:
        """Send the current scene's figure (``kind``: render, terms or mistake) to the browser as a download.

        The figure is made in a worker process (:class:`~phonglab.app.download.Exports`);
        a copy is written on the server only when the app has an export folder.
        """
        try:
            kind = kind if kind in download.KINDS else "render"
            mistake = self.entry.lesson.mistake if self.entry and self.entry.lesson else None
            stem = f"lesson-{self.entry.number:02d}" if self.entry.number is not None else self.entry.path.stem
            # the mistake the view shows, if any: the export is shaded with it and carries the red band
            self.exports.start(self.scene, kind, stem, mistake, shown_mistake=self.view.mistake,
                               export_dir=self.export_dir)
        except Exception as exc:
            log.exception("export")
            self.notify("error", f"Export failed: {exc}")

    def _on_address(self, **_) -> None:
        """The page was opened with an address: open the lesson it names, apply its settings, show the page.

        A bad lesson name, a refused value or an unknown key gives a notice; the rest applies.
        The page shows no lesson until then (``page_ready``): a link's lesson is the first one drawn.
        """
        query = self.state[address.REQUEST_KEY]
        if query is None:  # the key's first value, not the page's: the page sends a string, empty or not
            return
        try:
            index, problem = address.lesson_index(query, self.entries)
            if problem:
                self.notify("warning", problem)
                return
            if index is not None and index != self.index:
                self.open_lesson(index)
            self._apply_address(query)
        finally:
            self.state.page_ready = True

    @_guarded
    def _apply_address(self, query) -> None:
        """Apply the settings of an address to the open lesson, each checked by the page's own control."""
        pairs, problems = address.read_query(query)
        if pairs and self.scene is not None and self.entry is not None and self.entry.ok:
            scratch = ctl.ControlSet(self.controls.frame, self.controls.lesson_paths, self.controls.extra)
            scene, options, refused = address.apply_settings(pairs, self.scene, self.options, scratch)
            problems += refused
            if scene is not self.scene or options != self.options:
                self.options = options
                self._show_scene(scene, turned=bool(options.get("turned")))
        if problems:
            self.notify("warning", address.notice(problems))

    def _open_from_list(self, index=None, *_, **__):
        """A lesson picked in the list: close the list and open it."""
        self.state.drawer = False
        self.open_lesson(index)

    def close(self) -> None:
        """Release the view's OpenGL resources and this session's trame registrations."""
        self._later.cancel()
        self.accuracy.close()
        self.compare.close()
        self.exports.close()
        self.pictures.close()
        self.student_code.close()  # its grading, waiting or running, is cancelled
        if self.view is not None:
            try:
                self.view.close()
            except Exception:
                log.exception("closing the view")
            self.view = None
        # trame and trame-vtk keep every server (and its VTK object map) by name
        from trame.app import core as trame_core
        from trame_vtk.modules import vtk as trame_vtk_module

        trame_core.AVAILABLE_SERVERS.pop(self.server.name, None)
        trame_vtk_module.HELPERS_PER_SERVER.pop(self.server.name, None)

