"""The worker of :mod:`phonglab.teaching.sandbox`: runs a student's ``shade`` inside the sandbox.

Run by the sandbox, never imported by the grader::

    python -I -S -B /grader/worker.py /sandbox/STUDENT.py MEMORY_BYTES CPU_SECONDS

It sees only what the sandbox binds: the standard library, NumPy in
``/grader/site``, this file and ``/grader/shade_helpers.py``. It imports
nothing of phonglab (the package is not there). It talks to the grader over
its standard input and output, one JSON object per line:

1. it imports NumPy and the helper module, lowers its resource limits for
   good (address space, CPU time, 64 open files, files may not grow, no core
   dumps: without capabilities they cannot be raised again) and answers
   ``{"ready": true}``;
2. it imports the student's file and answers ``{"loaded": true}`` or
   ``{"load_error": "one line"}``;
3. for every request ``{"points", "normals", "eye", "material", "lights"}``
   it calls ``shade(point, normal, eye, material, lights)`` once per point,
   with the material and lights as :mod:`shade_helpers` objects, and
   answers ``{"results": [...]}``: per point either ``[r, g, b]`` or the
   one-line error message (a string).

The student's ``input()`` and ``print()`` do not reach the grader's pipes:
those are moved to new file descriptors, standard input reads ``/dev/null``
and whatever the student prints or writes to standard error is dropped.
"""

import errno
import json
import os
import sys
import traceback

#: how long a student's message may be in the report
MESSAGE_CHARS = 300
#: where the sandbox puts NumPy and the helper module
GRADER_DIR = "/grader"
SITE_DIR = GRADER_DIR + "/site"
#: what a student who reaches for the package is told
NO_PHONGLAB = ("phonglab is not available in a graded exercise: write the model with NumPy, math and "
               "shade_helpers (normalize, dot, reflect)")
#: what a refused system call means here
REFUSED = "refused by the grader's sandbox: shade needs no files, programs, signals or network"


class NoShade(Exception):
    """The student's file loaded but defines no callable ``shade``."""


def one_line(exc, student_file, shown_name):
    """``Type: message (line N)``, the line being the last one in the student's file."""
    line = None
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename == student_file:
            line = frame.lineno
    if isinstance(exc, SyntaxError) and exc.filename == student_file:
        line = exc.lineno
        text = f"{type(exc).__name__}: {exc.msg}"
    elif isinstance(exc, ImportError) and str(getattr(exc, "name", "") or "").split(".")[0] == "phonglab":
        text = f"{type(exc).__name__}: {NO_PHONGLAB}"
    else:
        text = f"{type(exc).__name__}: {exc}".rstrip(": ")
        if isinstance(exc, OSError) and exc.errno == errno.EPERM:
            text += f" ({REFUSED})"
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


def _limit(memory, cpu):
    """The resource limits, soft = hard: without capabilities nothing in the sandbox can raise them."""
    import resource
    import signal

    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past RLIMIT_FSIZE fails instead of killing us
    for which, value in ((resource.RLIMIT_AS, memory), (resource.RLIMIT_CPU, cpu), (resource.RLIMIT_NOFILE, 64),
                         (resource.RLIMIT_FSIZE, 0), (resource.RLIMIT_CORE, 0)):
        resource.setrlimit(which, (value, value))


def main(argv):
    student_file, memory, cpu = argv[1], int(argv[2]), int(argv[3])
    # the grader's pipes on new descriptors; the student's stdin/stdout/stderr go nowhere
    requests = os.fdopen(os.dup(0), "rb")
    replies = os.fdopen(os.dup(1), "w", encoding="utf-8")
    null = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(null, fd)
    os.close(null)
    sys.stdin = open(os.devnull)
    sys.stdout = sys.stderr = _Sink()

    def reply(obj):
        replies.write(json.dumps(obj) + "\n")
        replies.flush()

    sys.path[:0] = [SITE_DIR, GRADER_DIR]
    import importlib.util

    import numpy as np

    import shade_helpers

    _limit(memory, cpu)
    reply({"ready": True})

    shown_name = os.path.basename(student_file)
    try:
        spec = importlib.util.spec_from_file_location("student", student_file)
        module = importlib.util.module_from_spec(spec)
        sys.modules["student"] = module
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
        material = shade_helpers.material_from(request["material"])
        lights = [shade_helpers.light_from(spec_) for spec_ in request["lights"]]
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
