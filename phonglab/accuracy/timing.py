"""Timing helpers shared by the studies: medians of repeats, in seconds."""

from __future__ import annotations

import math
import statistics
import sys
import time


def median_time(fn, repeats: int, *, warmup: bool = True, min_seconds: float = 0.005) -> tuple[float, object]:
    """The median wall-clock time of one ``fn()`` call over ``repeats`` samples, and its last result.

    A first, untimed call warms caches and lazy imports (unless ``warmup`` is
    False, when it is the first sample if it took ``min_seconds`` or more). Calls quicker than
    ``min_seconds`` are repeated in a loop within each sample, so the clock's
    resolution and the scheduler's jitter do not dominate.
    """
    start = time.perf_counter()
    result = fn()
    first = time.perf_counter() - start
    loops = max(1, math.ceil(min_seconds / first)) if first > 0 else 1
    # the first call counts as a sample only when it is unwarmed and long enough alone
    times = [first] if (not warmup and loops == 1) else []
    while len(times) < max(1, repeats):
        start = time.perf_counter()
        for _ in range(loops):
            result = fn()
        times.append((time.perf_counter() - start) / loops)
    return statistics.median(times), result


def interleaved_times(fns: dict, repeats: int, *, min_seconds: float = 0.005) -> dict:
    """Median times of several functions timed in turn, one sample of each per round.

    Taking turns spreads a busy moment of a shared machine over all of them
    instead of penalising whichever ran then, so their ratios are fair.
    Returns ``{name: seconds per call}``.
    """
    loops, samples = {}, {}
    for name, fn in fns.items():
        start = time.perf_counter()
        fn()  # warm up, and size the loop
        first = time.perf_counter() - start
        loops[name] = max(1, math.ceil(min_seconds / first)) if first > 0 else 1
        samples[name] = []
    for _ in range(max(1, repeats)):
        for name, fn in fns.items():
            start = time.perf_counter()
            for _ in range(loops[name]):
                fn()
            samples[name].append((time.perf_counter() - start) / loops[name])
    return {name: statistics.median(times) for name, times in samples.items()}


class Progress:
    """One-line progress messages on stderr, or nothing when ``quiet``."""

    def __init__(self, quiet: bool = True):
        self.quiet = quiet
        self.start = time.perf_counter()

    def __call__(self, message: str) -> None:
        if not self.quiet:
            elapsed = time.perf_counter() - self.start
            print(f"[accuracy {elapsed:6.1f} s] {message}", file=sys.stderr, flush=True)
