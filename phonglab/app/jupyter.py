"""The lesson view in a Jupyter notebook: ``phonglab.show("lessons/04-specular.md")``.

:func:`show` builds the page's own app (:class:`~phonglab.app.lesson_app.LessonApp`:
the picture with its arrows, the lesson's controls, the readout) on a trame
server of its own and starts it in the kernel's event loop, as trame's
Jupyter support does (``exec_mode="task"``); the cell shows the page in an
iframe. Each call makes a new, independent view. The returned
:class:`LessonView` holds the scene: ``view.scene`` is what the page shows
and ``view.replace("lights[1].position", [0, 3, 3])`` changes it, on the page
too; ``view.figure()`` displays the same scene as an inline figure. The cell
shows the iframe once the server listens (``await view.ready`` waits for it).

The iframe's address comes from trame's own iframe builders: in a plain
Jupyter server it is ``http://localhost:PORT/``; inside JupyterHub
(``JUPYTERHUB_SERVICE_PREFIX`` set) it is ``{prefix}proxy/PORT/``, the
single-user server's jupyter-server-proxy route, because the browser
cannot reach the kernel's port on the hub's machine directly.
``TRAME_IFRAME_BUILDER=serverproxy`` with ``PHONGLAB_JUPYTER_BASE`` chooses
the proxy path in a Jupyter server without the hub.

Needs the ``jupyter`` extra (``pip install -e ".[jupyter]"``); the
``phonglab`` command does not.
"""

from __future__ import annotations

import itertools
import os
import socket
import tempfile
from pathlib import Path
from types import SimpleNamespace

#: the iframe's height in the cell, in pixels
HEIGHT = 820
_names = itertools.count(1)


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _settings(settings: dict) -> list[tuple[str, object]]:
    """``show``'s keyword settings as field paths: ``material__ks`` is ``material.ks``, ``lights_1__position`` is ``lights[1].position``."""
    from phonglab.app.keys import field_path

    return [(field_path(key), value) for key, value in settings.items()]


