"""The lesson page's layout: every widget of the page, bound to the app's state keys.

This module only draws. It knows the state keys the app fills (``lesson_html``,
``readout``, ``control_values``, ...; see :class:`~phonglab.app.lesson_app.LessonApp`)
and calls back into the app through :class:`Handlers`; it keeps no state of
its own. Its entry points:

* :func:`initial_state` gives every state key the page shows, with the value
  it has before a lesson is open;
* :func:`build_page` lays out the whole page once per tab: the bar, the
  lesson list, the lesson's text, the view with its tools, the accuracy
  panel, the readout and the planner's verdict;
* :func:`build_controls` (re)draws the controls panel, a template the page
  includes by name, whenever the set of controls changes (a new lesson, a
  light of another type). A value change alone never redraws it: the widgets
  follow their state keys.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Callable

from trame.ui.html import DivLayout
from trame.ui.vuetify3 import VAppLayout
from trame.widgets import client, html
from trame_client.widgets.core import AbstractElement
from trame.widgets import vtk as vtk_widgets
from trame.widgets import vuetify3 as v3

from phonglab.app import download
from phonglab.app.accuracy_panel import METHODS as ACCURACY_METHODS
from phonglab.app.accuracy_panel import RESOLUTIONS as ACCURACY_RESOLUTIONS
from phonglab.app import check_question, student_code
from phonglab.app.client import ArrowLetters, ColorPush
from phonglab.app.control import Control
from phonglab.app.controls import MODELS as MODEL_NAMES
from phonglab.app.controls import TERMS, cone_switch
from phonglab.app.keys import state_key
from phonglab.app import truth_ui
from phonglab.app.slider_access import slider_attributes
from phonglab.app.wording import spoken_label


def initial_state() -> dict:
    """Every state key the page shows, with its value before a lesson is open (new objects each call)."""
    return {
        "drawer": False,
        "lesson_index": -1,
        "lesson_title": "",
        "lesson_number": None,
        "lesson_goal_html": "",
        "lesson_html": "",
        "lesson_errors": [],
        "experiments": [],
        "question_html": "",
        "answer_html": "",
        "has_model_control": False,  # the lesson lets the student switch the model: the comparison is offered
        "show_answer": False,
        "readout": None,
        "plan_computed": [],
        "plan_skipped": [],
        "legend": [],
        "arrow_tips": [],
        "arrow_camera": None,
        "notice": None,
        "phonglab_download": None,  # a figure on its way to the browser (app/download.py)
        "url_query": "",  # the address of the view shown (app/address.py)
        "url_request": None,  # the address the page was opened with
        "page_ready": False,  # the lesson the address names is open: until then the page shows it is loading
        "in_cell": False,  # shown in a notebook cell (app/jupyter.py): the view beside the controls at every width
        "view_colors": None,
        "pixel_src": "",
        "pixel_pending": False,  # a newer per-pixel picture is being made (app/pixel_picture.py)
        "pixel_mode": False,
        "pixel_hint": "",
        "control_values": {},
        "control_labels": {},
        "has_view": False,
        "pick_target": "probe",
        "mistake": None,
        "mistake_note": "",
    }


#: the name of the controls panel's template (:func:`build_controls`)
CONTROLS_TEMPLATE = "phonglab_controls"


@dataclass(frozen=True)
class Handlers:
    """What the page's buttons and the view call on the app.

    Each takes the arguments the browser sends (checked by the app, not here).
    """

    open_lesson: Callable  #: ``(index)``: a lesson picked in the list
    reset_lesson: Callable  #: ``()``: the Reset button
    export_figure: Callable  #: ``()``: the Export PNG button
    apply_experiment: Callable  #: ``(index)``: an experiment's Apply button
    pick: Callable  #: ``(event)``: a click on the view (``event["ray"]``)
    camera: Callable  #: ``(camera)``: the browser's camera after a turn or zoom
    check_answer: Callable | None = None  #: ``(answer)``: the check question's Check button
    student_code: Callable | None = None  #: ``(code)``: "Grade my code"; None: no panel (the default)
    camera_move: Callable | None = None  #: ``(camera)``: the browser's camera during a turn or zoom
    view_ready: Callable | None = None  #: ``()``: the browser's 3D view is on the page (send it the camera)


#: the trigger the page's 3D view calls once it is on the page (``www/phonglab.js``)
VIEW_READY = "phonglab_view_ready"


def address_element():
    """``<phonglab-address :query="url_query">``: keeps the address bar on the lesson (``www/phonglab.js``)."""

    class Address(AbstractElement):
        def __init__(self, **kwargs):
            super().__init__("phonglab-address", **kwargs)
            self._attr_names += ["query"]

    return Address(query=("url_query", ""))


class NoticeTimer(AbstractElement):
    """``<phonglab-notice-timer :notice="notice">``: an "info" or "success" notice goes after a few seconds."""

    def __init__(self, **kwargs):
        super().__init__("phonglab-notice-timer", **kwargs)
        self._attr_names += ["notice"]


def build_page(server, render_window, handlers: Handlers):
    """Lay out the page for one tab.

    Parameters
    ----------
    server : trame server
    render_window : vtkRenderWindow
        The window the local view shows (the app's SceneView's).
    handlers : Handlers

    Returns
    -------
    (layout, view)
        The page's layout and its ``VtkLocalView`` (the app calls its
        ``update()`` and ``push_camera()``).
    """
    page = _Page(server, render_window, handlers)
    page.build()
    if handlers.view_ready is not None:
        server.controller.trigger(VIEW_READY)(lambda *_, **__: handlers.view_ready())
    return page.layout, page.view


class _Page:
    """The page's columns as methods, sharing the server, the window and the handlers."""

    def __init__(self, server, render_window, handlers: Handlers):
        self.server = server
        self.render_window = render_window
        self.handlers = handlers
        self.layout = None
        self.view = None

    def build(self):
        with VAppLayout(self.server, full_height=True) as self.layout:
            self.layout.root.classes = "phonglab"
            with v3.VAppBar(density="compact", elevation=1, classes="phonglab-bar"):
                v3.VAppBarNavIcon(click="drawer = !drawer", classes="phonglab-menu", title="Lesson list",
                                  aria_label="Lesson list", __properties=[("aria_label", "aria-label")])
                html.Div("phonglab", classes="phonglab-brand")
                # until the lesson the address names is open, no lesson's title (the first one's, say)
                html.Div(
                    "{{ !page_ready ? '' : (lesson_number != null ? lesson_number + ' · ' : '') + lesson_title }}",
                    classes="phonglab-lesson-title",
                )
                v3.VSpacer()
                v3.VBtn("Reset", prepend_icon="mdi-restore", variant="text", click=self.handlers.reset_lesson,
                        disabled=("!page_ready || lesson_errors.length > 0",), classes="phonglab-reset")
                v3.VBtn("Export PNG", prepend_icon="mdi-image-outline", variant="tonal", color="primary",
                        click=self.handlers.export_figure, disabled=("!page_ready || lesson_errors.length > 0",),
                        loading=("export_busy",),  # the figure is being made in a worker (app/download.py)
                        classes="phonglab-export ml-2 mr-2")
                # more figures to download: the per-term figure and the mistake comparison
                with v3.VMenu():
                    with html.Template(v_slot_activator="{ props }"):
                        v3.VBtn(icon="mdi-menu-down", v_bind="props", variant="text", density="comfortable",
                                disabled=("!page_ready || lesson_errors.length > 0",), title="More figures to download",
                                classes="phonglab-export-more mr-2")
                    with v3.VList(density="compact"):
                        download.export_menu_items(self.handlers.export_figure)
                download.download_link()
                address_element()
            with v3.VNavigationDrawer(v_model=("drawer",), temporary=True, width=300, classes="phonglab-drawer"):
                v3.VListSubheader("Lessons")
                with v3.VList(density="compact", nav=True):
                    with v3.VListItem(
                        v_for="item in lessons",
                        key="item.index",
                        active=("item.index === lesson_index",),
                        click=(self.handlers.open_lesson, "[item.index]"),
                        classes="phonglab-lesson-item",
                    ):
                        with v3.Template(v_slot_prepend=True):
                            html.Span("{{ item.number != null ? item.number : '·' }}", classes="phonglab-num")
                        v3.VListItemTitle("{{ item.title }}")
                        with v3.Template(v_slot_append=True):
                            v3.VIcon("mdi-alert-circle-outline", color="error", v_if="!item.ok", size="small")
            with v3.VMain(classes="phonglab-main"):
                # the page's lesson, with its address's settings, from its first drawn frame: nothing before
                with html.Div(classes=("in_cell ? 'phonglab-grid phonglab-in-cell' : 'phonglab-grid'",),
                              v_if="page_ready"):
                    self._lesson_column()
                    self._view_column()
                    self._control_column()
                with html.Div(v_else=True, classes="phonglab-loading", role="status"):
                    v3.VProgressCircular(indeterminate=True, size=28, width=3, color="primary")
                    html.Span("Opening the lesson…")

    def _lesson_column(self):
        with html.Div(classes="phonglab-text"):
            with html.Div(v_if="lesson_errors.length", classes="phonglab-errors"):
                html.H2("This lesson file has problems")
                html.P("Fix them in the file and reload the page. phonglab check lists them too.")
                with html.Ul():
                    html.Li("{{ e }}", v_for="(e, i) in lesson_errors", key="i", classes="phonglab-error")
            with html.Div(v_else=True):
                html.H1("{{ lesson_title }}", classes="phonglab-h1")
                html.Div(v_if="lesson_goal_html", v_html=("'<b>Goal.</b> ' + lesson_goal_html",),
                         classes="phonglab-goal")
                html.Div(v_html=("lesson_html",), classes="phonglab-body")
                with html.Div(v_if="experiments.length", classes="phonglab-experiments"):
                    html.H3("Experiments")
                    with v3.VCard(v_for="x in experiments", key="x.index", variant="outlined",
                                  classes="phonglab-experiment mb-2"):
                        with v3.VCardText(classes="d-flex align-center"):
                            with html.Div(classes="flex-grow-1 pr-2"):
                                html.Div(v_html=("x.label",), classes="font-weight-medium")
                                html.Div(v_if="x.text", v_html=("x.text",), classes="text-body-2")
                            v3.VBtn("Apply", size="small", color="primary", variant="flat",
                                    click=(self.handlers.apply_experiment, "[x.index]"), classes="phonglab-apply")
                with html.Div(v_if="mistake", classes="phonglab-mistake"):
                    html.H3("A common mistake: {{ mistake.title }}")
                    html.P("{{ mistake.looks_like }}")
                    with html.Div(classes="phonglab-code"):
                        html.Div("wrong", classes="phonglab-code-tag phonglab-code-wrong")
                        html.Code("{{ mistake.wrong }}")
                        html.Div("right", classes="phonglab-code-tag phonglab-code-right")
                        html.Code("{{ mistake.right }}")
                    v3.VSwitch(v_model=("view__mistake", False), v_if="mistake.available", color="error",
                               label="Show the mistake in the picture", density="compact", hide_details=True,
                               classes="phonglab-mistake-switch")
                    html.P("{{ mistake_note }}", v_if="mistake_note", classes="phonglab-note phonglab-mistake-note")
                    # where the lesson has the interpolation control: one click to where the mistake shows
                    v3.VBtn("Show it with per-pixel shading", v_if="mistake_note && interpolation != null",
                            click="interpolation = 'pixel'; view__mistake = true", size="small", variant="tonal",
                            color="error", classes="phonglab-mistake-pixel")
                # a lesson's [check], its open question, or both
                with html.Div(v_if="question_html || check", classes="phonglab-question"):
                    html.H3("Check yourself")
                    if self.handlers.check_answer is not None:  # answer first, then the explanation
                        check_question.build(self.handlers.check_answer)
                    # the lesson's open question, which the explanation answers, set apart from the check's
                    html.H4("Think about it", v_if="check && question_html", classes="phonglab-think")
                    html.Div(v_if="question_html", v_html=("question_html",), classes="phonglab-open-question")
                    v3.VBtn("{{ show_answer ? 'Hide answer' : 'Show answer' }}", size="small", variant="text",
                            v_if=f"answer_html && ({check_question.REVEAL_IF})",
                            color="primary", click="show_answer = !show_answer", classes="phonglab-answer-btn px-0")
                    html.Div(v_if="show_answer && answer_html", v_html=("answer_html",), classes="phonglab-answer")
                if self.handlers.student_code is not None:  # only with phonglab serve --allow-student-code
                    student_code.build(self.handlers.student_code)

    def _view_column(self):
        with html.Div(classes="phonglab-centre"):
            # the legend and the view's tools in a bar above the picture: nothing of the page covers the scene
            with html.Div(classes="phonglab-viewbar", v_if="!lesson_errors.length"):
                with html.Div(classes="phonglab-legend"):
                    with html.Span(v_for="v in legend", key="v.letter", classes="phonglab-chip",
                                   title=("v.meaning",)):
                        html.Span("", classes="phonglab-swatch", style=("{background: v.color}",))
                        html.B("{{ v.letter }}")
                    # the arrows off and on again: a highlight at the probe lies under them
                    hide = "view__arrows_hidden ? 'Show the arrows' : 'Hide the arrows, to see the surface under them'"
                    with html.Button(type="button", classes="phonglab-chip phonglab-arrows-toggle",
                                     click="view__arrows_hidden = !view__arrows_hidden", title=(hide,),
                                     aria_label=(hide,), aria_pressed=("view__arrows_hidden ? 'true' : 'false'",),
                                     __properties=[("aria_label", "aria-label"), ("aria_pressed", "aria-pressed")]):
                        v3.VIcon(icon=("view__arrows_hidden ? 'mdi-eye-off-outline' : 'mdi-eye-outline'",), size="small")
                        html.Span("arrows hidden", v_if="view__arrows_hidden")
                with html.Div(classes="phonglab-tools"):
                    with v3.VBtnToggle(v_model=("view__term",), mandatory=True, density="compact",
                                       variant="outlined", divided=True, classes="phonglab-term-toggle"):
                        for value, title in TERMS:
                            v3.VBtn(title.replace(" terms", ""), value=value, size="small",
                                    classes=f"phonglab-term-{value}")
                    # not in the accuracy lesson: its panel stands where the readout would, so a probe
                    # there had no numbers to show, and a moved light would not reach the panel's sphere
                    with v3.VBtnToggle(v_model=("pick_target",), mandatory=True, density="compact",
                                       variant="outlined", divided=True, classes="phonglab-pick-toggle",
                                       v_if="!accuracy"):
                        # named for a screen reader and a tooltip too: a narrow bar shows their icons alone
                        v3.VBtn("Probe", value="probe", size="small", prepend_icon="mdi-target",
                                aria_label="Probe", title="A click on the view moves the probe",
                                __properties=[("aria_label", "aria-label")])
                        v3.VBtn("Light", value="light", size="small", prepend_icon="mdi-lightbulb-outline",
                                aria_label="Light", title="A click on the view moves the light",
                                __properties=[("aria_label", "aria-label")])
                    # the scene under Phong and under Cook–Torrance, side by side below the view
                    v3.VBtn("Compare models", size="small", prepend_icon="mdi-compare", v_if="has_model_control",
                            variant=("view__compare ? 'flat' : 'tonal'",), color="primary",
                            click="view__compare = !view__compare", classes="phonglab-compare-toggle",
                            aria_pressed=("view__compare ? 'true' : 'false'",), aria_label="Compare models",
                            __properties=[("aria_pressed", "aria-pressed"), ("aria_label", "aria-label")],
                            title="Show this scene under Phong and under Cook–Torrance, side by side")
            with html.Div(classes="phonglab-view"):
                with vtk_widgets.VtkLocalView(
                    self.render_window,
                    ref="phonglab_view",
                    picking_modes=("['click']",),
                    click=(self.handlers.pick, "[$event]"),
                    interactor_settings=("view_interaction", _INTERACTION),
                    interactor_events=("['EndAnimation', 'Animation']",),
                    EndAnimation=(self.handlers.camera, "[trame.refs.phonglab_view.getCamera()]"),
                    Animation=(self.handlers.camera_move or self.handlers.camera,
                               "[trame.refs.phonglab_view.getCamera()]"),
                ) as self.view:
                    ColorPush(push=("view_colors",), expect=("!pixel_mode",), picture=("pixel_src",))
                    # in every mode; over the core's picture, only while the view's eye is the picture's
                    ArrowLetters(tips=("arrow_tips", []), camera=("arrow_camera", None), covered=("pixel_mode",))
                client.SizeObserver("view_size", classes="phonglab-size")  # laid over the view: see the CSS
                with html.Div(v_if="pixel_mode", classes="phonglab-pixel"):
                    # decoded with the page's update: the picture shows in the frame its readout does. None
                    # until the first picture comes (switching to per pixel): an empty one showed a broken image
                    html.Img(v_if="pixel_src", src=("pixel_src",), alt="per-pixel shading by the core",
                             decoding="sync")
                    html.Div("updating the picture…", v_if="pixel_pending", role="status",
                             classes="phonglab-pixel-updating")
                self._compare_panel()
                # the view's foot, from the bottom up: the hint line (or the mistake's banner in its place),
                # then a notice stacked above them, so that it covers neither
                with html.Div(classes="phonglab-foot"):
                    self._notice()
                    truth_ui.wrong_banner()
                    html.Div(
                        "{{ pixel_mode ? pixel_hint + (accuracy ? '' : ' · click to pick') + ' · turn the view: the "
                        "picture follows when you let go' : (accuracy ? 'Drag to turn' : (pick_target === 'light' ? "
                        "'Click the surface to put the light above it' : 'Click the surface to move the probe') + "
                        "' · drag to turn') + ' · wheel to zoom' }}",
                        classes="phonglab-hint",
                    )
            self._accuracy_panel()
            self._readout_panel()

    def _compare_panel(self):
        """Phong beside Cook–Torrance over the view: the scene under both models from the view's eye (a worker's)."""
        with html.Div(classes="phonglab-compare", v_if="view__compare"):
            with html.Div(classes="phonglab-compare-head"):
                html.Span("Phong beside Cook–Torrance: the same mesh, lights and eye, each shaded per pixel by "
                          "the core; it follows your changes", classes="phonglab-section")
                v3.VBtn("Back to the 3D view", size="small", variant="tonal", prepend_icon="mdi-close",
                        click="view__compare = false", classes="phonglab-compare-close")
            v3.VProgressLinear(indeterminate=True, v_if="compare_busy", color="primary", height=2)
            # a picture per model, its caption page text under it: drawn into a picture the page scales
            # down, the captions were about 7 px tall on a laptop
            with html.Div(v_if="compare_png.panels.length", classes=(
                    "compare_png.stacked ? 'phonglab-compare-figures phonglab-compare-stacked' : "
                    "'phonglab-compare-figures'",)):
                with html.Figure(v_for="p in compare_png.panels", key="p.model", classes=(
                        "p.own ? 'phonglab-compare-figure phonglab-compare-own' : 'phonglab-compare-figure'",)):
                    html.Img(src=("p.src",), alt=("'this scene under ' + p.caption",),
                             classes="phonglab-compare-picture")
                    with html.Figcaption(classes="phonglab-compare-caption"):
                        html.Span("{{ p.caption }}")
                        html.Span("the scene's model", v_if="p.own", classes="phonglab-compare-own-tag")
            html.Div("Making the comparison… (a few seconds)", role="status",
                     v_if="!compare_png.panels.length && compare_png.status === 'making'", classes="phonglab-note")
            html.Div("{{ compare_png.error }}", v_if="compare_png.status === 'failed'", role="status",
                     classes="phonglab-note")

    def _accuracy_panel(self):
        """The accuracy lesson's panel: the error images for a picked method and mesh, and the plot."""
        with html.Div(classes="phonglab-accuracy", v_if="accuracy"):
            with html.Div(classes="phonglab-accuracy-head"):
                html.Span("Error against the exact sphere", classes="phonglab-section")
                with v3.VBtnToggle(v_model=("accuracy_method",), mandatory=True, density="compact",
                                   variant="outlined", divided=True, classes="phonglab-accuracy-method"):
                    for value, title in ACCURACY_METHODS:
                        v3.VBtn(title, value=value, size="small", classes=f"phonglab-accuracy-method-{value}")
                with v3.VBtnToggle(v_model=("accuracy_resolution",), mandatory=True, density="compact",
                                   variant="outlined", divided=True, classes="phonglab-accuracy-resolution"):
                    for value in ACCURACY_RESOLUTIONS:
                        v3.VBtn(str(value), value=(str(value),), size="small",  # bound: a number, not a string
                                classes=f"phonglab-accuracy-resolution-{value}")
                html.Span("segments", classes="phonglab-note")
            html.Div("{{ accuracy_unpicked }}", v_if="accuracy_unpicked", role="status",
                     classes="phonglab-note phonglab-accuracy-unpicked")
            v3.VProgressLinear(indeterminate=True, v_if="accuracy_busy", color="primary", height=2,
                               classes="phonglab-accuracy-busy")
            html.Div("{{ accuracy_measuring }}", v_if="accuracy_busy && accuracy_view",
                     classes="phonglab-note phonglab-accuracy-measuring-images")
            self._try_again("accuracy_failed", "accuracy_failed", "phonglab-accuracy-images-failed")
            html.Div("Measuring… (the first picture takes a few seconds)", v_if="!accuracy_view && !accuracy_failed",
                     classes="phonglab-note phonglab-accuracy-wait")
            with html.Div(v_if="accuracy_view", classes="phonglab-accuracy-images"):
                for key, caption in (
                    ("render", "'render: ' + accuracy_view.method + ', ' + accuracy_view.resolution + ' segments'"),
                    ("reference", "'exact sphere'"),
                    ("error", "'error |render \u2212 exact|, α = ' + accuracy_view.alpha"),
                ):
                    with html.Figure(classes=f"phonglab-accuracy-figure phonglab-accuracy-{key}"):
                        html.Img(src=(f"accuracy_view.{key}",), alt=key)
                        html.Figcaption(f"{{{{ {caption} }}}}")
                with html.Div(classes="phonglab-accuracy-scale"):
                    html.Img(src=("accuracy_view.scale",), alt="error colour scale")
                    with html.Div(classes="phonglab-accuracy-ticks"):
                        html.Span("{{ t }}", v_for="(t, i) in accuracy_view.scale_labels", key="i")
                with html.Div(classes="phonglab-accuracy-figures"):
                    with html.Div(v_for="f in accuracy_view.figures", key="f.name", title=("f.title",),
                                  classes="phonglab-accuracy-number"):
                        html.Span("{{ f.name }}", classes="phonglab-term-name")
                        html.Span("{{ f.value }}", classes="phonglab-mono",
                                  data_figure=("f.name",), __properties=[("data_figure", "data-figure")])
                html.Div("{{ accuracy_view.timing }}", v_if="accuracy_view.timing",
                         classes="phonglab-note phonglab-accuracy-timing")
            html.Div("What accuracy costs in time (quick run of phonglab bench accuracy)",
                     classes="phonglab-section mt-3")
            with html.Div(v_if="accuracy_plot.status === 'measuring'", classes="phonglab-accuracy-measuring"):
                v3.VProgressCircular(indeterminate=True, size=18, width=2, color="primary")
                html.Span("measuring… the four studies take about five seconds", classes="phonglab-note")
            self._try_again("accuracy_plot.status === 'failed'", "accuracy_plot.error", "phonglab-accuracy-failed")
            html.Img(v_if="accuracy_plot.src", src=("accuracy_plot.src",),
                     alt="error against time for the four studies", title="click to enlarge",
                     click="accuracy_zoom = true", classes="phonglab-accuracy-plot")
            with v3.VDialog(v_model=("accuracy_zoom",), max_width="96vw", classes="phonglab-accuracy-zoom"):
                with v3.VCard(click="accuracy_zoom = false"):
                    html.Img(src=("accuracy_plot.src",), classes="phonglab-accuracy-plot-large")

    @staticmethod
    def _notice():
        """The page's notice, at the foot of the view above its hint line: it covers none of the controls nor
        the hint, and a notice that only informs ("Applied: …") goes by itself after a few seconds
        (``www/phonglab.js``)."""
        with v3.VAlert(
            v_if="notice",
            type=("notice.kind",),
            variant="tonal",
            density="compact",
            closable=True,
            classes="phonglab-notice",
            click_close="notice = null",
        ):
            html.Span(v_html=("notice.html",))  # escaped by notify(): only the subscripts are markup
        NoticeTimer(notice=("notice",))

    @staticmethod
    def _try_again(condition: str, words: str, css: str):
        """Why a study did not finish (state expression ``words``), and a button that measures again."""
        with html.Div(v_if=condition, role="status", classes=f"phonglab-note phonglab-try-again {css}"):
            html.Span(f"{{{{ {words} }}}}")
            v3.VBtn("Try again", size="small", variant="tonal", color="primary", prepend_icon="mdi-refresh",
                    click="accuracy_retry = accuracy_retry + 1", classes="phonglab-try-again-btn ml-2")

    def _readout_panel(self):
        with html.Div(classes="phonglab-readout", v_if="readout && !accuracy"):
            with html.Div(classes="phonglab-readout-head"):
                html.Span("At the probe", classes="phonglab-section")
                html.Span("{{ readout.point }}", classes="phonglab-mono phonglab-point")
            with html.Div(classes="phonglab-dots"):
                # with several directed lights: whose dots these are, and that light's own terms beside them
                html.Div("{{ readout.light_name }} (its vectors are drawn)", v_if="readout.light_name",
                         classes="phonglab-light-name")
                with html.Div(v_for="d in readout.dots", key="d.name", classes="phonglab-dot"):
                    html.Span(v_html=("d.tex",))
                    html.Span("=", classes="phonglab-eq")
                    html.Span("{{ d.value }}", classes="phonglab-mono phonglab-dot-value",
                              data_name=("d.name",), __properties=[("data_name", "data-name")])
                    with html.Span(v_if="d.term", classes="phonglab-dot-term"):
                        html.Span("", classes="phonglab-swatch", style=("{background: d.term.hex}",))
                        html.Span("{{ readout.light_name }}'s {{ d.term.name }}", classes="phonglab-term-name")
                        html.Span("{{ d.term.value }}", classes="phonglab-mono", data_light_term=("d.term.name",),
                                  __properties=[("data_light_term", "data-light-term")])
            html.Div("All lights together", v_if="readout.light_name", classes="phonglab-light-name")
            with html.Div(classes="phonglab-terms"):
                with html.Div(v_for="t in readout.terms", key="t.name", classes="phonglab-term",
                              title="RGB, before clipping to the screen's 0..1"):
                    html.Span("", classes="phonglab-swatch", style=("{background: t.hex}",))
                    html.Span("{{ t.name }}", classes="phonglab-term-name")
                    html.Span("{{ t.value }}", classes="phonglab-mono",
                              data_term=("t.name",), __properties=[("data_term", "data-term")])
            truth_ui.mistaken_terms()
            html.Div(v_html=("readout.equation",), classes="phonglab-equation")
            html.Div(v_html=("n",), v_for="(n, i) in readout.notes_html", key="i", classes="phonglab-note")
            truth_ui.display_note()

    def _control_column(self):
        with html.Div(classes="phonglab-side"):
            client.ServerTemplate(name=CONTROLS_TEMPLATE)
            with html.Div(classes="phonglab-plan", v_if="!lesson_errors.length"):
                html.Div("What the planner computes", classes="phonglab-section")
                with html.Div(v_for="p in plan_computed", key="p.effect", classes="phonglab-plan-row"):
                    v3.VIcon("mdi-check-circle", color="success", size="small")
                    html.B("{{ p.effect }}")
                    html.Span(v_html=("p.html",), classes="phonglab-plan-reason")  # escaped, subscripts set
                with html.Div(v_for="p in plan_skipped", key="p.effect",
                              classes="phonglab-plan-row phonglab-plan-skipped"):
                    v3.VIcon("mdi-minus-circle-outline", color="grey", size="small")
                    html.B("{{ p.effect }}")
                    html.Span(v_html=("p.html",), classes="phonglab-plan-reason")


