"""``phonglab bench ui``: slider key press to changed pixels, in a real browser.

The benchmark starts two servers on free 127.0.0.1 ports and opens their
pages in one headless Chromium (Playwright):

* the minimal trame app of :mod:`phonglab.bench.ui_baseline` (plain NumPy,
  ``VtkLocalView.update()``) on a sphere of about 100k vertices, and
* phonglab's own app (``phonglab serve`` on a lessons folder holding a
  lesson whose sphere has at least 100 000 vertices, and lesson 4 from the
  source tree), moving its shininess slider: in one tab on the large
  sphere, in a second tab in lesson 4 (opened at its address with Gouraud
  shading, so the core shades the lesson's own mesh for every update).

Then it takes, in turn and from a settled view each time, one key press of
the baseline's slider, one of phonglab's, one in lesson 4 and one drag of
phonglab's view (:mod:`phonglab.bench.ui_turn`), in an order that rotates
each round, until each has its count. Interleaved so, they see the same load
on the machine, and a change of load during the run moves them together
instead of skewing their ratio. Only the page being measured hashes its
pixels.

For a key press it measures, inside the page, the time from the key event
to the first animation frame whose pixels differ: a ``requestAnimationFrame``
loop reads the view's WebGL canvas with ``gl.readPixels`` and hashes it (the
page's WebGL contexts are created with ``preserveDrawingBuffer`` so the
pixels can be read at any time). The servers write their own time per
update to a file (:mod:`phonglab.app.timing`); for phonglab's key presses the
benchmark also reads the server process's CPU clock before the press and
after it (:class:`~phonglab.bench.ui_probe.Probe`), so the relay, the state
messages, the put-off panels and the page's answer are all in that figure.
Lesson 4's presses are measured by that clock alone (:class:`ServerPress`):
its page reads no pixels back, whose hashing loop would take a core from
the server on a 2-core machine.

It prints the median and 95th percentile of both apps, phonglab's median as
a ratio to the baseline's (target ≤ 1.0) and phonglab's server time per
update (target ≤ 30 ms), each with PASS or MISS; the server's CPU time per
slider update on lesson 4's mesh (target ≤ 3 ms); then the turn's figures;
then how long the page's Export PNG took to download, the first time after
the server started and later (:mod:`phonglab.bench.ui_export`).

The helpers that start and stop servers and Chromium are shared with the
browser tests.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

from phonglab.bench.ui_probe import Probe
from phonglab.bench.ui_report import (  # noqa: F401  (the targets and the report, here for the tests too)
    LESSON_CPU_MS_TARGET,
    RATIO_TARGET,
    SERVER_MS_TARGET,
    _report,
    _report_turn,
    percentile,
)

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

#: the lesson whose mesh the per-update CPU target is measured on, from the source tree's lessons/
LESSON_FILE = Path(__file__).resolve().parents[2] / "lessons" / "04-specular.md"
#: its address: the lesson with its vertices shaded by the core (Gouraud, as its own experiments set it)
LESSON_QUERY = "lesson=04-specular&interpolation=gouraud"
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
  // lazy: a frame in which no WebGL call could have changed the canvas keeps its hash without reading the
  // pixels back (the drawing buffer is preserved, so they are the same); a tab that waits then costs nothing
  const DRAWS = ["drawArrays", "drawElements", "drawArraysInstanced", "drawElementsInstanced",
                 "drawRangeElements", "clear", "clearBufferfv", "clearBufferiv", "clearBufferuiv",
                 "clearBufferfi", "blitFramebuffer"];
  const drawn = new WeakSet();
  HTMLCanvasElement.prototype.getContext = function (type, attributes) {
    const webgl = type === "webgl" || type === "webgl2" || type === "experimental-webgl";
    if (webgl) {
      attributes = Object.assign({}, attributes || {}, { preserveDrawingBuffer: true });
    }
    const context = getContext.call(this, type, attributes);
    if (webgl && context && !drawn.has(context)) {
      drawn.add(context);
      for (const name of DRAWS) {
        const call = context[name];
        if (typeof call === "function") {
          context[name] = function (...args) { bench.dirty = true; return call.apply(this, args); };
        }
      }
    }
    return context;
  };
  const bench = (window.__phonglabBench = {
    armed: false, t0: null, latency: null, base: 0, last: 0, stable: 0, frames: 0,
    selector: "canvas", paused: false, lazy: false, dirty: true, reads: 0, heard: 0, quiet: 0,
  });
  // every message a websocket of the page receives is counted: `quiet` is the number of frames since the
  // server last said anything, so a wait can tell a settled view from one whose next update is on its way
  const Socket = window.WebSocket;
  window.WebSocket = class extends Socket {
    constructor(...args) {
      super(...args);
      this.addEventListener("message", () => { bench.heard += 1; });
    }
  };
  let heardSeen = 0;
  let pixels = null, seen = null;
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
    if (bench.paused) {  // another page is being measured: no reading back here
      bench.stable = 0;
      requestAnimationFrame(frame);
      return;
    }
    const c = canvas();
    const shape = c ? [c, c.width, c.height] : null;
    const moved = !shape || !seen || shape.some((x, i) => x !== seen[i]);
    let h = bench.last;
    if (!bench.lazy || bench.dirty || moved || bench.last === 0) {
      bench.dirty = false;
      seen = shape;
      h = hash();
      bench.reads += 1;
    }
    bench.frames += 1;
    bench.quiet = bench.heard === heardSeen ? bench.quiet + 1 : 0;
    heardSeen = bench.heard;
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

#: :data:`MEASURE_JS` for tests: it reads the pixels back only after a frame in which WebGL drew (or the
#: canvas changed size), so a tab waiting on the server costs no readback; ``bench ui`` keeps reading every
#: frame, as its figures were measured
LAZY_MEASURE_JS = MEASURE_JS + "window.__phonglabBench.lazy = true;\n"


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


def copy_lesson(folder) -> int:
    """Copy :data:`LESSON_FILE` into the benchmark's lessons ``folder``; returns its mesh's vertex count."""
    from phonglab.render.mesh import build_mesh
    from phonglab.scene import load_lesson

    if not LESSON_FILE.is_file():
        raise RuntimeError(f"{LESSON_FILE} is missing: `phonglab bench ui` runs from the source tree, "
                           "whose lessons/ folder holds the lesson it measures")
    (Path(folder) / LESSON_FILE.name).write_text(LESSON_FILE.read_text(encoding="utf-8"), encoding="utf-8")
    return build_mesh(load_lesson(LESSON_FILE).scene.geometry).n_points


# ---------------------------------------------------------------------------
# measuring one app


def open_page(browser, url, canvas: str, *scripts: str):
    """A new page at ``url`` with :data:`MEASURE_JS` (and ``scripts``), once its view's first picture has settled."""
    page = browser.new_page(viewport=VIEWPORT)
    try:
        page.add_init_script(MEASURE_JS)
        for script in scripts:
            page.add_init_script(script)
        page.goto(url)
        page.wait_for_selector(canvas, timeout=90_000)
        page.evaluate("(selector) => { window.__phonglabBench.selector = selector; }", canvas)
        page.wait_for_function(
            "() => { const b = window.__phonglabBench; return b.last !== 0 && b.stable > 20; }", timeout=120_000
        )
    except Exception:
        page.close()
        raise
    return page


