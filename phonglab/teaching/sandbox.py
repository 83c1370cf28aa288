"""Run a student's ``shade`` in a sandbox made by the operating system, with time limits.

The grader never imports the student's file. :class:`Sandbox` starts a
fresh Python worker (:mod:`phonglab.teaching.sandbox_worker`) inside a
bubblewrap sandbox (:mod:`phonglab.teaching.isolation`: its own user, PID,
network and mount namespaces, a read-only view of only the interpreter,
NumPy, the worker and the helper module, an empty private ``/tmp``, and a
seccomp filter) and hands it the student's file from memory; the two talk
over pipes, one JSON line per request and per answer. Every case has a time
limit, the whole run has another, and a case that hangs, crashes the worker
or breaks a limit is a failed case with a one-line reason: the sandbox is
killed and a fresh one started for the next case.

The phonglab package is not in the sandbox: the student's code gets NumPy,
``math`` and :mod:`phonglab.teaching.shade_helpers`; the expected colours
are computed here, in the grader, and never sent to the worker. Nothing of a
grading is written on the host: the student's file lives in the sandbox's
own tmpfs, which disappears with it, also when the grader is killed with
``kill -9`` (``--die-with-parent``).

The worker can still forge its own answers (it writes them): the grade is
practice feedback for the student, whose own code it is.

A grading can be cancelled from another thread (:class:`Cancel`): the
sandbox it runs is killed at once and the run raises :class:`Cancelled`.
"""

from __future__ import annotations

import contextlib
import contextvars
import json
import math
import os
import select
import signal
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from phonglab.teaching import isolation
from phonglab.teaching.isolation import SandboxUnavailable

__all__ = ["Limits", "LoadError", "Outcome", "Sandbox", "StudentFile", "Cancel", "Cancelled",
           "SandboxUnavailable", "cancelled_by", "MAX_FILE_BYTES"]

#: longest answer line read from the worker (a batch of points is well below)
MAX_REPLY = 8 << 20
#: the largest student file graded, in bytes
MAX_FILE_BYTES = 1 << 20
#: bytes of bwrap's own error output kept to explain a sandbox that did not start
MAX_ERROR_BYTES = 4096


@dataclass(frozen=True)
class Limits:
    """The limits one grading run gives the student's code.

    Attributes
    ----------
    time_limit : float
        Seconds per case (one call of ``shade``).
    total_limit : float
        Seconds for all cases together; cases after it are failed, not run.
    memory : int
        Bytes of address space (``RLIMIT_AS``).
    startup : float
        Seconds for the sandbox to start and import NumPy (not the
        student's time).
    load_limit : float
        Seconds for importing the student's file.
    """

    time_limit: float = 2.0
    total_limit: float = 120.0
    memory: int = 2 << 30
    startup: float = 60.0
    load_limit: float = 10.0

    @property
    def cpu_seconds(self) -> int:
        """``RLIMIT_CPU`` of one worker: every second it may be given, and a margin."""
        return int(math.ceil(self.total_limit + self.startup + self.load_limit)) + 5


class LoadError(Exception):
    """The student's file cannot be loaded; ``str()`` is the one-line reason."""


class Cancelled(Exception):
    """The grading was cancelled (the tab closed, or the student submitted again)."""


@dataclass(frozen=True)
class StudentFile:
    """A student's file held in memory: its name (shown in messages) and its bytes."""

    name: str
    data: bytes


@dataclass(frozen=True)
class Outcome:
    """What one call of the student's ``shade`` gave: a value or an error, never both."""

    value: np.ndarray | None = None  # (3,) float64
    error: str | None = None


class Cancel:
    """A grading's cancel switch, safe to flip from any thread.

    The sandboxes started under it (:func:`cancelled_by`) register
    themselves; :meth:`cancel` kills the running one and makes every later
    step raise :class:`Cancelled`.
    """

    def __init__(self):
        self._lock = threading.Lock()
        self._set = False
        self._boxes: set[Sandbox] = set()

    @property
    def is_set(self) -> bool:
        return self._set

    def cancel(self) -> None:
        with self._lock:
            self._set = True
            boxes = list(self._boxes)
        for box in boxes:
            box.kill()

    def check(self) -> None:
        """Raise :class:`Cancelled` once cancelled."""
        if self._set:
            raise Cancelled

    def _add(self, box) -> None:
        with self._lock:
            if self._set:
                raise Cancelled
            self._boxes.add(box)

    def _remove(self, box) -> None:
        with self._lock:
            self._boxes.discard(box)


_CANCEL: contextvars.ContextVar[Cancel | None] = contextvars.ContextVar("phonglab_grading_cancel", default=None)


@contextlib.contextmanager
def cancelled_by(cancel: Cancel | None):
    """Every :class:`Sandbox` made in this block (this thread or task) obeys ``cancel``."""
    token = _CANCEL.set(cancel)
    try:
        yield cancel
    finally:
        _CANCEL.reset(token)


class _Timeout(Exception):
    pass


class _Died(Exception):
    pass


