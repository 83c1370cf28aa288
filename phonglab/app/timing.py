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
    """Time the block and append ``label ms`` to the timing file, if one is set."""
    start = time.perf_counter()
    try:
        yield
    finally:
        record(label, (time.perf_counter() - start) * 1000.0)


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
