"""``phonglab bench ui``, the page's Export PNG: click to the browser's download, first and later.

A student who opens the page and exports at once meets the server's worker
processes as they are just after it started; a later export finds them
ready. Both are timed in the benchmark's own page, from the click on
"Export PNG" to the moment the browser has the download:

* the first export after the server started, as soon as the page has drawn
  its first picture (the time since the server started is printed with it:
  the workers start with the server and warm up in the background
  meanwhile, :mod:`phonglab.app.worker`);
* :data:`LATER` exports after the key-press rounds, each once the previous
  one has downloaded.

The machine's load average is printed with the figures: on a loaded
machine an export takes several times as long.
"""

from __future__ import annotations

import os
import statistics
import time

#: the page's export button
EXPORT_BUTTON = ".phonglab-export"
#: exports timed after the first
LATER = 3
#: the longest one export may take before the benchmark gives up, in ms
EXPORT_TIMEOUT_MS = 600_000


def time_export(page) -> float:
    """Seconds from a click on the page's Export PNG to the download in the browser."""
    with page.expect_download(timeout=EXPORT_TIMEOUT_MS) as download:
        started = time.perf_counter()
        page.locator(EXPORT_BUTTON).click()
    download.value  # the download has arrived when the block ends
    return time.perf_counter() - started


def first_export(page, server_started: float) -> dict:
    """The first export after the server started (``server_started``: its ``time.monotonic()``)."""
    after = time.monotonic() - server_started
    return {"seconds": time_export(page), "after_start": after, "load": os.getloadavg()[0]}


def later_exports(page, count: int = LATER) -> dict:
    """``count`` exports, one after the other."""
    seconds = [time_export(page) for _ in range(count)]
    return {"seconds": seconds, "load": os.getloadavg()[0]}


def report(first: dict, later: dict) -> None:
    """Print the export times: the first, the later ones' median, their ratio and the load average."""
    median = statistics.median(later["seconds"])
    print(f"export PNG, click to download: first after the server started {first['seconds']:.1f} s "
          f"(clicked {first['after_start']:.0f} s after the start, load average {first['load']:.1f}); "
          f"later ones median {median:.1f} s of {len(later['seconds'])} "
          f"({', '.join(f'{s:.1f}' for s in later['seconds'])} s, load average {later['load']:.1f}); "
          f"first / later {first['seconds'] / median:.2f}")
