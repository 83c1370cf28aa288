"""Heavy work from one tab, done in worker processes so the event loop every tab shares stays free.

Every tab of ``phonglab serve`` is served by one asyncio event loop. A
figure export (seconds of VTK rendering), the accuracy lesson's studies and
error images take far longer than a slider's update: run in the loop, they
would hold every other tab's page still. They run here instead:

* in a small pool of :data:`WORKERS` worker processes shared by every tab,
  started (spawned, not forked: the server holds threads and OpenGL
  contexts) on the first job, in a thread of their own. VTK's OpenGL contexts belong to the thread
  that made them, so a worker makes its own; what travels is the frozen
  :class:`~phonglab.scene.Scene` (pickled) and the bytes of the result;
* at a lower CPU priority (``nice`` +:data:`NICE`): on a machine with few
  cores, the server's loop, which answers every tab, is served first;
* ending with the server, however it ends: each worker watches a pipe only
  the server holds open (the lifeline) and exits when it closes, so a server
  killed outright (``kill -9``) leaves no worker rendering on for nobody;
* at most :data:`MAX_PENDING` jobs at once over the whole server: past it a
  tab is told the server is busy and to try again, instead of a queue that
  grows with every click.

:class:`TabJob` is one tab's slot for one kind of heavy job: one job at a
time, a later request while one runs is refused with a notice (exports) and
a result the tab no longer wants (a stale one) is dropped.

This module imports only the standard library at import time: the worker
processes import it.
"""

from __future__ import annotations

import asyncio
import atexit
import concurrent.futures
import contextlib
import logging
import multiprocessing
import os
import signal
import threading

log = logging.getLogger(__name__)

__all__ = ["WORKERS", "NICE", "MAX_PENDING", "TIMEOUT", "ServerBusy", "WorkerError", "submit", "started", "pending", "shutdown", "TabJob"]

#: worker processes shared by every tab of the server
WORKERS = 2
#: how much lower the workers' CPU priority is than the server's (``nice`` increment)
NICE = 10
#: most heavy jobs queued or running at once, over all tabs
MAX_PENDING = 8
#: the longest a tab waits for a job before the page says it failed (seconds)
TIMEOUT = 180.0
#: how long stopping waits for the pool's own clean-up before leaving it to exit
SHUTDOWN_WAIT = 2.0

_lock = threading.Lock()
_pool = None
_pending = 0
_starting = False  # the pool is being started in a thread
_generation = 0  # counts shutdowns: a pool started before one is not used
_waiting = []  # (function, args, future) submitted while it starts
_lifeline = None  # the write end of the pipe whose closing ends the workers (kept open while the pool runs)


class WorkerError(RuntimeError):
    """A job failed in a worker with an exception that cannot travel back whole (its text is kept)."""


class ServerBusy(RuntimeError):
    """More than :data:`MAX_PENDING` heavy jobs would be waiting: the tab should try again later."""


def _start_worker(lifeline) -> None:
    # Ctrl-C reaches the whole process group: the server stops its workers itself
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # the server's event loop answers every tab: it gets the CPU first
    with contextlib.suppress(OSError, AttributeError):
        os.nice(NICE)
    # a worker ends with its server, however the server ends (kill -9 included)
    threading.Thread(target=_end_with_server, args=(lifeline,), name="phonglab-lifeline", daemon=True).start()


def _end_with_server(lifeline) -> None:
    """In a worker: wait on the read end of the server's lifeline pipe; end the process when it closes.

    Only the server holds the write end, and the kernel closes it when the
    server exits, however it exits: the read then fails at once, and the
    worker ends without running any clean-up (its job's result has no one to go to).
    """
    try:
        while True:
            lifeline.recv_bytes()  # nothing is ever sent: this returns only at end of file
    except (EOFError, OSError):
        pass
    os._exit(0)


def _call(function, args):
    """``function(*args)`` in a worker; a failure is re-raised as one that survives the trip back.

    The pool's result thread unpickles what a worker raised; an exception
    whose class cannot be rebuilt from its ``args`` would stop that thread
    and every later job with it.
    """
    import pickle

    try:
        return function(*args)
    except Exception as exc:
        try:
            pickle.loads(pickle.dumps(exc))
        except Exception:
            raise WorkerError(f"{type(exc).__name__}: {exc}") from None
        raise


def _finished(_future) -> None:
    global _pending
    with _lock:
        _pending = max(0, _pending - 1)


def _start_pool(generation: int) -> None:
    """Start the workers and hand them the jobs that waited.

    Run in a thread: spawning the workers would hold the event loop for a
    tenth of a second or more.
    """
    global _pool, _starting, _lifeline
    context = multiprocessing.get_context("spawn")
    try:
        # the lifeline: the workers get its read end, this process alone keeps its write end
        lifeline, keep = context.Pipe(duplex=False)
        pool = context.Pool(WORKERS, initializer=_start_worker, initargs=(lifeline,))
    except Exception as exc:  # noqa: BLE001 - every waiting job fails with it
        with _lock:
            waiting = []
            if generation == _generation:
                waiting, _waiting[:], _starting = list(_waiting), [], False
        for _, _, future in waiting:
            future.set_exception(exc)
        return
    with _lock:
        wanted = generation == _generation  # False: shut down meanwhile
        if wanted:
            _pool, _starting, _lifeline = pool, False, keep
            for function, args, future in _waiting:
                _apply(pool, function, args, future)
            _waiting.clear()
    if wanted:
        # any process that started workers stops them before it exits, not in Pool.__del__
        atexit.register(shutdown)
    else:
        keep.close()
        pool.terminate()


