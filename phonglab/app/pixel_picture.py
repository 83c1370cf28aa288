"""One tab's per-pixel picture, made off the event loop every tab shares.

In pixel mode, and for a translucent mesh, the page shows the core's
picture of the view: the state key ``pixel_src``, a PNG ``data:`` URL. At
the page's largest view (1600 × 1600) making it takes a second or more,
nearly all of it NumPy: the core shading every covered pixel, compositing
by depth, drawing the letters, the PNG. Run in the event loop, that second
is one every other tab waits through. So the screenshot is made in two
parts (:mod:`phonglab.render.pixel_job`): the VTK part (render, read the
buffers, the G-buffer passes) in the loop, because VTK's OpenGL contexts
belong to its thread; the NumPy part and the PNG in a worker thread, where
NumPy lets go of the interpreter for its array work.

What :class:`PixelPicture` promises:

* **one job per tab at a time**. A request while one runs is remembered;
  when the job ends, the newest request remembered is prepared (its VTK part,
  for the view as it is then) and started. Requests in between are
  coalesced into that one.
* **the picture follows, newest last**. Jobs run one after another, each
  for the newest scene when it starts, and each finished picture is shown:
  during a slider drag the picture keeps up as fast as pictures are made
  (a picture may be a scene or two behind the slider until the drag
  pauses, then the last one is the newest scene's). An older picture never
  replaces a newer one, and a picture arriving after the page left pixel
  mode (:meth:`~PixelPicture.drop`) is not shown.
* **without a running event loop** (scripts, tests) the picture is made at
  once, in the caller's thread, as it always was.
* **what belongs to the picture comes with it**. A request may bring
  ``along`` state (the readout, the letters' tips): computed for the view
  the job is prepared for, in the same moment, and set in the same state
  update as the picture, so the page never shows numbers for an eye its
  picture does not show. :data:`PENDING_KEY` is True while a picture newer
  than the one shown is being made (the page says the picture is updating).
* a failure in the thread is logged with its traceback; the tab gets a
  one-line notice, without it.

The worker threads are the pictures' own (:func:`picture_threads`), all
started together when the first picture is asked for. The event loop's
default pool started a thread only when every one it had was busy, so a
moment when the machine ran slow and pictures overlapped left the server
with more threads than before, for good (the session-leak test saw 23
grow to 25).
"""

from __future__ import annotations

import asyncio
import base64
import functools
import io
import logging
import os
import threading
from concurrent.futures import ThreadPoolExecutor

from phonglab.app import owned

log = logging.getLogger(__name__)

#: the state key the page's picture is read from
STATE_KEY = "pixel_src"
#: the state key that is True while a newer picture than the one shown is being made
PENDING_KEY = "pixel_pending"
#: the pictures' worker threads: as many as the event loop's default pool may grow to
PICTURE_THREADS = min(32, (os.cpu_count() or 1) + 4)

_threads: ThreadPoolExecutor | None = None
_threads_made = threading.Lock()


def picture_threads() -> ThreadPoolExecutor:
    """The process's pool for the pictures' NumPy part, its :data:`PICTURE_THREADS` threads all started at once.

    A pool starts a thread for a job only when none is idle; here every
    thread is made the first time, each held by a job until all exist, so
    how many pictures overlap later never changes the server's threads.
    """
    global _threads
    with _threads_made:
        if _threads is None:
            pool = ThreadPoolExecutor(max_workers=PICTURE_THREADS, thread_name_prefix="phonglab-picture")
            all_there = threading.Barrier(PICTURE_THREADS)
            for started in [pool.submit(all_there.wait) for _ in range(PICTURE_THREADS)]:
                started.result()
            _threads = pool
        return _threads


def picture_url(job) -> str:
    """``job.finish()`` (the picture, uint8 RGB) as a PNG ``data:`` URL; no VTK, safe in a worker thread."""
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(job.finish()).save(buffer, format="PNG", compress_level=1)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


