"""One web server, one trame session per browser tab, and the guard in front of them.

A trame server keeps a single shared state: every browser connected to it
sees and moves the same sliders. :class:`SessionServer` gives each WebSocket
connection (each tab) its own trame application instead, the way trame's
``trame.tools.serve`` does: the page's static files are served once, and a
fresh app is built for every ``/ws`` connection and torn down when it closes.

Between the browser and its app the server relays wslink messages, and
checks them on the way (:mod:`phonglab.app.guard`, :mod:`phonglab.app.protocol`):

1. ``/ws`` and the launcher ``POST /paraview/`` answer only the page's own
   origin and the ``--allow-origin`` list (HTTP 403 otherwise);
2. the first message must be a hello carrying this server's random secret,
   which only the launcher hands out; the app is built after it, and only
   while fewer than ``max_sessions`` are open (else the socket closes with
   1013, "try again later", and the page says the server is full);
3. every later message is reassembled within :data:`~phonglab.app.protocol.MAX_MESSAGE_BYTES`,
   must call an RPC method the page uses, with sane arguments, may write only
   the state keys the page defines (:class:`~phonglab.app.protocol.StateWrites`),
   and is paced by a per-connection budget (:class:`~phonglab.app.guard.CallBudget`);
4. the app's error replies reach the browser without their traceback.

The server binds 127.0.0.1 unless told otherwise.
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import ctypes.util
import functools
import logging
import re
import secrets
import signal
import uuid
from pathlib import Path
from typing import Callable

import aiohttp
from aiohttp import web

from phonglab.app import guard, protocol

log = logging.getLogger(__name__)

#: seconds between WebSocket pings
HEARTBEAT_SECONDS = 30
#: seconds a new connection has to send its hello
HELLO_SECONDS = 10
#: how often the hello's clock looks at the event loop, in seconds
HELLO_TICK = 0.25
#: seconds the server waits for its sessions' sockets to close when it stops
STOP_SECONDS = 1.0
#: what a tab sees when the server already has its sessions
FULL_MESSAGE = "The server is full ({n} sessions open): try again later."


def _release_memory() -> None:
    """Give the memory a closed session freed back to the system (glibc keeps it in its arenas otherwise).

    A session's mesh, render window and arrays are freed when it closes, but
    glibc's allocator keeps most of the freed pages for later use, so the
    server's resident memory grew by several megabytes per closed tab;
    ``malloc_trim(0)`` returns them. Elsewhere than glibc this does nothing.
    """
    trim = _malloc_trim()
    if trim is not None:
        trim(0)


@functools.lru_cache(maxsize=1)
def _malloc_trim():
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None


def check_origin(origins: guard.OriginPolicy, request: web.Request) -> None:
    """Raise HTTP 403 (and log why) unless ``origins`` lets ``request`` through."""
    refusal = origins.refusal(request)
    if refusal is not None:
        log.warning("refused %s %s from %s: %s", request.method, request.path, request.remote, refusal)
        raise web.HTTPForbidden(text=f"{refusal}\n")


def normal_prefix(prefix: str) -> str:
    """A URL path prefix as ``/a/b/``: one slash at each end.

    Raises
    ------
    ValueError
        For anything but a plain path (letters, digits, ``-._~/@``).
    """
    if not isinstance(prefix, str) or not re.fullmatch(r"[A-Za-z0-9\-._~/@]{0,400}", prefix) or "//" in prefix.strip("/"):
        raise ValueError(f"url prefix must be a path like /user/ana/phonglab/, got {prefix!r}")
    inner = prefix.strip("/")
    return f"/{inner}/" if inner else "/"


def add_page_routes(web_app: web.Application, make_app: Callable) -> str:
    """Serve the page on ``web_app``: ``/`` and ``/index.html`` (with :data:`~phonglab.app.guard.PAGE_SCRIPT`), its static files.

    ``make_app("__www__")`` is built once to learn the trame client's folder
    and the folders every module the app enables serves. Returns the page's HTML.
    """
    www = make_app("__www__").server
    page_html = guard.inject_page_script((Path(www._www) / "index.html").read_text(encoding="utf-8"))

    async def index(request: web.Request):
        query = f"?{request.query_string}" if request.query_string else ""
        raise web.HTTPFound(f"index.html{query}")

    async def page(request: web.Request):
        return web.Response(text=page_html, content_type="text/html",
                            headers={"Cache-Control": "no-cache, no-store, must-revalidate"})

    web_app.router.add_get("/", index)
    web_app.router.add_get("/index.html", page)
    routes = []
    for prefix in sorted(www.serve, reverse=True):  # the trame client, then every module the app enables
        directory = www.serve[prefix]
        if isinstance(directory, (list, tuple)):
            directory = directory[0]
        routes.append(web.static(f"/{prefix}", directory, append_version=True))
    routes.append(web.static("/", www._www, append_version=True))
    web_app.add_routes(routes)
    return page_html


async def listen(web_app: web.Application, host: str, port: int, on_ready, stopped, closing) -> None:
    """Serve ``web_app`` on ``host:port`` until the future ``stopped`` is done; then ``await closing()`` and shut down.

    ``on_ready(port)`` is called with the bound port once connections are
    accepted. Handlers still running after ``closing`` are cancelled
    :data:`STOP_SECONDS` later.
    """
    runner = web.AppRunner(web_app, handle_signals=False, access_log=None, shutdown_timeout=STOP_SECONDS)
    await runner.setup()
    try:
        site = web.TCPSite(runner, host, port)
        await site.start()
        bound = site._server.sockets[0].getsockname()[1] if site._server and site._server.sockets else port
        if on_ready is not None:
            on_ready(bound)
        await stopped
    finally:
        await closing()
        await runner.cleanup()


def on_stop_signals(loop, stop: Callable, mark: Callable) -> Callable:
    """Make SIGINT and SIGTERM call ``mark()`` at once and ``stop()`` in ``loop``; returns what undoes it.

    The loop's own signal handlers run only when the loop gets its turn, and
    while tabs open, each session's build holds it for about a second: a
    class opening the lesson kept the server deaf to Ctrl-C for seconds. A
    Python signal handler runs between two bytecodes instead, so the builds
    still waiting are skipped (``mark``) and the stop follows the one in
    progress. Outside the main thread the loop's handlers are used.
    """
    def handler(signum, frame):
        mark()
        loop.call_soon_threadsafe(stop)

    try:
        previous = {signum: signal.signal(signum, handler) for signum in (signal.SIGINT, signal.SIGTERM)}
    except ValueError:  # not the main thread
        for signum in (signal.SIGINT, signal.SIGTERM):
            with contextlib.suppress(NotImplementedError, RuntimeError):
                loop.add_signal_handler(signum, stop)
        return lambda: None

    def restore():
        for signum, old in previous.items():
            signal.signal(signum, old)

    return restore


def _vtk_web(name: str):
    """trame-vtk's helper for the trame server ``name`` (None when it has none)."""
    from trame_vtk.modules import vtk as trame_vtk_module

    return trame_vtk_module.HELPERS_PER_SERVER.get(name)


