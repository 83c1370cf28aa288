"""The accuracy lesson's panel in a real browser: the plot, the picker, the error images.

The test lesson ``11-accuracy.md`` (:data:`phonglab.bench.scenes.LESSONS`) gets the panel by
its name. The plot is measured once per server process in worker
processes; while it is being measured, another tab keeps working.
"""

from __future__ import annotations


import pytest
from conftest import open_tab
from waiting import wait_for

PLOT = ".phonglab-accuracy-plot"


def shown(app_page) -> dict:
    """The panel as the page shows it: error image, caption and figures, read in one go."""
    return app_page.page.evaluate(
        """() => {
            const img = document.querySelector('.phonglab-accuracy-error img');
            const caption = document.querySelector('.phonglab-accuracy-render figcaption');
            const figures = {};
            for (const e of document.querySelectorAll('[data-figure]')) figures[e.dataset.figure] = e.innerText.trim();
            return { error: img ? img.src : '', caption: caption ? caption.innerText : '', figures };
        }"""
    )


@pytest.fixture(scope="module")
def server(serve_app, lesson_dir, export_dir):
    """This module's own server (the default session limit, written out, keys it apart from the shared one).

    The plot is measured once a server process, and the first test here watches it being measured: on the
    shared server, any earlier tab on the accuracy lesson would have measured it already.
    """
    return serve_app(lesson_dir, "--export-dir", export_dir, "--max-sessions", "60")


#: every animation frame from now on, until the plot is ready: each status the plot has in the page's state, in
#: turn, and whether the panel showed its "measuring" line in any frame of it
SEEN_JS = """() => {
  const seen = (window.__accuracySeen = []);
  function frame() {
    const plot = window.trame.state.get('accuracy_plot');
    const line = document.querySelector('.phonglab-accuracy-measuring');
    const status = plot ? plot.status : null;
    const shown = !!(line && line.offsetParent !== null);
    if (status && (!seen.length || seen[seen.length - 1].status !== status)) seen.push({ status, shown });
    else if (status) seen[seen.length - 1].shown ||= shown;
    if (status !== 'ready') requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
}"""


def number(text: str) -> float:
    return float(text.replace(" ms", ""))


def test_accuracy_lesson_shows_the_plot_and_the_picked_error_images(app_page, new_tab):
    page = app_page.page
    other = new_tab()
    assert not page.locator(".phonglab-accuracy").count(), "the accuracy panel shows on lesson 1"
    page.evaluate(SEEN_JS)
    app_page.open_lesson("Accuracy costs time")
    # what the page showed while it opened, frame by frame (on a loaded machine the plot may be ready by the
    # time the lesson has settled; that another tab stays responsive while it is measured is pinned with a
    # controlled measurement in tests/test_app_offload.py)
    seen = page.evaluate("() => window.__accuracySeen")
    measuring = [f for f in seen if f["status"] == "measuring"]
    assert measuring and all(f["shown"] for f in measuring), f"the page never said it was measuring: {seen[:5]}"
    assert seen.index(measuring[0]) < next((i for i, f in enumerate(seen) if f["status"] == "ready"), len(seen)), seen
    # while the server has a study of one tab, another tab still gets its updates
    before = other.readout()
    other.set_state("lights_1__azimuth", "-40")
    wait_for(lambda: other.readout()["dots"] != before["dots"], "the other tab's vectors to follow its light")
    # the first pick follows the lesson's scene: Gouraud on 16 segments
    first = wait_for(lambda: (s := shown(app_page))["error"].startswith("data:image/png") and s, "the error images",
                     timeout=90)  # computed in worker processes, which a loaded machine starts slowly
    assert "gouraud, 16 segments" in first["caption"], first["caption"]
    assert set(first["figures"]) >= {"RMSE", "max error", "peak error", "time"}, first["figures"]
    # the plot arrives
    wait_for(lambda: app_page.state("accuracy_plot")["status"] != "measuring", "the accuracy plot", timeout=120)
    assert app_page.state("accuracy_plot")["status"] == "ready", app_page.state("accuracy_plot")["error"]
    plot = page.locator(PLOT)
    assert plot.get_attribute("src").startswith("data:image/png;base64,")
    assert page.evaluate(f"() => document.querySelector('{PLOT}').naturalWidth") > 500
    # per pixel on 64 segments: a new error image, and a far smaller error
    page.locator(".phonglab-accuracy-method-pixel").click()
    page.locator(".phonglab-accuracy-resolution-64").click()
    picked = wait_for(lambda: "pixel, 64 segments" in (s := shown(app_page))["caption"] and s,
                      "the error images of per-pixel shading on 64 segments", timeout=90)
    assert picked["error"] != first["error"], "the error image did not change"
    assert picked["figures"] != first["figures"]
    for name in ("RMSE", "peak error"):
        assert number(picked["figures"][name]) < number(first["figures"][name]) / 5, (
            f"{name}: per pixel on 64 segments {picked['figures'][name]}, Gouraud on 16 {first['figures'][name]}")


@pytest.mark.parametrize("key, value_js, field", [
    ("accuracy_resolution", "7", "accuracy.resolution"),
    ("accuracy_resolution", "'16'", "accuracy.resolution"),
    ("accuracy_method", "'phong'", "accuracy.method"),
    ("accuracy_method", "null", "accuracy.method"),
])
def test_bad_picker_values_are_refused(app_page, key, value_js, field):
    app_page.open_lesson("Accuracy costs time")
    before = app_page.state(key)
    app_page.set_state(key, value_js)
    notice = wait_for(lambda: app_page.page.locator(".phonglab-notice").all_inner_texts(), "a refusal notice")
    assert "Refused" in notice[0] and field in notice[0], f"{key} = {value_js}: notice {notice}"
    wait_for(lambda: app_page.state(key) == before, f"{key} to return to {before!r}")


def test_the_enlarged_plot_fits_a_1366_by_768_window_whole(browser, server):
    """A click on the plot enlarges it; its bottom row and x-axes were cut off at 768 px high."""

    with open_tab(browser, server, width=1366, height=768) as tab:
        tab.open_lesson("Accuracy costs time")
        wait_for(lambda: tab.state("accuracy_plot")["status"] == "ready", "the accuracy plot", timeout=120)
        tab.page.locator(PLOT).click()
        large = tab.page.locator(".phonglab-accuracy-plot-large")
        large.wait_for(state="visible")
        tab.page.wait_for_timeout(400)  # the dialog's opening transition
        box = tab.page.evaluate("""() => {
            const img = document.querySelector('.phonglab-accuracy-plot-large');
            const r = img.getBoundingClientRect();
            const bottom = document.elementFromPoint(r.left + r.width / 2, r.bottom - 3);
            return {left: r.left, top: r.top, right: r.right, bottom: r.bottom, width: r.width, height: r.height,
                    natural: img.naturalWidth / img.naturalHeight, bottomIsImage: bottom === img,
                    innerWidth: window.innerWidth, innerHeight: window.innerHeight};
        }""")
        assert box["top"] >= 0 and box["left"] >= 0, box
        assert box["bottom"] <= box["innerHeight"] and box["right"] <= box["innerWidth"], f"cut off: {box}"
        assert abs(box["width"] / box["height"] - box["natural"]) < 0.02, f"the plot is stretched: {box}"
        assert box["bottomIsImage"], f"the plot's bottom edge is hidden: {box}"
        assert box["width"] > 0.6 * box["innerWidth"], f"the enlarged plot is hardly larger than the inline one: {box}"
        large.click()
        wait_for(lambda: not tab.state("accuracy_zoom"), "the enlarged plot to close on a click")