class PixelPicture:
    """The picture of one tab's view, its NumPy half made in a worker thread.

    Parameters
    ----------
    state : trame state
        Gets :data:`STATE_KEY` (flushed when a picture comes from the thread).
    notify : callable
        ``notify(kind, text)``: a notice on the page.

    Attributes
    ----------
    serial : int
        Counts requests and drops: a job's picture is shown only if no drop came after it started.
    pending : bool
        A newer picture than the one shown is being made (also in the state, :data:`PENDING_KEY`).
    """

    def __init__(self, state, notify):
        self.state = state
        self.notify = notify
        self.serial = 0
        self._dropped = 0  # the serial of the last drop: pictures started before it are not shown
        self._running = None  # the job in its thread (an asyncio future), or None
        self._next = None  # the newest request made while a job runs: (prepare, along)
        self._closed = False
        self.pending = False  # what PENDING_KEY says
        state[PENDING_KEY] = False

    @property
    def busy(self) -> bool:
        """True while a job is being finished in its thread."""
        return self._running is not None

    def request(self, prepare, along=None) -> None:
        """Show the picture ``prepare()`` stands for, once it is made, with ``along()``'s state.

        Parameters
        ----------
        prepare : callable
            Called in the loop's thread (now, or when the job running ends):
            does the VTK part and returns a job whose ``finish()`` makes the
            picture (:func:`phonglab.render.pixel_job.prepare`). Its
            exceptions reach the caller when it is called now.
        along : callable, optional
            Called right after ``prepare``, for the same view: a dict of state
            keys set together with the picture (what belongs to it).
        """
        self.serial += 1
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no server loop (scripts, tests): at once
            loop = None
        if loop is None:
            self._next = None
            job = prepare()
            extra = along() if along is not None else {}
            self.state[STATE_KEY] = picture_url(job)
            for key, value in extra.items():
                self.state[key] = value
            self._pending(False)
        elif self._running is not None:
            self._next = (prepare, along)  # made after the job running (a newer request replaces it)
            self._pending(True)
        else:
            self._pending(True)
            self._start(loop, prepare, along)

    def drop(self) -> None:
        """No picture is wanted (the page left pixel mode): a job running and a request waiting are not shown."""
        self.serial += 1
        self._dropped = self.serial
        self._next = None
        self._pending(False)

    def close(self) -> None:
        """The tab is closing: nothing more is started or shown."""
        self.drop()
        self._closed = True

    def _pending(self, value: bool) -> None:
        if self.pending != value:
            self.pending = value
            self.state[PENDING_KEY] = value

    def _start(self, loop, prepare, along=None) -> None:
        serial = self.serial
        job = prepare()  # the VTK part, here in the loop's thread
        extra = along() if along is not None else {}  # for the same view, now
        self._running = loop.run_in_executor(picture_threads(), picture_url, job)
        self._running.add_done_callback(functools.partial(self._done, serial, extra))

    def _done(self, serial: int, extra: dict, future) -> None:
        """Back in the loop's thread: show the picture unless it was dropped; start the request waiting."""
        self._running = None
        if self._closed:
            return
        try:
            url = future.result()
        except Exception as exc:
            log.exception("the per-pixel picture")
            if serial > self._dropped:
                self.notify("error", f"Could not make the per-pixel picture: {owned.reason(exc)}")
        else:
            if serial > self._dropped:
                self.state[STATE_KEY] = url
                for key, value in extra.items():
                    self.state[key] = value
        waiting, self._next = self._next, None
        if waiting is not None:
            try:
                self._start(asyncio.get_running_loop(), *waiting)
            except Exception as exc:
                log.exception("the per-pixel picture")
                self.notify("error", f"Could not make the per-pixel picture: {owned.reason(exc)}")
                self._pending(False)
        else:
            self._pending(False)
        self.state.flush()
