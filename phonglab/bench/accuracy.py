"""``phonglab bench accuracy``: what each gain in accuracy costs in time.

Runs the four studies of :mod:`phonglab.accuracy` (interpolation, precision,
Phong against Blinn-Phong, finite-size lights), prints one table per study
(or ``--json``) and, when ``--figure PATH`` is given, writes the figure:
error against time, log–log, one curve per method (no file is written
without ``--figure``). Every error is against a stated reference and every time
is a median of repeats measured in this run. ``--quick`` takes a few
seconds; the full run about a minute, with progress on stderr.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

HELP = "what each gain in accuracy costs in time"


def add_arguments(parser):
    parser.add_argument("--quick", action="store_true",
                        help="smaller images, fewer resolutions and samples (a few seconds)")
    parser.add_argument("--json", action="store_true", help="print the studies as JSON instead of tables")
    parser.add_argument("--figure", default=None, metavar="PATH",
                        help="write the figure there, .png, .svg or .pdf (default: no figure)")


def _check_figure_path(value: str) -> Path:
    from phonglab.accuracy.figure import FORMATS
    from phonglab.bench.usage import UsageError

    path = Path(value)
    if path.suffix.lower().lstrip(".") not in FORMATS:
        raise UsageError(f"--figure: must end in .png, .svg or .pdf, got {value!r}")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise UsageError(f"--figure: the folder {str(folder)!r} does not exist, got {value!r}")
    return path


def run(args) -> int:
    from phonglab.accuracy import format_report, run_studies, write_figure
    from phonglab.accuracy.timing import Progress

    figure = _check_figure_path(args.figure) if args.figure is not None else None
    start = time.perf_counter()
    progress = Progress(quiet=bool(args.quick))
    results = run_studies(quick=args.quick, progress=progress)
    written = None
    if figure is not None:
        progress("drawing the figure")
        try:
            written = write_figure(results, figure)
        except OSError as exc:
            from phonglab.bench.usage import UsageError

            raise UsageError(f"--figure: cannot write {str(figure)!r}: {exc.strerror or exc}") from None
    results["figure"] = written
    results["seconds"] = time.perf_counter() - start
    if args.json:
        print(json.dumps(results, indent=2))
    else:
        print(format_report(results), end="")
        where = f"figure written to {written}" if written else "no figure (ask with --figure PATH)"
        print(f"{where} ({results['seconds']:.1f} s in all)")
    if not args.quick:
        progress("done")
    sys.stdout.flush()
    return 0
