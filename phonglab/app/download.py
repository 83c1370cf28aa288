"""Figures from the page, delivered to the student's browser as downloads.

The server renders the figure (:func:`phonglab.render.figure`) into a
temporary folder, reads the bytes and hands them to the page as a
``data:`` URL in the state key :data:`STATE_KEY`; ``www/phonglab.js``
turns each new value into an ``<a download>`` click. A copy stays on the
server only when the server was started with an export folder; it is
written whole or not at all (a hidden temporary renamed into place).

Rendering takes seconds: :class:`Exports` runs it in a worker process
(:mod:`phonglab.app.worker`), never in the event loop every tab shares, one
export per tab at a time. The page shows :data:`BUSY_KEY` (true while the
figure is being made) and a notice; a second click meanwhile is told to wait.
"""

from __future__ import annotations

import base64
import tempfile
import time
from pathlib import Path

#: the state key that carries a download to the page: ``{"name", "url", "serial"}`` or None
STATE_KEY = "phonglab_download"
#: the state key that is true while this tab's export is being made
BUSY_KEY = "export_busy"

#: what the page can export: kind -> (file name suffix, options of :func:`phonglab.render.figure`)
KINDS = {
    "render": ("", {"vectors": "NLRVH"}),
    "terms": ("-terms", {"terms": True}),
    "mistake": ("-mistake", {"compare": True}),
}


def file_name(stem: str, kind: str, when: float | None = None) -> str:
    """``lesson-04-terms-20260101-120000.png``: the stem, the kind's suffix and the time."""
    suffix, _ = KINDS[kind]
    stamp = time.strftime("%Y%m%d-%H%M%S", time.localtime(when))
    return f"{stem}{suffix}-{stamp}.png"


def render_png(scene, kind: str, mistake: str | None = None, *, shown_mistake: str | None = None) -> bytes:
    """The figure of ``kind`` for ``scene`` as PNG bytes.

    ``mistake`` is the common mistake the comparison shows; ``shown_mistake``
    the one the page's view shows, if any: a render or terms figure is then
    shaded with it and carries the red "deliberately wrong" band.

    Raises
    ------
    ValueError
        ``kind`` is not one of :data:`KINDS`.
    phonglab.render.FigureError
        The figure cannot be made (e.g. the mistake comparison without a mistake).
    """
    from phonglab.render import figure

    if kind not in KINDS:
        raise ValueError(f"export: kind must be one of {', '.join(KINDS)}, got {kind!r}")
    _, options = KINDS[kind]
    with tempfile.TemporaryDirectory(prefix="phonglab-export-") as folder:
        if kind == "mistake":
            extra = {"mistake": mistake}
        else:
            extra = {"mistake": shown_mistake} if shown_mistake else {}
        path = figure(scene, Path(folder) / "figure.png", **options, **extra)
        return path.read_bytes()


def _render_job(scene, kind: str, mistake: str | None, shown_mistake: str | None) -> bytes:
    """:func:`render_png` with positional arguments only (what a worker process is handed)."""
    return render_png(scene, kind, mistake, shown_mistake=shown_mistake)


def data_url(data: bytes, mime: str = "image/png") -> str:
    """``data:image/png;base64,...``: bytes the page can save without another request."""
    return f"data:{mime};base64," + base64.b64encode(data).decode("ascii")


def server_copy(folder, name: str, data: bytes) -> Path:
    """Write ``data`` as ``folder/name`` (the folder made if needed), whole or not at all; return the path."""
    from phonglab.render._files import write_atomically

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    write_atomically(path, lambda tmp: Path(tmp).write_bytes(data))
    return path


class Exports:
    """One tab's exports: rendered in a worker process, one at a time, delivered as downloads.

    Parameters
    ----------
    state : trame state
    notify : callable
        ``notify(kind, text)``: a notice on the page.
    """

    def __init__(self, state, notify):
        from phonglab.app.worker import TabJob

        self.state = state
        self.notify = notify
        self.serial = 0
        self.job = TabJob(state, BUSY_KEY)

    def start(self, scene, kind: str, stem: str, mistake: str | None = None, shown_mistake: str | None = None,
              export_dir=None) -> None:
        """Render ``kind`` of ``scene`` in a worker; the download reaches the page when it is done.

        ``mistake`` and ``shown_mistake`` are :func:`render_png`'s; a server
        copy is kept in ``export_dir`` unless it is None.

        While this tab's previous export is being made, or the server has too
        many heavy jobs, nothing starts and a notice says to try again.
        """
        from phonglab.app.worker import ServerBusy

        name = file_name(stem, kind)
        try:
            started = self.job.start(_render_job, (scene, kind, mistake, shown_mistake),
                                     lambda data: self._deliver(name, data, export_dir), self._failed)
        except ServerBusy as exc:
            self.notify("warning", f"Export not started: {exc}")
            return
        if not started:
            self.notify("info", "Still making the last export: try again when it has downloaded.")
        elif self.job.busy:
            self.notify("info", f"Making {name}…")

    def _deliver(self, name: str, data: bytes, export_dir) -> None:
        self.serial += 1
        self.state[STATE_KEY] = {"name": name, "url": data_url(data), "serial": self.serial}
        if export_dir is None:
            self.notify("success", f"Downloading {name}")
            return
        try:
            path = server_copy(export_dir, name, data)
        except OSError as exc:
            self.notify("error", f"Downloading {name}, but the server copy could not be written: {exc.strerror or exc}")
        else:
            self.notify("success", f"Saved {path}; downloading {name}")

    def _failed(self, exc: BaseException) -> None:
        self.notify("error", f"Export failed: {exc}")

    def close(self) -> None:
        """The tab closed: a figure still being made is not delivered."""
        self.job.close()


def download_link():
    """``<phonglab-download :file="phonglab_download">``: saves each new file the server sends.

    Placed once in the page (see ``www/phonglab.js``); needs a trame layout
    being built (it attaches to the current parent element).
    """
    from trame_client.widgets.core import AbstractElement

    from phonglab.app.client import MODULE

    class DownloadLink(AbstractElement):
        def __init__(self, **kwargs):
            super().__init__("phonglab-download", **kwargs)
            if self.server:
                self.server.enable_module(MODULE)
            self._attr_names += ["file"]

    return DownloadLink(file=(STATE_KEY, None))


def export_menu_items(export):
    """The page's export menu: one entry per figure kind (``export(kind)`` on click)."""
    from trame.widgets import vuetify3 as v3

    entries = [("render", "This view (PNG)", "mdi-image-outline", None),
               ("terms", "Per-term figure (PNG)", "mdi-view-grid-outline", None),
               ("mistake", "Correct vs. common mistake (PNG)", "mdi-alert-outline", "!mistake")]
    for kind, title, icon, disabled in entries:
        v3.VListItem(title=title, prepend_icon=icon, click=(export, f"['{kind}']"),
                     disabled=(disabled,) if disabled else False,
                     classes=f"phonglab-export-{kind}")
