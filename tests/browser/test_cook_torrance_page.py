"""Lesson 13 in headless Chromium: the roughness and metallic sliders, Cook–Torrance's readout, the compare view.

A student opens the physically based lesson, reads D, V and F at the probe, moves the roughness slider and
watches the picture and the readout follow, then turns on "Compare models" and sees the scene under Phong
and under Cook–Torrance side by side, redrawn when the roughness moves again.
"""

from __future__ import annotations

from real_lessons import lesson_tab, visit
from waiting import wait_for


def test_roughness_and_metallic_sliders_the_readout_and_the_compare_view(browser, serve_app):
    with lesson_tab(browser, serve_app, 1280, 800) as tab:
        visit(tab, "lesson=13-physically-based")
        page = tab.page
        assert tab.state("model") == "cook-torrance"
        labels = page.locator(".phonglab-equation .eq-label").all_inner_texts()
        assert {"D", "V", "F"} <= set(labels), f"the readout's rows: {labels}"
        specular_before = tab.readout()["terms"]["specular"]
        picture_before = tab.pixel_hash()

        # the roughness slider: one key step of 0.01, five times
        thumb = tab.slider("material__roughness")
        thumb.focus()
        for _ in range(5):
            page.keyboard.press("ArrowRight")
        wait_for(lambda: abs(float(tab.state("material__roughness")) - 0.40) < 1e-9,
                 "the roughness to go from 0.35 to 0.40 after five key steps")
        wait_for(lambda: tab.readout()["terms"]["specular"] != specular_before,
                 "the specular term at the probe to follow the roughness")
        tab.wait_settled()
        assert tab.pixel_hash() != picture_before, "the picture did not change with the roughness"
        assert tab.slider("material__metallic").count() == 1, "no metallic slider"

        # the compare view: both models side by side, Cook–Torrance's redrawn when the roughness moves again
        page.locator(".phonglab-compare-toggle").click()
        page.wait_for_selector("img.phonglab-compare-picture", timeout=120_000)
        wait_for(lambda: page.evaluate(
            "() => { const i = [...document.querySelectorAll('img.phonglab-compare-picture')];"
            " return i.length === 2 && i.every(p => p.complete && p.naturalWidth > 0); }"),
            "the comparison's two pictures to load", timeout=120)
        cook_torrance = ".phonglab-compare-figure:nth-child(2) img.phonglab-compare-picture"
        first = page.get_attribute(cook_torrance, "src")
        assert "view.compare=true" in page.url or tab.state("view__compare") is True
        thumb.focus()
        page.keyboard.press("ArrowRight")
        wait_for(lambda: page.get_attribute(cook_torrance, "src") != first,
                 "the comparison to be redrawn for roughness 0.41", timeout=120)
        # off: the panel goes
        page.locator(".phonglab-compare-toggle").click()
        page.wait_for_selector(".phonglab-compare", state="detached", timeout=30_000)
