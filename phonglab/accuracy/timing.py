"""Timing helpers shared by the studies: the fastest of several repeats, in seconds.

Every timed function is first called untimed (the *warm-up*: lazy imports,
first allocations, caches), then timed in ``repeats`` samples, and the
fastest sample is reported: on a shared machine the other samples were
slowed by something else (another process, another worker's study), so the
fastest is the one that varies least between runs (on 2 busy cores the
median of five still moved by a third from run to run, the fastest by about
a tenth). Calls quicker than ``min_seconds`` are looped within a sample so
the clock's resolution does not dominate. Functions
compared with each other are timed in turns (:func:`interleaved_times`):
one sample of each per round, so a busy moment of a shared machine lands on
all of them instead of on whichever happened to run then.

The clock is a parameter (``clock``, :func:`time.perf_counter` by default)
so tests can check the mechanism (warm-ups untimed, the fastest of N) with a
fake clock, without asserting anything about real time.
"""

from __future__ import annotations

import math
import sys
import time

#: untimed calls of each function before its samples: the first pays for
#: imports and allocations, the second sizes the loop on a warm function
WARMUPS = 2


def _loops(seconds: float, min_seconds: float) -> int:
    return max(1, math.ceil(min_seconds / seconds)) if seconds > 0 else 1


def best_time(fn, repeats: int, *, warmup: bool = True, min_seconds: float = 0.005,
              clock=time.perf_counter) -> tuple[float, object]:
    """The fastest wall-clock time of one ``fn()`` call over ``repeats`` samples, and its last result.

    Untimed calls (:data:`WARMUPS`) warm caches and lazy imports (unless ``warmup`` is
    False, when the first call is the first sample if it took ``min_seconds`` or more). Calls quicker than
    ``min_seconds`` are repeated in a loop within each sample, so the clock's
    resolution and the scheduler's jitter do not dominate.
    """
    start = clock()
    result = fn()
    first = clock() - start
    if warmup:
        for _ in range(WARMUPS - 1):  # size the loop on a warm call
            start = clock()
            result = fn()
            first = clock() - start
    loops = _loops(first, min_seconds)
    # the first call counts as a sample only when it is unwarmed and long enough alone
    times = [first] if (not warmup and loops == 1) else []
    while len(times) < max(1, repeats):
        start = clock()
        for _ in range(loops):
            result = fn()
        times.append((clock() - start) / loops)
    return min(times), result


def interleaved_times(fns: dict, repeats: int, *, min_seconds: float = 0.005, clock=time.perf_counter) -> dict:
    """The fastest times of several functions timed in turn, one sample of each per round.

    Every function is warmed up (:data:`WARMUPS` untimed calls, all of them
    before any sample is taken), then ``repeats`` rounds take one sample of
    each. Taking turns spreads a busy moment of a shared machine over all of
    them instead of penalising whichever ran then, so their ratios are fair.
    Returns ``{name: fastest seconds per call}``.
    """
    loops, samples = {}, {name: [] for name in fns}
    for _ in range(WARMUPS):
        for name, fn in fns.items():
            start = clock()
            fn()  # warm up, and size the loop on the last warm-up
            loops[name] = _loops(clock() - start, min_seconds)
    for _ in range(max(1, repeats)):
        for name, fn in fns.items():
            start = clock()
            for _ in range(loops[name]):
                fn()
            samples[name].append((clock() - start) / loops[name])
    return {name: min(times) for name, times in samples.items()}


class Progress:
    """One-line progress messages on stderr, or nothing when ``quiet``."""

    def __init__(self, quiet: bool = True):
        self.quiet = quiet
        self.start = time.perf_counter()

    def __call__(self, message: str) -> None:
        if not self.quiet:
            elapsed = time.perf_counter() - self.start
            print(f"[accuracy {elapsed:6.1f} s] {message}", file=sys.stderr, flush=True)
