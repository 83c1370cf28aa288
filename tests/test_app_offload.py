"""Heavy work from one tab (an export, the accuracy lesson's first run) leaves the other tabs responsive.

``phonglab serve`` runs in its own process. Tab B measures the round trip of
a cheap call (the measure of the flood test of ``tests/test_app_security.py``:
the median of many calls, here sent on a fixed schedule so that a stall
counts for every call it delays) while idle, then
while tab A makes the server do seconds of work: exporting figures again
and again, or the accuracy lesson's first run (its studies, from the moment
the lesson is open: opening a lesson rebuilds the page's controls in the
loop, which is not what is measured here). The busy phase lasts until tab A's work is delivered, so it is defined by
work done, not by a clock. The busy median must stay within
:data:`BOUND` × the idle median measured in the same run.

Run in the event loop (as before the work moved to worker processes), each
export holds the loop for seconds and tab B's median round trip grows by a
factor of hundreds. The accuracy lesson's studies already ran in worker
processes; its test guards that they stay there.
"""

from __future__ import annotations

import asyncio
import re
import statistics
import threading
import time
from pathlib import Path
from types import SimpleNamespace

import msgpack
import pytest

from phonglab.app import protocol
from app_support import serving
from phonglab.bench.ui import log_tail
from test_app_security import LESSON, logged_in

ROOT = Path(__file__).resolve().parents[1]
#: tab B's busy median round trip may be at most this many times its idle median. What this
#: guards against is the loop held for seconds (an export in the loop: 100-250x here). The
#: workers share the machine's cores with the server, which costs its loop a few milliseconds
#: of wake-up latency against an idle median of about one (2-5x measured on 2 loaded cores)
BOUND = 10.0
#: round trips in the idle median
IDLE_PROBES = 100
#: fewest round trips in the busy median
BUSY_PROBES = 100
#: seconds between two of tab B's calls
PROBE_EVERY = 0.05
#: exports tab A must receive within its busy phase
EXPORTS = 2
#: the longest tab A's busy phase lasts (it ends earlier when its work is delivered)
BUSY_SECONDS = 90.0
PROBE_CALL = ("trame.lifecycle.update", ["client_unmounted"])


@pytest.fixture(scope="module")
def own_process(tmp_path_factory):
    lessons = tmp_path_factory.mktemp("lessons")
    (lessons / "01-sphere.md").write_text(LESSON, encoding="utf-8")
    (lessons / "02-accuracy.md").write_text((ROOT / "lessons" / "11-accuracy.md").read_text(encoding="utf-8"),
                                            encoding="utf-8")
    with serving(lessons, log_path=tmp_path_factory.mktemp("serve") / "serve.log") as server:
        yield SimpleNamespace(port=server["port"], process=server["process"], log=server["log"])


def trigger_of(template: str, args: str) -> str:
    """The trigger the page calls with ``args`` (as written in the page's template)."""
    found = re.search(r"trigger\('(trigger__\d+)',\s*\[" + re.escape(args) + r"\]", template)
    assert found, f"no trigger called with [{args}] in the page's template"
    return found.group(1)


class Messages:
    """Every message to a raw client, reassembled from its chunks, handed to ``seen`` as bytes."""

    def __init__(self, client, seen):
        self.client, self.seen, self.pending = client, seen, {}

    async def pump(self, until) -> None:
        while not until():
            try:
                message = await self.client.ws.receive(timeout=0.2)
            except asyncio.TimeoutError:
                continue
            if not isinstance(message.data, bytes):
                return  # the socket closed
            key, _, size = protocol.HEADER.unpack_from(message.data)
            self.pending[key] = self.pending.get(key, b"") + message.data[protocol.HEADER.size:]
            if len(self.pending[key]) >= size:
                self.seen(msgpack.unpackb(self.pending.pop(key), strict_map_key=False))


