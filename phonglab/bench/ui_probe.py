"""What ``phonglab bench ui``'s measured steps share: their latencies and the server's times for them.

A probe (:class:`phonglab.bench.ui.KeyPress`, :class:`phonglab.bench.ui_turn.Turn`)
takes one step at a time in a page and keeps the step's latency; the
server writes its own time per update to a timing file under a label
(:mod:`phonglab.app.timing`). The first steps are warm-up:
:meth:`Probe.start_measuring` forgets them, and the server's times are
counted from there.
"""

from __future__ import annotations

import time


class Probe:
    """A page's measured steps and the server's records under ``label`` in ``timing_path``."""

    def __init__(self, page, *, timing_path, label):
        self.page, self.timing_path, self.label = page, timing_path, label
        self.latency_ms: list[float] = []
        self._records_before = None

    def records(self) -> int:
        """How many updates the server has recorded under the label so far."""
        from phonglab.app import timing

        return len([r for r in timing.read(self.timing_path) if r[0] == self.label])

    def keep(self, latency_ms: float, records_before: int, timeout: float = 10.0) -> None:
        """Keep a step's latency once the server's record of it has landed (at most ``timeout`` s later)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and self.records() <= records_before:
            time.sleep(0.01)
        self.latency_ms.append(latency_ms)

    def start_measuring(self) -> None:
        """The steps so far were warm-up: keep the later ones (and the server's times from here)."""
        self.latency_ms.clear()
        self._records_before = self.records()

    def server_ms(self, cpu: bool = False) -> list[float]:
        """The server's wall-clock time per update since :meth:`start_measuring` (``cpu``: its CPU time)."""
        from phonglab.app import timing

        label = self.label + (timing.CPU_SUFFIX if cpu else "")
        return [ms for lab, ms in timing.read(self.timing_path) if lab == label][self._records_before or 0:]
