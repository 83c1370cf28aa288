"""The worker process of :mod:`phonglab.teaching.sandbox`: runs a student's ``shade``.

Run as a script, never imported by the grader::

    python -I -B sandbox_worker.py PHONGLAB_ROOT STUDENT_FILE SANDBOX_DIR

It talks to the grader over its standard input and output, one JSON object
per line:

1. it imports NumPy and :mod:`phonglab.core` (what every case needs), then
   installs the audit hook (:func:`install_audit_hook`) and answers
   ``{"ready": true}``;
2. it imports the student's file (a copy inside the sandbox folder) and
   answers ``{"loaded": true}`` or ``{"load_error": "one line"}``;
3. for every request ``{"points", "normals", "eye", "material", "lights"}``
   it calls ``shade(point, normal, eye, material, lights)`` once per point
   and answers ``{"results": [...]}``: per point either ``[r, g, b]`` or the
   one-line error message (a string).

The student's code cannot read the grader's pipes through ``input()`` or
``print()``: the pipes are moved to new file descriptors, standard input
reads ``/dev/null`` and whatever the student prints is dropped.
"""

from __future__ import annotations

import json
import os
import sys
import traceback

#: how long a student's message may be in the report
MESSAGE_CHARS = 300

#: audit events refused outright once the student's code may run (prefix match)
REFUSED_EVENTS = (
    "subprocess.", "os.system", "os.exec", "os.spawn", "os.posix_spawn", "os.fork", "os.forkpty",
    "pty.", "os.kill", "os.killpg", "signal.pthread_kill", "socket.", "ctypes.", "resource.",
    "os.remove", "os.rename", "os.rmdir", "os.mkdir", "os.chmod", "os.chown", "os.chflags",
    "os.symlink", "os.link", "os.truncate", "os.utime", "os.setxattr", "os.removexattr",
    "os.chdir", "os.chroot", "os.putenv", "os.unsetenv", "shutil.", "webbrowser.", "urllib.",
    "http.", "ftplib.", "smtplib.", "imaplib.", "poplib.", "nntplib.", "telnetlib.",
    "sys.addaudithook", "sys.settrace", "sys.setprofile", "_winapi.", "winreg.",
)

#: modules the student may not import (those not already loaded by NumPy)
REFUSED_MODULES = frozenset({
    "_posixsubprocess", "subprocess", "socket", "_socket", "ssl", "_ssl", "multiprocessing",
    "_multiprocessing", "pty", "cffi", "_cffi_backend", "_testcapi", "_testinternalcapi",
    "_xxsubinterpreters", "_xxinterpchannels", "asyncio", "selectors", "select", "mmap",
})

#: lights the requests may name
LIGHT_KINDS = ("AmbientLight", "PointLight", "DirectionalLight", "SpotLight")


class NoShade(Exception):
    """The student's file loaded but defines no callable ``shade``."""


def _inside(path: str, roots) -> bool:
    return any(path == root or path.startswith(root + os.sep) for root in roots)


def install_audit_hook(read_roots, sandbox: str) -> None:
    """Refuse file access outside the sandbox, new processes, sockets and ctypes.

    - ``open`` (and ``os.listdir``/``os.scandir``) of a path: reading is
      allowed inside the sandbox and below ``read_roots`` (Python's standard
      library, site-packages and the phonglab package, for imports); writing
      only inside the sandbox (where RLIMIT_FSIZE 0 still stops any byte).
      Paths are resolved with ``realpath`` first, so ``..`` and symlinks do
      not lead out.
    - every event in :data:`REFUSED_EVENTS`; importing a module of
      :data:`REFUSED_MODULES`.

    An audit hook cannot be removed once added. It is not a complete sandbox:
    code that reaches C without an audit event (a compiled extension already
    loaded, a bug in CPython) is not seen by it; the resource limits and the
    network namespace set by the grader are the other walls.
    """
    sandbox = os.path.realpath(sandbox)
    readable = tuple(sorted({os.path.realpath(r) for r in read_roots} | {sandbox}))
    busy = []  # realpath() may itself raise events: no recursion

    def where(path) -> str:
        if isinstance(path, bytes):
            path = os.fsdecode(path)
        return os.path.realpath(os.path.join(sandbox, os.fspath(path)))

    def hook(event, args):
        if busy:
            return
        if event == "open":
            path, _, flags = args
            if path is None or isinstance(path, int):
                return  # an already open file descriptor
            busy.append(1)
            try:
                full = where(path)
            finally:
                busy.pop()
            writing = isinstance(flags, int) and flags & (os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_APPEND | os.O_TRUNC)
            if writing and not _inside(full, (sandbox,)):
                raise PermissionError(f"sandbox: writing {full} is not allowed (only the sandbox folder)")
            if not _inside(full, readable):
                raise PermissionError(f"sandbox: reading {full} is not allowed (outside the sandbox)")
        elif event in ("os.listdir", "os.scandir"):
            path = args[0] if args and args[0] is not None else "."
            if isinstance(path, int):
                return
            busy.append(1)
            try:
                full = where(path)
            finally:
                busy.pop()
            if not _inside(full, readable):
                raise PermissionError(f"sandbox: listing {full} is not allowed (outside the sandbox)")
        elif event == "import":
            if str(args[0]).split(".")[0] in REFUSED_MODULES:
                raise PermissionError(f"sandbox: importing {args[0]} is not allowed in a graded exercise")
        elif event.startswith(REFUSED_EVENTS):
            raise PermissionError(f"sandbox: {event} is not allowed in a graded exercise")

    sys.addaudithook(hook)


