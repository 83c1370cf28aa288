"""Shared timing helpers for the benchmarks: medians of repeats, ratio tables.

Benchmarks report ratios against a baseline timed in the same run, because
absolute times on a shared machine say little.
"""

from __future__ import annotations

import statistics
import sys
import time


def median_time(fn, *, repeats: int = 5, warmup: int = 1) -> float:
    """Median wall time of ``fn()`` in seconds over ``repeats`` runs after ``warmup``."""
    for _ in range(warmup):
        fn()
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        samples.append(time.perf_counter() - t0)
    return statistics.median(samples)


def verdict(value: float, target: float, *, at_most: bool = True) -> str:
    """``PASS`` or ``MISS`` for a measured ratio against its target."""
    ok = value <= target if at_most else value >= target
    return "PASS" if ok else "MISS"


def progress(message: str) -> None:
    """One progress line on stderr (stdout keeps the results)."""
    print(message, file=sys.stderr, flush=True)


def table(rows, headers) -> str:
    """A plain aligned text table."""
    cells = [list(map(str, headers))] + [[str(c) for c in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(headers))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)
