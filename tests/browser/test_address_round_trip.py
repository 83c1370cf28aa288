"""The address in a real browser, on the real lessons: a link opens its lesson from the first frame, and the
address bar carries exactly the view on screen after every experiment of every lesson.

That the query of a view reopens the same view (readout to the last digit, picture pixel for pixel) is
checked for every experiment without a browser, through the same code the page runs
(``tests/test_app_address_scenes.py``). Here a tab applies every experiment of a lesson, for every lesson,
and its address bar must hold that query, at once (not a step behind); a few of those addresses are then
opened in a fresh tab and compared with the tab they came from, on screen. All lessons together cost about
2 minutes on 2 loaded cores (one server a worker, a tab a lesson, 5 fresh tabs); a test a lesson lets the
workers share them.
"""

from __future__ import annotations

import pytest
from real_lessons import LESSONS, drawn, lesson_tab
from waiting import wait_for

from phonglab.app import address
from phonglab.app import controls as ctl
from phonglab.scene.lessons import catalog

ENTRIES = [e for e in catalog(LESSONS)[0] if e.ok and e.lesson]
#: (lesson, experiment) whose address is also opened in a fresh tab: a slider's range passed, a colour no hex
#: code gives, a rolled camera and a new shape, per-pixel mode, a cutoff of 180°
FRESH = {("07-light-sources", 1), ("02-ambient", 2), ("06-blinn-phong", 2), ("04-specular", 2),
         ("07-light-sources", 0)}

#: every animation frame until the page's scene is drawn and stable: the header's text, whether the lesson's
#: page is shown, and the interpolation and lesson its state holds then
RECORD_JS = r"""
(() => {
  const frames = (window.__phonglabFrames = []);
  function frame() {
    const title = document.querySelector(".phonglab-lesson-title");
    const state = window.trame && window.trame.state;
    const shown = !!document.querySelector(".phonglab-grid");
    frames.push({
      header: title ? title.innerText.trim() : null,
      shown,
      interpolation: shown && state ? state.get("interpolation") : null,
      controls: Array.from(document.querySelectorAll(".phonglab-controls .phonglab-section, .phonglab-controls .phonglab-label"))
        .slice(0, 3).map((e) => e.innerText.trim()),
    });
    const bench = window.__phonglabBench;
    if (!(bench && bench.last !== 0 && bench.stable >= 10)) requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
})();
"""


def _entry(stem):
    return next(e for e in ENTRIES if e.path.stem == stem)


def expected_query(entry, k) -> str:
    """The query of lesson ``entry`` as it opens with experiment ``k`` applied (what the page's server writes)."""
    scene = entry.scene.replace_many(entry.lesson.experiments[k].settings)
    extra = {"view__mistake": ctl.MISTAKE_SWITCH} if entry.lesson.mistake else {}
    controls = ctl.ControlSet(ctl.Frame.of_camera(entry.scene.camera), entry.lesson.controls, extra)
    controls.update(scene)
    return address.ViewAddress().query(entry, scene, dict(address.DEFAULT_OPTIONS), controls)


def _search(page) -> str:
    return page.evaluate("() => decodeURIComponent(window.location.search)")


def _wait_address(page, wanted, what):
    try:
        page.wait_for_function("(q) => decodeURIComponent(window.location.search) === q", arg=wanted, timeout=30_000)
    except Exception:
        server = page.evaluate("() => window.trame.state.get('url_query')")
        pytest.fail(f"{what}: the address bar holds {_search(page)!r}, wanted {wanted!r}; the server's query "
                    f"is {server!r}", pytrace=False)


def _on_screen(tab) -> dict:
    """What the tab shows once settled (:func:`real_lessons.drawn`): the readout's texts, the controls' and the
    picture (the core's, or the canvas's pixel hash)."""
    page = tab.page
    wait_for(lambda: tab.state("readout"), "the readout")
    drawn(tab)
    texts = page.evaluate("""() => Array.from(document.querySelectorAll(
        '.phonglab-readout .phonglab-mono, .phonglab-readout .phonglab-light-name')).map((e) => e.innerText.trim())""")
    picture = (page.locator(".phonglab-pixel img").get_attribute("src") if tab.state("pixel_mode")
               else tab.pixel_hash())
    return {"readout": texts, "picture": picture, "controls": tab.state("control_values")}


def test_a_link_opens_its_lesson_from_the_first_frame(browser, serve_app):
    entry = _entry("08-interpolation")
    title = f"{entry.number} · {entry.title}"
    with lesson_tab(browser, serve_app) as tab:
        link = tab.server["url"] + "?lesson=08-interpolation&interpolation=flat"
        tab.page.add_init_script(RECORD_JS)
        tab.page.goto(link)
        drawn(tab)
        frames = tab.page.evaluate("() => window.__phonglabFrames")
        headers = [f["header"] for f in frames]
        wrong = [f for f in frames if f["header"] not in ("", None, title)
                 or (f["shown"] and (f["header"] != title or f["interpolation"] != "flat"))]
        assert not wrong, (link, f"{len(frames)} frames, first wrong: {wrong[:3]}", sorted(set(headers), key=headers.index))
        assert frames and frames[-1]["shown"] and headers[-1] == title, (link, frames[-3:])
        assert any(not f["shown"] for f in frames), "no loading frame recorded: the recording started too late"
        assert tab.state("interpolation") == "flat", tab.state("interpolation")


@pytest.mark.parametrize("stem", [e.path.stem for e in ENTRIES])  # a lesson a test: they share the workers
def test_after_every_experiment_the_address_bar_holds_the_view_and_reopens_it(browser, serve_app, stem):
    entry = _entry(stem)
    with lesson_tab(browser, serve_app) as tab:
        url = tab.server["url"]
        tab.page.goto(f"{url}?lesson={stem}")
        drawn(tab)
        _wait_address(tab.page, f"?lesson={stem}", stem)
        for k, experiment in enumerate(entry.lesson.experiments):
            tab.page.locator(".phonglab-apply").nth(k).click()
            wanted = expected_query(entry, k)
            _wait_address(tab.page, wanted, f"{stem}, after {experiment.label!r}")
            if (stem, k) in FRESH:
                shown = _on_screen(tab)
                with lesson_tab(browser, serve_app) as other:
                    other.page.goto(url + wanted)
                    drawn(other)
                    _wait_address(other.page, wanted, f"{stem} reopened")
                    # the fresh tab's view follows its size once drawn: the same view, when it has settled
                    seen = []
                    try:
                        wait_for(lambda: seen.append(_on_screen(other)) or seen[-1] == shown,
                                 f"{wanted} to show in a fresh tab what it showed in its own", timeout=90)
                    except pytest.fail.Exception:
                        differ = {n: (shown[n], seen[-1][n]) for n in shown if seen and seen[-1][n] != shown[n]}
                        raise AssertionError(f"{wanted}: own tab, fresh tab differ in {differ}") from None
            tab.page.locator(".phonglab-reset").click()
            _wait_address(tab.page, f"?lesson={stem}", f"{stem} reset")