#: groups of the lesson's controls shown without a heading while no other group has one above them
UNHEADED_GROUPS = ("Material", "Shading", "View")


def build_controls(server, chosen, all_controls=()) -> None:
    """Draw the controls panel: the lesson's controls (``chosen``), then every control by group."""
    with DivLayout(server, template_name=CONTROLS_TEMPLATE) as layout:
        layout.root.classes = "phonglab-controls"
        if chosen:
            html.Div("This lesson", classes="phonglab-section")
            group, headed = None, False
            for control in chosen:
                # the material, shading and view need no heading of their own, until they follow one
                # (lesson 5's k_d under "Light 2" read as a setting of that light)
                if control.group != group and (control.group not in UNHEADED_GROUPS or headed):
                    html.Div(control.group, classes="phonglab-subsection")
                    headed = True
                group = control.group
                _widget(control)
        if all_controls:
            with v3.VExpansionPanels(variant="accordion", classes="phonglab-all mt-3", multiple=True):
                groups = []
                for control in all_controls:
                    if control.group not in groups:
                        groups.append(control.group)
                for group in groups:
                    with v3.VExpansionPanel(title=group, classes="phonglab-group"):
                        with v3.VExpansionPanelText():
                            for control in all_controls:
                                if control.group == group:
                                    _widget(control, suffix="all")


