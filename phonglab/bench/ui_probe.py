"""What ``phonglab bench ui``'s measured steps share: their latencies and the server's times for them.

A probe (:class:`phonglab.bench.ui.KeyPress`, :class:`phonglab.bench.ui_turn.Turn`)
takes one step at a time in a page and keeps the step's latency; the
server writes its own time per update to a timing file under a label
(:mod:`phonglab.app.timing`). The first steps are warm-up:
:meth:`Probe.start_measuring` forgets them, and the server's times are
counted from there.

A probe given the server's process id also keeps the server's own CPU time
per step (:func:`process_cpu_seconds`, every thread of the process, the
kernel's time for its sockets included): from a settled page just before
the step to the page settled again after it, so the step's put-off work and
any answer of the page's to it (a turn's shown-colours message) are counted too.
"""

from __future__ import annotations

import time

def _cpu_clock(pid: int) -> int:
    """Linux's clock id of the CPU time of process ``pid`` (``MAKE_PROCESS_CPUCLOCK(pid, CPUCLOCK_SCHED)``)."""
    return ((~pid) << 3) | 2


def process_cpu_seconds(pid: int) -> float | None:
    """CPU time of process ``pid`` and all its threads, user and kernel, in seconds (None where it cannot be read).

    Read from the process's CPU-time clock, to the nanosecond (``/proc``'s
    times count whole clock ticks of 10 ms, coarser than one update).
    """
    try:
        return time.clock_gettime(_cpu_clock(pid))
    except (OSError, OverflowError, AttributeError):
        return None


class Probe:
    """A page's measured steps and the server's records under ``label`` in ``timing_path``.

    The records a step brings (those that land between its start and the
    end of :meth:`keep`) are the step's own: two probes may share a server
    and a label (two tabs of one server), and a page's other work under the
    same label (the panels after a turn) is not counted as a key press's.
    """

    def __init__(self, page, *, timing_path, label, server_pid=None):
        self.page, self.timing_path, self.label = page, timing_path, label
        self.server_pid = server_pid
        self.latency_ms: list[float] = []
        #: the server process's CPU time per step, ms (with ``server_pid``)
        self.process_cpu_ms: list[float] = []
        self._server = {False: [], True: []}  # the steps' own records: wall ms, CPU ms

    def server_cpu(self) -> float | None:
        """The server process's CPU time so far, in seconds (None without a ``server_pid`` or a readable clock)."""
        return None if self.server_pid is None else process_cpu_seconds(self.server_pid)

    def wait_quiet(self, span: float = 0.1, tolerance_ms: float = 0.3, timeout: float = 10.0) -> None:
        """Wait (at most ``timeout`` s) until the server spends less than ``tolerance_ms`` of CPU in ``span`` s."""
        deadline = time.monotonic() + timeout
        last = self.server_cpu()
        while last is not None and time.monotonic() < deadline:
            time.sleep(span)
            now = self.server_cpu()
            if now is None or (now - last) * 1000.0 < tolerance_ms:
                return
            last = now

    def keep_cpu(self, before: float | None) -> None:
        """Keep the server's CPU time since ``before`` (a :meth:`server_cpu` reading) as one step's."""
        after = self.server_cpu()
        if before is not None and after is not None:
            self.process_cpu_ms.append((after - before) * 1000.0)

    def _read(self, cpu: bool) -> list[float]:
        from phonglab.app import timing

        label = self.label + (timing.CPU_SUFFIX if cpu else "")
        return [ms for lab, ms in timing.read(self.timing_path) if lab == label]

    def records(self) -> int:
        """How many updates the server has recorded under the label so far."""
        return len(self._read(False))

    def keep(self, latency_ms: float, records_before: int, timeout: float = 10.0) -> None:
        """Keep a step's latency, and its server records once they have landed (at most ``timeout`` s later)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and (len(self._read(False)) <= records_before
                                               or len(self._read(True)) <= records_before):
            time.sleep(0.01)
        self.latency_ms.append(latency_ms)
        for cpu in (False, True):
            self._server[cpu] += self._read(cpu)[records_before:]

    def start_measuring(self) -> None:
        """The steps so far were warm-up: keep the later ones (and the server's times from here)."""
        self.latency_ms.clear()
        self.process_cpu_ms.clear()
        for kept in self._server.values():
            kept.clear()

    def server_ms(self, cpu: bool = False) -> list[float]:
        """The server's wall-clock time per update of the steps since :meth:`start_measuring` (``cpu``: its CPU time)."""
        return list(self._server[cpu])
