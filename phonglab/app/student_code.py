"""The "Your code" panel: a student pastes their ``shade`` and gets it graded on the server.

**Off unless the server is started with ``phonglab serve --allow-student-code``**,
which refuses to start when this machine cannot make the grader's sandbox.
The code is graded exactly as ``phonglab grade`` grades a file
(:func:`phonglab.teaching.grading.grade_file`): handed from memory to a
worker inside a bubblewrap sandbox (:mod:`phonglab.teaching.isolation`:
its own user, PID, network and mount namespaces, a read-only view of only
Python, NumPy and the helper module, a seccomp filter, CPU, memory and time
limits). Nothing of it is written on the server's disk.

The panel shows the grade report, the student's shading of a sphere beside
the core's and their difference (:func:`phonglab.accuracy.grade_picture.picture_png`),
and what isolated the run.

Gradings have their own bounded pool (:class:`GradingQueue`), shared by
every tab of the server: at most :func:`grading_slots` run at once, in
threads of their own (never the event loop, nor the thread pool the
per-pixel picture uses); the others wait in order, and each waiting tab is
shown its place. A tab has one grading at a time: submitting again cancels
the one queued or running (its sandbox is killed), and so does closing the
tab. The pasted text is checked like any value from the browser: a string
of at most :data:`MAX_CODE_BYTES` bytes (UTF-8).

State keys: ``student_code_enabled``, ``student_code`` (the textarea),
``student_busy``, ``student_status`` (the place in the queue, or that it
runs) and ``student_result`` (``{"score", "max_score", "passed", "report",
"picture", "diagnosis", "isolation"}`` or ``{"error"}``).
"""

from __future__ import annotations

import asyncio
import base64
import functools
import logging
import os
from concurrent.futures import ThreadPoolExecutor

log = logging.getLogger(__name__)

__all__ = ["MAX_CODE_BYTES", "check_code", "grade_code", "grading_slots", "GradingQueue", "queue",
           "StudentCodePanel", "initial_state", "build"]

#: the largest paste the page accepts, in bytes of UTF-8
MAX_CODE_BYTES = 64 * 1024


