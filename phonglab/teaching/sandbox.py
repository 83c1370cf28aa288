"""Run a student's ``shade`` in a separate, isolated, time-limited process.

The grader never imports the student's file. :class:`Sandbox` copies it into
a new, empty temporary folder and starts a fresh Python worker
(:mod:`phonglab.teaching.sandbox_worker`) that imports it there; the two talk
over pipes, one JSON line per request and per answer. Every case has a time
limit, the whole run has another, and a case that hangs, crashes the worker
or breaks a limit is a failed case with a one-line reason: the worker is
killed and a fresh one started for the next case.

What isolates the worker
------------------------
- **A separate process**: ``sys.executable -I -B`` (isolated mode: no
  ``PYTHON*`` variables, no user site-packages, the script's folder not on
  ``sys.path``; no ``.pyc`` written), in its own session so the grader can
  kill it and anything it started, with a clean environment (``PATH``,
  ``HOME`` and ``TMPDIR`` = the sandbox, one BLAS thread) and the sandbox as
  its working folder.
- **Resource limits** (``setrlimit`` before ``exec``): address space
  (``RLIMIT_AS``, default 2 GiB), CPU seconds for the whole run
  (``RLIMIT_CPU``), 64 open files (``RLIMIT_NOFILE``), no file may grow
  (``RLIMIT_FSIZE`` 0: the worker cannot write a byte to any file, so it
  cannot make a library to load either) and no core dumps.
- **No network** when the grader runs as root and ``unshare`` works: the
  worker starts in a new, empty network namespace (``unshare --net``), which
  has no interface but loopback. Otherwise only the audit hook refuses
  sockets. :attr:`Sandbox.isolation` lists what was applied.
- **An audit hook** (:pep:`578`), installed after NumPy and phonglab are
  imported and before the student's file is: it refuses opening files
  outside the sandbox (reading is allowed also under Python's standard
  library, site-packages and the phonglab package, which imports need),
  writing outside the sandbox, listing folders outside those,
  ``subprocess``/``os.system``/``exec``/``fork``/``spawn``, sockets,
  ``ctypes`` (loading a library or calling into one), ``setrlimit``,
  deleting/renaming/``chmod``, and importing the modules that only serve to
  get round it (``_posixsubprocess``, ``socket``, ``mmap``, ...).
- ``phonglab.shade`` is replaced in the worker by a function that raises:
  the exercise is to write it.

What it does not stop
---------------------
Audit hooks are not a security boundary (:pep:`578` says so): C code that
raises no audit event is not seen, and a determined attacker who finds such
a path, or a bug in CPython, gets the worker's rights. As root, those are
root's rights on every file the audit hook would have refused. The worker
can still read the files Python's own folders hold, spend its CPU and memory
limits, and see its own process (so it can find the grader's pipes and
forge answers: the grade is practice feedback, not an exam proctor). Run
untrusted submissions in a container or a throw-away VM as well; the web
page's grading feature is off by default for this reason.
"""

from __future__ import annotations

import functools
import json
import math
import os
import resource
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["Limits", "LoadError", "Outcome", "Sandbox", "network_isolation"]

WORKER = Path(__file__).with_name("sandbox_worker.py")

#: longest answer line read from the worker (a batch of points is well below)
MAX_REPLY = 8 << 20


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
        Seconds for the worker to import NumPy and phonglab (not the
        student's time).
    load_limit : float
        Seconds for importing the student's file.
    """

    time_limit: float = 2.0
    total_limit: float = 120.0
    memory: int = 2 << 30
    startup: float = 60.0
    load_limit: float = 10.0


class LoadError(Exception):
    """The student's file cannot be loaded; ``str()`` is the one-line reason."""


@dataclass(frozen=True)
class Outcome:
    """What one call of the student's ``shade`` gave: a value or an error, never both."""

    value: np.ndarray | None = None  # (3,) float64
    error: str | None = None


@functools.lru_cache(maxsize=1)
def network_isolation() -> tuple[str, ...]:
    """The command prefix that starts a process without network, or ``()``.

    ``unshare --net`` needs root (CAP_SYS_ADMIN); it is tried once with
    ``true`` and used only when that works.
    """
    unshare = shutil.which("unshare")
    if unshare is None or os.geteuid() != 0:
        return ()
    try:
        ok = subprocess.run([unshare, "--net", "true"], capture_output=True, timeout=10).returncode == 0
    except (OSError, subprocess.SubprocessError):
        ok = False
    return (unshare, "--net") if ok else ()


def _set_limits(limits: Limits):
    """``preexec_fn``: the resource limits, applied in the child before exec."""
    cpu = int(math.ceil(limits.total_limit + limits.startup + limits.load_limit)) + 5

    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (limits.memory, limits.memory))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
        resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64))
        resource.setrlimit(resource.RLIMIT_FSIZE, (0, 0))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    return apply


class _Timeout(Exception):
    pass


class _Died(Exception):
    pass