def open_lesson_page(browser, url):
    """:func:`open_page` at a phonglab address naming lesson 4 (:data:`LESSON_QUERY`), once that lesson shows."""
    page = open_page(browser, url, PHONGLAB_CANVAS)
    try:
        page.wait_for_function(
            "() => { const s = window.trame && window.trame.state; "
            "return s && s.get('lesson_number') === 4 && s.get('interpolation') === 'gouraud'; }",
            timeout=60_000)
        settle(page, frames=20)
    except Exception:
        page.close()
        raise
    return page


def settle(page, frames: int = 8) -> None:
    """Let ``page`` hash its pixels again and wait until ``frames`` animation frames show no change."""
    page.evaluate("() => { window.__phonglabBench.paused = false; }")
    page.wait_for_function(f"() => window.__phonglabBench.stable >= {frames}", timeout=30_000)


def pause(page) -> None:
    """Stop ``page`` reading its pixels back while another page is measured."""
    page.evaluate("() => { window.__phonglabBench.paused = true; }")


class KeyPress(Probe):
    """Key presses on one page's slider, each timed from the key event to changed pixels.

    Parameters
    ----------
    page : playwright Page
        Opened with :func:`open_page`.
    slider : str
        CSS selector of the slider's thumb (``[role=slider]``).
    timing_path : path
        The server's timing file (:mod:`phonglab.app.timing`).
    label : str
        Timing-file label of the server's updates.
    server_pid : int, optional
        The server's process: its CPU time per press is kept too (:class:`~phonglab.bench.ui_probe.Probe`).
    """

    def __init__(self, page, *, slider, timing_path, label, server_pid=None):
        super().__init__(page, timing_path=timing_path, label=label, server_pid=server_pid)
        self.slider = slider
        self._presses = 0

    def step(self) -> float:
        """One arrow key from a settled view, right and left in turn (the slider never reaches its end); ms."""
        page = self.page
        settle(page)
        page.locator(self.slider).first.focus()
        records = self.records()
        page.evaluate("() => window.__phonglabBench.arm()")
        cpu = self.server_cpu()
        page.keyboard.press("ArrowRight" if self._presses % 2 == 0 else "ArrowLeft")
        self._presses += 1
        page.wait_for_function("() => window.__phonglabBench.latency !== null", timeout=30_000)
        latency = page.evaluate("() => window.__phonglabBench.latency")
        self.keep(latency, records)
        if cpu is not None:
            settle(page)  # the panels and the page's answers to the update are in the server's time too
            self.keep_cpu(cpu)
        return latency


