"""The lesson page in a real browser: picture, readout, picking, lessons, sessions, bad input.

Each test opens its own tab (its own server session) on the lessons written
by ``conftest.py``. Pictures are compared through a hash of the view's WebGL
pixels read inside the page; numbers are read from the page's readout and
checked against the Phong model worked out here from the lesson's light and
eye.
"""

from __future__ import annotations

import math
import re
import urllib.request

import numpy as np
import pytest
from waiting import wait_for

from phonglab.bench import scenes

#: the first lesson's light and eye (the red sphere's)
LIGHT = np.array(scenes.LIGHT_POSITION)
EYE = np.array(scenes.EYE)


def expected_dots(point):
    """n·l, r·v, n·h at a point of the unit sphere for the first lesson's light and eye."""
    p = np.asarray(point, dtype=float)
    n = p / np.linalg.norm(p)
    l = (LIGHT - p) / np.linalg.norm(LIGHT - p)
    v = (EYE - p) / np.linalg.norm(EYE - p)
    r = 2 * np.dot(n, l) * n - l
    h = (l + v) / np.linalg.norm(l + v)
    return {"n·l": float(n @ l), "r·v": float(r @ v), "n·h": float(n @ h)}


def test_lesson_loads_with_typeset_maths_and_a_picture(app_page):
    page = app_page.page
    assert app_page.text(".phonglab-lesson-title") == "1 · A red sphere"
    body = app_page.text(".phonglab-text")
    # the maths is MathML, never raw $...$ (the escaped \$ stays a dollar)
    assert page.locator(".phonglab-body math").count() >= 2, body
    assert page.locator(".phonglab-body .math-block math[display=block]").count() == 1, body
    assert page.locator(".phonglab-goal math").count() == 2, body
    without_price = body.replace("Costs $0.", "")
    assert "$" not in without_price, f"raw dollar signs on the page:\n{body}"
    assert "Costs $0." in body, body
    # the view drew something, and the readout and planner are there
    assert app_page.pixel_hash() != 0
    assert page.locator(".phonglab-equation .eq-row math").count() == 5
    assert page.locator(".phonglab-plan-row").count() >= 3


def test_slider_changes_picture_and_readout(app_page):
    before_hash = app_page.pixel_hash()
    before = app_page.readout()
    value_before = app_page.text(".phonglab-control-material__shininess__log .phonglab-value")
    thumb = app_page.slider("material__shininess__log")
    thumb.focus()
    for _ in range(7):  # log10(α) up by 7 key steps of 0.03: α from 20 to about 32
        app_page.page.keyboard.press("ArrowRight")
    shown = ".phonglab-control-material__shininess__log .phonglab-value"
    # the last step: log10 α from 1.48 (α ≈ 30.2) to 1.51 (α ≈ 32.4); wait for the last one
    wait_for(lambda: 31.2 <= float(app_page.text(shown)) <= 33,
             f"α to go from {value_before} to 10^1.51 ≈ 32.4 after 7 key steps of 0.03 in log10 α")
    alpha = float(app_page.text(shown))
    wait_for(lambda: app_page.readout()["terms"]["specular"] != before["terms"]["specular"],
             "the specular term at the probe to change")
    app_page.wait_settled()
    assert app_page.pixel_hash() != before_hash, "the picture did not change after moving the shininess"
    # the scene field behind the slider holds α itself
    assert app_page.state("material__shininess") == pytest.approx(alpha, rel=0.02)


def test_clicking_the_surface_moves_the_probe_and_its_vectors(app_page):
    page = app_page.page
    before = app_page.readout()
    box = page.locator(".phonglab-view canvas").bounding_box()
    # left of the centre and a little down: on the sphere, away from the probe
    page.mouse.click(box["x"] + box["width"] * 0.38, box["y"] + box["height"] * 0.6)
    after = wait_for(lambda: (r := app_page.readout())["point"] != before["point"] and r, "the probe to move")
    p = np.array(after["point"])
    assert abs(np.linalg.norm(p) - 1.0) < 0.01, f"the probe {p} is not on the unit sphere"
    assert p[0] < -0.05 and p[1] < -0.05 and p[2] > 0.3, f"the probe {p} is not where the click was"
    expected = expected_dots(p)
    for name, value in after["dots"].items():
        assert value == pytest.approx(expected[name], abs=0.02), (
            f"{name} at probe {p}: page shows {value}, the model gives {expected[name]:.4f}"
        )
    app_page.wait_settled()


