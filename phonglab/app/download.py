"""Figures from the page, delivered to the student's browser as downloads.

The server renders the figure (:func:`phonglab.render.figure`) into a
temporary folder, reads the bytes and hands them to the page as a
``data:`` URL in the state key :data:`STATE_KEY`; ``www/phonglab.js``
turns each new value into an ``<a download>`` click. A copy stays on the
server only when the server was started with an export folder.
"""

from __future__ import annotations

import base64
import tempfile
import time
from pathlib import Path

#: the state key that carries a download to the page: ``{"name", "url", "serial"}`` or None
STATE_KEY = "phonglab_download"

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


def data_url(data: bytes, mime: str = "image/png") -> str:
    """``data:image/png;base64,...``: bytes the page can save without another request."""
    return f"data:{mime};base64," + base64.b64encode(data).decode("ascii")


def server_copy(folder, name: str, data: bytes) -> Path:
    """Write ``data`` as ``folder/name`` (the folder made if needed); return the path."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_bytes(data)
    return path


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
