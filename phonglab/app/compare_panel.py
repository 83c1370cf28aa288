"""The compare view: the scene under Phong and under Cook–Torrance, side by side, over the 3D view.

With the view's "Phong beside Cook–Torrance" switch on (the ``view.compare``
option, so an address can carry it), the tab shows a picture of its scene
per model, shaded per pixel by the core with that model: the same mesh,
lights, eye and probe. Each picture's caption (the model and the material
parameters its lobe uses, :func:`phonglab.render.captions.model_label`) is
page text under it, not drawn into the picture: the page scales a picture
to the view, and a caption drawn into it came out about 7 px tall on a
laptop. The pictures are made in a worker process
(:mod:`phonglab.app.worker`), never in the event loop, and follow the
scene: a change while they are being made asks for one more, for the newest
scene, when it is done.

State keys: ``compare_png`` (``{"status": "idle" | "making" | "ready" |
"failed", "panels": [{"model", "caption", "own", "src"}, ...], "stacked":
one above the other, "error": words or ""}``; a failed picture keeps the
last panels) and ``compare_busy`` (a picture is being made).
"""

from __future__ import annotations

import base64
import logging

from phonglab.app.worker import ServerBusy, TabJob
from phonglab.render.captions import COMPARED_MODELS, model_label

log = logging.getLogger(__name__)

__all__ = ["ComparePanel", "models_png", "panel_size", "SIZE"]

#: one panel's picture size in pixels when the view's size is not known
SIZE = (470, 380)
#: what the panel's heading and margins take of the view, in pixels (width, height)
FRAME = (24, 80)
#: the caption's line under each picture, and the gap between the pictures, in pixels
CAPTION = 30
GAP = 8
#: a picture's smallest and largest side, in pixels
SIDE_RANGE = (120, 1200)


def panel_size(view_size) -> tuple[tuple[int, int], bool]:
    """One picture's size for a view of ``view_size`` (width, height) pixels, and whether they are stacked.

    The pictures share the view less the heading, side by side, or one
    above the other where the view is taller than wide; each keeps a
    caption's line below it.
    """
    if not view_size:
        return SIZE, False
    low, high = SIDE_RANGE
    width, height = int(view_size[0]) - FRAME[0], int(view_size[1]) - FRAME[1]
    stacked = width < height
    n = len(COMPARED_MODELS)
    if stacked:
        width, height = width, (height - GAP * (n - 1)) // n - CAPTION
    else:
        width, height = (width - GAP * (n - 1)) // n, height - CAPTION
    return (min(max(width, low), high), min(max(height, low), high)), stacked


def models_png(scene, size=SIZE) -> list[bytes]:
    """PNG bytes of ``scene`` under each of the compared models, shaded per pixel, in their order (in a worker)."""
    import tempfile
    from pathlib import Path

    from phonglab.render import figure

    pictures = []
    with tempfile.TemporaryDirectory(prefix="phonglab-compare-") as folder:
        for model, _ in COMPARED_MODELS:
            # no arrows, as in the exported comparison: the pictures compare the shading
            path = figure(scene.replace("interpolation", "pixel").replace("model", model),
                          Path(folder) / f"{model}.png", size=tuple(size), vectors=None, supersample=1)
            pictures.append(path.read_bytes())
    return pictures


class ComparePanel:
    """One tab's comparison picture.

    Parameters
    ----------
    state : trame state
    """

    def __init__(self, state):
        self.state = state
        self._job = TabJob(state, "compare_busy")
        self._wanted = None  # (scene, size, stacked) the page should show, while the comparison is on
        self._making = None  # (scene, size, stacked) of the pictures being made
        self._shown = None  # (scene, size, stacked) of the pictures shown
        state.compare_png = {"status": "idle", "panels": [], "stacked": False, "error": ""}

    def follow(self, scene, on: bool, view_size=None) -> None:
        """The scene, the switch or the view's size changed: make the picture for the newest while it is on."""
        if not on or scene is None:
            self._wanted = None
            if self._job.busy:
                self._job.forget()
                self._making = None
            self.state.compare_png = {**self.state.compare_png, "status": "idle"}
            return
        self._wanted = (scene, *panel_size(view_size))
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
            self._job.start(models_png, self._making[:2], self._done, self._failed)
        except ServerBusy:
            self._failed(ServerBusy("the server is busy with other pictures"))

    def _done(self, pictures: list[bytes]) -> None:
        self._shown, self._making = self._making, None
        scene, _, stacked = self._shown
        if self._wanted is None:
            return  # switched off meanwhile
        panels = [{"model": model, "caption": model_label(scene, model), "own": model == scene.model,
                   "src": "data:image/png;base64," + base64.b64encode(data).decode("ascii")}
                  for (model, _), data in zip(COMPARED_MODELS, pictures)]
        self.state.compare_png = {"status": "ready", "panels": panels, "stacked": stacked, "error": ""}
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