def test_dragging_turns_the_view_without_moving_the_probe(app_page):
    page = app_page.page
    before = app_page.readout()
    # every probe point the server sends from now on, in order
    page.evaluate("""() => { window.__probes = [];
        window.trame.state.watch(['readout'], (r) => window.__probes.push(r && r.point)); }""")
    hash_before = app_page.pixel_hash()
    box = page.locator(".phonglab-view canvas").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 80, y + 10, steps=8)
    page.mouse.up()
    app_page.wait_settled()
    assert app_page.pixel_hash() != hash_before, "dragging did not turn the view"
    assert app_page.readout()["point"] == before["point"], "a drag moved the probe"
    # a click after the drag: once its probe is shown, the server has handled everything the drag sent
    page.mouse.click(x, y)
    wait_for(lambda: app_page.readout()["point"] != before["point"], "the click to move the probe")
    probes = page.evaluate("() => window.__probes")
    seen = [p for i, p in enumerate(probes) if i == 0 or p != probes[i - 1]]
    assert len(seen) == 2, f"probe points shown between the drag and the click: {seen}"


def test_switching_lessons_and_a_broken_lesson_shows_its_errors(app_page):
    page = app_page.page
    page.locator(".phonglab-menu").click()
    page.locator(".phonglab-lesson-item", has_text="A spotlight on a floor").click()
    wait_for(lambda: app_page.text(".phonglab-lesson-title") == "2 · A spotlight on a floor", "lesson 2's title")
    wait_for(lambda: page.locator(".phonglab-control-lights_1__cutoff").count() > 0, "the cutoff slider")
    assert app_page.state("lights_1__cutoff") == 25
    app_page.wait_settled()
    page.locator(".phonglab-menu").click()
    page.locator(".phonglab-lesson-item", has_text="A broken lesson").click()
    errors = wait_for(lambda: page.locator(".phonglab-error").all_inner_texts(), "the lesson's errors")
    assert any("material.kd" in e and "-3" in e for e in errors), f"errors shown: {errors}"
    assert "03-broken.md" in errors[0], errors


def test_two_tabs_keep_separate_state(app_page, new_tab):
    other = new_tab()
    key = "material__ks__level"
    assert app_page.state(key) == other.state(key) == pytest.approx(0.6)
    thumb = app_page.slider(key)
    thumb.focus()
    for _ in range(5):
        app_page.page.keyboard.press("ArrowLeft")
    wait_for(lambda: app_page.state("material__ks") == pytest.approx([0.55] * 3), "tab 1's k_s to reach 0.55")
    # tab 2 moves its own light; neither sees the other's change
    other.set_state("lights_1__azimuth", "10")
    wait_for(lambda: other.readout()["dots"] != app_page.readout()["dots"], "tab 2's vectors to change")
    # the readout and the control values of tab 2's change arrive together
    assert other.state(key) == pytest.approx(0.6), "tab 2's k_s moved with tab 1's slider"
    assert other.state("material__ks") == pytest.approx([0.6] * 3)
    # one more step on tab 1: once it shows, tab 1 has been refreshed after tab 2's change
    app_page.page.keyboard.press("ArrowLeft")
    wait_for(lambda: app_page.state("material__ks") == pytest.approx([0.54] * 3), "tab 1's k_s to reach 0.54")
    assert app_page.state("lights_1__azimuth") != pytest.approx(10), "tab 1's light moved with tab 2's"


