"""``phonglab grade FILE.py``: grade a student's ``shade()`` against the core.

The file defines ``shade(point, normal, eye, material, lights)`` for one
point (the contract is in :mod:`phonglab.teaching.grading` and in the
starter that ``phonglab grade --template [PATH]`` writes). It runs in a
bubblewrap sandbox (:mod:`phonglab.teaching.isolation`) on a fixed set of
cases in ten groups worth 100 points; the report shows, for every group,
passed or failed with its points, the worst case with its inputs, expected
and got, and the common mistake the wrong answers match.

``--json FILE`` also writes Gradescope's ``results.json``; ``--picture PNG``
(off by default) draws the student's shading of a sphere beside the core's
and the difference between them.

Exit status: 0 every case passes, 1 some fail, 2 the file cannot be loaded
(syntax error, import error, no ``shade``: the reason on one line), bad
usage, or no sandbox on this machine (one line saying what to install:
student code never runs unisolated).
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

from phonglab.accuracy.grade_picture import (  # noqa: F401  (the picture's parts, used by tests too)
    DIFFERENCE_RANGE,
    PICTURE_SIZE,
    picture_png,
    picture_scene,
    sphere_images,
)

def add_parser(subparsers):
    parser = subparsers.add_parser(
        "grade",
        help="grade a student's shade() for one point against the core",
        description="Run FILE.py's shade(point, normal, eye, material, lights) on a fixed set of cases in a "
                    "bubblewrap sandbox and compare it with phonglab.shade (one-sided Phong, local viewer, "
                    "float64). Exit status: 0 all pass, 1 some fail, 2 the file cannot be loaded.",
    )
    parser.add_argument("file", nargs="?", metavar="FILE.py", help="the student's file")
    parser.add_argument("--template", nargs="?", const="shade.py", metavar="PATH",
                        help="write the starter file (default shade.py) and stop; never overwrites a file")
    parser.add_argument("--json", metavar="FILE", help="also write the results in Gradescope's results.json format")
    parser.add_argument("--picture", metavar="PNG",
                        help="also draw the student's sphere beside the core's and their difference (off by default)")
    parser.add_argument("--time-limit", type=float, default=2.0, metavar="SECONDS",
                        help="time limit per case (default 2)")
    parser.add_argument("--total-limit", type=float, default=120.0, metavar="SECONDS",
                        help="time limit for all cases together (default 120)")
    return parser


def run(args) -> int:
    from phonglab.cli import UsageError
    from phonglab.teaching import grading

    if args.template is not None:
        if args.file is not None:
            raise UsageError("give either FILE.py to grade or --template, not both")
        return _write_template(Path(args.template), grading.starter_text())
    if args.file is None:
        raise UsageError("give FILE.py to grade, or --template [PATH] for a starter file")
    for name in ("time_limit", "total_limit"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            raise UsageError(f"--{name.replace('_', '-')}: must be a number of seconds > 0, got {value:g}")
    limits = grading.Limits(time_limit=args.time_limit, total_limit=args.total_limit)

    started = time.monotonic()
    try:
        report = grading.grade_file(args.file, limits)
    except grading.SandboxUnavailable as exc:
        raise UsageError(f"cannot grade: {exc}") from None
    except grading.LoadError as exc:
        reason = " ".join(str(exc).split())
        print(f"phonglab grade: cannot load {args.file}: {reason}", file=sys.stderr)
        if args.json:
            _write_json(args.json, grading.gradescope_results(None, load_error=reason,
                                                              execution_time=time.monotonic() - started))
        return 2
    print(grading.format_report(report))
    if args.json:
        _write_json(args.json, grading.gradescope_results(report, execution_time=time.monotonic() - started))
        print(f"wrote {args.json}")
    if args.picture:
        note = _write_picture(args.picture, args.file, limits)
        print(f"wrote {args.picture}" + (f" ({note})" if note else ""))
    return 0 if report.passed else 1


def _write_template(path: Path, text: str) -> int:
    from phonglab.cli import UsageError

    try:
        with open(path, "x", encoding="utf-8") as f:  # "x": refuse to overwrite
            f.write(text)
    except FileExistsError:
        raise UsageError(f"{path} exists: not overwritten (give another PATH)") from None
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None
    print(f"wrote {path}: fill in shade(), then run `phonglab grade {path}`")
    return 0


def _write_atomically(path, data: bytes) -> None:
    """Write ``data`` to a temporary file beside ``path``, then rename it: whole or not at all."""
    from phonglab.cli import UsageError

    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=path.suffix, dir=path.resolve().parent)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
            os.chmod(tmp, 0o644)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None


def _write_json(path, results: dict) -> None:
    _write_atomically(path, (json.dumps(results, indent=2, ensure_ascii=False) + "\n").encode("utf-8"))


def _write_picture(png, file, limits) -> str:
    """Draw ``student | core | difference`` into ``png``; a note on pixels without a colour."""
    data, note = picture_png(file, limits)
    if data is not None:
        _write_atomically(png, data)
    return note
