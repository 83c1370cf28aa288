"""Work a browser tab puts off: one way to schedule it.

A change the browser sends is answered in two steps: first what the student
waits for (the mesh's new colours), then, once that has left, the rest (the
readout, the arrows, the per-pixel picture). :class:`Later` holds the second
step as named jobs, added once and asked for any number of times:

- a job asked again while it waits still runs once;
- when a job's delay has passed, every job waiting with that delay runs, in
  the order the jobs were added (so the arrows are reshaped before the
  readout that lists their tips);
- without a running event loop (scripts, tests) an asked job runs at once;
- a job that raises is handed to ``on_error`` and the others still run.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Callable

log = logging.getLogger(__name__)

__all__ = ["Later"]


class Later:
    """Named jobs run a moment later on the server's event loop.

    Parameters
    ----------
    on_error : callable, optional
        ``on_error(name, exc)`` for a job that raises (default: logged).

    Examples
    --------
    >>> done = []
    >>> later = Later()
    >>> later.add("panels", lambda: done.append("panels"), delay=0.004)
    >>> later.ask("panels")  # no running loop here: at once
    >>> done
    ['panels']
    """

    def __init__(self, on_error: Callable | None = None):
        self._jobs: dict[str, tuple[Callable, float]] = {}
        self._waiting: set[str] = set()
        self._timers: dict[float, asyncio.Handle] = {}
        self._on_error = on_error

    def add(self, name: str, run: Callable[[], None], *, delay: float = 0.0) -> None:
        """Make ``run()`` the job called ``name``, run ``delay`` seconds after it is asked for."""
        self._jobs[name] = (run, float(delay))

    def ask(self, name: str) -> None:
        """Run the job ``name`` after its delay (at once without a running loop); once, however often asked."""
        run, delay = self._jobs[name]
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no server loop (scripts, tests): at once
            self._run(name, run)
            return
        self._waiting.add(name)
        if delay not in self._timers:
            self._timers[delay] = (loop.call_soon(self._fire, delay) if delay == 0
                                   else loop.call_later(delay, self._fire, delay))

    def waiting(self, name: str) -> bool:
        """True while the job ``name`` has been asked for and not run yet."""
        return name in self._waiting

    def run_waiting(self) -> None:
        """Run every waiting job now (in the order the jobs were added) instead of at its time."""
        for delay in list(self._timers):
            self._timers.pop(delay).cancel()
        self._fire(None)

    def cancel(self, name: str | None = None) -> None:
        """Forget the waiting job ``name`` (every waiting job when None)."""
        if name is None:
            self._waiting.clear()
        else:
            self._waiting.discard(name)
        busy = {self._jobs[n][1] for n in self._waiting}
        for delay in [d for d in self._timers if d not in busy]:
            self._timers.pop(delay).cancel()

    def _fire(self, delay) -> None:
        """The jobs waiting with ``delay`` (every waiting job when None), in the order they were added."""
        if delay is not None:
            self._timers.pop(delay, None)
        for name, (run, own) in list(self._jobs.items()):
            if name in self._waiting and (delay is None or own == delay):
                self._waiting.discard(name)
                self._run(name, run)

    def _run(self, name: str, run: Callable) -> None:
        try:
            run()
        except Exception as exc:  # a failed job must not stop the others, nor the server
            if self._on_error is None:
                log.exception("job %s", name)
            else:
                self._on_error(name, exc)