def _slim_vtk_web(name: str) -> None:
    """One image-encoding thread for the session's vtkWebApplication (it starts one per core).

    The page draws the mesh in the browser (local rendering): no image is
    ever encoded, and a class of 40 tabs would otherwise hold 40 × cores
    idle threads.
    """
    helper = _vtk_web(name)
    core = getattr(helper, "_vtk_core", None)
    if core is not None:
        core.SetNumberOfEncoderThreads(1)


def _release_vtk_web(helper) -> None:
    """Drop the closed session's vtkWebApplication, so that its threads end now.

    trame-vtk's helper and the session's wslink server refer to each other,
    and both to the application: without this, it (and its encoding
    threads) lived until Python's cycle collector came by, and a class's
    closed tabs left dozens of threads behind.
    """
    if helper is None:
        return
    root = getattr(helper, "_root_protocol", None)
    if root is not None:
        with contextlib.suppress(Exception):
            root.setSharedObject("app", None)
    with contextlib.suppress(AttributeError):
        helper._vtk_core = None


async def _first_message(socket: web.WebSocketResponse):
    """The connection's first message, within :data:`HELLO_SECONDS` of the event loop's own time.

    The hello's clock runs only while the loop is free to read it: when the
    loop is held up (several tabs' sessions being built one after the other,
    a second or so each), a hello that arrived meanwhile is still read,
    instead of the connection being dropped as silent while its hello waited
    in the buffer. A stall counts as two ticks of the clock at most.

    Raises
    ------
    ProtocolError
        When nothing arrives within :data:`HELLO_SECONDS` of the loop's responsive time.
    """
    loop = asyncio.get_running_loop()
    receive = asyncio.ensure_future(socket.receive())
    waited, last = 0.0, loop.time()
    try:
        while True:
            done, _ = await asyncio.wait({receive}, timeout=HELLO_TICK)
            if done:
                return receive.result()
            now = loop.time()
            waited += min(now - last, 2 * HELLO_TICK)  # a stall of the loop is not the client's silence
            last = now
            if waited >= HELLO_SECONDS:
                raise protocol.ProtocolError(f"no hello within {HELLO_SECONDS} s")
    finally:
        if not receive.done():
            receive.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await receive


class _Frame:
    """A binary WebSocket message as wslink's generic connection reads it (``.data``)."""

    __slots__ = ("data",)

    def __init__(self, data: bytes):
        self.data = data