@pytest.mark.parametrize(
    "key, value_js, field",
    [
        ("material__ks__level", "NaN", "material.ks.level"),
        ("material__ks__level", "'abc'", "material.ks.level"),
        ("material__ks__level", "7", "material.ks.level"),
        ("material__kd", "[1, 'x', 2]", "material.kd"),
        ("lights_1__attenuation_0", "0", "lights[1].attenuation[0]"),
        ("model", "'lambert'", "model"),
        ("lights_1__distance", "Infinity", "lights[1].distance"),
    ],
)
def test_bad_values_are_refused_and_the_server_survives(app_page, server, key, value_js, field):
    before = app_page.state(key)
    hash_before = app_page.pixel_hash()
    if key == "lights_1__attenuation_0":  # make a = 0 the last positive coefficient first
        assert app_page.state("lights_1__attenuation") == [1, 0, 0]
    app_page.set_state(key, value_js)
    notice = wait_for(lambda: app_page.page.locator(".phonglab-notice").all_inner_texts(), "a refusal notice")
    assert "Refused" in notice[0] and field in notice[0], f"{key} = {value_js}: notice {notice}"
    wait_for(lambda: app_page.state(key) == before, f"{key} to return to {before!r}")
    app_page.wait_settled()
    assert app_page.pixel_hash() == hash_before, f"{key} = {value_js} changed the picture although refused"
    # the server still serves pages and still takes good values
    with urllib.request.urlopen(server["url"] + "index.html", timeout=5) as response:
        assert response.status == 200
    app_page.set_state("material__ks__level", "0.3")
    wait_for(lambda: app_page.state("material__ks") == pytest.approx([0.3] * 3), "a good value to apply")


def test_experiment_answer_pixel_mode_and_export(app_page, export_dir):
    page = app_page.page
    page.locator(".phonglab-apply").first.click()
    wait_for(lambda: app_page.state("material__ks") == [0, 0, 0], "the experiment to set k_s = 0")
    assert not page.locator(".phonglab-answer").count()
    page.locator(".phonglab-answer-btn").click()
    assert page.locator(".phonglab-answer math").count() == 1
    # per-pixel shading shows the core's image over the view
    app_page.set_state("interpolation", "'pixel'")
    src = wait_for(lambda: page.locator(".phonglab-pixel img").get_attribute("src")
                   if page.locator(".phonglab-pixel img").count() else None, "the per-pixel image")
    assert src.startswith("data:image/png;base64,") and len(src) > 10_000, src[:80]
    before = set(export_dir.glob("*.png"))
    page.locator(".phonglab-export").click()
    notice = wait_for(lambda: [t for t in page.locator(".phonglab-notice").all_inner_texts() if "xport" in t or "Saved" in t],
                      "the export notice", timeout=60)
    new = set(export_dir.glob("*.png")) - before
    assert len(new) == 1 and "Saved" in notice[0], f"notice {notice}, new files {new}"
    png = next(iter(new)).read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    assert re.search(r"lesson-01-\d{8}-\d{6}\.png", next(iter(new)).name)
    assert math.isfinite(app_page.readout()["dots"]["n·l"])


def test_term_view_and_placing_the_light_by_clicking(app_page):
    page = app_page.page
    hash_all = app_page.pixel_hash()
    page.locator(".phonglab-term-specular").click()
    wait_for(lambda: app_page.state("view__term") == "specular", "the term view to switch to specular")
    # the browser sets the key itself: wait for the server's new colours, not only for the key
    wait_for(lambda: app_page.pixel_hash() != hash_all, "the specular-only view to differ from the full picture")
    # put the light above a point on the left of the sphere
    page.locator(".phonglab-pick-toggle button", has_text="Light").click()
    wait_for(lambda: app_page.state("pick_target") == "light", "the click target to become the light")
    probe = app_page.readout()["point"]
    box = page.locator(".phonglab-view canvas").bounding_box()
    page.mouse.click(box["x"] + box["width"] * 0.35, box["y"] + box["height"] * 0.5)
    azimuth = wait_for(lambda: (a := app_page.state("lights_1__azimuth")) < -10 and a, "the light to move left")
    assert app_page.readout()["point"] == probe, "placing the light moved the probe"
    position = np.array(app_page.state("lights_1__position"))
    distance = np.linalg.norm(position)
    assert distance == pytest.approx(np.linalg.norm(LIGHT), rel=1e-3), "the light kept its distance"
    assert position[0] < 0, f"light at {position} (azimuth {azimuth}) is not on the left"