class Prober:
    """Tab B: sends the cheap call every :data:`PROBE_EVERY` seconds, whether or not the last one was answered.

    Each round trip is the time from sending a call to its answer. Calls go
    out on a fixed schedule (not after the previous answer), so a stall of
    the server's loop delays every call that falls into it, not just one.
    """

    def __init__(self, client):
        self.client, self.sent, self.times, self.serial = client, {}, [], 0
        self.messages = Messages(client, self._seen)

    def _seen(self, message):
        started = self.sent.pop(message.get("id"), None)
        if started is not None:
            assert "error" not in message, message
            self.times.append(time.perf_counter() - started)

    async def probe(self, enough) -> list[float]:
        """Round trips of calls sent until ``enough()``; every answer awaited."""
        self.times = []
        stop = False
        pump = asyncio.create_task(self.messages.pump(lambda: stop))
        try:
            while not enough():
                self.serial += 1
                rpc_id = f"rpc:c1:probe{self.serial}"
                method, args = PROBE_CALL
                self.sent[rpc_id] = time.perf_counter()
                await self.client.send({"wslink": "1.0", "id": rpc_id, "method": method, "args": args, "kwargs": {}})
                await asyncio.sleep(PROBE_EVERY)
            for _ in range(1200):  # the answers still on their way
                if not self.sent:
                    break
                await asyncio.sleep(0.1)
            assert not self.sent, f"{len(self.sent)} calls were never answered"
        finally:
            stop = True
            await pump
        return self.times


def run(coroutine, seconds: float = 300.0):
    """Run ``coroutine`` in a thread of its own (as ``test_app_security.run``, with a longer limit)."""
    outcome = {}

    def target():
        try:
            outcome["value"] = asyncio.run(asyncio.wait_for(coroutine, seconds))
        except BaseException as exc:  # handed to the test's thread
            outcome["error"] = exc

    thread = threading.Thread(target=target)
    thread.start()
    thread.join(seconds + 30)
    if "error" in outcome:
        raise outcome["error"]
    assert "value" in outcome, f"the clients did not finish within {seconds + 30:.0f} s"
    return outcome["value"]


def in_thread(coroutine_function, *args):
    """Run ``coroutine_function(*args)`` in a thread with its own event loop (another browser tab)."""
    outcome = {}
    thread = threading.Thread(target=lambda: outcome.update(value=asyncio.run(coroutine_function(*args))),
                              daemon=True)
    thread.start()
    return thread, outcome


def published(message, key) -> list:
    """The state changes holding ``key`` in a state publication (empty for other messages)."""
    change = message.get("result")
    if str(message.get("id", "")).startswith("publish:trame.state.topic") and isinstance(change, dict) and key in change:
        return [change]
    return []


def measure(port: int, work, finished) -> tuple[float, float, list[float], dict]:
    """Tab B's idle and busy medians around tab A's ``work(client, tab)`` coroutine."""
    tab = {"done": False, "stop": False}

    async def tab_a():
        client = await logged_in(port)
        try:
            return await work(client, tab)
        finally:
            await client.__aexit__()

    async def tab_b():
        client = await logged_in(port)
        try:
            prober = Prober(client)
            await prober.probe(lambda: prober.serial >= 10)  # a session's first calls are not its pace
            idle = await prober.probe(lambda: len(prober.sent) + len(prober.times) >= IDLE_PROBES)
            thread, outcome = in_thread(tab_a)
            for _ in range(1200):  # tab A logs in and starts its work (opening a lesson is not part of it)
                if tab.get("started"):
                    break
                await asyncio.sleep(0.1)
            busy = await prober.probe(lambda: finished(tab) and len(prober.sent) + len(prober.times) >= BUSY_PROBES)
            tab["stop"] = True
            await asyncio.to_thread(thread.join, 120)
            # idle again once the work is done: the machine's load drifts meanwhile
            idle += await prober.probe(lambda: len(prober.sent) + len(prober.times) >= IDLE_PROBES)
            return idle, busy, outcome.get("value", {})
        finally:
            await client.__aexit__()

    idle, busy, report = run(tab_b())
    return statistics.median(idle), statistics.median(busy), busy, report


def check_ratio(own_process, label, attempts_made, idle, busy, times, report):
    ordered = sorted(times)
    slow = sum(t > 0.1 for t in times) / len(times)
    line = (f"{label}: idle {idle * 1000:.2f} ms, busy {busy * 1000:.2f} ms (median of {len(times)}; "
            f"90th percentile {ordered[int(0.9 * len(times))] * 1000:.0f} ms, max {ordered[-1] * 1000:.0f} ms, "
            f"{slow:.0%} over 100 ms), ratio {busy / idle:.2f}, tab A {report}")
    attempts_made.append(line)
    print("round trip", line)
    assert own_process.process.poll() is None, log_tail(own_process.log)
    return busy <= BOUND * idle


