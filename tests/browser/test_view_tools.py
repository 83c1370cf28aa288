"""Nothing of the page covers what a student works with: the notice never lies over the controls, and the
view's tools never lie over the scene (a light's marker turned under the "Specular" button).

At 1280×800 and 1920×1080 on the real lessons. About a minute and a half on 2 loaded cores.
"""

from __future__ import annotations

import pytest
from real_lessons import lesson_tab, visit

#: the boxes of what is asked for, in page pixels
BOXES_JS = """(selectors) => selectors.map((s) => Array.from(document.querySelectorAll(s))
  .filter((e) => e.checkVisibility())
  .map((e) => { const b = e.getBoundingClientRect(); return { what: s, x: b.left, y: b.top, w: b.width, h: b.height }; })
  .filter((b) => b.w > 0 && b.h > 0))"""


def _overlap(a, b) -> bool:
    return a["x"] < b["x"] + b["w"] - 0.5 and b["x"] < a["x"] + a["w"] - 0.5 and \
        a["y"] < b["y"] + b["h"] - 0.5 and b["y"] < a["y"] + a["h"] - 0.5


@pytest.fixture
def tab(request, browser, serve_app):
    with lesson_tab(browser, serve_app, *request.param) as page:
        yield page


def _open(tab, stem):
    visit(tab, f"lesson={stem}")


@pytest.mark.parametrize("tab, stem, experiment", [
    ((1280, 800), "07-light-sources", 2), ((1920, 1080), "07-light-sources", 2),  # light 2's type below it
    ((1280, 800), "10-beyond-phong", 0), ((1280, 800), "11-accuracy", 3),  # the planner's list below it
], indirect=["tab"], ids=["1280-07", "1920-07", "1280-10", "1280-11"])
def test_an_applied_notice_covers_no_control_and_goes_by_itself(tab, stem, experiment):
    _open(tab, stem)
    tab.page.locator(".phonglab-apply").nth(experiment).click()
    tab.page.wait_for_selector(".phonglab-notice", timeout=60_000)
    tab.page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
    notices, controls = tab.page.evaluate(BOXES_JS, [".phonglab-notice", ".phonglab-side, .phonglab-side *"])
    text = tab.text(".phonglab-notice")
    assert notices and text.startswith("Applied"), (stem, notices, text)
    covered = [c for c in controls if _overlap(notices[0], c)]
    assert not covered, f"{stem}: the notice {text!r} at {notices[0]} covers {len(covered)} boxes of the side panel"
    # a notice that only informs goes by itself (a warning or an error stays until closed)
    tab.page.wait_for_selector(".phonglab-notice", state="detached", timeout=30_000)


@pytest.mark.parametrize("tab", [(1280, 800), (1920, 1080)], indirect=True, ids=["1280", "1920"])
def test_the_views_tools_leave_the_scene_uncovered_when_it_is_turned(tab):
    _open(tab, "04-specular")
    page = tab.page
    box = page.locator(".phonglab-view canvas").bounding_box()
    cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx - 0.25 * box["width"], cy + 0.2 * box["height"], steps=10)
    page.mouse.up()
    page.wait_for_function("() => window.trame.state.get('camera__azimuth') !== 0", timeout=60_000)
    tab.wait_settled()
    views, tools = page.evaluate(BOXES_JS, [".phonglab-view", ".phonglab-tools .v-btn, .phonglab-chip, .phonglab-legend"])
    covering = [t for t in tools if _overlap(views[0], t)]
    assert views and not covering, f"the view's tools lie over the view {views}: {covering}"
    # the light's marker, where the view shows it: what is on top there is the view's picture, not a button
    on_top = page.evaluate("""() => {
      const view = window.phonglabView, canvas = document.querySelector('.phonglab-view canvas');
      const p = window.trame.state.get('lights_1__position'), r = canvas.getBoundingClientRect();
      const d = view.renderer.worldToNormalizedDisplay(p[0], p[1], p[2], r.width / r.height);
      const x = r.left + d[0] * r.width, y = r.top + (1 - d[1]) * r.height;
      if (x < r.left || x > r.right || y < r.top || y > r.bottom) return null;
      const e = document.elementFromPoint(x, y);
      return { x, y, inView: !!(e && e.closest('.phonglab-view')), button: !!(e && e.closest('button, .v-btn')) };
    }""")
    assert on_top is None or (on_top["inView"] and not on_top["button"]), on_top


@pytest.mark.parametrize("tab", [(1366, 768)], indirect=True, ids=["1366"])
def test_the_arrows_switch_hides_the_arrows_and_their_letters_and_brings_them_back(tab):
    # lesson 13's "Smooth" asks about a highlight under the V marker: the switch beside the legend hides the
    # arrows, keyboard-reachable and saying what it does
    _open(tab, "13-physically-based")
    page = tab.page
    switch = page.locator("button.phonglab-arrows-toggle")
    assert switch.get_attribute("aria-pressed") == "false" and "Hide the arrows" in switch.get_attribute("aria-label")
    letters = "() => Array.from(document.querySelectorAll('.phonglab-letters > *')).filter((e) => e.checkVisibility()).length"
    picture = tab.state("pixel_src")
    assert page.evaluate(letters) >= 3 and len(tab.state("legend")) == 5, (page.evaluate(letters), tab.state("legend"))
    switch.focus()
    page.keyboard.press("Enter")
    page.wait_for_function("() => window.trame.state.get('view__arrows_hidden') === true", timeout=30_000)
    page.wait_for_function("(p) => window.trame.state.get('pixel_src') !== p && !window.trame.state.get('pixel_pending')",
                           arg=picture, timeout=60_000)
    tab.wait_settled()
    assert page.evaluate(letters) == 0 and tab.state("legend") == [], (page.evaluate(letters), tab.state("legend"))
    assert switch.get_attribute("aria-pressed") == "true" and "arrows hidden" in switch.inner_text()
    switch.click()
    page.wait_for_function("() => (window.trame.state.get('legend') || []).length === 5", timeout=60_000)
    tab.wait_settled()
    assert switch.get_attribute("aria-pressed") == "false"