def _read_source(source) -> StudentFile:
    if isinstance(source, StudentFile):
        data, name = source.data, source.name
    else:
        path = Path(source)
        try:
            size = path.stat().st_size
            if size > MAX_FILE_BYTES:
                raise LoadError(f"{path}: the file is {size / 1024:.0f} kB, at most {MAX_FILE_BYTES >> 10} kB "
                                "are graded")
            with open(path, "rb") as f:
                data = f.read(MAX_FILE_BYTES + 1)
        except OSError as exc:
            raise LoadError(f"cannot read {path}: {exc.strerror or exc}") from None
        name = path.name
    if len(data) > MAX_FILE_BYTES:
        raise LoadError(f"the file is larger than {MAX_FILE_BYTES >> 10} kB")
    safe = "".join(c if c.isalnum() or c in "._-" else "_" for c in name)[:64]
    if not safe.endswith(".py") or safe.startswith("."):
        safe = "student.py"
    return StudentFile(safe, data)


class Sandbox:
    """A student's file loaded in a worker inside the operating system's sandbox.

    Use as a context manager; entering it starts the sandbox and imports the
    student's file, raising :class:`LoadError` with a one-line reason when
    that fails (syntax error, import error, no ``shade``, time limit), or
    :class:`SandboxUnavailable` when this machine cannot make the sandbox
    (the reason says what to install).

    Parameters
    ----------
    source : path or StudentFile
        The student's Python file; read here, handed to the sandbox from
        memory, never imported by the grader.
    limits : Limits

    Examples
    --------
    >>> with Sandbox("shade.py") as box:                      # doctest: +SKIP
    ...     outcomes = box.evaluate(points, normals, eye=eye, scene=encoded)
    """

    def __init__(self, source, limits: Limits = Limits()):
        self.source = source
        self.limits = limits
        self.isolation: tuple[str, ...] = ()
        self._file: StudentFile | None = None
        self._proc: subprocess.Popen | None = None
        self._lock = threading.Lock()
        self._cancel = _CANCEL.get()
        self._buffer = b""
        self._spent = 0.0  # seconds of the total limit used by cases

    # -- life cycle -----------------------------------------------------------

    def __enter__(self) -> Sandbox:
        self._file = _read_source(self.source)
        isolation.check()
        if self._cancel is not None:
            self._cancel._add(self)
        try:
            self._start()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def close(self) -> None:
        """Kill the sandbox (nothing of it stays on the host)."""
        self.kill()
        if self._cancel is not None:
            self._cancel._remove(self)

    def kill(self) -> None:
        """Kill the sandbox now; safe from any thread. The next request starts a fresh one."""
        with self._lock:
            proc, self._proc = self._proc, None
        if proc is None:
            return
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # bwrap; --die-with-parent and the PID namespace take the rest
        except (ProcessLookupError, PermissionError):
            pass
        for pipe in (proc.stdin, proc.stdout, proc.stderr):
            try:
                pipe.close()
            except OSError:
                pass
        proc.wait()

    def _start(self) -> None:
        """Start a sandboxed worker, wait until it is ready and has imported the student's file."""
        if self._cancel is not None:
            self._cancel.check()
        name = self._file.name
        opened = [isolation.memory_file("phonglab-seccomp", isolation.seccomp_program()),
                  isolation.memory_file("phonglab-student", self._file.data)]
        options, argv = isolation.command(name, [str(self.limits.memory), str(self.limits.cpu_seconds)],
                                          {"seccomp": opened[0], "code": opened[1]})
        try:
            proc = isolation.start(options, argv, opened, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, start_new_session=True)
        finally:
            for fd in opened:
                os.close(fd)
        with self._lock:
            self._proc = proc
        if self._cancel is not None and self._cancel.is_set:  # cancelled while it started
            self.kill()
            raise Cancelled
        self._buffer = b""
        self.isolation = (
            "bubblewrap sandbox: own user (uid 65534, no capabilities), PID, network, IPC and mount namespaces",
            "read-only view of only Python, NumPy and the helper module; empty private /tmp; no phonglab",
            "seccomp: no processes, threads, signals, ptrace, sockets, mounts or new files",
            f"limits: {self.limits.memory >> 20} MiB address space, CPU time, 64 files, no file writes, "
            f"{self.limits.time_limit:g} s per case, {self.limits.total_limit:g} s in all",
        )
        try:
            self._read(self.limits.startup)
        except _Timeout:
            self.kill()
            raise LoadError(f"the sandbox did not start within {self.limits.startup:g} s") from None
        except _Died as exc:
            raise LoadError(f"the sandbox could not start: {exc}") from None
        try:
            answer = self._read(self.limits.load_limit)
        except _Timeout:
            self.kill()
            raise LoadError(f"importing {name} took longer than {self.limits.load_limit:g} s") from None
        except _Died as exc:
            raise LoadError(f"importing {name} stopped the worker: {exc}") from None
        if "load_error" in answer:
            raise LoadError(str(answer["load_error"])[:1000])

    # -- talking to the worker ------------------------------------------------

    def _read(self, timeout: float) -> dict:
        """The next answer line, waiting at most ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        proc = self._proc
        if proc is None:
            raise _Died(self._why_gone())
        fd = proc.stdout.fileno()
        while b"\n" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise _Timeout
            try:
                ready, _, _ = select.select([fd], [], [], left)
                chunk = os.read(fd, 1 << 16) if ready else None
            except (OSError, ValueError):  # killed from another thread meanwhile
                raise _Died(self._why_gone()) from None
            if chunk is None:
                continue
            if not chunk:
                raise _Died(self._death(proc))
            self._buffer += chunk
            if len(self._buffer) > MAX_REPLY:
                raise _Died("the worker sent an answer too long to be one")
        line, self._buffer = self._buffer.split(b"\n", 1)
        try:
            answer = json.loads(line)
        except ValueError:
            raise _Died("the worker sent an answer that is not JSON") from None
        if not isinstance(answer, dict):
            raise _Died("the worker sent an answer that is not a JSON object")
        return answer

    def _why_gone(self) -> str:
        if self._cancel is not None and self._cancel.is_set:
            return "cancelled"
        return "the sandbox was stopped"

    def _death(self, proc) -> str:
        """Why the worker ended, in words."""
        try:
            status = proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            return "the worker closed its output"
        if self._cancel is not None and self._cancel.is_set:
            return "cancelled"
        if status < 0:
            name = signal.Signals(-status).name
            return f"the sandbox was stopped by {name}"
        # bwrap passes on the worker's status; a signal that ended the worker becomes 128 + its number
        if status > 128 and status - 128 in {s.value for s in signal.Signals}:
            name = signal.Signals(status - 128).name
            why = {"SIGXCPU": " (CPU time limit)", "SIGKILL": " (killed: memory or time limit)",
                   "SIGSEGV": " (crashed)", "SIGSYS": " (a refused system call)"}.get(name, "")
            return f"the worker was stopped by {name}{why}"
        try:
            detail = os.read(proc.stderr.fileno(), MAX_ERROR_BYTES).decode(errors="replace").strip()
        except (OSError, ValueError):
            detail = ""
        lines = [line for line in detail.splitlines() if line.strip()]
        return f"the worker exited with status {status}" + (f": {lines[-1][:200]}" if lines else "")

    def evaluate(self, points, normals, *, eye, scene: dict, time_limit: float | None = None) -> list[Outcome]:
        """Call the student's ``shade`` once per point, in the worker.

        Parameters
        ----------
        points, normals : array_like, shape (k, 3), float64
        eye : 3 floats
        scene : dict
            ``{"material": {...}, "lights": [...]}`` as made by
            :func:`phonglab.teaching.grading.encode_scene`.
        time_limit : float, optional
            Seconds for the whole request; default the per-case limit.

        Returns
        -------
        list of Outcome
            One per point. A time-out, a worker that died or a total limit
            that is spent makes every point of the request a failed outcome
            with the reason; the next request starts a fresh worker.

        Raises
        ------
        Cancelled
            When the grading was cancelled.
        """
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        normals = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
        k = len(points)
        limit = self.limits.time_limit if time_limit is None else time_limit
        left = self.limits.total_limit - self._spent
        if left <= 0:
            return [Outcome(error=f"not run: the total time limit of {self.limits.total_limit:g} s is spent")] * k
        request = {"points": points.tolist(), "normals": normals.tolist(),
                   "eye": [float(x) for x in eye], **scene}
        started = time.monotonic()  # a restart after a time-out counts towards the total too
        try:
            if self._proc is None:
                try:
                    self._start()
                except LoadError as exc:
                    return [Outcome(error=f"not run: {exc}")] * k
                left = self.limits.total_limit - self._spent - (time.monotonic() - started)
            try:
                self._proc.stdin.write((json.dumps(request) + "\n").encode())
                self._proc.stdin.flush()
            except (BrokenPipeError, OSError, ValueError, AttributeError):
                raise _Died(self._why_gone() if self._proc is None else self._death(self._proc)) from None
            answer = self._read(min(limit, left))
        except _Timeout:
            self.kill()
            total = left < limit
            why = (f"the total time limit of {self.limits.total_limit:g} s ran out" if total
                   else f"time limit: no answer within {limit:g} s (an endless loop?)")
            return [Outcome(error=why)] * k
        except _Died as exc:
            self.kill()
            if self._cancel is not None:
                self._cancel.check()
            return [Outcome(error=str(exc))] * k
        finally:
            self._spent += time.monotonic() - started
        outcomes = []
        results = answer.get("results")
        for item in results if isinstance(results, list) else []:
            if isinstance(item, str):
                outcomes.append(Outcome(error=item[:1000]))
            else:
                try:
                    value = np.asarray(item, dtype=np.float64).reshape(3)
                except (TypeError, ValueError):
                    outcomes.append(Outcome(error="the worker sent something that is not 3 numbers"))
                    continue
                outcomes.append(Outcome(value=value))
        if len(outcomes) != k:
            self.kill()
            return [Outcome(error="the worker answered a different number of points")] * k
        return outcomes
