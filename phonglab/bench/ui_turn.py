"""``phonglab bench ui``, second part: turning the view to re-shaded pixels.

Turning the view moves the model's eye (:mod:`phonglab.app.eye`): the
browser turns its copy of the mesh at once, with the old colours, and the
server re-shades the mesh for the new eye and pushes the colours back. This
part times that round trip in the page. Each step is one drag of
:data:`STEP_PX` pixels across the view (a few degrees), alternately left and
right so the highlight stays in view. The clock starts at the drag's mouse
move (the event's timestamp) and stops when the re-shaded colours are drawn
(``phonglab-colors-applied``, dispatched by ``www/phonglab.js`` right after
it renders them). The server records its time per re-shade under the label
``turn`` (:mod:`phonglab.app.timing`).
"""

from __future__ import annotations

import time

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
    if (turn.armed && turn.t0 !== null) {
      turn.latency = performance.now() - turn.t0;
      turn.armed = false;
    }
  });
  turn.arm = () => { turn.t0 = null; turn.latency = null; turn.armed = true; };
})();
"""


def measure_turn(browser, url, *, canvas, steps, warmup, timing_path, label="turn", viewport=None,
                 init_script=""):
    """Drag the view ``warmup + steps`` times; time each drag to its re-shaded pixels.

    Parameters
    ----------
    browser : playwright Browser
    url : str
    canvas : str
        CSS selector of the view's canvas.
    steps, warmup : int
        Measured and unmeasured drags.
    timing_path : path
        The server's timing file.
    label : str
        Timing-file label of the server's re-shades.
    viewport : dict, optional
    init_script : str
        More script to inject first (the pixel hash of :mod:`phonglab.bench.ui`).

    Returns
    -------
    dict
        ``latency_ms`` (list), ``server_ms`` (list), ``step_px``.
    """
    from phonglab.app import timing

    page = browser.new_page(viewport=viewport)
    try:
        if init_script:
            page.add_init_script(init_script)
        page.add_init_script(TURN_JS)
        page.goto(url)
        page.wait_for_selector(canvas, timeout=90_000)
        if init_script:  # the pixel hash of phonglab.bench.ui: wait for the first settled picture
            page.evaluate("(selector) => { window.__phonglabBench.selector = selector; }", canvas)
            page.wait_for_function(
                "() => { const b = window.__phonglabBench; return b.last !== 0 && b.stable > 20; }", timeout=120_000
            )
        page.wait_for_function("() => !!window.phonglabView", timeout=60_000)
        box = page.locator(canvas).first.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        latencies, before, missed = [], None, 0
        for i in range(warmup + steps):
            records = len([r for r in timing.read(timing_path) if r[0] == label])
            if i == warmup:
                before = records
            direction = 1 if i % 2 == 0 else -1
            page.evaluate("() => window.__phonglabTurn.arm()")
            page.mouse.move(x, y)
            page.mouse.down()
            page.mouse.move(x + direction * STEP_PX, y, steps=1)
            page.mouse.up()
            try:
                page.wait_for_function("() => window.__phonglabTurn.latency !== null", timeout=STEP_TIMEOUT_MS)
            except Exception:  # a drag that brought no re-shade (the camera did not change): counted, not timed
                missed += 1
                continue
            latency = page.evaluate("() => window.__phonglabTurn.latency")
            # the drag's end is re-shaded too: let it land before the next step
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline:
                if len([r for r in timing.read(timing_path) if r[0] == label]) > records:
                    break
                time.sleep(0.01)
            page.wait_for_timeout(150)
            if i >= warmup:
                latencies.append(latency)
        server = [ms for lab, ms in timing.read(timing_path) if lab == label][before:]
        if not latencies:
            raise RuntimeError(f"no drag of the view brought re-shaded colours back ({missed} drags)")
        return {"latency_ms": latencies, "server_ms": server, "step_px": STEP_PX, "missed": missed}
    finally:
        page.close()
