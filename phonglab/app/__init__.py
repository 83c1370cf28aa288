"""phonglab.app: the browser lesson app (trame).

``phonglab serve`` runs :func:`serve`: one web server on 127.0.0.1, one
:class:`~phonglab.app.lesson_app.LessonApp` per browser tab
(:class:`~phonglab.app.server.SessionServer`), so two students never move
each other's sliders.

Importing this package is cheap; trame, VTK and the render layer are loaded
when :func:`serve` or :func:`make_app` runs.
"""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path

__all__ = ["make_app", "serve"]


def make_app(target, *, export_dir=None, allow_student_code=False):
    """A factory ``name -> LessonApp`` for :class:`~phonglab.app.server.SessionServer`.

    Parameters
    ----------
    target : path
        A lessons folder, a lesson (``.md``) or a scene (``.toml``).
    export_dir : path or None
        Where the page's exports also keep a server copy (None: browser download only).
    allow_student_code : bool
        Show the "Your code" panel, which runs students' code on this server
        in the grader's sandbox (:mod:`phonglab.app.student_code`). Off by default.
    """
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    target = Path(target)

    def build(name):
        server = get_server(name, client_type="vue3")
        return LessonApp(server, target=target, export_dir=export_dir, allow_student_code=allow_student_code)

    return build


def serve(target, *, host: str = "127.0.0.1", port: int = 8080, export_dir=None, on_ready=None,
          allow_origins=(), max_sessions: int | None = None, allow_student_code=False, secret: str | None = None,
          one_session: bool = False, url_prefix: str = "/") -> None:
    """Serve the lessons at ``target`` until interrupted.

    Parameters
    ----------
    target : path
        A lessons folder, a lesson file or a scene file.
    host, port
        Where to listen (127.0.0.1 by default: this machine only; port 0 picks one).
    export_dir : path or None
        Where the page's exports also keep a server copy (None: browser download only).
    on_ready : callable, optional
        Called with the bound port once the server accepts connections.
    allow_origins : iterable of str
        Origins allowed besides the page's own (a proxy's public address).
    max_sessions : int, optional
        Tabs served at once (:data:`~phonglab.app.guard.DEFAULT_MAX_SESSIONS` by default).
    secret : str, optional
        The session secret (a random one by default).
    one_session : bool
        Serve one tab, and stop when it closes (a session process behind the launcher).
    url_prefix : str
        The path a proxy serves the page under (``/user/ana/phonglab/``); ``/`` by default.
    """
    from phonglab.app import accuracy_panel, download, worker
    from phonglab.app.server import SessionServer

    def ready(bound: int) -> None:
        # the export workers start and warm up in the background now, not on the first click (a session
        # process behind the launcher serves one tab: it starts them when that tab first exports)
        if not one_session:
            worker.start(warm=download.warm_up)
        if on_ready is not None:
            on_ready(bound)

    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    try:
        limits = {} if max_sessions is None else {"max_sessions": max_sessions}
        build = make_app(target, export_dir=export_dir, allow_student_code=allow_student_code)
        server = SessionServer(build, allow_origins=allow_origins, secret=secret, one_session=one_session,
                               url_prefix=url_prefix, **limits)
        asyncio.run(server.run(host, port, on_ready=ready))
    finally:
        # the worker processes (exports, the accuracy lesson), if any were started
        accuracy_panel.shutdown()