class LessonView:
    """One lesson view in a notebook: the page's app on a trame server in the kernel's event loop.

    Parameters
    ----------
    target : path
        A lesson (``.md``), a scene (``.toml``) or a lessons folder.
    settings : list of (path, value)
        Field settings applied to the lesson's scene before it is shown.
    height : int
        The iframe's height in pixels.
    """

    def __init__(self, target, settings=(), *, height: int = HEIGHT):
        from trame.app import get_server

        from phonglab.app.lesson_app import LessonApp

        target = Path(target)
        if not target.exists():
            raise FileNotFoundError(_missing(target))
        self.name = f"phonglab_notebook_{next(_names)}"
        self.height = height
        server = get_server(self.name, client_type="vue3")
        self.app = LessonApp(server, target=target)
        self.app.state.in_cell = True  # the view beside the controls in the cell's frame, however narrow
        if self.app.scene is None:
            problems = "; ".join(self.app.entry.errors) if self.app.entry is not None else "no scene"
            raise ValueError(f"{target}: the lesson has errors: {problems}")
        if settings:
            self.replace(dict(settings))
        self.port = _free_port()
        # trame's Jupyter support: the server runs as a task of the kernel's event loop
        server.start(exec_mode="task", port=self.port, host="localhost", open_browser=False,
                     show_connection_info=False, disable_logging=True, timeout=0)

    # ------------------------------------------------------------------
    # the scene

    @property
    def scene(self):
        """The scene the page shows now (after the student's and the notebook's changes)."""
        return self.app.scene

    def replace(self, path=None, value=None, /, **settings):
        """Change the scene, on the page too; returns the new scene.

        ``view.replace("material.ks", 0.9)``, ``view.replace({"material.ks": 0.9,
        "lights[1].position": [0, 3, 3]})`` or ``view.replace(material__ks=0.9)``
        (``__`` for ``.`` and ``_1`` for ``[1]``). Values are checked as in a
        scene file; a bad one raises ``phonglab.scene.SceneError`` naming the
        field, and the page keeps its scene.
        """
        pairs = list(path.items()) if isinstance(path, dict) else ([(path, value)] if path is not None else [])
        pairs += _settings(settings)
        scene = self.app.scene.replace_many(pairs)
        with self.app.state:
            self.app._show_scene(scene)
        return scene

    def figure(self, path=None, **options):
        """The current scene as a figure (``phonglab.figure``'s options); shown inline, or written to ``path``."""
        from phonglab.render import figure

        if path is not None:
            return figure(self.scene, path, **options)
        from IPython.display import Image

        with tempfile.TemporaryDirectory(prefix="phonglab-figure-") as folder:
            out = Path(folder) / "figure.png"
            figure(self.scene, out, **options)
            return Image(data=out.read_bytes(), format="png")

    # ------------------------------------------------------------------
    # the cell

    @property
    def url(self) -> str:
        """The address the cell's iframe opens (through JupyterHub's proxy inside the hub)."""
        return self._iframe()["src"]

    def _iframe(self) -> dict:
        from trame_client.ui.core import get_iframe_builder

        layout = SimpleNamespace(
            server=SimpleNamespace(port=self.port, name=self.name, client_type="vue3"),
            template_name="main", _template_name="trame__template_main",
            iframe_style=f"border: none; width: 100%; height: {self.height}px;",
            iframe_attrs={"class": "trame-iframe phonglab-iframe"},
            iframe_base_url=os.environ.get("PHONGLAB_JUPYTER_BASE", "http://localhost"),
        )
        return get_iframe_builder("default")(layout)

    @property
    def ready(self):
        """Resolves once the view's server listens: ``await view.ready`` in a cell, as trame's layouts do."""
        return self.app.server.ready

    def _repr_html_(self) -> str:
        attributes = " ".join(f'{key}="{value}"' for key, value in self._iframe().items())
        # in a block of its own: IPython warns about HTML that is a bare iframe, in every cell that shows one
        return f'<div class="phonglab-cell"><iframe {attributes}></iframe></div>'

    def _ipython_display_(self) -> None:
        """The cell's iframe, once the server listens.

        The server is a task of the kernel's loop, so it starts only after the
        cell that made it returns; an iframe shown at once may ask a port that
        does not listen yet (a loaded machine) and stay blank. Until the server
        is ready the cell says it is starting, then the same output becomes the iframe.
        """
        import asyncio
        import html

        from IPython.display import HTML, display

        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            loop = None
        if self.app.server.running or loop is None:
            display(HTML(self._repr_html_()))
            return
        handle = display(HTML(f'<div class="phonglab-starting">Starting the lesson view '
                              f'({html.escape(self.app.entry.title if self.app.entry else "")})…</div>'),
                         display_id=True)

        async def swap():
            try:
                await self.app.server.ready
            except Exception as exc:  # the server did not start: say so in the cell
                handle.update(HTML(f"<div>The lesson view could not start: {html.escape(str(exc))}</div>"))
                return
            handle.update(HTML(self._repr_html_()))

        self._swap = loop.create_task(swap())  # kept: a task nobody holds may be collected

    def __repr__(self) -> str:
        return f"<phonglab LessonView {self.app.entry.title if self.app.entry else ''!r} at {self.url}>"

    def close(self) -> None:
        """Stop this view's server and release its render window."""
        import asyncio

        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            loop = None
        if loop is not None:
            loop.create_task(self.app.server.stop())
        self.app.close()


def _missing(target: Path) -> str:
    """Why ``target`` cannot be shown: it does not exist; the names beside it that come close, if any."""
    import difflib

    folder = target.parent if target.parent.is_dir() else None
    names = sorted(p.name for p in folder.iterdir() if p.suffix in (".md", ".toml")) if folder else []
    close = difflib.get_close_matches(target.name, names, n=3, cutoff=0.6)
    if close:
        hint = "did you mean " + " or ".join(repr(str(folder / name)) for name in close) + "?"
    elif folder is None:
        hint = f"there is no folder {str(target.parent)!r} either (the notebook runs in {str(Path.cwd())!r})"
    else:
        hint = f"{str(folder)!r} holds {len(names)} lesson and scene files"
    return f"no such lesson or scene file: {str(target)!r}; {hint}"


def show(lesson_or_scene, /, *, height: int = HEIGHT, **settings) -> LessonView:
    """Show a lesson (or a scene file) in the notebook cell; the returned view holds its scene.

    Parameters
    ----------
    lesson_or_scene : path
        ``"lessons/04-specular.md"``, a scene ``.toml`` or a lessons folder.
    height : int
        The view's height in the cell, in pixels.
    **settings
        Scene fields to set first, ``__`` for ``.``: ``interpolation="gouraud"``,
        ``material__ks=0.8``, ``lights_1__position=[0, 3, 3]``.

    Returns
    -------
    LessonView
        Displayed by the cell when it is the cell's last value; ``view.scene``,
        ``view.replace(...)``, ``view.figure()``.

    Examples
    --------
    >>> view = phonglab.show("lessons/04-specular.md", interpolation="gouraud")  # doctest: +SKIP
    >>> view.replace("lights[1].position", [0.0, 3.0, 3.0])  # doctest: +SKIP
    """
    return LessonView(lesson_or_scene, _settings(settings), height=height)
