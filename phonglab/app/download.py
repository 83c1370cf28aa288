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
figure is being made) and, next to the button, :data:`PROGRESS_KEY`: what
the export waits for or how far it is ("Preparing… starting the figure
workers (1 of 2 ready), 4 s", "Preparing… view 2 of 4, 9 s"), updated every
second; a second click meanwhile is told to wait.
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
#: the state key that says how this tab's export goes, while it is made ("" otherwise)
PROGRESS_KEY = "export_progress"
#: seconds between two updates of :data:`PROGRESS_KEY`
PROGRESS_SECONDS = 1.0

#: what the page can export: kind -> (file name suffix, options of :func:`phonglab.render.figure`)
KINDS = {
    "render": ("", {"vectors": "NLRVH"}),
    "terms": ("-terms", {"terms": True}),
    "mistake": ("-mistake", {"compare": True}),
    "models": ("-models", {"models": True}),
    "furnace": ("-furnace", {"plot": "furnace"}),
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
    from phonglab.app.worker import report
    from phonglab.render import figure

    if kind not in KINDS:
        raise ValueError(f"export: kind must be one of {', '.join(KINDS)}, got {kind!r}")
    _, options = KINDS[kind]
    with tempfile.TemporaryDirectory(prefix="phonglab-export-") as folder:
        if kind == "mistake":
            extra = {"mistake": mistake}
        elif kind in ("models", "furnace"):  # the correct models only
            extra = {}
        else:
            extra = {"mistake": shown_mistake} if shown_mistake else {}
        # each view of a grid figure done is a step the page shows (in a worker; nothing elsewhere)
        path = figure(scene, Path(folder) / "figure.png", **options, **extra, progress=report)
        return path.read_bytes()


def _render_job(scene, kind: str, mistake: str | None, shown_mistake: str | None) -> bytes:
    """:func:`render_png` with positional arguments only (what a worker process is handed)."""
    return render_png(scene, kind, mistake, shown_mistake=shown_mistake)


def warm_up() -> None:
    """Make one small figure and throw it away: what a worker does before its first export.

    The first figure a process makes pays for importing VTK and PyVista and
    for making its OpenGL context (most of a first export's time); made
    here, at a lower priority, while nobody waits for it.
    """
    from phonglab.render import figure
    from phonglab.scene import scene_from_dict

    scene = scene_from_dict({
        "geometry": {"kind": "sphere", "resolution": 12},
        "material": {"ka": 0.1, "kd": 0.6, "ks": 0.5, "shininess": 20},
        "lights": [{"type": "point", "position": [2, 2, 3]}],
        "probe": [0.3, 0.4, 0.87],
    })
    with tempfile.TemporaryDirectory(prefix="phonglab-warm-") as folder:
        figure(scene, Path(folder) / "warm.png", size=(64, 48), vectors="NLRVH", supersample=1)


def progress_text(progress, ready: int, workers: int, seconds: float) -> str:
    """What the page says while an export is made.

    Parameters
    ----------
    progress : (done, total, label) or None
        :func:`phonglab.app.worker.progress` of the export's job: None while it waits for a worker.
    ready, workers : int
        Workers ready for a job, and how many there are.
    seconds : float
        Since the click.

    Examples
    --------
    >>> progress_text(None, 1, 2, 4.2)
    'Preparing… starting the figure workers (1 of 2 ready), 4 s'
    >>> progress_text((2, 4, "specular"), 2, 2, 9.0)
    'Preparing… view 2 of 4, 9 s'
    """
    if progress is None:
        step = (f"starting the figure workers ({ready} of {workers} ready)" if ready < workers
                else "waiting for a free figure worker")
    else:
        done, total, _ = progress
        step = f"view {done} of {total}" if total > 1 else "rendering"
    return f"Preparing… {step}, {seconds:.0f} s"


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
        self._ticker = None  # the task that updates PROGRESS_KEY while an export is made
        state[PROGRESS_KEY] = ""

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
            self._follow()

    def _follow(self) -> None:
        """Keep :data:`PROGRESS_KEY` saying how the export goes, every :data:`PROGRESS_SECONDS`, until it is done."""
        import asyncio

        from phonglab.app import worker

        loop = asyncio.get_running_loop()
        began = loop.time()

        def say() -> None:
            text = progress_text(worker.progress(self.job.worker_job), worker.ready_workers(), worker.WORKERS,
                                 loop.time() - began)
            if self.state[PROGRESS_KEY] != text:
                with self.state:
                    self.state[PROGRESS_KEY] = text

        async def tick() -> None:
            while self.job.busy:
                say()
                await asyncio.sleep(PROGRESS_SECONDS)
            if self.state[PROGRESS_KEY]:  # a result dropped (another lesson): nothing is being made
                with self.state:
                    self.state[PROGRESS_KEY] = ""

        say()
        self._ticker = loop.create_task(tick())

    def _done(self) -> None:
        """The export ended, whichever way: no progress to show any more."""
        if self._ticker is not None:
            self._ticker.cancel()
            self._ticker = None
        self.state[PROGRESS_KEY] = ""

    def _deliver(self, name: str, data: bytes, export_dir) -> None:
        self._done()
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
        self._done()
        self.notify("error", f"Export failed: {exc}")

    def close(self) -> None:
        """The tab closed: a figure still being made is not delivered."""
        self.job.close()
        if self._ticker is not None:
            self._ticker.cancel()
            self._ticker = None


def download_link():
    """``<phonglab-download :file="phonglab_download">``: saves each new file the server sends; and the export's progress.

    Placed once in the page's bar, after the export buttons (see
    ``www/phonglab.js``); needs a trame layout being built (it attaches to
    the current parent element). While an export is made, a short line
    beside it says how it goes (:data:`PROGRESS_KEY`), for screen readers too.
    """
    from trame.widgets import html
    from trame_client.widgets.core import AbstractElement

    from phonglab.app.client import MODULE

    class DownloadLink(AbstractElement):
        def __init__(self, **kwargs):
            super().__init__("phonglab-download", **kwargs)
            if self.server:
                self.server.enable_module(MODULE)
            self._attr_names += ["file"]

    html.Span(f"{{{{ {PROGRESS_KEY} }}}}", v_if=f"{BUSY_KEY} && {PROGRESS_KEY}", role="status",
              classes="phonglab-export-progress mr-2", style="font-size: 0.8rem; opacity: 0.75; white-space: nowrap")
    return DownloadLink(file=(STATE_KEY, None))


def export_menu_items(export):
    """The page's export menu: one entry per figure kind (``export(kind)`` on click)."""
    from trame.widgets import vuetify3 as v3

    # (kind, title, icon, disabled when, shown when): the models' figures in lessons that switch the model
    entries = [("render", "This view (PNG)", "mdi-image-outline", None, None),
               ("terms", "Per-term figure (PNG)", "mdi-view-grid-outline", None, None),
               ("mistake", "Correct vs. common mistake (PNG)", "mdi-alert-outline", "!mistake", None),
               ("models", "Phong beside Cook–Torrance (PNG)", "mdi-compare", None, "has_model_control"),
               ("furnace", "White furnace: light each model sends back (PNG)", "mdi-fire", None,
                "has_model_control")]
    for kind, title, icon, disabled, shown in entries:
        v3.VListItem(title=title, prepend_icon=icon, click=(export, f"['{kind}']"),
                     disabled=(disabled,) if disabled else False, v_if=shown,
                     classes=f"phonglab-export-{kind}")