class SessionServer:
    """Serve a trame app with one independent session per WebSocket connection.

    Parameters
    ----------
    make_app : callable
        ``make_app(name) -> TrameApp``: builds one app on a trame server called
        ``name``. It is called once with ``"__www__"`` to learn the static
        routes the page needs, then once per authenticated connection.
    on_session : callable, optional
        Called with ``(event, name)`` for ``"open"`` and ``"close"`` (logging, tests).
    max_sessions : int
        Sessions open at once; a tab past this number is told the server is full.
    allow_origins : iterable of str
        Origins allowed besides the page's own (``https://phong.school.org``
        when a proxy serves the app under another address).
    secret : str, optional
        The session secret; a random one (``secrets.token_urlsafe``) by default.
    one_session : bool
        Stop when the first session closes: a session process behind the
        launcher (:mod:`phonglab.app.launcher`), which serves one tab.
    url_prefix : str
        The path a proxy serves the page under (``/user/ana/phonglab/``
        behind JupyterHub's jupyter-server-proxy): the WebSocket address the
        launcher hands out starts with it. ``/`` when the page is served at the root.
    """

    def __init__(self, make_app: Callable, *, on_session: Callable | None = None,
                 max_sessions: int = guard.DEFAULT_MAX_SESSIONS, allow_origins=(), secret: str | None = None,
                 one_session: bool = False, url_prefix: str = "/"):
        if max_sessions < 1:
            raise ValueError(f"max_sessions must be at least 1, got {max_sessions}")
        self._make_app = make_app
        self._on_session = on_session
        self._stopped = None
        self._stopping = False  # set at once by a stop signal, even while a session's build holds the loop
        self.max_sessions = max_sessions
        self.one_session = one_session
        self.url_prefix = normal_prefix(url_prefix)
        self.origins = guard.OriginPolicy(allow_origins)
        self.secret = secret or secrets.token_urlsafe(32)
        self.sessions: dict[str, object] = {}
        self._admitted = 0  # sessions open or being built
        self._sockets: set = set()
        self._handlers: set = set()  # the WebSocket handlers' tasks, each closing its session when it ends
        self.web_app = web.Application()
        self.web_app.router.add_post("/paraview/", self._launcher)
        self.web_app.router.add_get("/ws", self._websocket)
        self._page_html = add_page_routes(self.web_app, make_app)

    # ------------------------------------------------------------------
    # HTTP handlers

    async def _launcher(self, request: web.Request):
        # the trame client first asks a launcher where its session lives and
        # takes the secret from the answer; only this server's own page may ask.
        # USE_HOST is replaced by the page's own host in the browser: nothing
        # from the request is echoed back
        self._check_origin(request)
        scheme = "wss" if request.headers["Origin"].lower().startswith("https:") else "ws"
        return web.json_response({"sessionURL": f"{scheme}://USE_HOST{self.url_prefix}ws", "secret": self.secret},
                                 headers={"Cache-Control": "no-store"})

    def _check_origin(self, request: web.Request) -> None:
        check_origin(self.origins, request)

    # ------------------------------------------------------------------
    # the WebSocket: hello, admission, relay

    async def _websocket(self, request: web.Request):
        self._check_origin(request)
        name = "s" + uuid.uuid4().hex
        # the close handshake waits STOP_SECONDS at most for the browser's answer
        socket = web.WebSocketResponse(max_msg_size=protocol.MAX_FRAME_BYTES, heartbeat=HEARTBEAT_SECONDS,
                                       timeout=STOP_SECONDS)
        await socket.prepare(request)
        self._sockets.add(socket)
        self._handlers.add(asyncio.current_task())
        try:
            if await self._admit(name, socket):
                self._admitted += 1
                try:
                    await self._relay(name, socket)
                finally:
                    self._admitted -= 1
                    if self.one_session:
                        self.stop()
        except protocol.ProtocolError as exc:
            log.warning("session %s from %s: %s; closing", name, request.remote, exc)
            await socket.close(code=aiohttp.WSCloseCode.POLICY_VIOLATION, message=str(exc)[:120].encode())
        except Exception:  # a broken session must not take the server down
            log.exception("session %s failed", name)
        finally:
            self._sockets.discard(socket)
            self._handlers.discard(asyncio.current_task())
        return socket

    async def _admit(self, name: str, socket: web.WebSocketResponse) -> bool:
        """Wait for the hello; True when its secret is right and there is room for one more session."""
        first = await _first_message(socket)
        if first.type != aiohttp.WSMsgType.BINARY:
            if first.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSING, aiohttp.WSMsgType.CLOSED):
                return False
            raise protocol.ProtocolError(f"first message is {first.type.name}, not a binary hello")
        secret, rpc_id = protocol.hello_secret(first.data)
        rpc_id = rpc_id if isinstance(rpc_id, str) else protocol.HELLO_ID
        if not secrets.compare_digest(secret.encode(), self.secret.encode()):
            log.warning("session %s: wrong secret; closing", name)
            await socket.send_bytes(protocol.error_reply(rpc_id, protocol.AUTHENTICATION_ERROR, "Authentication failed"))
            await socket.close(code=aiohttp.WSCloseCode.POLICY_VIOLATION, message=b"Authentication failed: reload the page.")
            return False
        if self._admitted >= self.max_sessions:
            full = FULL_MESSAGE.format(n=self.max_sessions)
            log.warning("session %s refused: %s", name, full)
            await socket.send_bytes(protocol.error_reply(rpc_id, protocol.EXCEPTION_ERROR, full))
            await socket.close(code=aiohttp.WSCloseCode.TRY_AGAIN_LATER, message=full.encode()[:120])
            return False
        return True

    async def _relay(self, name: str, socket: web.WebSocketResponse) -> None:
        """Build this tab's app and relay its messages both ways until the socket closes."""
        app = task = connection = None
        try:
            if self._stopping:
                return  # stopping: a session admitted meanwhile is not built (a build holds the loop a second)
            # build this tab's app and start its trame server without a network
            app = self._make_app(name)
            _slim_vtk_web(name)
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
            replies = protocol.ReplyFilter(name)

            async def to_browser(binary, content):
                if socket.closed:
                    return
                if binary:
                    content = replies.clean(content)
                    if content is not None:
                        await socket.send_bytes(content)
                else:
                    await socket.send_str(content)

            connection.on_message(to_browser)
            # the app's connection is in this process: log it in with the app's own secret
            await connection.send(True, _Frame(protocol.hello(app.server.protocol.secret)))
            chunks = protocol.Assembler()
            writes = protocol.StateWrites(app.server.state.has)
            budget = guard.CallBudget(crowded=lambda: self._admitted > 1)
            clock = asyncio.get_running_loop().time
            async for message in socket:
                if message.type == aiohttp.WSMsgType.BINARY:
                    await budget.take()
                    whole = chunks.feed(message.data)
                    if whole is None:
                        continue
                    rpc = protocol.unpack(whole)
                    refusal = protocol.check_call(rpc) or writes.refusal(rpc)
                    if refusal is not None:
                        log.info("session %s: refused %s: %s", name, rpc["method"][:80], refusal[1])
                        await socket.send_bytes(protocol.error_reply(rpc.get("id"), *refusal))
                        continue
                    log.debug("session %s: %s", name, rpc["method"])
                    single = len(whole) + protocol.HEADER.size == len(message.data)
                    started = clock()
                    await connection.send(True, _Frame(message.data if single else protocol.chunk(whole)))
                    budget.spent(clock() - started)
                elif message.type == aiohttp.WSMsgType.TEXT:
                    raise protocol.ProtocolError("text message; wslink speaks binary")
                elif message.type == aiohttp.WSMsgType.ERROR:
                    break
        finally:
            await self._close_session(name, app, task, connection)

    async def _close_session(self, name, app, task, connection) -> None:
        if app is None:
            return  # never built (the server was stopping)
        try:
            if connection is not None:
                await connection.close()
            if app is not None:
                await app.server.stop()
            if task is not None:
                await asyncio.wait_for(asyncio.shield(task), timeout=STOP_SECONDS)
        except Exception:
            log.exception("closing session %s", name)
        finally:
            session = self.sessions.pop(name, None)
            web_core = _vtk_web(name)
            closer = getattr(session, "close", None)
            if callable(closer):
                try:
                    closer()
                except Exception:
                    log.exception("releasing session %s", name)
            _release_vtk_web(web_core)
            _release_memory()
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
        restore = on_stop_signals(loop, self.stop, self._mark_stopping)
        try:
            await listen(self.web_app, host, port, on_ready, self._stopped, self._close_all)
        finally:
            restore()

    async def _close_all(self) -> None:
        """Close every tab's socket (code 1001, going away) and wait for their sessions to close.

        The sockets close together, each waiting :data:`STOP_SECONDS` at most
        for its browser's answer; then each session's handler closes its app
        and releases its view. Whatever is still running after twice that is
        cancelled by the web server's own shutdown.
        """
        sockets = list(self._sockets)
        if sockets:
            await asyncio.gather(*(socket.close(code=aiohttp.WSCloseCode.GOING_AWAY, message=b"server stopping")
                                   for socket in sockets), return_exceptions=True)
        handlers = [task for task in self._handlers if not task.done()]
        if handlers:
            await asyncio.wait(handlers, timeout=2 * STOP_SECONDS)

    def _mark_stopping(self) -> None:
        self._stopping = True

    def stop(self) -> None:
        """Ask :meth:`run` to return."""
        self._stopping = True
        if self._stopped is not None and not self._stopped.done():
            self._stopped.set_result(True)