def measure_within_bound(server, label, busy, enough):
    """Measure tab B while tab A runs ``busy``, up to three times (the machine is shared); fail if never within BOUND.

    ``enough(report)`` is None when tab A got its work done, else what it lacks (the test fails on it at once).
    """
    attempts = []
    for _ in range(3):  # the first measurement within the bound counts
        idle, busy_s, times, report = measure(server.port, busy, lambda tab: tab["done"])
        lacking = enough(report)
        assert lacking is None, f"{lacking}: {report}\n" + log_tail(server.log)
        if check_ratio(server, label, attempts, idle, busy_s, times, report):
            return
    pytest.fail(f"tab B's round trip passed {BOUND}x its idle value in every attempt:\n" + "\n".join(attempts))


def test_exports_from_one_tab_leave_another_tab_responsive(own_process):
    async def exporting(client, tab):
        state = (await client.call("trame.state.get"))["result"]["state"]
        export = trigger_of(state["trame__template_main"], "'render'")
        downloads, clicks, refused = [], 0, 0

        def seen(message):
            nonlocal refused
            for change in published(message, "phonglab_download"):
                if change["phonglab_download"]:
                    downloads.append(change["phonglab_download"]["name"])
            for change in published(message, "notice"):
                if "try again" in str(change["notice"]):
                    refused += 1

        messages = Messages(client, seen)
        pump = asyncio.create_task(messages.pump(lambda: tab["stop"]))
        tab["started"] = True
        deadline = time.monotonic() + BUSY_SECONDS
        try:
            while len(downloads) < EXPORTS and time.monotonic() < deadline:
                # one export after the other, and a second click while the first is made
                before = len(downloads)
                for _ in range(2 if clicks == 0 else 1):
                    await client.send({"wslink": "1.0", "id": f"rpc:c1:export{clicks}", "method": "trame.trigger",
                                       "args": [export, ["render"], {}], "kwargs": {}})
                    clicks += 1
                    await asyncio.sleep(0.5)
                while len(downloads) == before and time.monotonic() < deadline:
                    await asyncio.sleep(0.1)
        finally:
            tab["done"] = True
            tab["stop"] = True
            await pump
        return {"clicks": clicks, "downloads": len(downloads), "told to try again": refused}

    measure_within_bound(own_process, "exports", exporting,
                         lambda report: None if report.get("downloads", 0) >= EXPORTS else "tab A got no figures")


def test_the_accuracy_lessons_first_run_leaves_another_tab_responsive(own_process):
    async def opening(client, tab):
        state = (await client.call("trame.state.get"))["result"]["state"]
        open_lesson = trigger_of(state["trame__template_main"], "item.index")
        plots = []

        def seen(message):
            if message.get("id") == "rpc:c1:open":  # the lesson is open: its studies run from here on
                tab["open ms"] = round((time.perf_counter() - tab["opened"]) * 1000)
                tab["started"] = True
            for change in published(message, "accuracy_plot"):
                plots.append(change["accuracy_plot"].get("status"))

        messages = Messages(client, seen)
        pump = asyncio.create_task(messages.pump(lambda: tab["stop"]))
        deadline = time.monotonic() + BUSY_SECONDS
        try:
            tab["opened"] = time.perf_counter()
            await client.send({"wslink": "1.0", "id": "rpc:c1:open", "method": "trame.trigger",
                               "args": [open_lesson, [1], {}], "kwargs": {}})
            while time.monotonic() < deadline and not any(status in ("ready", "failed") for status in plots):
                await asyncio.sleep(0.1)
        finally:
            tab["done"] = True
            tab["stop"] = True
            await pump
        return {"plot": plots, "open ms": tab.get("open ms")}

    idle, busy, times, report = measure(own_process.port, opening, lambda tab: tab["done"])
    attempts = []
    ok = check_ratio(own_process, "accuracy first run", attempts, idle, busy, times, report)
    assert report["plot"][-1:] == ["ready"], f"the accuracy plot did not arrive: {report}\n" + log_tail(own_process.log)
    # the studies run once per server: a second measurement would not be a first run
    assert ok, f"tab B's round trip passed {BOUND}x its idle value:\n" + "\n".join(attempts)