#: true once the page shows colours pushed after ``hash`` (``phonglab.js`` keeps the hash of those it shows)
_NEW_COLOURS_SHOWN = """(hash) => {
  const s = window.trame && window.trame.state;
  const push = s && s.get("view_colors");
  const colours = window.phonglabView && window.phonglabView.phonglabColours;
  return !!push && push.hash !== hash && !!colours && colours.shown === push.hash;
}"""


class ServerPress(KeyPress):
    """Key presses on one page's slider, each measured by the server's CPU clock (lesson 4's figure).

    The page does not read its pixels back meanwhile: its hashing loop (a
    ``gl.readPixels`` of the whole canvas every animation frame) would keep
    a core busy, which on 2 cores slows the very server being measured. The
    browser still draws the new colours and typesets the readout. Each press
    starts from a quiet server and ends when the page shows the pushed
    colours, the server has recorded the update and gone quiet again; its
    time is key press to colours shown (measured here, not in the page).

    The presses sweep the slider one way, then back from its end, so each
    brings a value the tab has not shown lately, as a drag's steps do. (Going
    back and forth between two values, as the other pages' presses do, lets
    whatever the server keeps for a value it had answer the press.)
    """

    #: turn back this far (in the slider's units) before the slider's end
    MARGIN = 0.1
    #: the presses go down the slider (ArrowLeft) since they reached its top end
    _back = False

    def step(self) -> float:
        page = self.page
        pause(page)
        slider = page.locator(self.slider).first
        slider.focus()
        self.wait_quiet()
        now, low, high = (float(slider.get_attribute(f"aria-value{end}") or "nan") for end in ("now", "min", "max"))
        if now >= high - self.MARGIN:
            self._back = True
        elif now <= low + self.MARGIN:
            self._back = False
        shown = page.evaluate("() => (window.trame.state.get('view_colors') || {}).hash || null")
        records = self.records()
        cpu = self.server_cpu()
        start = time.perf_counter()
        page.keyboard.press("ArrowLeft" if self._back else "ArrowRight")
        self._presses += 1
        page.wait_for_function(_NEW_COLOURS_SHOWN, arg=shown, timeout=30_000)
        latency = (time.perf_counter() - start) * 1000.0
        self.keep(latency, records)
        self.wait_quiet()  # the put-off panels and the page's answer are in the server's time too
        self.keep_cpu(cpu)
        return latency


# ---------------------------------------------------------------------------
# command line


def add_arguments(parser) -> None:
    parser.add_argument("--presses", type=_positive, default=30, help="measured rounds: a key press in each app and a drag of the view (default 30)")
    parser.add_argument("--warmup", type=_non_negative, default=3, help="unmeasured rounds first (default 3)")
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


#: what the benchmark presses and drags in each app
PHONGLAB_SLIDER = ".phonglab-control-material__shininess__log [role=slider]"
PHONGLAB_CANVAS = ".phonglab-view canvas"
BASELINE_SLIDER = ".bench-slider [role=slider]"
BASELINE_CANVAS = ".bench-view canvas"


