"""One web server, one trame session per browser tab.

A trame server keeps a single shared state: every browser connected to it
sees and moves the same sliders. :class:`SessionServer` gives each WebSocket
connection (each tab) its own trame application instead, the way trame's
``trame.tools.serve`` does: the page's static files are served once, and a
fresh app is built for every ``/ws`` connection and torn down when it closes.

The server binds 127.0.0.1 unless told otherwise.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import signal
import uuid
from typing import Callable

import aiohttp
from aiohttp import web

log = logging.getLogger(__name__)

#: the largest WebSocket message accepted from a browser, in bytes
MAX_MESSAGE_BYTES = 10_000_000
#: seconds between WebSocket pings
HEARTBEAT_SECONDS = 30


class SessionServer:
    """Serve a trame app with one independent session per WebSocket connection.

    Parameters
    ----------
    make_app : callable
        ``make_app(name) -> TrameApp``: builds one app on a trame server called
        ``name``. It is called once with ``"__www__"`` to learn the static
        routes the page needs, then once per connection.
    on_session : callable, optional
        Called with ``(event, name)`` for ``"open"`` and ``"close"`` (logging, tests).
    """

    def __init__(self, make_app: Callable, *, on_session: Callable | None = None):
        self._make_app = make_app
        self._on_session = on_session
        self._stopped = None
        self.sessions: dict[str, object] = {}
        self._sockets: set = set()
        self.web_app = web.Application()
        self.web_app.router.add_get("/", self._index)
        self.web_app.router.add_post("/paraview/", self._launcher)
        self.web_app.router.add_get("/ws", self._websocket)
        # static files: the trame client, then every module the app enables
        www = make_app("__www__").server
        routes = []
        for prefix in sorted(www.serve, reverse=True):
            directory = www.serve[prefix]
            if isinstance(directory, (list, tuple)):
                directory = directory[0]
            routes.append(web.static(f"/{prefix}", directory, append_version=True))
        routes.append(web.static("/", www._www, append_version=True))
        self.web_app.add_routes(routes)

    # ------------------------------------------------------------------
    # HTTP handlers

    async def _index(self, request: web.Request):
        query = f"?{request.query_string}" if request.query_string else ""
        raise web.HTTPFound(f"index.html{query}")

    async def _launcher(self, request: web.Request):
        # the trame client first asks a launcher where its session lives; answer
        # directly with this server's WebSocket endpoint
        scheme = "wss" if request.secure else "ws"
        return web.json_response({"sessionURL": f"{scheme}://{request.host}/ws"})

    async def _websocket(self, request: web.Request):
        name = "s" + uuid.uuid4().hex
        socket = web.WebSocketResponse(max_msg_size=MAX_MESSAGE_BYTES, heartbeat=HEARTBEAT_SECONDS)
        await socket.prepare(request)
        self._sockets.add(socket)
        app = task = connection = None
        try:
            # build this tab's app and start its trame server without a network
            app = self._make_app(name)
            self.sessions[name] = app
            self._notify("open", name)
            task = app.server.start(
                backend="generic",
                exec_mode="task",
                open_browser=False,
                show_connection_info=False,
                disable_logging=True,
                timeout=0,
            )
            await app.server.ready
            connection = await app.server._server.ws.connect()

            async def to_browser(binary, content):
                if socket.closed:
                    return
                if binary:
                    await socket.send_bytes(content)
                else:
                    await socket.send_str(content)

            connection.on_message(to_browser)
            # relay the browser's messages to this session
            async for message in socket:
                if message.type in (aiohttp.WSMsgType.BINARY, aiohttp.WSMsgType.TEXT):
                    await connection.send(message.type == aiohttp.WSMsgType.BINARY, message)
                elif message.type == aiohttp.WSMsgType.ERROR:
                    break
        except Exception:  # a broken session must not take the server down
            log.exception("session %s failed", name)
        finally:
            self._sockets.discard(socket)
            await self._close_session(name, app, task, connection)
        return socket

    async def _close_session(self, name, app, task, connection) -> None:
        try:
            if connection is not None:
                await connection.close()
            if app is not None:
                await app.server.stop()
            if task is not None:
                await asyncio.wait_for(asyncio.shield(task), timeout=5)
        except Exception:
            log.exception("closing session %s", name)
        finally:
            session = self.sessions.pop(name, None)
            closer = getattr(session, "close", None)
            if callable(closer):
                try:
                    closer()
                except Exception:
                    log.exception("releasing session %s", name)
            self._notify("close", name)

    def _notify(self, event: str, name: str) -> None:
        if self._on_session is not None:
            self._on_session(event, name)

    # ------------------------------------------------------------------
    # running

    async def run(self, host: str = "127.0.0.1", port: int = 8080, on_ready: Callable | None = None) -> None:
        """Listen on ``host:port`` until :meth:`stop`, SIGINT or SIGTERM.

        Parameters
        ----------
        host, port
            Where to listen; port 0 picks a free port.
        on_ready : callable, optional
            Called with the bound port once the server accepts connections.
        """
        loop = asyncio.get_running_loop()
        self._stopped = loop.create_future()
        # Ctrl-C and SIGTERM end the run normally (aiohttp's own handlers would exit with status 1)
        for signum in (signal.SIGINT, signal.SIGTERM):
            with contextlib.suppress(NotImplementedError, RuntimeError):
                loop.add_signal_handler(signum, self.stop)
        runner = web.AppRunner(self.web_app, handle_signals=False, access_log=None)
        await runner.setup()
        site = web.TCPSite(runner, host, port)
        await site.start()
        bound = site._server.sockets[0].getsockname()[1] if site._server and site._server.sockets else port
        if on_ready is not None:
            on_ready(bound)
        try:
            await self._stopped
        finally:
            # close the open tabs' sockets so their sessions end, then the server
            for socket in list(self._sockets):
                with contextlib.suppress(Exception):
                    await socket.close(code=aiohttp.WSCloseCode.GOING_AWAY, message=b"server stopping")
            await runner.cleanup()

    def stop(self) -> None:
        """Ask :meth:`run` to return."""
        if self._stopped is not None and not self._stopped.done():
            self._stopped.set_result(True)
