"""``phonglab bench ui``, second part: turning the view to re-shaded pixels.

Turning the view moves the model's eye (:mod:`phonglab.app.eye`): the
browser turns its copy of the mesh at once, with the old colours, and the
server re-shades the mesh for the new eye and pushes the colours back. This
part times that round trip in the page. Each step is one drag of
:data:`STEP_PX` pixels across the view (a few degrees), alternately left and
right so the highlight stays in view, and each starts from a settled view,
as the key presses do. The clock starts at the drag's mouse move (the
event's timestamp) and stops, as for a key press, at the first animation
frame whose pixels hold the re-shaded colours: ``www/phonglab.js``
dispatches ``phonglab-colors-applied`` when vtk.js has drawn a frame with
new colours, and the next animation frame reads the canvas's pixels
(``gl.readPixels`` waits until that frame is really drawn). The server
records its time per re-shade under the label ``turn``
(:mod:`phonglab.app.timing`).
"""

from __future__ import annotations

from phonglab.bench.ui_probe import Probe

#: pixels per drag step (vtk.js turns the camera by a few degrees for this)
STEP_PX = 24
#: how long a drag may wait for its re-shaded colours before it counts as missed (ms)
STEP_TIMEOUT_MS = 45_000

# Injected before the page's scripts: the clock for one turn
TURN_JS = r"""
(() => {
  const turn = (window.__phonglabTurn = { armed: false, t0: null, latency: null, applied: 0 });
  document.addEventListener("pointermove", (event) => {
    if (turn.armed && turn.t0 === null && event.buttons) turn.t0 = event.timeStamp;
  }, true);
  window.addEventListener("phonglab-colors-applied", () => {
    turn.applied += 1;
    if (!turn.armed || turn.t0 === null) return;
    turn.armed = false;
    const t0 = turn.t0;
    requestAnimationFrame(() => {  // the pixels of the frame just drawn, read back: it is on screen
      const c = document.querySelector((window.__phonglabBench || {}).selector || "canvas");
      const gl = c && (c.getContext("webgl2") || c.getContext("webgl"));
      if (gl) gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      turn.latency = performance.now() - t0;
    });
  });
  turn.arm = () => { turn.t0 = null; turn.latency = null; turn.armed = true; };
})();
"""


class Turn(Probe):
    """Drags of one page's view, each timed from the mouse move to the re-shaded pixels.

    Parameters
    ----------
    page : playwright Page
        Opened with :func:`phonglab.bench.ui.open_page` and :data:`TURN_JS`.
    canvas : str
        CSS selector of the view's canvas.
    timing_path : path
        The server's timing file.
    settle : callable
        ``settle(page)`` waits until the view shows no change (:func:`phonglab.bench.ui.settle`).
    label : str
        Timing-file label of the server's re-shades.
    """

    step_px = STEP_PX

    def __init__(self, page, *, canvas, timing_path, settle, label="turn"):
        super().__init__(page, timing_path=timing_path, label=label)
        self.canvas, self.settle = canvas, settle
        self.missed = 0
        self._steps = 0

    def start_measuring(self) -> None:
        """The drags so far were warm-up: keep the later ones (and the server's times from here)."""
        super().start_measuring()
        self.missed = 0

    def step(self) -> float | None:
        """One drag from a settled view, alternately right and left; its latency in ms (None: no re-shade came)."""
        page = self.page
        self.settle(page)
        box = page.locator(self.canvas).first.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        direction = 1 if self._steps % 2 == 0 else -1
        self._steps += 1
        records = self.records()
        page.evaluate("() => window.__phonglabTurn.arm()")
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + direction * STEP_PX, y, steps=1)
        page.mouse.up()
        try:
            page.wait_for_function("() => window.__phonglabTurn.latency !== null", timeout=STEP_TIMEOUT_MS)
        except Exception:  # a drag that brought no re-shade (the camera did not change): counted, not timed
            self.missed += 1
            return None
        latency = page.evaluate("() => window.__phonglabTurn.latency")
        self.keep(latency, records)  # (the drag's end is re-shaded and synchronised too)
        return latency
