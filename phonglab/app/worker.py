"""Heavy work from one tab, done in worker processes so the event loop every tab shares stays free.

Every tab of ``phonglab serve`` is served by one asyncio event loop. A
figure export (seconds of VTK rendering), the accuracy lesson's studies and
error images take far longer than a slider's update: run in the loop, they
would hold every other tab's page still. They run here instead:

* in a small pool of :data:`WORKERS` worker processes shared by every tab,
  started (spawned, not forked: the server holds threads and OpenGL
  contexts) in a thread of their own: ``phonglab serve`` starts them as
  soon as it listens (:func:`start`), and each then makes a small figure in
  the background, so the first export does not wait for VTK's imports and
  OpenGL context; elsewhere they start with the first job. VTK's OpenGL
  contexts belong to the thread that made them, so a worker makes its own;
  what travels is the frozen :class:`~phonglab.scene.Scene` (pickled) and
  the bytes of the result;
* telling the server how a job goes: which workers are ready, when a job
  leaves the queue, and the steps a figure reports (:func:`report`), read
  with :func:`progress` and :func:`ready_workers` (the page says
  "preparing…" with them);
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
import functools
import itertools
import logging
import multiprocessing
import os
import signal
import threading

log = logging.getLogger(__name__)

__all__ = ["WORKERS", "NICE", "MAX_PENDING", "TIMEOUT", "ServerBusy", "WorkerError", "start", "submit", "started",
           "pending", "progress", "ready_workers", "report", "shutdown", "TabJob"]

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
_waiting = []  # (job, function, args, future) submitted while it starts
_lifeline = None  # the write end of the pipe whose closing ends the workers (kept open while the pool runs)
_jobs = itertools.count(1)  # job numbers, for their progress
_open_jobs: set[int] = set()  # jobs submitted and not finished
_started_jobs: dict[int, tuple[int, int, str]] = {}  # open job -> (done, total, label), once a worker took it
_ready: set[int] = set()  # process ids of workers ready for a job (warmed up when asked to)
_pool_events = []  # the queue the running pool's workers tell into

# in a worker: where it tells the server how its job goes, and which job it runs
_events = None
_job = None


class WorkerError(RuntimeError):
    """A job failed in a worker with an exception that cannot travel back whole (its text is kept)."""


class ServerBusy(RuntimeError):
    """More than :data:`MAX_PENDING` heavy jobs would be waiting: the tab should try again later."""


def _start_worker(lifeline, events, warm) -> None:
    global _events
    _events = events
    # Ctrl-C reaches the whole process group: the server stops its workers itself
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # the server's event loop answers every tab: it gets the CPU first
    with contextlib.suppress(OSError, AttributeError):
        os.nice(NICE)
    # a worker ends with its server, however the server ends (kill -9 included)
    threading.Thread(target=_end_with_server, args=(lifeline,), name="phonglab-lifeline", daemon=True).start()
    if warm is not None:
        try:
            warm()
        except Exception:  # noqa: BLE001 - a worker that cannot warm up still takes jobs
            log.exception("warming up a worker")
    _tell("ready", os.getpid())


def _tell(*event) -> None:
    """In a worker: send ``event`` to the server (nothing when there is no server listening)."""
    if _events is not None:
        with contextlib.suppress(Exception):
            _events.put(event)


def report(done: int, total: int, label: str = "") -> None:
    """In a worker's job: ``done`` of ``total`` steps are made (``label`` the last); the page shows it.

    Outside a worker job (a script, a test), nothing happens.
    """
    if _job is not None:
        _tell("step", _job, int(done), int(total), str(label))


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


def _call(job, function, args):
    """``function(*args)`` in a worker; a failure is re-raised as one that survives the trip back.

    The server hears when the job starts (it has left the queue). The
    pool's result thread unpickles what a worker raised; an exception whose
    class cannot be rebuilt from its ``args`` would stop that thread and
    every later job with it.
    """
    import pickle

    global _job
    _job = job
    _tell("start", job)
    try:
        return function(*args)
    except Exception as exc:
        try:
            pickle.loads(pickle.dumps(exc))
        except Exception:
            raise WorkerError(f"{type(exc).__name__}: {exc}") from None
        raise
    finally:
        _job = None


def _listen(events, generation: int) -> None:
    """In the server, a thread: what the workers tell, kept for :func:`progress` and :func:`ready_workers`."""
    while True:
        try:
            event = events.get()
        except (EOFError, OSError):
            return
        if event is None:  # the pool stopped
            return
        with _lock:
            if generation != _generation:
                return
            kind = event[0]
            if kind == "ready":
                _ready.add(event[1])
            elif kind == "start" and event[1] in _open_jobs:  # (a finished job's news may come late)
                _started_jobs[event[1]] = (0, 0, "")
            elif kind == "step" and event[1] in _started_jobs:
                _started_jobs[event[1]] = tuple(event[2:5])


def _finished(job, _future) -> None:
    global _pending
    with _lock:
        _pending = max(0, _pending - 1)
        _open_jobs.discard(job)
        _started_jobs.pop(job, None)


def _start_pool(generation: int, warm=None) -> None:
    """Start the workers (each calling ``warm()`` first, when given) and hand them the jobs that waited.

    Run in a thread: spawning the workers would hold the event loop for a
    tenth of a second or more.
    """
    global _pool, _starting, _lifeline
    context = multiprocessing.get_context("spawn")
    try:
        # the lifeline: the workers get its read end, this process alone keeps its write end
        lifeline, keep = context.Pipe(duplex=False)
        events = context.SimpleQueue()
        pool = context.Pool(WORKERS, initializer=_start_worker, initargs=(lifeline, events, warm))
    except Exception as exc:  # noqa: BLE001 - every waiting job fails with it
        with _lock:
            waiting = []
            if generation == _generation:
                waiting, _waiting[:], _starting = list(_waiting), [], False
        for *_, future in waiting:
            future.set_exception(exc)
        return
    with _lock:
        wanted = generation == _generation  # False: shut down meanwhile
        if wanted:
            _pool, _starting, _lifeline = pool, False, keep
            _pool_events[:] = [events]
            for job, function, args, future in _waiting:
                _apply(pool, job, function, args, future)
            _waiting.clear()
    if wanted:
        threading.Thread(target=_listen, args=(events, generation), name="phonglab-worker-events",
                         daemon=True).start()
        # any process that started workers stops them before it exits, not in Pool.__del__
        atexit.register(shutdown)
    else:
        keep.close()
        pool.terminate()


def _apply(pool, job, function, args, future) -> None:
    pool.apply_async(_call, (job, function, args), callback=future.set_result, error_callback=future.set_exception)


def _start_locked(warm) -> None:
    """Start the pool in a thread unless it runs or is starting (the caller holds ``_lock``)."""
    global _starting
    if _pool is None and not _starting:
        _starting = True
        threading.Thread(target=_start_pool, args=(_generation, warm), name="phonglab-worker-start",
                         daemon=True).start()


def start(*, warm=None) -> None:
    """Start the worker processes now, in the background, each calling ``warm()`` before its first job.

    Returns at once (the processes are spawned in a thread, at a lower CPU
    priority than the caller). ``warm``, a module-level function, does
    what a first job would pay for (:func:`phonglab.app.download.warm_up`
    makes a small figure: VTK's imports, an OpenGL context), so the first
    job finds the workers ready. Does nothing while they run.
    """
    with _lock:
        _start_locked(warm)


def submit(function, *args, limit: int | None = MAX_PENDING) -> concurrent.futures.Future:
    """Run ``function(*args)`` in a worker process; a Future of its result, with its job number as ``.job``.

    ``function`` must be importable by name (a module-level function) and
    its arguments and result picklable. The workers start now if they have
    not yet (not warmed up).

    Raises
    ------
    ServerBusy
        When ``limit`` jobs (None: no limit) are already queued or running.
    """
    global _pending
    future = concurrent.futures.Future()
    future.set_running_or_notify_cancel()
    with _lock:
        if limit is not None and _pending >= limit:
            raise ServerBusy(f"the server is busy with {_pending} figures and studies; try again in a moment")
        _pending += 1
        future.job = next(_jobs)
        _open_jobs.add(future.job)
        future.add_done_callback(functools.partial(_finished, future.job))
        if _pool is not None:
            _apply(_pool, future.job, function, args, future)
            return future
        _waiting.append((future.job, function, args, future))
        _start_locked(None)
    return future


def started() -> bool:
    """Whether the worker processes are running or starting."""
    with _lock:
        return _pool is not None or _starting


def pending() -> int:
    """Heavy jobs queued or running now."""
    with _lock:
        return _pending


def ready_workers() -> int:
    """How many workers are ready for a job (started, and warmed up when :func:`start` was given ``warm``)."""
    with _lock:
        return min(len(_ready), WORKERS) if _pool is not None else 0


def progress(job: int) -> tuple[int, int, str] | None:
    """How job ``job`` goes: None while it waits for a worker, else ``(done, total, label)`` of its steps.

    ``total`` is 0 until the job reports a step (:func:`report`).
    """
    with _lock:
        return _started_jobs.get(job)


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
        events, _pool_events[:] = list(_pool_events), []
        _ready.clear()
        _open_jobs.clear()
        _started_jobs.clear()
    for *_, future in waiting:
        future.set_exception(RuntimeError("the server is stopping"))
    for queue in events:  # the listening thread ends
        with contextlib.suppress(Exception):
            queue.put(None)
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
        self.worker_job = None  # the worker job of the latest start (see progress())
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
        self.worker_job = future.job
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
