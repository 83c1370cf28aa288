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

A click, a turn and the view's size are handled by
:class:`~phonglab.app.view_input.ViewInput`, which this class mixes in.

Nothing a browser sends can stop the server: every handler catches its
errors and reports them on the page.
"""

from __future__ import annotations

import logging
from pathlib import Path

from trame.app import TrameApp

from phonglab.app import controls as ctl
from phonglab.app.control import ControlError
from phonglab.app.control_state import ControlState
from phonglab.app.wording import plain_label, symbols_html
from phonglab.app.view_input import ViewInput, guarded as _guarded
from phonglab.app import eye, owned, page, shared, sync, text
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
from phonglab.render.options import VECTOR_LETTERS
from phonglab.render.translucency import translucent
from phonglab.scene import Scene, SceneError, load_lesson, load_scene, plan
from phonglab.scene.loader import lesson_files

log = logging.getLogger(__name__)

#: size of the server-side image in pixel mode (width, height)
PIXEL_SIZE = (960, 720)
#: seconds between sending a view update and refreshing the panels (lets the update leave first)
PANEL_DELAY = 0.004


# the lesson list: titles, numbers and problems as the scene layer reads them
from phonglab.scene.lessons import Entry, catalog, load_entry  # noqa: E402,F401


class LessonApp(ViewInput, TrameApp):
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
        self.entries, first = shared.lesson_catalog(target)  # read-only, shared by every tab
        self.index = None
        self.entry = None
        self.scene = None
        self.options = {"term": "color"}
        self.view = None  # SceneView, created with the first good scene
        self.controls = ctl.ControlSet(ctl.Frame())  # the open lesson's controls
        self._watched = set()  # state keys with a change handler
        self.control_state = ControlState()  # the control values written into the state
        self._address_to_open = None  # the address whose lesson is being opened (_on_address)
        self._glyphs = (None, {})  # the arrows as last formatted for the page: (what the view showed, state values)
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
        text = owned.short(message)
        # "html": the text escaped, with k_a, k_d, k_s set as the formulas set them (k with a subscript)
        self.state.notice = {"kind": kind, "text": text, "html": symbols_html(text), "serial": self._notice_serial}

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
            s.update(shared.lesson_texts(None))
            s.has_model_control = False
            s.view__compare = False  # the previous lesson's comparison goes with its controls
            self.compare.follow(None, False)
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
        s.update(shared.lesson_texts(lesson))
        self._mistake = s.mistake = self._mistake_info()
        extra = {"view__compare": ctl.COMPARE_SWITCH, "view__arrows_hidden": ctl.ARROWS_SWITCH}
        if self._mistake and self._mistake.get("available"):
            extra["view__mistake"] = ctl.MISTAKE_SWITCH
        self.controls = ctl.ControlSet(ctl.Frame.of_camera(entry.scene.camera),
                                       lesson.controls if lesson else (), extra)
        self.options = {"term": "color"}
        self.accuracy.open(entry, entry.scene)
        # an address that opens this lesson: shown once, with its settings (not the lesson's own scene first)
        query, self._address_to_open = self._address_to_open, None
        scene, problems = self._address_settings(query, entry.scene) if query is not None else (entry.scene, [])
        self._show_scene(scene, new_lesson=True, turned=bool(self.options.get("turned")))
        if problems:
            self.notify("warning", address.notice(problems))

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
        ctl.keep_hues(self.scene, scene, self.options)  # a coefficient set to 0 keeps its colour for later
        self._show_scene(scene)
        self.notify("info", f"Applied: {plain_label(experiment.label)}")  # the label's $k_s$ as k_s

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
        self.view.update(scene, keep_view_angle=turned, scene_plan=self._planned(scene))
        arrows = "" if self.options.get("arrows_hidden") else VECTOR_LETTERS
        if self.view.vectors != arrows:  # hidden to see the surface under them, or shown again
            self.view.set_vectors(arrows)
            colours_only = False  # the scene the browser draws lost or got back its arrows
        if new_lesson and self._camera_moved and not turned:
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
        # the reasons as the planner wrote them, and as the page shows them (escaped, k_a as k with subscript a)
        s.plan_computed = [{"effect": e, "reason": r, "html": symbols_html(r)} for e, r in verdict.computed]
        s.plan_skipped = [{"effect": e, "reason": r, "html": symbols_html(r)} for e, r in verdict.skipped]
        # probe readout and vector legend; over the core's picture they come with it (_refresh_pixels)
        if not s.pixel_mode:
            for key, value in self._probe_panels().items():
                if s[key] != value:  # the legend and tips stay as they are while only colours change
                    s[key] = value
        self.accuracy.follow(scene)
        self.compare.follow(scene, bool(self.options.get("compare")), self.view.size if self.view else None)
        # controls: drawn again only when their set changes; their values follow every scene
        rebuilt = self.controls.update(scene)
        values = self.control_state.sync(s, self.controls, scene, self.options)
        # the address bar: the lesson and the settings that differ from the lesson's
        s[address.QUERY_KEY] = self.address.query(self.entry, scene, self.options, self.controls, values)
        if rebuilt:
            s.control_labels = {c.key: text.inline(c.label) for c in self.controls.widgets}
            shared.controls_template(self.server, page.CONTROLS_TEMPLATE, self.controls.chosen, self.controls.widgets,
                                     page.build_controls)
            for key in self.controls.by_key:
                if key not in self._watched:
                    self._watched.add(key)
                    s.change(key)(self._watcher(key))

    def _probe_panels(self) -> dict:
        """The readout, the legend and the letters' tips for the scene and eye the view has now."""
        scene = self.scene
        point, normal = self.view.probe
        camera = self.view.camera_state()
        glyphs = (tuple(self.view.legend()), tuple(self.view.arrow_tips()), frozenset(self.view.hidden_letters()))
        if glyphs != self._glyphs[0]:  # formatted again only when the arrows, their letters or what hides them move
            legend = [{"letter": l, "meaning": m, "color": c} for l, m, c in glyphs[0]]
            self._glyphs = (glyphs, {"legend": legend,
                                     "arrow_tips": client.arrow_tips(list(glyphs[1]), legend, hidden=set(glyphs[2]))})
        return {
            "readout": probe_readout(scene, point, normal, self.view.light_index, mistake=self.view.mistake),
            **self._glyphs[1],
            # the camera the tips and readout are for (and, in pixel mode, the picture that comes with them)
            "arrow_camera": {"position": list(camera.eye), "view_angle": camera.view_angle},
        }

    # ------------------------------------------------------------------
    # browser input

    def _watcher(self, key):
        def on_change(**_):
            self.control_state.written(key)
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
            # only colours changed: they alone go to the browser (in pixel mode too, for the mesh under the picture)
            colours_only = Scene.changes(self.scene, scene).colours_only
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

    def _job_failed(self, name: str, exc: Exception) -> None:
        """A put-off job raised: said on the page; the server and the other jobs go on."""
        log.error("%s failed", name, exc_info=exc)
        what = {"panels": "refresh the panels"}.get(name, "follow the view's camera")
        self.notify("error", f"Could not {what}: {type(exc).__name__}: {exc}")
        self.state.flush()

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
                self._address_to_open = query  # open_lesson applies it before showing the lesson
                try:
                    self.open_lesson(index)
                finally:
                    applied, self._address_to_open = self._address_to_open is None, None
                if applied:
                    return
            self._apply_address(query)
        finally:
            self.state.page_ready = True

    @_guarded
    def _apply_address(self, query) -> None:
        """Apply the settings of an address to the open lesson, each checked by the page's own control."""
        if self.scene is not None and self.entry is not None and self.entry.ok:
            old_options = self.options
            scene, problems = self._address_settings(query, self.scene)
            if scene is not self.scene or self.options != old_options:
                self._show_scene(scene, turned=bool(self.options.get("turned")))
        else:
            problems = address.read_query(query)[1]
        if problems:
            self.notify("warning", address.notice(problems))

    def _address_settings(self, query, scene):
        """``scene`` and the view options with an address's settings applied: ``(scene, problems)``."""
        pairs, problems = address.read_query(query)
        if pairs:
            scratch = ctl.ControlSet(self.controls.frame, self.controls.lesson_paths, self.controls.extra)
            scene, self.options, refused = address.apply_settings(pairs, scene, self.options, scratch)
            problems += refused
        return scene, problems

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

