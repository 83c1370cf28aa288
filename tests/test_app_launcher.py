"""``phonglab serve --launcher``: one process per tab behind one address, with the single server's rules.

The launcher runs in a process of its own; the students are the simulated
ones of ``phonglab bench load`` (:mod:`phonglab.bench.load_student`) or raw
wslink clients, so each rule is tried the way a browser or an attacker would.
"""

from __future__ import annotations

import asyncio
import contextlib
import random
import socket
import struct
import time
from pathlib import Path
from types import SimpleNamespace

import aiohttp
import msgpack
import pytest
from app_support import serving
from test_app_security import LESSON, run

from phonglab.app import protocol
from phonglab.bench import load_server
from phonglab.bench.load_student import Student
from phonglab.bench.ui import log_tail

MAX_SESSIONS = 2
IDLE_SECONDS = 10


def free_range(count: int) -> int:
    """The first of ``count`` consecutive 127.0.0.1 ports that are free now."""
    for _ in range(200):
        first = random.randint(20000, 60000)
        try:
            for port in range(first, first + count):
                with socket.socket() as s:
                    s.bind(("127.0.0.1", port))
            return first
        except OSError:
            continue
    raise RuntimeError("no free port range")


def _launcher(tmp_path_factory, *flags):
    folder = tmp_path_factory.mktemp("lessons")
    (folder / "01-sphere.md").write_text(LESSON, encoding="utf-8")
    log_path = tmp_path_factory.mktemp("launcher") / "serve.log"
    first = free_range(MAX_SESSIONS)
    with serving(folder, "--launcher", "--max-sessions", str(MAX_SESSIONS), "--session-ports", str(first),
                 *flags, log_path=log_path, timeout=120) as served:
        yield SimpleNamespace(url=served["url"], port=served["port"], process=served["process"], log=log_path,
                              first=first)


@pytest.fixture(scope="module")
def launcher(tmp_path_factory):
    yield from _launcher(tmp_path_factory)


@pytest.fixture(scope="module")
def idle_launcher(tmp_path_factory):
    """A launcher that ends a tab's session after IDLE_SECONDS without a message."""
    yield from _launcher(tmp_path_factory, "--idle-timeout", str(IDLE_SECONDS))


@pytest.fixture(autouse=True)
def no_sessions_left(launcher):
    """Each test starts once the previous test's session processes have ended (their ports are free)."""
    run(wait_until(lambda: not sessions_of(launcher), "the previous test's session processes to end"))


def sessions_of(launcher) -> dict[int, int]:
    """The launcher's session processes now: pid -> port."""
    found = {}
    for pid in load_server.tree(launcher.process.pid)[1:]:
        try:
            words = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if b"--one-session" in words:
            found[pid] = int(words[words.index(b"--port") + 1])
    return found


