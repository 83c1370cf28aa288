"""The "Your code" panel: a student pastes their ``shade`` and gets it graded on the server.

**Off unless the server is started with ``phonglab serve --allow-student-code``.**
Running a student's code on the server is remote code execution by design:
it is meant for a trusted classroom. The code is graded exactly as
``phonglab grade`` grades a file (:func:`phonglab.teaching.grading.grade_file`):
it is written into a new temporary folder and run in a separate worker
process (:mod:`phonglab.teaching.sandbox`): ``python -I`` with a clean
environment, CPU, memory, open-file and file-size limits (it cannot write a
byte), a time limit per case and per run, no network when a new network
namespace can be made, and an audit hook that refuses opening files outside
its folder, starting programs, sockets and ``ctypes``. Audit hooks are not a
security boundary: on a shared machine run the server in a container too.

The panel shows the grade report, the student's shading of a sphere beside
the core's and their difference (:func:`phonglab.accuracy.grade_picture.picture_png`),
and what isolated the run. Grading spawns processes and takes seconds: it runs in
a thread (:func:`asyncio.to_thread`), never in the event loop every tab shares,
one run per tab at a time. The pasted text is checked like any value from the
browser: a string of at most :data:`MAX_CODE_BYTES` bytes (UTF-8).

State keys: ``student_code_enabled``, ``student_code`` (the textarea),
``student_busy`` and ``student_result`` (``{"score", "max_score", "passed",
"report", "picture", "diagnosis", "isolation"}`` or ``{"error"}``).
"""

from __future__ import annotations

import asyncio
import base64
import logging
import tempfile
from pathlib import Path

log = logging.getLogger(__name__)

__all__ = ["MAX_CODE_BYTES", "check_code", "grade_code", "StudentCodePanel", "initial_state", "build"]

#: the largest paste the page accepts, in bytes of UTF-8
MAX_CODE_BYTES = 64 * 1024


def initial_state(enabled: bool) -> dict:
    """The panel's state keys for a new tab."""
    return {"student_code_enabled": bool(enabled), "student_code": "", "student_busy": False, "student_result": None}


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


def grade_code(code: str, limits=None) -> dict:
    """Grade ``code`` (already checked) in the sandbox; the result as the page shows it.

    Blocking: seconds of work in worker processes. Call it in a thread.
    """
    from phonglab.accuracy.grade_picture import picture_png
    from phonglab.teaching import grading

    limits = limits or grading.Limits()
    with tempfile.TemporaryDirectory(prefix="phonglab-student-") as folder:
        path = Path(folder) / "shade.py"
        path.write_text(code, encoding="utf-8")
        try:
            report = grading.grade_file(path, limits)
        except grading.LoadError as exc:
            return {"error": "The code cannot be loaded: " + " ".join(str(exc).split())}
        data, note = picture_png(path, limits)
    return {
        "score": report.score,
        "max_score": report.max_score,
        "passed": report.passed,
        "report": grading.format_report(report).replace(str(path), "your code"),
        "picture": "data:image/png;base64," + base64.b64encode(data).decode("ascii") if data else "",
        "picture_note": note,
        "diagnosis": report.diagnosis,
        "isolation": list(report.isolation),
    }


class StudentCodePanel:
    """The panel for one tab.

    Parameters
    ----------
    state : trame state
    enabled : bool
        Whether the server was started with ``--allow-student-code``. When
        False, :meth:`submit` refuses and the page has no panel.
    """

    def __init__(self, state, enabled: bool = False, limits=None):
        self.state = state
        self.enabled = bool(enabled)
        self.limits = limits
        self._task = None
        state.update(initial_state(self.enabled))

    def submit(self, code=None, *_, **__) -> None:
        """Check the pasted code and grade it in a thread; the result arrives in ``student_result``."""
        if not self.enabled:
            return  # the page has no panel; a forged call changes nothing
        if self._task is not None and not self._task.done():
            self.state.student_result = {"error": "Still grading the last paste: wait for its result."}
            return
        try:
            code = check_code(code)
        except ValueError as exc:
            self.state.student_result = {"error": str(exc)}
            return
        self.state.student_busy = True
        self.state.student_result = None
        self._task = asyncio.get_running_loop().create_task(self._grade(code))

    async def _grade(self, code: str) -> None:
        try:
            result = await asyncio.to_thread(grade_code, code, self.limits)
        except Exception as exc:  # noqa: BLE001 - the page says so; the server keeps serving
            log.exception("grading a student's code failed")
            result = {"error": f"Grading failed: {type(exc).__name__}: {exc}"}
        with self.state:  # the changes go to the browser when the block ends
            self.state.student_busy = False
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
        v3.VBtn("Grade my code", size="small", color="primary", variant="flat", loading=("student_busy",),
                disabled=("student_busy",), click=(submit, "[student_code]"), classes="phonglab-student-code-btn mt-1")
        with html.Div(v_if="student_result", classes="phonglab-student-result"):
            html.P("{{ student_result.error }}", v_if="student_result.error", classes="phonglab-student-error")
            with html.Div(v_else=True):
                html.Div("Score: {{ student_result.score }}/{{ student_result.max_score }}",
                         classes="phonglab-student-score font-weight-medium")
                html.Img(v_if="student_result.picture", src=("student_result.picture",),
                         alt="your shading, the core's and their difference", classes="phonglab-student-picture",
                         style="max-width: 100%")
                html.Pre("{{ student_result.report }}", classes="phonglab-student-report",
                         style="white-space: pre-wrap; font-size: 11px; max-height: 24em; overflow: auto")
