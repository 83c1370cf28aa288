"""``phonglab bench ui``: slider key press to changed pixels, in a real browser.

The benchmark starts a server on a free 127.0.0.1 port, opens its page in
headless Chromium (Playwright) and presses a slider's arrow key 30 times,
letting the view settle between presses. For every press it measures, inside
the page, the time from the key event to the first animation frame whose
pixels differ: a ``requestAnimationFrame`` loop reads the view's WebGL canvas
with ``gl.readPixels`` and hashes it (the page's WebGL contexts are created
with ``preserveDrawingBuffer`` so the pixels can be read at any time). The
server writes its own time per update to a file (:mod:`phonglab.app.timing`).

It does this for two apps on the same 100k-vertex sphere, in the same run:

* the minimal trame app of :mod:`phonglab.bench.ui_baseline` (plain NumPy,
  ``VtkLocalView.update()``), and
* phonglab's own app (``phonglab serve`` on a one-lesson folder whose sphere
  has at least 100 000 vertices), moving its shininess slider.

It prints the median and 95th percentile of both, phonglab's median as a
ratio to the baseline's (target ≤ 1.0) and phonglab's server time per update
(target ≤ 30 ms), each with PASS or MISS.

The helpers that start and stop servers and Chromium are shared with the
browser tests.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

HELP = "slider-to-pixels and turn-to-re-shaded-pixels latency in a real browser against a minimal trame app"

#: Debian's Chromium
CHROMIUM = "/usr/bin/chromium"
#: flags for headless Chromium on a machine without GPU or network
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
]
#: what to tell someone without Chromium
CHROMIUM_MISSING = (
    f"Chromium was not found at {CHROMIUM}; install it with `apt-get install -y chromium` "
    "(the browser tests and `phonglab bench ui` drive it through Playwright)"
)

#: targets printed with PASS/MISS
RATIO_TARGET = 1.0
SERVER_MS_TARGET = 30.0
#: vertices of the benchmark sphere
VERTICES = 100_000
#: vertices of the baseline's sphere (see phonglab.bench.ui_baseline)
BASELINE_POINTS = 320 * (315 - 2) + 2
#: browser window for both apps
VIEWPORT = {"width": 1280, "height": 800}

# Injected before any page script runs. It asks every WebGL context to keep
# its drawing buffer (so gl.readPixels sees the last frame at any time) and
# runs a requestAnimationFrame loop that hashes the view's canvas each frame.
MEASURE_JS = r"""
(() => {
  const getContext = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (type, attributes) {
    if (type === "webgl" || type === "webgl2" || type === "experimental-webgl") {
      attributes = Object.assign({}, attributes || {}, { preserveDrawingBuffer: true });
    }
    return getContext.call(this, type, attributes);
  };
  const bench = (window.__phonglabBench = {
    armed: false, t0: null, latency: null, base: 0, last: 0, stable: 0, frames: 0,
    selector: "canvas",
  });
  let pixels = null;
  function canvas() {
    return document.querySelector(bench.selector);
  }
  // FNV-1a over the canvas's RGBA pixels, read from its own WebGL context
  function hash() {
    const c = canvas();
    if (!c || !c.width || !c.height) return 0;
    const gl = c.getContext("webgl2") || c.getContext("webgl");
    if (!gl) return 0;
    const size = c.width * c.height * 4;
    if (!pixels || pixels.length !== size) pixels = new Uint8Array(size);
    const bound = gl.getParameter(gl.FRAMEBUFFER_BINDING);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    gl.bindFramebuffer(gl.FRAMEBUFFER, bound);
    const words = new Uint32Array(pixels.buffer);
    let h = 2166136261 >>> 0;
    for (let i = 0; i < words.length; i++) {
      h ^= words[i];
      h = Math.imul(h, 16777619) >>> 0;
    }
    return h;
  }
  // the key event's timestamp starts the clock
  document.addEventListener("keydown", (event) => {
    if (bench.armed && bench.t0 === null) bench.t0 = event.timeStamp;
  }, true);
  function frame() {
    const h = hash();
    bench.frames += 1;
    if (bench.armed && bench.t0 !== null && h !== bench.base) {
      bench.latency = performance.now() - bench.t0;
      bench.armed = false;
    }
    bench.stable = h === bench.last ? bench.stable + 1 : 0;
    bench.last = h;
    requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
  bench.arm = () => {
    bench.base = hash();
    bench.t0 = null;
    bench.latency = null;
    bench.armed = true;
    return bench.base;
  };
  bench.hash = hash;
})();
"""


# ---------------------------------------------------------------------------
# servers and browsers (shared with tests/browser)


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(command, *, log_path, env=None) -> subprocess.Popen:
    """Start a server command in its own process group, output to ``log_path``."""
    log = open(log_path, "wb")
    try:
        return subprocess.Popen(
            list(command),
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            env={**os.environ, **(env or {})},
            start_new_session=True,
        )
    finally:
        log.close()


def wait_until_serving(process: subprocess.Popen, port: int, *, log_path=None, timeout: float = 60.0) -> None:
    """Wait until ``http://127.0.0.1:port/index.html`` answers 200.

    Raises
    ------
    RuntimeError
        If the process exits first or the time runs out; the message holds the
        end of the server's log.
    """
    url = f"http://127.0.0.1:{port}/index.html"
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"the server exited with status {process.returncode}:\n{log_tail(log_path)}")
        try:
            with urllib.request.urlopen(url, timeout=2) as response:
                if response.status == 200:
                    return
        except (urllib.error.URLError, ConnectionError, OSError):
            pass
        time.sleep(0.2)
    raise RuntimeError(f"the server did not answer {url} within {timeout:.0f} s:\n{log_tail(log_path)}")


def stop_server(process: subprocess.Popen, *, timeout: float = 10.0) -> None:
    """Stop a server started by :func:`start_server`: its whole process group, by PID.

    SIGINT first (what Ctrl-C sends; trame's own server stops on it), then
    SIGTERM, then SIGKILL, each after ``timeout`` seconds without an exit.
    """
    for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
        if process.poll() is not None:
            break
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signum)
        with contextlib.suppress(subprocess.TimeoutExpired):
            process.wait(timeout=timeout)
    # the leader is gone; make sure nothing it started lingers in its group
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(process.pid, signal.SIGKILL)


def log_tail(log_path, lines: int = 30) -> str:
    """The last lines of a log file ('' when there is none)."""
    if not log_path:
        return ""
    try:
        text = Path(log_path).read_text(errors="replace")
    except OSError:
        return ""
    return "\n".join(text.splitlines()[-lines:])


def launch_chromium(playwright):
    """Launch headless Debian Chromium through Playwright.

    Raises
    ------
    RuntimeError
        With the install command, when Chromium is missing.
    """
    if not os.path.exists(CHROMIUM):
        raise RuntimeError(CHROMIUM_MISSING)
    return playwright.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)


def serve_command(target, port: int) -> list[str]:
    """The command line that serves phonglab's app for ``target`` (lesson or folder)."""
    return [sys.executable, "-m", "phonglab.cli", "serve", os.fspath(target), "--host", "127.0.0.1", "--port", str(port)]


# ---------------------------------------------------------------------------
# the benchmark lesson


def sphere_resolution(vertices: int = VERTICES) -> tuple[int, int]:
    """The smallest sphere resolution whose mesh has at least ``vertices`` points.

    Returns
    -------
    (resolution, points)
    """
    from phonglab.render.mesh import build_mesh
    from phonglab.scene import Geometry

    def points(resolution):
        return build_mesh(Geometry(kind="sphere", resolution=resolution)).n_points

    low, high = 8, 1024
    if points(high) < vertices:
        return high, points(high)
    while low < high:  # binary search on the (increasing) vertex count
        middle = (low + high) // 2
        if points(middle) >= vertices:
            high = middle
        else:
            low = middle + 1
    return low, points(low)


def write_bench_lesson(folder, resolution: int) -> Path:
    """A one-lesson folder: a sphere of ``resolution`` with a shininess slider (:func:`phonglab.bench.scenes.bench_lesson`)."""
    from phonglab.bench.scenes import bench_lesson

    path = Path(folder) / "01-bench.md"
    path.write_text(bench_lesson(resolution), encoding="utf-8")
    return path


# ---------------------------------------------------------------------------
# measuring one app


def measure_app(browser, url, *, slider, canvas, presses, warmup, timing_path, label, settle_frames=8):
    """Press a slider's right arrow ``warmup + presses`` times; time key to pixels.

    Parameters
    ----------
    browser : playwright Browser
    url : str
    slider : str
        CSS selector of the slider's thumb (``[role=slider]``).
    canvas : str
        CSS selector of the view's canvas.
    presses, warmup : int
        Measured and unmeasured presses.
    timing_path : path
        The server's timing file (:mod:`phonglab.app.timing`).
    label : str
        Timing-file label of the server's updates.
    settle_frames : int
        Animation frames with unchanged pixels that count as "settled".

    Returns
    -------
    dict
        ``latency_ms`` (list), ``server_ms`` (list), ``canvas`` ("WxH" device pixels).
    """
    from phonglab.app import timing

    page = browser.new_page(viewport=VIEWPORT)
    try:
        page.add_init_script(MEASURE_JS)
        page.goto(url)
        page.wait_for_selector(canvas, timeout=90_000)
        page.evaluate("(selector) => { window.__phonglabBench.selector = selector; }", canvas)
        # the first picture: wait for a non-blank, settled canvas
        page.wait_for_function(
            "() => { const b = window.__phonglabBench; return b.last !== 0 && b.stable > 20; }", timeout=90_000
        )
        size = page.evaluate(
            "(s) => { const c = document.querySelector(s); return [c.width, c.height]; }", canvas
        )
        thumb = page.locator(slider).first
        thumb.focus()
        latencies, updates_before = [], None
        for i in range(warmup + presses):
            updates = len([r for r in timing.read(timing_path) if r[0] == label])
            if i == warmup:
                updates_before = updates
            page.wait_for_function(
                f"() => window.__phonglabBench.stable >= {settle_frames}", timeout=30_000
            )
            page.evaluate("() => window.__phonglabBench.arm()")
            page.keyboard.press("ArrowRight")
            page.wait_for_function("() => window.__phonglabBench.latency !== null", timeout=30_000)
            latency = page.evaluate("() => window.__phonglabBench.latency")
            # let the server's update land in its timing file before the next press
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline:
                if len([r for r in timing.read(timing_path) if r[0] == label]) > updates:
                    break
                time.sleep(0.01)
            if i >= warmup:
                latencies.append(latency)
        server = [ms for lab, ms in timing.read(timing_path) if lab == label][updates_before:]
        return {"latency_ms": latencies, "server_ms": server, "canvas": f"{size[0]}x{size[1]}"}
    finally:
        page.close()


def percentile(values, q: float) -> float:
    """The q-th percentile (0..100), linear between order statistics."""
    ordered = sorted(values)
    if not ordered:
        return float("nan")
    position = (len(ordered) - 1) * q / 100.0
    lower = int(position)
    upper = min(lower + 1, len(ordered) - 1)
    return ordered[lower] + (ordered[upper] - ordered[lower]) * (position - lower)


# ---------------------------------------------------------------------------
# command line


def add_arguments(parser) -> None:
    parser.add_argument("--presses", type=_positive, default=30, help="measured key presses per app (default 30)")
    parser.add_argument("--warmup", type=_non_negative, default=3, help="unmeasured presses first (default 3)")
    parser.add_argument(
        "--vertices", type=_positive, default=VERTICES, help=f"sphere vertices, at least (default {VERTICES})"
    )


def _positive(text: str) -> int:
    return _int_at_least(text, 1)


def _non_negative(text: str) -> int:
    return _int_at_least(text, 0)


def _int_at_least(text: str, low: int) -> int:
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}") from None
    if value < low:
        raise argparse.ArgumentTypeError(f"must be at least {low}, got {value}")
    return value


def _progress(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _verdict(value: float, target: float) -> str:
    return "PASS" if value <= target else "MISS"


def run(args) -> int:
    from playwright.sync_api import sync_playwright

    from phonglab.bench.usage import UsageError

    if not os.path.exists(CHROMIUM):
        raise UsageError(CHROMIUM_MISSING)
    presses, warmup = args.presses, args.warmup
    resolution, points = sphere_resolution(args.vertices)
    results = {}
    with tempfile.TemporaryDirectory(prefix="phonglab-bench-ui-") as tmp, sync_playwright() as playwright:
        browser = launch_chromium(playwright)
        try:
            # phonglab's app first: its view size is then given to the baseline
            lessons = Path(tmp) / "lessons"
            lessons.mkdir()
            write_bench_lesson(lessons, resolution)
            _progress(f"phonglab: sphere resolution {resolution} ({points} vertices), {presses} presses")
            results["phonglab"] = _run_app(
                browser,
                lambda port: serve_command(lessons, port),
                tmp,
                "phonglab",
                slider=".phonglab-control-material__shininess__log [role=slider]",
                canvas=".phonglab-view canvas",
                presses=presses,
                warmup=warmup,
                label="view",
                turns=presses,
            )
            css = results["phonglab"]["css"]
            _progress(f"baseline: {BASELINE_POINTS} vertices, view {css[0]}x{css[1]} CSS px, {presses} presses")
            results["baseline"] = _run_app(
                browser,
                lambda port: [sys.executable, "-m", "phonglab.bench.ui_baseline", "--host", "127.0.0.1",
                              "--port", str(port), "--view-size", f"{css[0]}x{css[1]}"],
                tmp,
                "baseline",
                slider=".bench-slider [role=slider]",
                canvas=".bench-view canvas",
                presses=presses,
                warmup=warmup,
                label="baseline",
            )
        finally:
            browser.close()
    _report(results, points)
    return 0


def _run_app(browser, command, tmp, name, *, slider, canvas, presses, warmup, label, turns=0) -> dict:
    port = free_port()
    command = command(port)
    timing_path = Path(tmp) / f"{name}-timing.txt"
    log_path = Path(tmp) / f"{name}-server.log"
    process = start_server(command, log_path=log_path, env={"PHONGLAB_UI_TIMING": str(timing_path)})
    try:
        wait_until_serving(process, port, log_path=log_path)
        result = measure_app(
            browser,
            f"http://127.0.0.1:{port}/",
            slider=slider,
            canvas=canvas,
            presses=presses,
            warmup=warmup,
            timing_path=timing_path,
            label=label,
        )
        if turns:
            from phonglab.bench.ui_turn import measure_turn

            _progress(f"{name}: {turns} turns of the view")
            result["turn"] = measure_turn(browser, f"http://127.0.0.1:{port}/", canvas=canvas, steps=turns,
                                          warmup=warmup, timing_path=timing_path, viewport=VIEWPORT,
                                          init_script=MEASURE_JS)
    except Exception as exc:
        raise RuntimeError(f"{name}: {exc}\n--- server log ---\n{log_tail(log_path)}") from exc
    finally:
        stop_server(process)
    width, height = (int(x) for x in result["canvas"].split("x"))
    result["css"] = (width, height)  # device pixel ratio 1 in headless Chromium
    return result


def _report(results: dict, points: int) -> None:
    rows = []
    for name in ("baseline", "phonglab"):
        r = results[name]
        rows.append(
            (
                name,
                f"{statistics.median(r['latency_ms']):.1f}",
                f"{percentile(r['latency_ms'], 95):.1f}",
                f"{statistics.median(r['server_ms']):.1f}" if r["server_ms"] else "n/a",
                f"{percentile(r['server_ms'], 95):.1f}" if r["server_ms"] else "n/a",
                r["canvas"],
                str(len(r["latency_ms"])),
            )
        )
    headers = ("app", "median ms", "p95 ms", "server median ms", "server p95 ms", "canvas px", "presses")
    widths = [max(len(h), *(len(row[i]) for row in rows)) for i, h in enumerate(headers)]
    print(f"phonglab bench ui: key press to changed pixels, headless Chromium, sphere of {points} vertices")
    print("  ".join(h.ljust(w) for h, w in zip(headers, widths)))
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    ratio = statistics.median(results["phonglab"]["latency_ms"]) / statistics.median(results["baseline"]["latency_ms"])
    server = results["phonglab"]["server_ms"]
    server_median = statistics.median(server) if server else float("inf")
    print(f"latency ratio phonglab / baseline (medians): {ratio:.2f}  target <= {RATIO_TARGET:.1f}  "
          f"{_verdict(ratio, RATIO_TARGET)}")
    print(f"phonglab server time per update (median): {server_median:.1f} ms  target <= {SERVER_MS_TARGET:.0f} ms  "
          f"{_verdict(server_median, SERVER_MS_TARGET)}")
    turn = results["phonglab"].get("turn")
    if turn:
        _report_turn(turn, results["baseline"]["latency_ms"])


def _report_turn(turn: dict, baseline_latency: list) -> None:
    """Turn of the view to re-shaded pixels, against the baseline's key press to pixels (median and p90)."""
    latency, server = turn["latency_ms"], turn["server_ms"]
    median = statistics.median(latency)
    baseline_ms = statistics.median(baseline_latency)
    server_median = statistics.median(server) if server else float("inf")
    print(f"turn to re-shaded pixels ({len(latency)} drags of {turn['step_px']} px, {turn['missed']} without a "
          f"re-shade): median {median:.1f} ms, "
          f"p95 {percentile(latency, 95):.1f} ms; server per re-shade median {server_median:.1f} ms, "
          f"p95 {percentile(server, 95) if server else float('nan'):.1f} ms")
    ratio = median / baseline_ms
    print(f"turn ratio phonglab turn / baseline key press (medians): {ratio:.2f}  target <= {RATIO_TARGET:.1f}  "
          f"{_verdict(ratio, RATIO_TARGET)}")
    print(f"turn ratio at the 90th percentile: {percentile(latency, 90) / percentile(baseline_latency, 90):.2f} "
          f"(turn p90 {percentile(latency, 90):.1f} ms, baseline key press p90 "
          f"{percentile(baseline_latency, 90):.1f} ms)")
    print(f"phonglab server time per re-shade (median): {server_median:.1f} ms  target <= {SERVER_MS_TARGET:.0f} ms  "
          f"{_verdict(server_median, SERVER_MS_TARGET)}")
