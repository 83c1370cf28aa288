"""phonglab inside JupyterHub: a jupyter-server-proxy entry that starts ``phonglab serve`` in each student's server.

With the ``jupyter`` extra installed in the single-user image, every
student's Jupyter server lists "phonglab" in JupyterLab's launcher and
serves the app at ``{base_url}phonglab/`` (``/user/ana/phonglab/``):
jupyter-server-proxy starts ``phonglab serve`` on a free port the first time
the address is opened and proxies HTTP and the WebSocket to it, behind the
hub's own login. Nothing but the student's browser reaches the server: it
listens on 127.0.0.1 inside the student's container, and the page's origin
is the hub's address, which the proxy passes on as the request's host.

Which lessons it serves: ``PHONGLAB_LESSONS`` (a lesson, scene or folder)
if set, else ``./lessons`` of the directory Jupyter started in, else the
lessons shipped with phonglab. The entry point is declared in
``pyproject.toml`` (``jupyter_serverproxy_servers``); a hub administrator
may instead put :func:`setup_phonglab`'s dict in ``c.ServerProxy.servers``.
"""

from __future__ import annotations

import os
import sys

#: the environment variable naming the lessons to serve
LESSONS_ENV = "PHONGLAB_LESSONS"
#: seconds jupyter-server-proxy waits for the server to answer (building the first page takes a few)
START_TIMEOUT = 120


def setup_phonglab() -> dict:
    """The jupyter-server-proxy server entry for phonglab (see the module's notes).

    ``{port}`` and ``{base_url}`` are filled in by jupyter-server-proxy.
    """
    command = [sys.executable, "-m", "phonglab.cli", "serve", "--host", "127.0.0.1", "--port", "{port}",
               "--url-prefix", "{base_url}phonglab/"]
    lessons = os.environ.get(LESSONS_ENV)
    if lessons:
        command.append(lessons)
    return {
        "command": command,
        "timeout": START_TIMEOUT,
        # the app's own paths (index.html, /ws, /paraview/) under {base_url}phonglab/
        "absolute_url": False,
        "new_browser_tab": True,
        "launcher_entry": {"enabled": True, "title": "phonglab"},
    }
