"""What the app's tests share: a LessonApp on a lesson folder of its own, a browser camera turned about the eye,
``phonglab serve`` in a process of its own, and a session server in a thread of the test's process."""

from __future__ import annotations

import contextlib

import numpy as np


def open_app(folder, name: str, text: str, server_name: str):
    """A :class:`~phonglab.app.lesson_app.LessonApp` on ``folder`` holding one lesson file ``name`` with ``text``.

    Close it with ``.close()``; exports go to ``folder / "exports"``.
    """
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    (folder / name).write_text(text, encoding="utf-8")
    server = get_server(f"{server_name}-{folder.name}", client_type="vue3")
    return LessonApp(server, target=folder, export_dir=folder / "exports")


def browser_camera(scene, degrees: float) -> dict:
    """A browser camera as vtk.js sends it: the scene's eye turned ``degrees`` about the up axis."""
    c = scene.camera
    a = np.radians(degrees)
    offset = np.subtract(c.eye, c.focal_point)
    turn = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    return {"position": (np.add(c.focal_point, turn @ offset)).tolist(), "focalPoint": list(c.focal_point),
            "viewUp": list(c.up), "viewAngle": c.view_angle}


def start_app(target, *flags: str, log_path, port: int | None = None, timeout: float = 60.0) -> dict:
    """``phonglab serve target *flags`` on 127.0.0.1, started and answering.

    ``port`` is a free one when not given (a restart passes the old one). Returns a dict with ``url``,
    ``port``, ``process`` and ``log`` (the server's output). Raises ``RuntimeError`` holding the end
    of the log when the server exits or does not answer within ``timeout`` seconds; the process is
    stopped by then.
    """
    from phonglab.bench.ui import free_port, serve_command, start_server, stop_server, wait_until_serving

    port = free_port() if port is None else port
    process = start_server(serve_command(target, port) + list(flags), log_path=log_path)
    try:
        wait_until_serving(process, port, log_path=log_path, timeout=timeout)
    except BaseException:
        stop_server(process)
        raise
    return {"url": f"http://127.0.0.1:{port}/", "port": port, "process": process, "log": log_path}


@contextlib.contextmanager
def serving(target, *flags: str, log_path, timeout: float = 60.0):
    """:func:`start_app` for a ``with`` block: the server is stopped (its process group, by PID) on leaving."""
    from phonglab.bench.ui import stop_server

    server = start_app(target, *flags, log_path=log_path, timeout=timeout)
    try:
        yield server
    finally:
        stop_server(server["process"])


@contextlib.contextmanager
def in_thread(server, timeout: float = 120.0):
    """Run a :class:`~phonglab.app.server.SessionServer` on a free 127.0.0.1 port in a thread of its own.

    Yields the bound port; the server is stopped (in its own loop) and its thread joined on leaving.
    """
    import asyncio
    import threading

    started = threading.Event()
    where = {}

    def ready(port):
        where["port"], where["loop"] = port, asyncio.get_running_loop()
        started.set()

    thread = threading.Thread(target=lambda: asyncio.run(server.run("127.0.0.1", 0, on_ready=ready)), daemon=True)
    thread.start()
    assert started.wait(timeout), "the session server did not start"
    try:
        yield where["port"]
    finally:
        where["loop"].call_soon_threadsafe(server.stop)
        thread.join(30)
