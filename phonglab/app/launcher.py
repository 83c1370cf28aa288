"""``phonglab serve --launcher``: one phonglab process per browser tab, behind one address.

The session server (:mod:`phonglab.app.server`) runs every tab in one
process, on one event loop: one core serves the whole class. This front
uses wslink's own launcher, the one trame documents for multi-user
deployments (``wslink.launcher``: a session manager handing out ports from a
range, a process manager starting one command per session and waiting for
its ready line, a proxy mapping from session id to port), so that each tab
gets a process of its own and a class spreads over all the machine's cores:

1. the page asks ``POST /paraview/`` (its own origin only, as before);
   the front takes a port from the range, starts ``phonglab serve LESSON
   --port P`` for one session on 127.0.0.1 with a fresh secret (handed over
   in the environment, not on the command line), waits for its ready line,
   and answers ``sessionURL = ws(s)://USE_HOST/proxy/ID`` and the
   secret;
2. the page's WebSocket ``/proxy/ID`` (its own origin only) is
   joined to that process's ``/ws``; the process checks the hello's secret,
   every message's size, method and arguments and the pace, exactly as a
   single server does;
3. when the tab's socket closes, when it sends nothing for ``idle``
   seconds, or when it never connects, the process is stopped and its port
   returned. At most ``max_sessions`` processes run at once (the port
   range's size); the next tab is told the server is full.

The browser sees one address; the session processes listen on 127.0.0.1 only.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import secrets
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

import aiohttp
from aiohttp import web
from wslink import launcher as wslink_launcher

from phonglab.app import guard, protocol
from phonglab.app.server import (FULL_MESSAGE, STOP_SECONDS, add_page_routes, check_origin, listen, normal_prefix,
                                 on_stop_signals)

log = logging.getLogger(__name__)

#: the environment variable that hands a session process its secret
SECRET_ENV = "PHONGLAB_SESSION_SECRET"
#: the line a session process prints once it accepts connections (``phonglab serve``'s own)
READY_LINE = "phonglab: serving"
#: seconds a session process has to print its ready line
START_SECONDS = 60
#: seconds a tab has to open its WebSocket after the launcher answered it
CONNECT_SECONDS = 30
#: seconds without a message from the tab before its session is ended (students who left a tab open)
IDLE_SECONDS = 30 * 60
#: the first port of the session processes' range, unless told otherwise
FIRST_PORT = 9100
#: seconds a session process has to exit after SIGTERM before it is killed
KILL_SECONDS = 5 * STOP_SECONDS
#: seconds a launch waits for a slot when every port is taken, so that a tab
#: reloaded at the session limit gets the slot its old process is giving back
SLOT_SECONDS = KILL_SECONDS + 1


def launcher_config(*, command: list[str], first_port: int, sessions: int, log_dir: str, timeout: int) -> dict:
    """The launcher's configuration, in the form of wslink's launcher file.

    ``${port}`` in ``command`` is replaced by the session's port. Written to
    ``log_dir/launcher.json`` for reference; the same dict drives this front.
    """
    return {
        "configuration": {
            "host": "127.0.0.1", "port": 0, "endpoint": "paraview", "log_dir": log_dir,
            "proxy_file": str(Path(log_dir) / "proxy-mapping.txt"),
            "sessionURL": "ws://USE_HOST/proxy/${id}",
            "timeout": timeout, "fields": [], "sanitize": {},
        },
        "resources": [{"host": "127.0.0.1", "port_range": [first_port, first_port + sessions - 1]}],
        "properties": {},
        "apps": {"phonglab": {"cmd": command, "ready_line": READY_LINE}},
    }


class _Processes(wslink_launcher.ProcessManager):
    """wslink's process manager, with the secret in the environment and each process in its own group."""

    def startProcess(self, session):  # noqa: N802 (wslink's name)
        log_path = self._getLogFilePath(session["id"])
        with log_path.open("a+", buffering=1, encoding="utf-8") as output:
            try:
                process = subprocess.Popen(session["cmd"], stdout=output, stderr=subprocess.STDOUT,
                                           stdin=subprocess.DEVNULL, start_new_session=True,
                                           env={**os.environ, SECRET_ENV: session["secret"]})
            except OSError:
                log.exception("could not start a session process: %s", " ".join(session["cmd"]))
                return None
        self.processes[session["id"]] = process
        return process



