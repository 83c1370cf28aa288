"""``phonglab.show`` in JupyterLab, in headless Chromium: the cell shows the lesson view, and a slider moved in
it changes the picture."""

from __future__ import annotations

import json
import sys
import time
import urllib.request
from pathlib import Path

import pytest
from waiting import wait_for

from phonglab.bench.ui import LAZY_MEASURE_JS, free_port, log_tail, start_server, stop_server

pytestmark = pytest.mark.browser

LESSON_4 = Path(__file__).resolve().parents[2] / "lessons" / "04-specular.md"


@pytest.fixture()
def jupyterlab(tmp_path):
    """JupyterLab on a free 127.0.0.1 port (no token), with a notebook whose one cell shows lesson 4."""
    import nbformat

    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(
        f"import phonglab\nview = phonglab.show({str(LESSON_4)!r}, interpolation='gouraud')\nview")]
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(notebook, tmp_path / "view.ipynb")
    port = free_port()
    log_path = tmp_path / "jupyterlab.log"
    process = start_server(
        [sys.executable, "-m", "jupyterlab", "--no-browser", "--ip=127.0.0.1", f"--port={port}", "--allow-root",
         "--ServerApp.token=", "--ServerApp.password=", f"--ServerApp.root_dir={tmp_path}"],
        log_path=log_path, env={"JUPYTER_CONFIG_DIR": str(tmp_path / "config")})
    try:
        deadline = time.monotonic() + 120
        while True:
            assert process.poll() is None, f"JupyterLab exited:\n{log_tail(log_path)}"
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status", timeout=5):
                    break
            except OSError:
                assert time.monotonic() < deadline, f"JupyterLab did not answer:\n{log_tail(log_path)}"
                time.sleep(0.5)
        yield {"url": f"http://127.0.0.1:{port}/lab/tree/view.ipynb", "api": f"http://127.0.0.1:{port}/api/",
               "log": log_path, "process": process}
    finally:
        stop_server(process)


def _kernel_idle(api: str) -> bool:
    """True once the notebook's kernel has started and waits for a cell."""
    with urllib.request.urlopen(api + "sessions", timeout=10) as answer:
        sessions = json.load(answer)
    return any(s.get("kernel", {}).get("execution_state") == "idle" for s in sessions)


#: the boxes of the view and of the shininess slider in the cell's frame, and the frame's size
SIDE_BY_SIDE_JS = """() => {
  const box = (s) => { const b = document.querySelector(s).getBoundingClientRect();
                       return { left: b.left, top: b.top, right: b.right, bottom: b.bottom }; };
  return { view: box('.phonglab-view'), slider: box('.phonglab-control-material__shininess__log [role=slider]'),
           width: innerWidth, height: innerHeight };
}"""


def test_a_notebook_cell_shows_the_lesson_view_and_a_slider_changes_the_picture(browser, jupyterlab):
    # a laptop's window, JupyterLab's file browser open: the cell's frame is about 830 px wide
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.add_init_script(LAZY_MEASURE_JS)  # in every frame: the cell's iframe too
    try:
        page.goto(jupyterlab["url"])
        page.wait_for_selector(".jp-Notebook .jp-Cell", timeout=120_000)
        wait_for(lambda: _kernel_idle(jupyterlab["api"]), "the notebook's kernel to be ready", timeout=120)
        editor = page.locator(".jp-Notebook .jp-Cell .jp-InputArea-editor").first
        editor.click()
        wait_for(lambda: page.evaluate("() => !!document.activeElement && "
                                       "!!document.activeElement.closest('.jp-InputArea-editor')"),
                 "the cell's editor to take the focus", timeout=30)
        page.keyboard.press("Shift+Enter")
        page.wait_for_selector("iframe.phonglab-iframe", timeout=180_000)
        frame = page.frame_locator("iframe.phonglab-iframe")
        frame.locator(".phonglab-view canvas").first.wait_for(timeout=180_000)
        inner = next(f for f in page.frames if "/index.html" in f.url and "ui=main" in f.url)
        inner.evaluate("() => { window.__phonglabBench.selector = '.phonglab-view canvas'; }")
        inner.wait_for_function("() => { const b = window.__phonglabBench; return b.last !== 0 && b.stable >= 10; }",
                                timeout=120_000)
        # the view and the slider side by side in the cell's frame, both in sight: in one column the
        # controls came a page below the view, and no slider could be moved while watching the picture
        boxes = inner.evaluate(SIDE_BY_SIDE_JS)
        view, slider, height = boxes["view"], boxes["slider"], boxes["height"]
        assert slider["left"] >= view["right"] - 1 and slider["bottom"] <= height and view["bottom"] <= height, (
            f"in a frame {boxes['width']} x {height} px the view {view} and the shininess slider {slider} "
            "are not side by side in sight")
        before_hash = inner.evaluate("() => window.__phonglabBench.hash()")
        before = inner.evaluate("() => window.trame.state.get('material__shininess__log')")
        thumb = frame.locator(".phonglab-control-material__shininess__log [role=slider]").first
        thumb.focus()
        for _ in range(5):
            thumb.press("ArrowRight")
        wait_for(lambda: inner.evaluate("() => window.trame.state.get('material__shininess__log')") != before,
                 "the shininess slider to move", timeout=30)
        wait_for(lambda: inner.evaluate("() => window.__phonglabBench.hash()") != before_hash,
                 "the picture to change after the slider moved", timeout=60)
        assert not errors, errors
        assert jupyterlab["process"].poll() is None, log_tail(jupyterlab["log"])
    finally:
        context.close()