#: mouse: left turns, shift-left pans, wheel zooms; a plain click picks
_INTERACTION = [
    {"button": 1, "action": "Rotate"},
    {"button": 2, "action": "Pan"},
    {"button": 3, "action": "Zoom", "scrollEnabled": True},
    {"button": 1, "action": "Pan", "shift": True},
    {"button": 1, "action": "Zoom", "control": True},
]


def _widget(control: Control, suffix: str = "") -> None:
    """One control's widget, bound to its state key."""
    css = f"phonglab-control phonglab-control-{control.key}" + (f" phonglab-control-{suffix}" if suffix else "")
    key = control.key
    label = f"control_labels['{key}']"
    if control.kind == "slider":
        # a slider of one model's (shininess: Phong's; roughness: Cook–Torrance's) is greyed under another
        unused = f"!{json.dumps(list(control.models))}.includes(model)".replace('"', "'") if control.models else None
        # a spot's cutoff slider (1–90°) is greyed while its "no cone" switch holds the cutoff at 180°
        switch = cone_switch(control.path)
        cone = state_key(switch) if switch else None
        dim = " || ".join(f"({c})" for c in (unused, cone) if c)
        with html.Div(classes=css, style=(f"{dim} ? 'opacity: 0.6' : ''",) if dim else None):
            with html.Div(classes="phonglab-control-head"):
                html.Span(v_html=(label,), classes="phonglab-label")
                if unused:
                    names = " and ".join(dict(MODEL_NAMES).get(m, m) for m in control.models)
                    html.Span(f"used by {names} only", v_if=unused, classes="phonglab-note phonglab-model-note")
                shown = f"control_values['{key}']"
                if cone:
                    shown = f"({cone} ? '180° (no cone)' : {shown})"
                html.Span(f"{{{{ {shown} }}}}", classes="phonglab-mono phonglab-value")
            v3.VSlider(
                v_model=(key,),
                min=control.low,
                max=control.high,
                step=control.step,
                hide_details=True,
                density="compact",
                color="primary",
                thumb_size=14,
                track_size=3,
                **slider_attributes(control),  # the thumb's aria-label; the arrow keys' step
            )
    elif control.kind == "color":
        with html.Div(classes=css + " phonglab-color-row"):
            html.Span(v_html=(label,), classes="phonglab-label")
            html.Input(type="color", value=(key,), change=f"{key} = $event.target.value", classes="phonglab-color",
                       aria_label=spoken_label(control), __properties=[("aria_label", "aria-label")])
    elif control.kind == "select":
        with html.Div(classes=css):
            v3.VSelect(
                v_model=(key,),
                items=(_js_items(control.items),),
                label=control.label,
                density="compact",
                variant="outlined",
                hide_details=True,
                classes="mt-2",
            )
    elif control.kind == "switch":
        with html.Div(classes=css):
            v3.VSwitch(v_model=(key,), label=control.label, density="compact", hide_details=True, color="primary")


def _js_items(items) -> str:
    """Select items as a JavaScript literal that fits in an HTML attribute (single quotes)."""
    return "[" + ", ".join(
        "{value: %s, title: %s}" % (json.dumps(v).replace("'", "\\'").replace('"', "'"),
                                    json.dumps(t).replace("'", "\\'").replace('"', "'"))
        for v, t in items
    ) + "]"
