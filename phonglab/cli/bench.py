"""``phonglab bench NAME``: benchmarks, printed as ratios to a baseline timed in the same run.

Each benchmark is a module ``phonglab.bench.NAME`` with::

    HELP: str                                   # one line for --help
    def add_arguments(parser) -> None: ...
    def run(args) -> int: ...

Benchmarks are never tests: no test asserts a time.
"""

from __future__ import annotations

import importlib

BENCHMARKS = {
    "core": "the shading core against plain NumPy and the memory-copy floor",
    "planner": "planned scenes against the full evaluation",
    "accuracy": "what each gain in accuracy costs in time",
    "ui": "slider-to-pixels latency in a real browser against a minimal trame app",
    "load": "simulated students over WebSockets: latency, updates/s and capacity, one process and the launcher",
}


def add_parser(subparsers):
    parser = subparsers.add_parser("bench", help="measure speed and accuracy (ratios, same run)")
    sub = parser.add_subparsers(dest="benchmark", metavar="BENCHMARK", required=True)
    for name, help_text in BENCHMARKS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.set_defaults(_bench_module=f"phonglab.bench.{name}")
        _add_arguments(name, p)
    return parser


def _add_arguments(name, parser):
    try:
        module = importlib.import_module(f"phonglab.bench.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"phonglab.bench.{name}":
            raise
        return
    module.add_arguments(parser)


def run(args) -> int:
    module = importlib.import_module(args._bench_module)
    return int(module.run(args) or 0)
