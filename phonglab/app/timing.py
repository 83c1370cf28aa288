"""Server-side timing of view updates, for ``phonglab bench ui``.

When the environment variable ``PHONGLAB_UI_TIMING`` names a file, every
update of the 3D view appends one line ``<label> <milliseconds>`` to it. The
benchmark starts the server with that variable set and reads the file back;
without it nothing is recorded.
"""

from __future__ import annotations

import os
import time
from contextlib import contextmanager

#: environment variable naming the timing file
ENV = "PHONGLAB_UI_TIMING"


@contextmanager
def timed(label: str):
    """Time the block and append its wall and CPU ms (:func:`record_lap`) to the timing file, if one is set."""
    clock = Stopwatch()
    try:
        yield
    finally:
        record_lap(label, *clock.split())


class Stopwatch:
    """Wall-clock and CPU time of the calling thread since it was made (or since :meth:`split`), in ms.

    The CPU time is the thread's own (``time.thread_time``): on a machine
    where the browser draws in software on the same cores, wall time also
    counts the time other processes had the CPU.
    """

    def __init__(self):
        self._wall, self._cpu = time.perf_counter(), time.thread_time()

    def split(self) -> tuple[float, float]:
        """``(wall_ms, cpu_ms)`` since the start or the last split; starts the next lap."""
        wall, cpu = time.perf_counter(), time.thread_time()
        lap = ((wall - self._wall) * 1000.0, (cpu - self._cpu) * 1000.0)
        self._wall, self._cpu = wall, cpu
        return lap


def record_lap(label: str, wall_ms: float, cpu_ms: float) -> None:
    """Append ``label wall_ms`` and ``label_cpu cpu_ms`` to the timing file, if one is set."""
    record(label, wall_ms)
    record(f"{label}{CPU_SUFFIX}", cpu_ms)


#: label suffix of the CPU-time records
CPU_SUFFIX = "_cpu"


def record(label: str, ms: float) -> None:
    """Append ``label ms`` to the timing file, if one is set."""
    path = os.environ.get(ENV)
    if path:
        with open(path, "a", encoding="utf-8") as handle:
            handle.write(f"{label} {ms:.3f}\n")


def read(path) -> list[tuple[str, float]]:
    """The ``(label, ms)`` records of a timing file, oldest first (empty if missing)."""
    try:
        with open(path, encoding="utf-8") as handle:
            lines = handle.read().splitlines()
    except FileNotFoundError:
        return []
    records = []
    for line in lines:
        label, _, ms = line.rpartition(" ")
        try:
            records.append((label, float(ms)))
        except ValueError:
            continue
    return records
