"""The panel of the lesson "Accuracy costs time": the accuracy plot and the error images.

When the accuracy lesson is open (a lesson file named ``NN-accuracy.md``),
the page shows

* the accuracy plot (:func:`phonglab.accuracy.accuracy_plot_png`): the quick
  studies, about five seconds of work, done once per server process and
  kept for every tab after that;
* a picker (method, mesh resolution) and, for the pick, the render, the
  exact sphere and the false-coloured error image with its scale bar and
  figures (:func:`phonglab.accuracy.error_images`, at the lesson's current
  shininess α).

Both are computed in worker processes (:func:`submit`), never in the
server's event loop that every tab shares, and reach the page as PNG data
URLs. The page shows "measuring…" meanwhile. A session asks for at most one
set of error images at a time; picks made while one is being computed are
merged into the last one.

A study that cannot finish (no result within :data:`TIMEOUT`, a worker that
died, an error) is told in plain words (:func:`failure_words`), never as an
exception; the last plot and images stay on the page, and a "Try again"
button (the state key ``accuracy_retry``) measures again.

This module imports only the standard library at import time: the worker
processes import it to run :func:`plot_data_url` and :func:`error_panel`.
"""

from __future__ import annotations

import asyncio
import base64
import concurrent.futures
import concurrent.futures.process
import io
import logging
import math
import tempfile
import threading
from pathlib import Path

from phonglab.accuracy.interpolation import ERROR_IMAGE_SIZE

log = logging.getLogger(__name__)

#: a lesson file ``NN-<slug>.md`` with this slug gets the panel
LESSON_SLUG = "accuracy"
#: the picker's methods: value -> label
METHODS = (("flat", "Flat"), ("gouraud", "Gouraud"), ("pixel", "Per pixel"))
#: the picker's mesh resolutions (segments around the sphere): up to 256, the finest the lesson's text
#: quotes (Gouraud there first comes closer to the peak than per pixel on 16)
RESOLUTIONS = (8, 16, 32, 64, 128, 256)
#: the pick shown first when the lesson's own scene is not one of the choices
DEFAULT_PICK = ("gouraud", 16)
#: the longest wait for a result before the page says it failed (seconds)
TIMEOUT = 180.0
#: size of the error images in pixels (width = height): the size lesson claims measure
IMAGE_SIZE = ERROR_IMAGE_SIZE


# ---------------------------------------------------------------------------
# checking the picker's values (they come from the browser)


def check_method(value) -> str:
    """The picker's method, or ValueError naming the value and the methods allowed."""
    allowed = [m for m, _ in METHODS]
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"accuracy.method: must be one of {', '.join(allowed)}, got {value!r}")
    return value


def check_resolution(value) -> int:
    """The picker's resolution, or ValueError naming the value and the resolutions allowed."""
    allowed = ", ".join(str(r) for r in RESOLUTIONS)
    number = None
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
        if float(value).is_integer():
            number = int(value)
    if number not in RESOLUTIONS:
        raise ValueError(f"accuracy.resolution: must be one of {allowed}, got {value!r}")
    return number


def is_accuracy_lesson(path) -> bool:
    """Whether the lesson file at ``path`` is the accuracy lesson (``NN-accuracy.md``)."""
    stem = Path(path).stem
    return stem.split("-", 1)[-1] == LESSON_SLUG


def pick_for(scene) -> tuple[str, int] | None:
    """The picker's (method, resolution) for a scene, or None when the scene is not one of the choices."""
    method, resolution = scene.interpolation, scene.geometry.resolution
    if method in dict(METHODS) and resolution in RESOLUTIONS:
        return method, int(resolution)
    return None