def _apply(pool, function, args, future) -> None:
    pool.apply_async(_call, (function, args), callback=future.set_result, error_callback=future.set_exception)


def submit(function, *args, limit: int | None = MAX_PENDING) -> concurrent.futures.Future:
    """Run ``function(*args)`` in a worker process; a Future of its result.

    ``function`` must be importable by name (a module-level function) and
    its arguments and result picklable.

    Raises
    ------
    ServerBusy
        When ``limit`` jobs (None: no limit) are already queued or running.
    """
    global _pending, _starting
    future = concurrent.futures.Future()
    future.set_running_or_notify_cancel()
    with _lock:
        if limit is not None and _pending >= limit:
            raise ServerBusy(f"the server is busy with {_pending} figures and studies; try again in a moment")
        _pending += 1
        future.add_done_callback(_finished)
        if _pool is not None:
            _apply(_pool, function, args, future)
            return future
        _waiting.append((function, args, future))
        if not _starting:
            _starting = True
            threading.Thread(target=_start_pool, args=(_generation,), name="phonglab-worker-start",
                             daemon=True).start()
    return future


def started() -> bool:
    """Whether the worker processes are running (they start with the first job)."""
    with _lock:
        return _pool is not None or _starting


def pending() -> int:
    """Heavy jobs queued or running now."""
    with _lock:
        return _pending


def shutdown() -> None:
    """Stop the worker processes at once (work in progress is dropped).

    A signal to the whole process group (``docker stop``, ``kill -- -PGID``)
    may already have killed the workers, and ``Pool.terminate`` can then wait
    for ever on results that never come. So the workers left are killed
    outright and the pool's own clean-up gets :data:`SHUTDOWN_WAIT` seconds
    in a daemon thread: stopping the server never hangs.
    """
    global _pool, _pending, _starting, _generation, _lifeline
    with _lock:
        pool, _pool, _pending, _starting = _pool, None, 0, False
        lifeline, _lifeline = _lifeline, None
        _generation += 1
        waiting, _waiting[:] = list(_waiting), []
    for _, _, future in waiting:
        future.set_exception(RuntimeError("the server is stopping"))
    if pool is None:
        return
    for worker in list(getattr(pool, "_pool", ())):
        with contextlib.suppress(Exception):
            worker.kill()
    if lifeline is not None:
        lifeline.close()
    cleanup = threading.Thread(target=pool.terminate, name="phonglab-worker-stop", daemon=True)
    cleanup.start()
    cleanup.join(SHUTDOWN_WAIT)


class TabJob:
    """One tab's slot for one kind of heavy job: at most one at a time, stale results dropped.

    Parameters
    ----------
    state : trame state
        Where the result lands; ``busy_key`` is True while a job runs (the
        page shows progress from it).
    busy_key : str
        A state key.

    Notes
    -----
    :meth:`start` runs ``function(*args)`` in a worker and, back in the
    server's event loop, calls ``done(result)`` or ``failed(exc)`` inside a
    ``with state:`` block (the changes go to the browser when it ends). A
    result that arrives after :meth:`forget` (a newer lesson, a closed tab)
    is dropped. Without a running event loop (scripts, tests) the job runs
    inline.
    """

    def __init__(self, state, busy_key: str):
        self.state = state
        self.busy_key = busy_key
        self._serial = 0
        self._task = None
        self._closed = False
        state[busy_key] = False

    @property
    def busy(self) -> bool:
        """Whether a job of this slot is running."""
        return self._task is not None and not self._task.done()

    def start(self, function, args, done, failed) -> bool:
        """Start ``function(*args)``; False (nothing started) while one runs.

        Raises
        ------
        ServerBusy
            The server has too many heavy jobs already.
        """
        if self.busy:
            return False
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no server loop: at once, in this thread
            try:
                result = function(*args)
            except Exception as exc:  # noqa: BLE001 - reported like a worker's failure
                failed(exc)
            else:
                done(result)
            return True
        future = submit(function, *args)
        self._serial += 1
        self.state[self.busy_key] = True
        self._task = loop.create_task(self._wait(self._serial, future, done, failed))
        return True

    async def _wait(self, serial, future, done, failed) -> None:
        try:
            result = await asyncio.wait_for(asyncio.shield(asyncio.wrap_future(future)), timeout=TIMEOUT)
            error = None
        except asyncio.CancelledError:
            raise
        except asyncio.TimeoutError:
            result, error = None, TimeoutError(f"no result after {TIMEOUT:.0f} s")
        except Exception as exc:  # noqa: BLE001 - the worker's failure, shown on the page
            result, error = None, exc
        if self._closed or serial != self._serial:
            return  # stale: the tab moved on
        with self.state:  # the changes go to the browser when the block ends
            self.state[self.busy_key] = False
            try:
                failed(error) if error is not None else done(result)
            except Exception:
                log.exception("delivering a heavy job's result")

    def forget(self) -> None:
        """Drop the running job's result when it comes (the tab moved on)."""
        self._serial += 1
        if self.busy:
            self._task.cancel()
        self._task = None
        self.state[self.busy_key] = False

    def close(self) -> None:
        """The tab closed: no result is delivered any more."""
        self._closed = True
        if self._task is not None:
            self._task.cancel()
