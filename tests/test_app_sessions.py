"""Sessions come and go without leaving anything behind, a busy server still reads every hello, and a signal stops it.

The footprint and signal tests run ``phonglab serve`` in a process of its
own and drive it with the simulated students of ``phonglab bench load``
(:mod:`phonglab.bench.load_student`), which speak the page's own protocol.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import signal
import threading
import time
from pathlib import Path
from types import SimpleNamespace

import aiohttp
import pytest
from app_support import in_thread, serving
from test_app_security import LESSON, Client, run, secret_of

from phonglab.app import server as server_module
from phonglab.bench import load
from phonglab.bench.load_student import Student
from phonglab.bench.ui import log_tail

LESSON_4 = Path(__file__).resolve().parents[1] / "lessons" / "04-specular.md"


@pytest.fixture()
def lessons(tmp_path) -> Path:
    (tmp_path / "01-sphere.md").write_text(LESSON, encoding="utf-8")
    return tmp_path


def test_closed_sessions_return_their_threads_and_memory(tmp_path):
    sessions = 4 * load.LEAK_BATCH
    with serving(LESSON_4, log_path=tmp_path / "serve.log") as served:
        found = load.session_footprint(served["url"], served["process"].pid, sessions)
        alive = served["process"].poll() is None
    print(found)
    threads, rss = found.grown()
    assert alive, log_tail(tmp_path / "serve.log")
    assert threads <= load.LEAK_TOLERANCE and rss <= load.LEAK_TOLERANCE, (
        f"{found}; allowed +{load.LEAK_TOLERANCE:.0%} each\n{log_tail(tmp_path / 'serve.log')}")


# ---------------------------------------------------------------------------
# a hello that arrives while the event loop is busy building another session


@pytest.fixture()
def slow_builds(lessons, monkeypatch):
    """A SessionServer whose session builds hold the event loop for twice the hello's time.

    ``building`` is set while a build holds the loop, so a test can send a
    hello exactly then.
    """
    from phonglab.app import make_app

    monkeypatch.setattr(server_module, "HELLO_SECONDS", 1.0)
    real = make_app(lessons)
    building = threading.Event()

    def build(name):
        app = real(name)
        if name != "__www__":
            building.set()
            time.sleep(2 * server_module.HELLO_SECONDS)  # the cost of building a large session, in the loop
            building.clear()
        return app

    opened = []
    server = server_module.SessionServer(build, on_session=lambda event, name: opened.append(event))
    with in_thread(server) as port:
        yield SimpleNamespace(port=port, building=building, opened=opened)


def test_a_hello_sent_while_another_session_is_built_is_read(slow_builds):
    async def attempt():
        secret = await secret_of(slow_builds.port)
        first, second, third = Client(slow_builds.port), Client(slow_builds.port), Client(slow_builds.port)
        for client in (first, second, third):
            await client.__aenter__()
        try:
            hello = asyncio.ensure_future(first.hello(secret))
            for _ in range(600):  # until the first session's build holds the server's loop
                if slow_builds.building.is_set():
                    break
                await asyncio.sleep(0.05)
            assert slow_builds.building.is_set(), "the first session was never built"
            answers = await asyncio.gather(hello, second.hello(secret), third.hello(secret))
            return answers, [c.ws.close_code for c in (first, second, third)]
        finally:
            for client in (first, second, third):
                await client.__aexit__()

    answers, codes = run(attempt())
    assert all(a and "result" in a for a in answers), (answers, codes)
    assert codes == [None, None, None], codes


# ---------------------------------------------------------------------------
# stopping


#: a bound for a stop: 8 times the 2 s aimed at, so the test does not flake under load (each tab that
#: never answers the close may hold its socket for STOP_SECONDS; they close together)
STOP_BOUND = 16.0


async def _silent_tab(url: str):
    """A logged-in tab that stops reading (a frozen or suspended browser): it never answers the close."""
    from test_app_security import Client

    port = int(url.rstrip("/").rsplit(":", 1)[1])
    client = Client(port)
    client.http = aiohttp.ClientSession()
    client.ws = await client.http.ws_connect(f"http://127.0.0.1:{port}/ws", headers={"Origin": client.origin},
                                             max_msg_size=0, autoclose=False, autoping=False)
    answer = await client.hello(await secret_of(port))
    assert answer and "result" in answer, answer
    return client


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signal_stops_the_server_and_closes_its_sessions(lessons, tmp_path, signum):
    with serving(lessons, log_path=tmp_path / "serve.log") as served:
        process = served["process"]

        async def stop():
            students = [Student(served["url"], seed=i) for i in range(2)]
            await asyncio.gather(*(s.open() for s in students))
            silent = [await _silent_tab(served["url"]) for _ in range(2)]
            try:
                await asyncio.gather(*(s.act() for s in students))
                sent = time.monotonic()
                process.send_signal(signum)
                while process.poll() is None and time.monotonic() - sent < STOP_BOUND:
                    await asyncio.sleep(0.02)
                took = time.monotonic() - sent
                for s in students:  # the server closed each socket: wait for the close to reach the client
                    await asyncio.wait_for(s.closed.wait(), 10)
                return took, [s._ws.close_code for s in students]
            finally:
                await asyncio.gather(*(s.close() for s in students))
                for client in silent:
                    client.ws._autoclose = True
                    await client.http.close()

        took, codes = run(stop())
        print(f"{signal.Signals(signum).name} with four sessions open, two of them not answering: "
              f"the server exited after {took:.2f} s")
        assert process.poll() is not None, f"still running {STOP_BOUND:.0f} s after {signal.Signals(signum).name}"
        assert process.returncode == 0, (process.returncode, log_tail(tmp_path / "serve.log"))
        assert codes == [aiohttp.WSCloseCode.GOING_AWAY] * 2, (codes, log_tail(tmp_path / "serve.log"))
        assert "Traceback" not in log_tail(tmp_path / "serve.log", 200), log_tail(tmp_path / "serve.log", 200)


def test_a_stop_signal_skips_the_sessions_still_waiting_to_be_built(lessons, monkeypatch):
    # the server runs in this (the main) thread, where a signal handler can be installed; the tabs in another
    from phonglab.app import make_app

    real = make_app(lessons)
    building = threading.Event()
    events = []

    def build(name):
        app = real(name)
        if name != "__www__":
            building.set()
            time.sleep(2.0)  # the cost of building a large session, in the loop (a signal interrupts the sleep)
        return app

    server = server_module.SessionServer(build, on_session=lambda event, name: events.append(event))
    tabs = {}

    def open_tabs(port):
        async def go():
            secret = await secret_of(port)
            clients = [Client(port) for _ in range(4)]
            for client in clients:
                await client.__aenter__()
            try:
                hello = {"wslink": "1.0", "id": "system:c0:0", "method": "wslink.hello",
                         "args": [{"secret": secret}], "kwargs": {}}
                await asyncio.gather(*(client.send(hello) for client in clients))
                for _ in range(600):
                    if building.is_set():
                        break
                    await asyncio.sleep(0.05)
                os.kill(os.getpid(), signal.SIGTERM)  # while the first build holds the loop
                for client in clients:
                    with contextlib.suppress(asyncio.TimeoutError):
                        while (await client.ws.receive(timeout=30)).type == aiohttp.WSMsgType.BINARY:
                            pass
                tabs["codes"] = [client.ws.close_code for client in clients]
            finally:
                for client in clients:
                    await client.__aexit__()

        threading.Thread(target=lambda: asyncio.run(go()), daemon=True).start()

    before = signal.getsignal(signal.SIGTERM)
    asyncio.run(asyncio.wait_for(server.run("127.0.0.1", 0, on_ready=open_tabs), 120))
    assert signal.getsignal(signal.SIGTERM) is before, "the server's signal handler was left in place"
    assert events.count("open") == 1, f"sessions built after the stop signal: {events}"
    assert events.count("close") == 1, events