def one_line(exc: BaseException, student_file: str, shown_name: str) -> str:
    """``Type: message (line N)``, the line being the last one in the student's file."""
    line = None
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename == student_file:
            line = frame.lineno
    if isinstance(exc, SyntaxError) and exc.filename == student_file:
        line = exc.lineno
        text = f"{type(exc).__name__}: {exc.msg}"
    else:
        text = f"{type(exc).__name__}: {exc}".rstrip(": ")
    text = " ".join(text.split())
    if len(text) > MESSAGE_CHARS:
        text = text[: MESSAGE_CHARS - 1] + "…"
    return f"{text} ({shown_name} line {line})" if line else text


class _Sink:
    """Standard output for the student: accepts and drops everything."""

    encoding = "utf-8"

    def write(self, s):
        return len(s)

    def flush(self):
        pass

    def isatty(self):
        return False


def _as_rgb(value, np):
    """The student's return value as 3 Python floats, or ValueError/TypeError saying why not."""
    try:
        a = np.asarray(value)
    except Exception as exc:  # e.g. ragged lists
        raise TypeError(f"shade returned {type(value).__name__}, expected 3 floats (R, G, B): {exc}") from None
    if a.dtype.kind not in "iuf":
        raise TypeError(f"shade returned {type(value).__name__} of {a.dtype}, expected 3 floats (R, G, B)")
    if a.shape != (3,):
        raise ValueError(f"shade returned shape {a.shape}, expected 3 values (R, G, B)")
    return [float(x) for x in a.astype(np.float64)]


def main(argv) -> int:
    phonglab_root, student_file, sandbox = argv[1:4]
    # the grader's pipes on new descriptors; the student's stdin/stdout go nowhere
    requests = os.fdopen(os.dup(0), "rb")
    replies = os.fdopen(os.dup(1), "w", encoding="utf-8")
    null = os.open(os.devnull, os.O_RDWR)
    os.dup2(null, 0)
    os.dup2(null, 1)
    sys.stdin = open(os.devnull)
    sys.stdout = _Sink()
    import importlib.util
    import signal
    import sysconfig

    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past RLIMIT_FSIZE fails instead of killing us

    def reply(obj):
        replies.write(json.dumps(obj) + "\n")
        replies.flush()

    # what every case needs, imported before the hook
    sys.path.insert(0, phonglab_root)
    import numpy as np

    import phonglab.core as core

    def not_here(*args, **kwargs):
        raise RuntimeError("phonglab's own shading is not available in a graded exercise: write the model yourself")

    for module in (sys.modules["phonglab"], core, sys.modules["phonglab.core.shading"]):
        module.shade = not_here
    paths = sysconfig.get_paths()
    roots = {paths[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")}
    roots |= {os.path.dirname(os.path.dirname(np.__file__)), os.path.dirname(core.__path__[0])}
    os.chdir(sandbox)
    install_audit_hook(roots, sandbox)
    reply({"ready": True})

    shown_name = os.path.basename(student_file)
    try:
        spec = importlib.util.spec_from_file_location("student", student_file)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        shade = getattr(module, "shade", None)
        if not callable(shade):
            raise NoShade(f"{shown_name} defines no function shade(point, normal, eye, material, lights)")
    except BaseException as exc:  # noqa: BLE001 - anything the student's file does is reported
        reply({"load_error": str(exc) if isinstance(exc, NoShade) else one_line(exc, student_file, shown_name)})
        return 0
    reply({"loaded": True})

    for line in requests:
        request = json.loads(line)
        material = core.Material(**request["material"])
        lights = []
        for spec_ in request["lights"]:
            kind = spec_.pop("type")
            if kind not in LIGHT_KINDS:
                raise ValueError(f"unknown light type {kind!r}")
            lights.append(getattr(core, kind)(**spec_))
        eye = np.array(request["eye"], dtype=np.float64)
        results = []
        for point, normal in zip(request["points"], request["normals"]):
            try:
                value = shade(np.array(point, dtype=np.float64), np.array(normal, dtype=np.float64),
                              eye.copy(), material, list(lights))
                results.append(_as_rgb(value, np))
            except BaseException as exc:  # noqa: BLE001 - the student's exception is a failed case
                results.append(one_line(exc, student_file, shown_name))
        reply({"results": results})
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
