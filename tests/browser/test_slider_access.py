"""The sliders of a real lesson (lesson 4) for a keyboard and a screen reader.

Every slider thumb (Vuetify's ``[role=slider]``) has an ``aria-label`` naming
its control as :func:`phonglab.app.wording.spoken_label` does; one press of
the right arrow on the log-scale shininess slider changes α by a step one can
see (:data:`phonglab.app.controls.SHININESS_KEY_STEP`), not by 0.01 of its
exponent.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from waiting import wait_for

from phonglab.app import controls as ctl
from phonglab.app.wording import spoken_label
from phonglab.bench.ui import log_tail
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[2] / "lessons"
SLUG = "04-specular"
SHININESS = "material__shininess__log"


@pytest.fixture(scope="module")
def lesson4(browser, serve_app):
    """A tab on ``phonglab serve lessons/`` showing lesson 4, and the lesson's catalogue entry."""
    served = serve_app(LESSONS)  # shared with the other tests of the real lessons
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        page = context.new_page()
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(f"{served['url']}?lesson={SLUG}")
        page.wait_for_function(
            "(q) => window.trame && window.trame.state && window.trame.state.get('url_query') === q"
            " && document.querySelector('.phonglab-control [role=slider]')",
            arg=f"?lesson={SLUG}", timeout=60_000)
        entry = next(e for e in catalog(LESSONS)[0] if e.path.stem == SLUG)
        yield page, entry
        assert not errors, f"JavaScript errors on the page: {errors}"
        assert served["process"].poll() is None, f"the server died:\n{log_tail(served['log'])}"
    finally:
        context.close()


def test_every_slider_thumb_is_named_after_its_control(lesson4):
    page, entry = lesson4
    controls = ctl.ControlSet(ctl.Frame.of_camera(entry.scene.camera), entry.lesson.controls)
    controls.update(entry.scene)
    thumbs = page.evaluate("""() => [...document.querySelectorAll('[role=slider]')].map((t) => {
        const box = t.closest('.phonglab-control');
        const cls = box ? [...box.classList].find((c) => c.startsWith('phonglab-control-') &&
                                                 c !== 'phonglab-control-all') : null;
        return { key: cls ? cls.slice('phonglab-control-'.length) : null, label: t.getAttribute('aria-label') };
    })""")
    assert len(thumbs) >= 3, f"lesson 4 shows too few sliders: {thumbs}"
    for thumb in thumbs:
        assert thumb["key"] in controls.by_key, f"a slider outside a control box: {thumb}"
        wanted = spoken_label(controls.by_key[thumb["key"]])
        assert thumb["label"] and thumb["label"] == wanted, f"{thumb['key']}: aria-label {thumb['label']!r}, wanted {wanted!r}"
    assert any(t["key"] == SHININESS and "shininess" in t["label"] for t in thumbs), thumbs


def test_one_arrow_key_changes_the_shininess_visibly(lesson4):
    page, _ = lesson4
    before = page.evaluate("(k) => window.trame.state.get(k)", SHININESS)
    thumb = page.locator(f".phonglab-control-{SHININESS}:not(.phonglab-control-all) [role=slider]").first
    thumb.focus()
    page.keyboard.press("ArrowRight")
    after = wait_for(lambda: (v := page.evaluate("(k) => window.trame.state.get(k)", SHININESS)) != before and v,
                     f"the shininess slider to move from log10 α = {before}")
    ratio = 10.0 ** (after - before)
    assert ratio >= 1.02, f"one arrow key moved log10 α from {before} to {after}: α × {ratio:.4f}"
    assert after == pytest.approx(round(before + ctl.SHININESS_KEY_STEP, 2), abs=1e-9), (before, after)
    # the server took it: the scene's α follows
    wait_for(lambda: page.evaluate("() => window.trame.state.get('material__shininess')")
             == pytest.approx(10.0 ** after, rel=1e-3), f"the scene's α to become 10^{after}")
    # and back: the left arrow undoes it
    page.keyboard.press("ArrowLeft")
    back = wait_for(lambda: (v := page.evaluate("(k) => window.trame.state.get(k)", SHININESS)) != after and v,
                    "the shininess slider to move back")
    assert back == pytest.approx(round(before, 2), abs=1e-9), (before, after, back)