def unpicked_words(scene) -> str:
    """Why the picker shows another mesh than the view's, in a student's words."""
    method, resolution = scene.interpolation, scene.geometry.resolution
    if method not in dict(METHODS):
        return f"The view's {method} shading is not one of the panel's methods: the panel keeps its own pick."
    choices = ", ".join(str(r) for r in RESOLUTIONS)
    return (f"The view's mesh has {resolution:g} segments, not one of the panel's ({choices}): "
            f"the panel keeps its own pick. Pick one above, or set the view's resolution to one of them.")


# ---------------------------------------------------------------------------
# the work, run in a worker process


def png_data_url(image) -> str:
    """An RGB uint8 image (height, width, 3) as a ``data:image/png;base64,...`` URL."""
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def plot_data_url() -> str:
    """Run the quick studies and return the accuracy plot as a PNG data URL."""
    from phonglab.accuracy import accuracy_plot_png

    with tempfile.TemporaryDirectory(prefix="phonglab-accuracy-") as folder:
        path = accuracy_plot_png(Path(folder) / "accuracy.png")
        data = Path(path).read_bytes()
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def failure_words(exc: BaseException, what: str, kept: bool = False) -> str:
    """Why ``what`` (a study, "The error images …") has no result, in a student's words: no exception names.

    ``kept``: the page still shows the last figures (it says so).

    >>> failure_words(TimeoutError("no result after 180 s"), "The accuracy plot", kept=True)
    'The accuracy plot did not finish within 3 minutes: the server is busy. The last figures stay.'
    """
    if isinstance(exc, (TimeoutError, concurrent.futures.TimeoutError)):
        wait = f"{TIMEOUT / 60:.0f} minutes" if TIMEOUT >= 120 else f"{TIMEOUT:.0f} seconds"
        why = f"did not finish within {wait}: the server is busy"
    elif isinstance(exc, (concurrent.futures.process.BrokenProcessPool, concurrent.futures.CancelledError)):
        why = "stopped: the process measuring it ended"
    else:
        why = "stopped with an error (the server's log has the details)"
    return f"{what} {why}." + (" The last figures stay." if kept else "")


def _figure(value: float) -> str:
    return f"{value:.3g}" if value >= 1e-3 else f"{value:.2e}"


def _milliseconds(seconds: float) -> str:
    return f"{seconds * 1000:.3g} ms"


def error_panel(method: str, resolution: int, shininess: float, display: str = "srgb",
                exposure: float = 1.0) -> dict:
    """The error images and figures for one pick, ready for the page.

    Returns
    -------
    dict
        ``method``, ``resolution``, ``shininess``, ``display``, ``exposure`` (the request), ``alpha``
        (the shininess as the page writes it), the data
        URLs ``render``, ``reference``, ``error`` and ``scale`` (the scale
        bar), ``scale_labels`` (the errors at the bar's ticks) and
        ``figures``: a list of ``{"name", "value", "title"}`` (RMSE, max
        error, peak error, highlight RMSE, time, the exact sphere's time) and
        ``timing``: how the times were measured, in words (:func:`timing_words`).
        The render and reference images are encoded for the display as the
        scene's ``display`` and ``exposure`` say (sRGB by default).
    """
    from phonglab.accuracy import error_images, error_scale_bar

    view = error_images(method, int(resolution), size=IMAGE_SIZE, shininess=float(shininess),
                        encoding=display, exposure=float(exposure))
    lo, hi = view.error_range
    decades = round(math.log10(hi / lo))
    from phonglab.app.equation import exponent

    return {
        "method": method,
        "resolution": int(resolution),
        "shininess": float(shininess),
        "alpha": exponent(shininess),  # α as the slider and the readout write it (245.47, not 245.470892)
        "display": display,
        "exposure": float(exposure),
        "render": png_data_url(view.render),
        "reference": png_data_url(view.reference),
        "error": png_data_url(view.error),
        "scale": png_data_url(error_scale_bar(256, 10)),
        "scale_labels": [_power_of_ten(lo * 10**k) for k in range(decades + 1)],
        "timing": timing_words(view.repeats),
        "figures": [
            {"name": "RMSE", "value": _figure(view.rmse), "title": "root-mean-square error over the sphere"},
            {"name": "max error", "value": _figure(view.max_error), "title": "the largest error of any pixel"},
            {"name": "peak error", "value": _figure(view.peak_error),
             "title": "the error at the brightest pixel of the exact highlight"},
            {"name": "highlight RMSE", "value": _figure(view.highlight_rmse),
             "title": "root-mean-square error inside the exact highlight"},
            {"name": "time", "value": _milliseconds(view.time),
             "title": f"the method's shading work, {_fastest_words(view.repeats)}"},
            {"name": "exact sphere", "value": _milliseconds(view.reference_time),
             "title": f"shading the exact sphere (the reference), {_fastest_words(view.repeats)}"},
        ],
    }