def run(args) -> int:
    from playwright.sync_api import sync_playwright

    from phonglab.bench import ui_export
    from phonglab.bench.ui_turn import TURN_JS, Turn
    from phonglab.bench.usage import UsageError

    if not os.path.exists(CHROMIUM):
        raise UsageError(CHROMIUM_MISSING)
    presses, warmup = args.presses, args.warmup
    resolution, points = sphere_resolution(args.vertices)
    servers = []
    with tempfile.TemporaryDirectory(prefix="phonglab-bench-ui-") as tmp, sync_playwright() as playwright, \
            contextlib.ExitStack() as stack:
        browser = launch_chromium(playwright)
        stack.callback(browser.close)
        try:
            # phonglab's app first: its view size is then given to the baseline
            lessons = Path(tmp) / "lessons"
            lessons.mkdir()
            write_bench_lesson(lessons, resolution)
            lesson_points = copy_lesson(lessons)
            _progress(f"phonglab: sphere resolution {resolution} ({points} vertices)")
            ours = _serve(stack, servers, lambda port: serve_command(lessons, port), tmp, "phonglab")
            our_page = open_page(browser, ours["url"], PHONGLAB_CANVAS, TURN_JS)
            stack.callback(our_page.close)
            _progress("phonglab: the first export after the server started")
            pause(our_page)  # no reading back of pixels meanwhile
            first_export = ui_export.first_export(our_page, ours["started"])
            _progress(f"phonglab: {LESSON_FILE.name} ({lesson_points} vertices) in a second tab, Gouraud")
            lesson_page = open_lesson_page(browser, f"{ours['url']}index.html?{LESSON_QUERY}")
            stack.callback(lesson_page.close)
            css = our_page.evaluate("(s) => { const c = document.querySelector(s); return [c.width, c.height]; }",
                                    PHONGLAB_CANVAS)  # device pixel ratio 1 in headless Chromium
            _progress(f"baseline: {BASELINE_POINTS} vertices, view {css[0]}x{css[1]} CSS px")
            base = _serve(stack, servers, lambda port: [
                sys.executable, "-m", "phonglab.bench.ui_baseline", "--host", "127.0.0.1", "--port", str(port),
                "--view-size", f"{css[0]}x{css[1]}"], tmp, "baseline")
            base_page = open_page(browser, base["url"], BASELINE_CANVAS)
            stack.callback(base_page.close)
            probes = {
                "baseline": KeyPress(base_page, slider=BASELINE_SLIDER, timing_path=base["timing"], label="baseline"),
                "phonglab": KeyPress(our_page, slider=PHONGLAB_SLIDER, timing_path=ours["timing"], label="view",
                                     server_pid=ours["pid"]),
                "lesson": ServerPress(lesson_page, slider=PHONGLAB_SLIDER, timing_path=ours["timing"], label="view",
                                      server_pid=ours["pid"]),
                "turn": Turn(our_page, canvas=PHONGLAB_CANVAS, timing_path=ours["timing"], settle=settle),
            }
            _progress(f"{warmup} warm-up and {presses} measured rounds, each: a baseline key press, a phonglab "
                      "key press, one in lesson 4 and a drag of phonglab's view, in rotating order")
            _interleave(probes, [base_page, our_page, lesson_page], presses=presses, warmup=warmup)
            _progress(f"phonglab: {ui_export.LATER} later exports")
            pause(base_page)
            pause(our_page)
            pause(lesson_page)
            later_exports = ui_export.later_exports(our_page)
        except Exception as exc:
            logs = "\n".join(f"--- {s['name']} server log ---\n{log_tail(s['log'])}" for s in servers)
            raise RuntimeError(f"{exc}\n{logs}") from exc
        # the servers' own times, read before their folder goes
        size = f"{css[0]}x{css[1]}"
        results = {name: {"latency_ms": probes[name].latency_ms, "server_ms": probes[name].server_ms(),
                          "server_cpu_ms": probes[name].server_ms(cpu=True), "canvas": size,
                          "process_cpu_ms": probes[name].process_cpu_ms}
                   for name in ("baseline", "phonglab", "lesson")}
        results["lesson"]["points"] = lesson_points
        turn = probes["turn"]
        results["phonglab"]["turn"] = {"latency_ms": turn.latency_ms, "server_ms": turn.server_ms(),
                                       "server_cpu_ms": turn.server_ms(cpu=True),
                                       "step_px": turn.step_px, "missed": turn.missed}
    _report(results, points)
    ui_export.report(first_export, later_exports)
    return 0


def _serve(stack, servers: list, command, tmp, name: str) -> dict:
    """Start a server (stopped by ``stack``) that records its times; wait until it answers."""
    port = free_port()
    server = {"name": name, "url": f"http://127.0.0.1:{port}/", "timing": Path(tmp) / f"{name}-timing.txt",
              "log": Path(tmp) / f"{name}-server.log"}
    server["started"] = time.monotonic()
    process = start_server(command(port), log_path=server["log"], env={"PHONGLAB_UI_TIMING": str(server["timing"])})
    server["pid"] = process.pid
    servers.append(server)
    stack.callback(stop_server, process)
    wait_until_serving(process, port, log_path=server["log"])
    return server


def _interleave(probes: dict, pages: list, *, presses: int, warmup: int) -> None:
    """``warmup + presses`` rounds of one step of every probe, the order rotating by one each round.

    Before each step every other page stops reading back its pixels.
    """
    order = list(probes)
    for round_ in range(warmup + presses):
        if round_ == warmup:
            for probe in probes.values():
                probe.start_measuring()
        for name in order[round_ % len(order):] + order[:round_ % len(order)]:
            probe = probes[name]
            for page in pages:
                if page is not probe.page:
                    pause(page)
            probe.step()
        if (round_ + 1) % 5 == 0 or round_ + 1 == warmup + presses:
            _progress(f"  round {round_ + 1} of {warmup + presses}")