def grading_slots(cpus: int | None = None, memory: int | None = None, limits=None) -> int:
    """How many gradings one server runs at once: K = max(1, min(⌊cores / 2⌋, ⌊memory / (2 × limit)⌋)).

    A grading keeps one core busy, so half the cores are left to the page
    (the event loop, per-pixel pictures, exports); and each may use its
    address-space limit (``Limits.memory``, 2 GiB), so they may take half
    the memory at most. 2 cores and 24 GiB give 1; 8 cores and 32 GiB give 4.
    """
    from phonglab.teaching.sandbox import Limits

    limits = limits or Limits()
    if cpus is None:
        cpus = len(os.sched_getaffinity(0))
    if memory is None:
        memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    return max(1, min(cpus // 2, memory // (2 * limits.memory)))


def initial_state(enabled: bool) -> dict:
    """The panel's state keys for a new tab."""
    return {"student_code_enabled": bool(enabled), "student_code": "", "student_busy": False,
            "student_status": "", "student_result": None}


def check_code(value) -> str:
    """The pasted code, or ValueError naming what is wrong and the limit."""
    if not isinstance(value, str):
        raise ValueError(f"student_code: must be the text of a Python file, got {type(value).__name__}")
    size = len(value.encode("utf-8", "surrogatepass"))
    if size > MAX_CODE_BYTES:
        raise ValueError(f"student_code: must be at most {MAX_CODE_BYTES // 1024} kB, got {size / 1024:.0f} kB")
    if not value.strip():
        raise ValueError("student_code: is empty; paste a file that defines shade(point, normal, eye, material, lights)")
    return value


def grade_code(code: str, limits=None, cancel=None) -> dict | None:
    """Grade ``code`` (already checked) in the sandbox; the result as the page shows it.

    Blocking: seconds of work in a sandbox. Call it in a thread. Returns
    None when ``cancel`` (a :class:`~phonglab.teaching.sandbox.Cancel`) was
    flipped meanwhile.
    """
    from phonglab.accuracy.grade_picture import picture_png
    from phonglab.teaching import grading

    limits = limits or grading.Limits()
    source = grading.StudentFile("shade.py", code.encode("utf-8", "surrogatepass"))
    try:
        with grading.cancelled_by(cancel):
            try:
                report = grading.grade_file(source, limits)
            except grading.LoadError as exc:
                return {"error": "The code cannot be loaded: " + " ".join(str(exc).split())}
            data, note = picture_png(source, limits)
    except grading.Cancelled:
        return None
    except grading.SandboxUnavailable as exc:
        return {"error": f"Grading is not available on this server: {exc}"}
    return {
        "score": report.score,
        "max_score": report.max_score,
        "passed": report.passed,
        "report": grading.format_report(report),
        "picture": "data:image/png;base64," + base64.b64encode(data).decode("ascii") if data else "",
        "picture_note": note,
        "diagnosis": report.diagnosis,
        "isolation": list(report.isolation),
    }


class _Job:
    """One tab's grading: waiting, running, then done."""

    def __init__(self, code, limits, on_place, on_done):
        from phonglab.teaching.sandbox import Cancel

        self.code, self.limits = code, limits
        self.cancel = Cancel()
        self.on_place, self.on_done = on_place, on_done
        self.future = None

    def run(self):
        return grade_code(self.code, self.limits, self.cancel)


class GradingQueue:
    """The server's gradings: at most ``slots`` at once in threads of their own, the rest waiting in order.

    Parameters
    ----------
    slots : int
        Gradings run at once (:func:`grading_slots` by default).
    """

    def __init__(self, slots: int | None = None):
        self.slots = slots or grading_slots()
        self._executor = ThreadPoolExecutor(max_workers=self.slots, thread_name_prefix="phonglab-grading")
        self._waiting: list[_Job] = []
        self._running: set[_Job] = set()

    @property
    def running(self) -> int:
        return len(self._running)

    @property
    def waiting(self) -> int:
        return len(self._waiting)

    def submit(self, job: _Job) -> None:
        """Queue ``job`` (in the event loop's thread); it starts when a slot is free."""
        self._waiting.append(job)
        self._pump()

    def cancel(self, job: _Job) -> None:
        """Drop a waiting job, or kill a running one's sandbox (its slot is free when its thread ends)."""
        job.cancel.cancel()
        if job in self._waiting:
            self._waiting.remove(job)
            self._pump()

    def _pump(self) -> None:
        loop = asyncio.get_running_loop()
        while self._waiting and len(self._running) < self.slots:
            job = self._waiting.pop(0)
            self._running.add(job)
            job.on_place(0)
            job.future = loop.run_in_executor(self._executor, job.run)
            job.future.add_done_callback(functools.partial(self._done, job))
        for place, job in enumerate(self._waiting, 1):
            job.on_place(place)

    def _done(self, job: _Job, future) -> None:
        self._running.discard(job)
        try:
            result = future.result()
        except Exception as exc:  # noqa: BLE001 - the page says so; the server keeps serving
            log.exception("grading a student's code failed")
            result = {"error": f"Grading failed: {type(exc).__name__}: {exc}"}
        if not job.cancel.is_set:
            job.on_done(result)
        self._pump()


_QUEUE: GradingQueue | None = None


def queue() -> GradingQueue:
    """The server's one grading queue (made at the first grading)."""
    global _QUEUE
    if _QUEUE is None:
        _QUEUE = GradingQueue()
    return _QUEUE


class StudentCodePanel:
    """The panel for one tab.

    Parameters
    ----------
    state : trame state
    enabled : bool
        Whether the server was started with ``--allow-student-code``. When
        False, :meth:`submit` refuses and the page has no panel.
    limits : Limits, optional
    grading_queue : GradingQueue, optional
        The server's queue (:func:`queue` by default).
    """

    def __init__(self, state, enabled: bool = False, limits=None, grading_queue: GradingQueue | None = None):
        self.state = state
        self.enabled = bool(enabled)
        self.limits = limits
        self._queue = grading_queue
        self._job: _Job | None = None
        state.update(initial_state(self.enabled))

    @property
    def busy(self) -> bool:
        """True while this tab's grading waits or runs."""
        return self._job is not None

    def submit(self, code=None, *_, **__) -> None:
        """Check the pasted code and queue its grading; a grading of this tab still waiting or running is cancelled."""
        if not self.enabled:
            return  # the page has no panel; a forged call changes nothing
        try:
            code = check_code(code)
        except ValueError as exc:
            self.state.student_result = {"error": str(exc)}
            return
        self._drop()
        job = _Job(code, self.limits, self._placed, None)
        job.on_done = functools.partial(self._finished, job)
        self._job = job
        self.state.student_busy = True
        self.state.student_result = None
        (self._queue or queue()).submit(job)

    def close(self) -> None:
        """The tab is closing: its grading, waiting or running, is cancelled (the sandbox killed)."""
        self._drop()

    def _drop(self) -> None:
        job, self._job = self._job, None
        if job is not None:
            (self._queue or queue()).cancel(job)

    def _placed(self, place: int) -> None:
        """The job's place: 0 running, n > 0 waiting behind n − 1 others."""
        if place == 0:
            text = "Grading your code…"
        else:
            text = f"Waiting for a free grader: number {place} in the queue"
        with self.state:  # sent to the browser when the block ends
            self.state.student_status = text

    def _finished(self, job, result) -> None:
        if job is not self._job:
            return
        self._job = None
        with self.state:
            self.state.student_busy = False
            self.state.student_status = ""
            self.state.student_result = result


def build(submit) -> None:
    """The panel's widgets (shown only when ``student_code_enabled``)."""
    from trame.widgets import html
    from trame.widgets import vuetify3 as v3

    with html.Div(v_if="student_code_enabled", classes="phonglab-student-code"):
        html.H3("Your code")
        html.P("Paste a Python file that defines shade(point, normal, eye, material, lights) for one point "
               "(phonglab grade --template writes a starter). It is graded on this server, in a sandbox.",
               classes="phonglab-note")
        v3.VTextarea(v_model=("student_code",), rows=8, auto_grow=False, variant="outlined", density="compact",
                     spellcheck=False, counter=MAX_CODE_BYTES, hide_details="auto",
                     classes="phonglab-student-code-text phonglab-mono",
                     placeholder="def shade(point, normal, eye, material, lights): ...")
        v3.VBtn("Grade my code", size="small", color="primary", variant="flat",
                click=(submit, "[student_code]"), classes="phonglab-student-code-btn mt-1")
        html.P("{{ student_status }}", v_if="student_status", classes="phonglab-student-status phonglab-note")
        with html.Div(v_if="student_result", classes="phonglab-student-result"):
            html.P("{{ student_result.error }}", v_if="student_result.error", classes="phonglab-student-error")
            with html.Div(v_else=True):
                html.Div("Score: {{ student_result.score }}/{{ student_result.max_score }}",
                         classes="phonglab-student-score font-weight-medium")
                # shrunk to the column, where its captions and scale are a few pixels tall: a click shows it
                # at its own size (the column scrolls sideways), another click shrinks it again
                with html.Div(v_if="student_result.picture", classes="phonglab-student-picture-box"):
                    html.Img(src=("student_result.picture",), alt="your shading, the core's and their difference",
                             title="Click to see the picture at full size; click again to fit it",
                             classes="phonglab-student-picture",
                             click="$event.target.classList.toggle('phonglab-student-picture-full')")
                    html.Div("Click the picture to see it at full size.", classes="phonglab-note")
                html.Pre("{{ student_result.report }}", classes="phonglab-student-report",
                         style="white-space: pre-wrap; font-size: 11px; max-height: 24em; overflow: auto")