class Sandbox:
    """A student's file loaded in an isolated worker process.

    Use as a context manager; entering it starts the worker and imports the
    student's file, raising :class:`LoadError` with a one-line reason when
    that fails (syntax error, import error, no ``shade``, time limit).

    Parameters
    ----------
    source : path
        The student's Python file; it is copied, never imported here.
    limits : Limits

    Examples
    --------
    >>> with Sandbox("shade.py") as box:                      # doctest: +SKIP
    ...     outcomes = box.evaluate(points, normals, eye=eye, scene=encoded)
    """

    def __init__(self, source, limits: Limits = Limits()):
        self.source = Path(source)
        self.limits = limits
        self.isolation: tuple[str, ...] = ()
        self._dir: str | None = None
        self._proc: subprocess.Popen | None = None
        self._buffer = b""
        self._spent = 0.0  # seconds of the total limit used by cases

    # -- life cycle -----------------------------------------------------------

    def __enter__(self) -> Sandbox:
        try:
            text = self.source.read_bytes()
        except OSError as exc:
            raise LoadError(f"cannot read {self.source}: {exc.strerror or exc}") from None
        self._dir = tempfile.mkdtemp(prefix="phonglab-grade-")
        name = self.source.name if self.source.name.endswith(".py") else "student.py"
        self._copy = os.path.join(self._dir, name)
        with open(self._copy, "wb") as f:
            f.write(text)
        try:
            self._start()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def close(self) -> None:
        """Kill the worker and remove the sandbox folder."""
        self._kill()
        if self._dir is not None:
            shutil.rmtree(self._dir, ignore_errors=True)
            self._dir = None

    def _start(self) -> None:
        """Start a worker, wait until it is ready and has imported the student's file."""
        net = network_isolation()
        command = [*net, sys.executable, "-I", "-B", str(WORKER),
                   str(Path(__file__).resolve().parents[2]), self._copy, self._dir]
        env = {"PATH": os.defpath, "HOME": self._dir, "TMPDIR": self._dir, "LC_ALL": "C.UTF-8",
               "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
        self._proc = subprocess.Popen(
            command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            cwd=self._dir, env=env, start_new_session=True, preexec_fn=_set_limits(self.limits),
        )
        self._buffer = b""
        self.isolation = (
            "separate process (python -I), clean environment, empty temporary folder",
            f"limits: {self.limits.memory >> 20} MiB address space, CPU time, 64 files, no file writes",
            "network: none (new network namespace)" if net else "network: refused by the audit hook only",
            "audit hook: no files outside the sandbox, no processes, sockets or ctypes",
        )
        try:
            self._read(self.limits.startup)
        except _Timeout:
            raise LoadError(f"the worker did not start within {self.limits.startup:g} s") from None
        except _Died as exc:
            raise LoadError(f"the worker could not start: {exc}") from None
        try:
            answer = self._read(self.limits.load_limit)
        except _Timeout:
            raise LoadError(f"importing {self.source.name} took longer than {self.limits.load_limit:g} s") from None
        except _Died as exc:
            raise LoadError(f"importing {self.source.name} stopped the worker: {exc}") from None
        if "load_error" in answer:
            raise LoadError(answer["load_error"])

    def _kill(self) -> None:
        proc, self._proc = self._proc, None
        if proc is None:
            return
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # the worker and anything it started
        except (ProcessLookupError, PermissionError):
            pass
        for pipe in (proc.stdin, proc.stdout):
            try:
                pipe.close()
            except OSError:
                pass
        proc.wait()

    # -- talking to the worker ------------------------------------------------

    def _read(self, timeout: float) -> dict:
        """The next answer line, waiting at most ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        fd = self._proc.stdout.fileno()
        while b"\n" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise _Timeout
            ready, _, _ = select.select([fd], [], [], left)
            if not ready:
                continue
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                raise _Died(self._death())
            self._buffer += chunk
            if len(self._buffer) > MAX_REPLY:
                raise _Died("the worker sent an answer too long to be one")
        line, self._buffer = self._buffer.split(b"\n", 1)
        try:
            return json.loads(line)
        except ValueError:
            raise _Died("the worker sent an answer that is not JSON") from None

    def _death(self) -> str:
        """Why the worker ended, in words."""
        try:
            status = self._proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            return "the worker closed its output"
        if status < 0:
            name = signal.Signals(-status).name
            why = {"SIGXCPU": " (CPU time limit)", "SIGKILL": " (killed: memory or time limit)",
                   "SIGSEGV": " (crashed)"}.get(name, "")
            return f"the worker was stopped by {name}{why}"
        return f"the worker exited with status {status}"

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
            except (BrokenPipeError, OSError):
                raise _Died(self._death()) from None
            answer = self._read(min(limit, left))
        except _Timeout:
            self._kill()
            total = left < limit
            why = (f"the total time limit of {self.limits.total_limit:g} s ran out" if total
                   else f"time limit: no answer within {limit:g} s (an endless loop?)")
            return [Outcome(error=why)] * k
        except _Died as exc:
            self._kill()
            return [Outcome(error=str(exc))] * k
        finally:
            self._spent += time.monotonic() - started
        outcomes = []
        for item in answer.get("results", []):
            if isinstance(item, str):
                outcomes.append(Outcome(error=item))
            else:
                outcomes.append(Outcome(value=np.asarray(item, dtype=np.float64)))
        if len(outcomes) != k:
            self._kill()
            return [Outcome(error="the worker answered a different number of points")] * k
        return outcomes
