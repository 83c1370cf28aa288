"""The compare view: the scene under Phong and under Cook–Torrance, side by side, under the 3D view.

With the view's "Phong beside Cook–Torrance" switch on (the ``view.compare``
option, so an address can carry it), the tab shows a picture of its scene
shaded by both models: the same mesh, lights, eye and probe, each panel
shaded per pixel by the core with its own model
(:func:`phonglab.render.figures.models_figure`), labelled with the
material parameters its lobe uses. It is made in a worker process
(:mod:`phonglab.app.worker`), never in the event loop, and follows the
scene: a change while one is being made asks for one more, for the newest
scene, when it is done.

State keys: ``compare_png`` (``{"status": "idle" | "making" | "ready" |
"failed", "src": data URL or "", "error": words or ""}``; a failed picture
keeps the last one's ``src``) and ``compare_busy`` (a picture is being
made).
"""

from __future__ import annotations

import base64
import logging

from phonglab.app.worker import ServerBusy, TabJob

log = logging.getLogger(__name__)

__all__ = ["ComparePanel", "models_png", "SIZE"]

#: the comparison's size in pixels (two panels side by side) when the view's size is not known
SIZE = (960, 420)
#: what the panel's heading takes of the view's height, in pixels
HEADING = 80
#: the comparison's smallest and largest side, in pixels
SIDE_RANGE = (240, 1600)


def picture_size(view_size) -> tuple[int, int]:
    """The comparison's size for a view of ``view_size`` (width, height) pixels: the view less its heading."""
    if not view_size:
        return SIZE
    low, high = SIDE_RANGE
    width, height = view_size
    return (min(max(int(width), low), high), min(max(int(height) - HEADING, low), high))


def models_png(scene, size=SIZE) -> bytes:
    """PNG bytes of ``scene`` under each compared model, side by side, shaded per pixel (in a worker)."""
    import tempfile
    from pathlib import Path

    from phonglab.render import figure

    with tempfile.TemporaryDirectory(prefix="phonglab-compare-") as folder:
        path = figure(scene.replace("interpolation", "pixel"), Path(folder) / "models.png", size=tuple(size),
                      models=True, supersample=1)
        return path.read_bytes()


class ComparePanel:
    """One tab's comparison picture.

    Parameters
    ----------
    state : trame state
    """

    def __init__(self, state):
        self.state = state
        self._job = TabJob(state, "compare_busy")
        self._wanted = None  # (scene, size) the page should show, while the comparison is on
        self._making = None  # (scene, size) of the picture being made
        self._shown = None  # (scene, size) of the picture shown
        state.compare_png = {"status": "idle", "src": "", "error": ""}

    def follow(self, scene, on: bool, view_size=None) -> None:
        """The scene, the switch or the view's size changed: make the picture for the newest while it is on."""
        if not on or scene is None:
            self._wanted = None
            if self._job.busy:
                self._job.forget()
                self._making = None
            self.state.compare_png = {**self.state.compare_png, "status": "idle"}
            return
        self._wanted = (scene, picture_size(view_size))
        if self._wanted == self._shown and not self._job.busy:
            return
        self._start()

    def _start(self) -> None:
        if self._job.busy or self._wanted is None:
            return  # the newest scene is made when the running one is done
        self._making = self._wanted
        self.state.compare_png = {**self.state.compare_png, "status": "making", "error": ""}
        try:
            # (without a server loop, in scripts and tests, the picture is made here and _done runs at once)
            self._job.start(models_png, self._making, self._done, self._failed)
        except ServerBusy:
            self._failed(ServerBusy("the server is busy with other pictures"))

    def _done(self, data: bytes) -> None:
        self._shown, self._making = self._making, None
        if self._wanted is None:
            return  # switched off meanwhile
        src = "data:image/png;base64," + base64.b64encode(data).decode("ascii")
        self.state.compare_png = {"status": "ready", "src": src, "error": ""}
        if self._wanted != self._shown:
            self._start()

    def _failed(self, exc: Exception) -> None:
        log.warning("comparison picture: %s", exc)
        self._making = None
        self.state.compare_png = {**self.state.compare_png, "status": "failed",
                                  "error": "The comparison could not be made this time; change a setting to try "
                                           "again."}

    def close(self) -> None:
        """The tab closed: nothing more is delivered."""
        self._job.close()