def _fastest_words(repeats: int) -> str:
    """How one time was measured, for its tooltip."""
    return f"the fastest of {repeats} runs after a warm-up, timed in turns with the other"


def timing_words(repeats: int) -> str:
    """The note under the panel's times: how they were measured and what they can be compared with.

    >>> timing_words(5)[:61]
    'Times: the fastest of 5 runs each, after a warm-up, measured '
    """
    return (f"Times: the fastest of {repeats} runs each, after a warm-up, measured live on this machine. "
            f"They vary between runs: compare the two times of one pick, not times of different picks.")


def _power_of_ten(value: float) -> str:
    exponent = round(math.log10(value))
    if exponent == 0:
        return "1"
    digits = str(exponent).replace("-", "\u2212")
    superscript = digits.translate(str.maketrans("0123456789\u2212", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻"))
    return f"10{superscript}"


# ---------------------------------------------------------------------------
# worker processes, shared by every tab of this server process

_lock = threading.Lock()
_plot = None  # concurrent Future of plot_data_url(), kept once it succeeded


def submit(function, *args) -> concurrent.futures.Future:
    """Run ``function(*args)`` in a worker process of :mod:`phonglab.app.worker`; a Future of its result.

    The workers are shared with the page's other heavy work (exports) and
    run at a lower CPU priority than the server's event loop. The panel's
    own requests are few (one plot per server, one set of images per tab at
    a time), so they are not held to the server's job limit.
    """
    from phonglab.app import worker

    return worker.submit(function, *args, limit=None)


def plot_future() -> concurrent.futures.Future:
    """The accuracy plot's Future: started on the first call, kept once it succeeded, retried after a failure."""
    global _plot
    with _lock:
        plot = _plot
    if plot is None or (plot.done() and plot.exception() is not None):
        plot = submit(plot_data_url)
        with _lock:
            _plot = plot
    return plot


def forget_plot(future) -> None:
    """Drop ``future`` as the plot's (it failed or took too long): the next request measures again."""
    global _plot
    with _lock:
        if _plot is future:
            _plot = None


def shutdown() -> None:
    """Stop the worker processes at once (work in progress is dropped); see :func:`phonglab.app.worker.shutdown`."""
    global _plot
    from phonglab.app import worker

    with _lock:
        _plot = None
    worker.shutdown()


# ---------------------------------------------------------------------------
# one tab's panel


class AccuracyPanel:
    """The accuracy panel's state for one tab (one :class:`~phonglab.app.lesson_app.LessonApp`).

    State keys: ``accuracy`` (the panel is shown), ``accuracy_method`` and
    ``accuracy_resolution`` (the picker), ``accuracy_plot`` (``{"status":
    "measuring" | "ready" | "failed", "src", "error"}``; a failed plot keeps
    the last plot's ``src``), ``accuracy_view`` (the last :func:`error_panel`
    result, or None), ``accuracy_busy`` (error images are being computed),
    ``accuracy_measuring`` (what they are, in words), ``accuracy_failed``
    (why the last ones did not come, in words, or "") and ``accuracy_retry``
    (the page's "Try again" counts it up), ``accuracy_unpicked`` (why the
    picker did not follow the view's mesh, in words, or "").

    Parameters
    ----------
    state : trame state
    notify : callable
        ``notify(kind, text)``: a notice on the page.
    """

    def __init__(self, state, notify):
        self.state = state
        self.notify = notify
        self.active = False
        self._scene_pick = None  # the scene's (interpolation, resolution) last seen
        self._pick = DEFAULT_PICK  # the picker's last good (method, resolution)
        self._shininess = None
        self._display = ("srgb", 1.0)  # the scene's display encoding and exposure, for the images
        self._wanted = None  # (method, resolution, shininess, display, exposure) the page should show
        self._running = None  # the request being computed
        self._tasks = set()
        self._closed = False
        s = state
        s.accuracy = False
        s.accuracy_method, s.accuracy_resolution = DEFAULT_PICK
        s.accuracy_plot = {"status": "idle", "src": "", "error": ""}
        s.accuracy_view = None
        s.accuracy_busy = False
        s.accuracy_measuring = ""
        s.accuracy_failed = ""
        s.accuracy_retry = 0
        s.accuracy_zoom = False
        s.accuracy_unpicked = ""
        self._plot_src = ""  # the last plot shown: it stays when measuring again fails
        s.change("accuracy_method")(lambda **_: self._on_pick("accuracy_method", check_method))
        s.change("accuracy_resolution")(lambda **_: self._on_pick("accuracy_resolution", check_resolution))
        s.change("accuracy_retry")(lambda **_: self.retry())

    # -- lesson and scene

    def open(self, entry, scene) -> None:
        """A lesson was opened: show the panel if it is the accuracy lesson, else hide it."""
        self.active = bool(entry is not None and entry.lesson is not None and is_accuracy_lesson(entry.path))
        self.state.accuracy = self.active
        self._scene_pick = None
        if not self.active:
            return
        self._start_plot()
        self.follow(scene)

    def follow(self, scene) -> None:
        """The scene changed: the picker follows a new interpolation or resolution, α is used for the images."""
        if not self.active or scene is None:
            return
        scene_pick = (scene.interpolation, scene.geometry.resolution)
        if scene_pick != self._scene_pick:
            self._scene_pick = scene_pick
            pick = pick_for(scene)
            if pick is not None or self._wanted is None:
                self.state.accuracy_method, self.state.accuracy_resolution = pick or DEFAULT_PICK
            # a student who moved the view's mesh to a size the picker has not sees why the panel stayed
            self.state.accuracy_unpicked = "" if pick is not None else unpicked_words(scene)
        self._shininess = float(scene.material.shininess)
        self._display = (scene.display, float(scene.exposure))
        self._request()

    # -- the picker

    def _on_pick(self, key, check) -> None:
        """A picker value from the browser: checked, then the images follow (or a notice and the old value)."""
        which = 0 if key == "accuracy_method" else 1
        try:
            value = check(self.state[key])
        except ValueError as exc:
            self.notify("error", f"Refused: {exc}. The previous value stays.")
            self.state[key] = self._pick[which]
            return
        pick = list(self._pick)
        pick[which] = value
        self._pick = tuple(pick)
        if self.active:
            self._request()

    def _request(self) -> None:
        """Ask for the error images of the picker's values at the current α (merged while one is computed)."""
        try:
            method = check_method(self.state.accuracy_method)
            resolution = check_resolution(self.state.accuracy_resolution)
        except ValueError:
            return  # refused by _on_pick, which puts the previous value back
        self._pick = (method, resolution)
        wanted = (method, resolution, self._shininess if self._shininess is not None else 200.0,
                  *self._display)
        if wanted == self._wanted:
            return
        self._wanted = wanted
        if self._running is None:
            self._start_images()

    def retry(self) -> None:
        """The page's "Try again": measure the plot again if it failed, and the images of the pick."""
        if not self.active:
            return
        if self.state.accuracy_plot.get("status") == "failed":
            self._start_plot()
        if self.state.accuracy_failed:
            self.state.accuracy_failed = ""
            self._wanted = None  # the same pick again
            self._request()

    def _start_images(self) -> None:
        request = self._wanted
        self._running = request
        self.state.accuracy_busy = True
        self.state.accuracy_measuring = f"measuring {_pick_words(request)}…"
        self._when_done(submit(error_panel, *request), lambda future: self._images_done(request, future))

    def _images_done(self, request, future) -> None:
        self._running = None
        try:
            result = future.result()
        except Exception as exc:
            log.error("error images for %s failed: %r", request, exc)
            if request == self._wanted:  # the last images stay; the page says why no new ones came
                self.state.accuracy_failed = failure_words(exc, f"The error images for {_pick_words(request)}",
                                                           kept=self.state.accuracy_view is not None)
        else:
            if request == self._wanted:
                self.state.accuracy_view = result
                self.state.accuracy_failed = ""
        if self._wanted != request and self.active:
            self._start_images()
        else:
            self.state.accuracy_busy = False
            self.state.accuracy_measuring = ""

    # -- the plot

    def _start_plot(self) -> None:
        future = plot_future()
        if future.done() and future.exception() is None:
            self._plot_src = future.result()
            self.state.accuracy_plot = {"status": "ready", "src": self._plot_src, "error": ""}
            return
        self.state.accuracy_plot = {"status": "measuring", "src": self._plot_src, "error": ""}
        self._when_done(future, lambda done: self._plot_done(future, done))

    def _plot_done(self, started, future) -> None:
        """The plot's Future ``started`` is done, or given up (``future``, then failed with a timeout)."""
        try:
            src = future.result()
        except Exception as exc:
            forget_plot(started)  # measured anew next time, even if the first is still running
            log.error("the accuracy plot failed: %r", exc)
            self.state.accuracy_plot = {"status": "failed", "src": self._plot_src,
                                        "error": failure_words(exc, "The accuracy plot's four studies",
                                                               kept=bool(self._plot_src))}
        else:
            self._plot_src = src
            self.state.accuracy_plot = {"status": "ready", "src": src, "error": ""}

    # -- waiting without blocking the event loop

    def _when_done(self, future, callback) -> None:
        """Call ``callback(future)`` once ``future`` is done, in the server's event loop.

        Without a running loop (scripts, tests) the callback runs in the
        thread that completes the future, as soon as it is done.
        """
        if future.done():  # a result kept from before (the plot), or work run inline
            self._deliver(callback, future)
            return
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            loop = None
        if loop is None:
            future.add_done_callback(lambda done: self._deliver(callback, done))
            return
        task = loop.create_task(self._wait(future, callback))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _wait(self, future, callback) -> None:
        try:
            await asyncio.wait_for(asyncio.shield(asyncio.wrap_future(future)), timeout=TIMEOUT)
        except asyncio.CancelledError:
            raise
        except Exception:
            pass  # the callback reads the failure from the future
        if self._closed:
            return
        with self.state:  # the changes go to the browser when the block ends
            self._deliver(callback, _timed_out(future))

    def _deliver(self, callback, future) -> None:
        if self._closed:
            return
        try:
            callback(future)
        except Exception:
            log.exception("accuracy panel")

    def close(self) -> None:
        """Stop waiting for results (the tab closed)."""
        self._closed = True
        for task in list(self._tasks):
            task.cancel()


def _pick_words(request) -> str:
    """``Gouraud, 16 segments`` for a request (method, resolution, ...)."""
    return f"{dict(METHODS).get(request[0], request[0])}, {request[1]} segments"


def _timed_out(future) -> concurrent.futures.Future:
    """``future`` itself when done, else a Future that failed with a timeout."""
    if future.done():
        return future
    failed = concurrent.futures.Future()
    failed.set_exception(TimeoutError(f"no result after {TIMEOUT:.0f} s"))
    return failed