async def wait_until(predicate, what: str, timeout: float = 60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        await asyncio.sleep(0.1)
    raise AssertionError(f"timed out after {timeout:.0f} s waiting for {what}; last value: {predicate()!r}")


def test_two_tabs_get_two_processes_and_closing_a_tab_ends_its_process(launcher):
    async def attempt():
        first, second = Student(launcher.url, seed=1), Student(launcher.url, seed=2)
        await first.open()
        await second.open()
        try:
            both = sessions_of(launcher)
            moved = [await s.act() for s in (first, second)]
            await first.close()
            remaining = await wait_until(lambda: len(sessions_of(launcher)) == 1 and sessions_of(launcher),
                                         "the closed tab's process to end")
            return both, moved, remaining
        finally:
            await first.close()
            await second.close()

    both, moved, remaining = run(attempt())
    assert len(both) == 2 and len(set(both.values())) == 2, both
    assert all(port in range(launcher.first, launcher.first + MAX_SESSIONS) for port in both.values()), both
    assert all(t.reply is not None for t in moved), moved
    assert set(remaining) < set(both), (both, remaining)
    assert launcher.process.poll() is None, log_tail(launcher.log)


@contextlib.asynccontextmanager
async def every_slot_taken(launcher):
    """MAX_SESSIONS students with their tabs open (closed again on the way out)."""
    students = [Student(launcher.url, seed=i) for i in range(MAX_SESSIONS)]
    try:
        for s in students:
            await s.open()
        yield students
    finally:
        for s in students:
            await s.close()


def test_a_tab_past_the_session_limit_is_told_the_server_is_full(launcher):
    async def attempt():
        async with every_slot_taken(launcher), aiohttp.ClientSession() as http:
            async with http.post(launcher.url + "paraview/", json={},
                                 headers={"Origin": f"http://127.0.0.1:{launcher.port}"}) as answer:
                return answer.status, await answer.json()

    status, answer = run(attempt())
    assert status == 503 and "full" in answer["error"], (status, answer)


@pytest.mark.parametrize("origin", ["http://evil.example", "null", None])
def test_a_foreign_origin_is_refused_at_the_launcher_and_the_proxy(launcher, origin):
    async def attempt():
        headers = {"Origin": origin} if origin else {}
        async with aiohttp.ClientSession() as http:
            async with http.post(launcher.url + "paraview/", json={}, headers=headers) as answer:
                launched = answer.status
            with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                await http.ws_connect(launcher.url + "proxy/x", headers=headers)
            return launched, refused.value.status

    assert run(attempt()) == (403, 403), origin


async def _raw_session(launcher, secret_change=lambda s: s):
    """POST /paraview/, then the proxy's WebSocket with the (changed) secret: (ws, http, hello answer)."""
    origin = f"http://127.0.0.1:{launcher.port}"
    http = aiohttp.ClientSession()
    async with http.post(launcher.url + "paraview/", json={}, headers={"Origin": origin}) as answer:
        launch = await answer.json()
    if "sessionURL" not in launch:
        await http.close()
        raise AssertionError(f"the launcher answered {answer.status} {launch!r}")
    url = launch["sessionURL"].replace("USE_HOST", f"127.0.0.1:{launcher.port}").replace("ws://", "http://")
    ws = await http.ws_connect(url, headers={"Origin": origin}, max_msg_size=0)
    hello = {"wslink": "1.0", "id": protocol.HELLO_ID, "method": "wslink.hello",
             "args": [{"secret": secret_change(launch["secret"])}], "kwargs": {}}
    await ws.send_bytes(protocol.chunk(msgpack.packb(hello)))
    reply = await ws.receive(timeout=60)
    answer = msgpack.unpackb(reply.data[protocol.HEADER.size:]) if reply.type == aiohttp.WSMsgType.BINARY else None
    return ws, http, answer


def test_a_wrong_secret_through_the_launcher_opens_no_session(launcher):
    async def attempt():
        ws, http, answer = await _raw_session(launcher, lambda secret: "wslink-secret")
        try:
            await ws.receive(timeout=30)
            return answer, ws.close_code
        finally:
            await ws.close()
            await http.close()

    answer, code = run(attempt())
    assert answer["error"]["code"] == protocol.AUTHENTICATION_ERROR, answer
    assert code == aiohttp.WSCloseCode.POLICY_VIOLATION, code
    assert run(wait_until(lambda: not sessions_of(launcher), "the refused session's process to end")) is True


def test_an_oversized_message_through_the_launcher_closes_the_socket(launcher):
    async def attempt():
        ws, http, answer = await _raw_session(launcher)
        try:
            assert answer and "result" in answer, answer
            await ws.send_bytes(struct.pack("<III", 7, 0, protocol.MAX_MESSAGE_BYTES + 1) + b"x" * 16)
            await ws.receive(timeout=30)
            return ws.close_code
        finally:
            await ws.close()
            await http.close()

    assert run(attempt()) == aiohttp.WSCloseCode.POLICY_VIOLATION


def test_an_idle_tab_is_closed_and_its_process_ended(idle_launcher):
    launcher = idle_launcher

    async def attempt():
        student = Student(launcher.url, seed=9)
        await student.open()
        started = time.monotonic()
        try:
            await asyncio.wait_for(student.closed.wait(), 10 * IDLE_SECONDS)
            took = time.monotonic() - started
            await wait_until(lambda: not sessions_of(launcher), "the idle session's process to end")
            return took, student._ws.close_code
        finally:
            await student.close()

    took, code = run(attempt())
    print(f"an idle tab was closed after {took:.1f} s (idle timeout {IDLE_SECONDS} s)")
    assert took >= IDLE_SECONDS and code == aiohttp.WSCloseCode.GOING_AWAY, (took, code)


def test_an_unknown_session_id_is_refused(launcher):
    async def attempt():
        async with aiohttp.ClientSession() as http:
            with pytest.raises(aiohttp.WSServerHandshakeError) as refused:
                await http.ws_connect(launcher.url + "proxy/nope",
                                      headers={"Origin": f"http://127.0.0.1:{launcher.port}"})
            return refused.value.status

    assert run(attempt()) == 404


def test_a_tab_reloaded_at_the_session_limit_gets_the_slot_its_old_tab_gives_back(launcher):
    """A reload closes the old tab's socket and asks for a session at once; its old process is still stopping."""
    async def attempt():
        async with every_slot_taken(launcher) as students:
            await students[0].close()  # the reload: no wait for the old process to end
            ws, http, answer = await _raw_session(launcher)
            await ws.close()
            await http.close()
            return answer

    answer = run(attempt())
    assert answer and "result" in answer, answer
