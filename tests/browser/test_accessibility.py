"""What a screen reader hears: every control in the Tab order has a name, and every slider says what the page shows.

Read from Chromium's accessibility tree (``Accessibility.getFullAXTree`` over the DevTools protocol): the
nodes a keyboard reaches and their names, the sliders and their numbers. A slider's spoken value is its
``aria-valuetext`` when it has one, else its number (WAI-ARIA); Chromium 156's tree leaves that text out of
the node (its ``valuetext`` is empty even for a fixed ``aria-valuetext``), so it is read from each slider
node the tree lists, through the node itself. The shininess slider's number is log10 α (1.48) while the
page shows α (30): without the text a screen reader says 1.48.
"""

from __future__ import annotations

import pytest
from real_lessons import lesson_tab, visit
from waiting import wait_for

#: for a slider node: its name, its number, its aria-valuetext and the value its control shows beside it
SLIDER_JS = """function () {
  const control = this.closest('.phonglab-control');
  const shown = control && control.querySelector('.phonglab-value');
  return { label: this.getAttribute('aria-label'), now: this.getAttribute('aria-valuenow'),
           text: this.getAttribute('aria-valuetext'), shown: shown ? shown.textContent.trim() : null };
}"""


@pytest.fixture
def tab(browser, serve_app):
    with lesson_tab(browser, serve_app) as page:
        yield page


def _open(tab, stem):
    visit(tab, f"lesson={stem}")
    # every group of "all controls" open, so their widgets are in the tree too
    for title in tab.page.locator(".phonglab-group .v-expansion-panel-title").all():
        title.click()
    tab.page.wait_for_function("() => document.querySelectorAll('.phonglab-control-all').length > 0", timeout=30_000)


def _tree(tab):
    cdp = tab.page.context.new_cdp_session(tab.page)
    cdp.send("Accessibility.enable")
    return cdp, cdp.send("Accessibility.getFullAXTree")["nodes"]


def _sliders(cdp, nodes) -> list[dict]:
    out = []
    for node in nodes:
        if node.get("ignored") or node.get("role", {}).get("value") != "slider":
            continue
        handle = cdp.send("DOM.resolveNode", {"backendNodeId": node["backendDOMNodeId"]})["object"]["objectId"]
        seen = cdp.send("Runtime.callFunctionOn", {"objectId": handle, "functionDeclaration": SLIDER_JS,
                                                   "returnByValue": True})["result"]["value"]
        out.append({"name": node.get("name", {}).get("value", ""), "value": node.get("value", {}).get("value"), **seen})
    return out


@pytest.mark.parametrize("stem", ["04-specular", "07-light-sources"])
def test_every_control_a_keyboard_reaches_has_a_name_and_says_what_the_page_shows(tab, stem):
    _open(tab, stem)
    cdp, nodes = _tree(tab)
    focusable = [n for n in nodes if not n.get("ignored")
                 and any(p["name"] == "focusable" and p["value"].get("value") for p in n.get("properties", []))]
    unnamed = [(n.get("role", {}).get("value"), n.get("backendDOMNodeId")) for n in focusable
               if not n.get("name", {}).get("value", "").strip()]
    described = []
    for role, backend in unnamed:
        html = cdp.send("DOM.getOuterHTML", {"backendNodeId": backend})["outerHTML"]
        described.append(f"{role}: {html[:160]}")
    assert not unnamed, f"{stem}: focusable without a name:\n" + "\n".join(described)
    sliders = _sliders(cdp, nodes)
    assert len(sliders) >= 6, (stem, sliders)
    wrong = [s for s in sliders if not s["shown"] or s["text"] != s["shown"] or s["name"] != s["label"]]
    assert not wrong, f"{stem}: sliders whose spoken value is not the one shown: {wrong}"


def test_the_shininess_slider_says_alpha_and_follows_a_key(tab):
    _open(tab, "04-specular")
    cdp, nodes = _tree(tab)
    shininess = [s for s in _sliders(cdp, nodes) if s["name"] == "shininess α"]
    assert shininess and all(s["text"] == "30" and abs(s["value"] - 1.477) < 0.01 for s in shininess), shininess
    thumb = tab.slider("material__shininess__log")
    thumb.focus()
    thumb.press("ArrowRight")
    shown = wait_for(lambda: (t := tab.text(".phonglab-control-material__shininess__log .phonglab-value")) != "30" and t,
                     "the shininess to move")
    wait_for(lambda: thumb.get_attribute("aria-valuetext") == shown,
             f"the slider to say {shown}, it says {thumb.get_attribute('aria-valuetext')}")
    cdp, nodes = _tree(tab)
    assert [s["text"] for s in _sliders(cdp, nodes) if s["name"] == "shininess α"] == [shown, shown]