def _stop(process: subprocess.Popen) -> None:
    """SIGTERM (the session process closes its tab and exits), then SIGKILL after a few seconds."""
    with contextlib.suppress(ProcessLookupError):
        process.send_signal(signal.SIGTERM)
    try:
        process.wait(timeout=KILL_SECONDS)
    except subprocess.TimeoutExpired:
        with contextlib.suppress(ProcessLookupError):
            process.kill()
        process.wait()


class Launcher:
    """Serve the page and start one session process per tab (see the module's notes).

    Parameters
    ----------
    make_app : callable
        As for :class:`~phonglab.app.server.SessionServer`; built once, for the page's static files.
    command : list of str
        A session process's command line, with ``${port}`` for its port; it
        reads its secret from :data:`SECRET_ENV` and serves one tab.
    max_sessions : int
        Session processes at once (ports ``first_port`` … ``first_port + max_sessions - 1``).
    allow_origins : iterable of str
        Origins allowed besides the page's own.
    idle : float
        Seconds without a message from a tab before its session ends.
    on_session : callable, optional
        Called with ``(event, session id, pid)`` for ``"start"`` and ``"stop"`` (tests, logging).
    url_prefix : str
        The path a proxy serves the page under (see :class:`~phonglab.app.server.SessionServer`).
    """

    def __init__(self, make_app: Callable, *, command: list[str], max_sessions: int = guard.DEFAULT_MAX_SESSIONS,
                 first_port: int = FIRST_PORT, allow_origins=(), idle: float = IDLE_SECONDS,
                 on_session: Callable | None = None, url_prefix: str = "/"):
        self.origins = guard.OriginPolicy(allow_origins)
        self.max_sessions = max_sessions
        self.idle = idle
        self.url_prefix = normal_prefix(url_prefix)
        self._on_session = on_session
        self._log_dir = tempfile.mkdtemp(prefix="phonglab-launcher-")
        self.config = launcher_config(command=command, first_port=first_port, sessions=max_sessions,
                                      log_dir=self._log_dir, timeout=START_SECONDS)
        mapping = wslink_launcher.ProxyMappingManagerTXT(self.config["configuration"]["proxy_file"])
        self.sessions = wslink_launcher.SessionManager(self.config, mapping)
        self.processes = _Processes(self.config)
        self._connected: set[str] = set()
        self._ending: set = set()  # tasks ending sessions no tab connected to
        self._stopping: set[str] = set()  # sessions whose process is being stopped
        self._freed = asyncio.Event()  # set each time a session's port is given back
        self._sockets: set = set()
        self._stopped = None
        self.web_app = web.Application()
        self.web_app.router.add_post("/paraview/", self._launch)
        self.web_app.router.add_get("/proxy/{session}", self._proxy)
        add_page_routes(self.web_app, make_app)

    # ------------------------------------------------------------------
    # starting a tab's process

    def _check_origin(self, request: web.Request) -> None:
        check_origin(self.origins, request)

    async def _launch(self, request: web.Request):
        self._check_origin(request)
        session = await self._free_slot()
        if session is None:
            full = FULL_MESSAGE.format(n=self.max_sessions)
            log.warning("launch refused: %s", full)
            return web.json_response({"error": full}, status=503, headers={"Cache-Control": "no-store"})
        process = self.processes.startProcess(session)
        if process is None:
            self.sessions.deleteSession(session["id"])
            return web.json_response({"error": "The session could not be started."}, status=503)
        self._notify("start", session["id"], process.pid)
        started = time.monotonic()
        while not self.processes.isReady(session, 0) or not self.processes.isRunning(session["id"]):
            if not self.processes.isRunning(session["id"]) or time.monotonic() - started > START_SECONDS:
                log.error("session process %s did not start:\n%s", session["id"], self._log_tail(session["id"]))
                await self._end(session["id"])
                return web.json_response({"error": "The session could not be started."}, status=503)
            await asyncio.sleep(0.05)
        asyncio.get_running_loop().call_later(CONNECT_SECONDS, self._end_unconnected, session["id"])
        scheme = "wss" if request.headers["Origin"].lower().startswith("https:") else "ws"
        return web.json_response({"sessionURL": f"{scheme}://USE_HOST{self.url_prefix}proxy/{session['id']}",
                                  "secret": session["secret"]}, headers={"Cache-Control": "no-store"})

    async def _free_slot(self):
        """A new session with a port, or None when none came free within SLOT_SECONDS.

        A tab that closes gives its port back only once its process has
        exited, a second or so later; a reload at the session limit would be
        told the server is full by its own old tab without this wait.
        """
        loop = asyncio.get_running_loop()
        deadline = loop.time() + SLOT_SECONDS
        while True:
            await self._reap()
            # nothing from the request reaches the command line: the options are the launcher's own
            session = self.sessions.createSession({"application": "phonglab", "secret": secrets.token_urlsafe(32)})
            remaining = deadline - loop.time()
            if session is not None or remaining <= 0:
                return session
            self._freed.clear()
            with contextlib.suppress(asyncio.TimeoutError):
                # a port given back wakes the wait; a process that ended by itself is found by _reap
                await asyncio.wait_for(self._freed.wait(), min(remaining, STOP_SECONDS))

    def _log_tail(self, session_id: str) -> str:
        try:
            return "\n".join(self.processes._getLogFilePath(session_id).read_text(errors="replace").splitlines()[-20:])
        except OSError:
            return ""

    def _end_unconnected(self, session_id: str) -> None:
        if session_id not in self._connected and self.sessions.getSession(session_id) is not None:
            log.warning("session %s: no tab connected within %s s; ending it", session_id, CONNECT_SECONDS)
            self._ending.add(asyncio.ensure_future(self._end(session_id)))

    async def _end(self, session_id: str) -> None:
        """Stop a session's process (in a thread: it may take a second), then give its port back.

        Only the event loop's thread changes the session and port books, and a
        port is handed out again only once its process has exited.
        """
        if session_id in self._stopping:
            return
        self._stopping.add(session_id)
        process = self.processes.processes.pop(session_id, None)
        try:
            if process is not None:
                await asyncio.to_thread(_stop, process)
                self._notify("stop", session_id, process.pid)
        finally:
            if self.sessions.getSession(session_id) is not None:
                self.sessions.deleteSession(session_id)
            self._connected.discard(session_id)
            self._stopping.discard(session_id)
            self._freed.set()
            with contextlib.suppress(OSError):
                self.processes._getLogFilePath(session_id).unlink()

    async def _reap(self) -> None:
        """Give back the ports of processes that ended by themselves (their tab closed)."""
        for session_id in self.processes.listEndedProcess():
            await self._end(session_id)

    def _notify(self, event: str, session_id: str, pid: int) -> None:
        if self._on_session is not None:
            self._on_session(event, session_id, pid)

    # ------------------------------------------------------------------
    # the tab's WebSocket, joined to its process

    async def _proxy(self, request: web.Request):
        self._check_origin(request)
        session_id = request.match_info["session"]
        session = self.sessions.getSession(session_id)
        if session is None or session_id in self._connected:
            raise web.HTTPNotFound(text="no such session\n")
        self._connected.add(session_id)
        port = session["port"]
        socket = web.WebSocketResponse(max_msg_size=protocol.MAX_FRAME_BYTES, timeout=STOP_SECONDS,
                                       heartbeat=30)
        await socket.prepare(request)
        self._sockets.add(socket)
        try:
            async with aiohttp.ClientSession() as http:
                async with http.ws_connect(f"http://127.0.0.1:{port}/ws", headers={"Origin": f"http://127.0.0.1:{port}"},
                                           max_msg_size=0) as upstream:
                    await self._join(socket, upstream)
        except (aiohttp.ClientError, OSError) as exc:
            log.warning("session %s: %s", session_id, exc)
        finally:
            self._sockets.discard(socket)
            if not socket.closed:
                await socket.close()
            await self._end(session_id)
        return socket

    async def _join(self, browser: web.WebSocketResponse, upstream) -> None:
        """Relay both ways until either side closes or the tab is idle; a close is passed on with its code."""
        last = [time.monotonic()]

        async def up():
            async for message in browser:
                last[0] = time.monotonic()
                if message.type == aiohttp.WSMsgType.BINARY:
                    await upstream.send_bytes(message.data)
                elif message.type == aiohttp.WSMsgType.TEXT:
                    await upstream.send_str(message.data)
            await upstream.close()

        async def down():
            closing = (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSING, aiohttp.WSMsgType.CLOSED,
                       aiohttp.WSMsgType.ERROR)
            while True:
                message = await upstream.receive()
                if message.type in closing:
                    break
                if message.type == aiohttp.WSMsgType.BINARY:
                    await browser.send_bytes(message.data)
                elif message.type == aiohttp.WSMsgType.TEXT:
                    await browser.send_str(message.data)
            # the session's own close (1008 refused, 1013 full, 1001 stopping) reaches the page with its reason
            reason = message.extra if message.type == aiohttp.WSMsgType.CLOSE and isinstance(message.extra, str) else ""
            await browser.close(code=upstream.close_code or aiohttp.WSCloseCode.GOING_AWAY,
                                message=reason.encode()[:120])

        async def idle():
            while True:
                await asyncio.sleep(min(60.0, self.idle / 4))
                if time.monotonic() - last[0] > self.idle:
                    await browser.close(code=aiohttp.WSCloseCode.GOING_AWAY, message=b"idle: reload the page")
                    return

        tasks = [asyncio.ensure_future(t) for t in (up(), down(), idle())]
        try:
            await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
        finally:
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

    # ------------------------------------------------------------------
    # running

    async def run(self, host: str = "127.0.0.1", port: int = 8080, on_ready: Callable | None = None) -> None:
        """Listen until :meth:`stop`, SIGINT or SIGTERM; then end every session process."""
        loop = asyncio.get_running_loop()
        self._stopped = loop.create_future()
        restore = on_stop_signals(loop, self.stop, lambda: None)
        (Path(self._log_dir) / "launcher.json").write_text(_json(self.config), encoding="utf-8")
        try:
            await listen(self.web_app, host, port, on_ready, self._stopped, self._close_all)
        finally:
            restore()
            shutil.rmtree(self._log_dir, ignore_errors=True)

    async def _close_all(self) -> None:
        """Close every tab's socket (code 1001), then end every session process."""
        await asyncio.gather(*(s.close(code=aiohttp.WSCloseCode.GOING_AWAY, message=b"server stopping")
                               for s in list(self._sockets)), return_exceptions=True)
        await self._end_all()

    async def _end_all(self) -> None:
        for process in list(self.processes.processes.values()):  # all at once: each closes its tab and exits
            with contextlib.suppress(ProcessLookupError):
                process.send_signal(signal.SIGTERM)
        await asyncio.gather(*(self._end(session_id) for session_id in list(self.processes.processes)),
                             *self._ending, return_exceptions=True)

    def stop(self) -> None:
        """Ask :meth:`run` to return."""
        if self._stopped is not None and not self._stopped.done():
            self._stopped.set_result(True)


def _json(config: dict) -> str:
    import json

    return json.dumps(config, indent=2)


def session_command(target, *, allow_student_code: bool = False, export_dir=None) -> list[str]:
    """The command line of one session process for ``target`` (``${port}`` stands for its port)."""
    command = [sys.executable, "-m", "phonglab.cli", "serve", os.fspath(Path(target).resolve()),
               "--host", "127.0.0.1", "--port", "${port}", "--one-session"]
    if allow_student_code:
        command.append("--allow-student-code")
    if export_dir is not None:
        command += ["--export-dir", os.fspath(Path(export_dir).resolve())]
    return command
