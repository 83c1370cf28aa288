"""A lesson's common mistake in a real browser: the switch changes the picture and back.

The test lessons (:data:`phonglab.bench.scenes.LESSONS`) are lesson 4, whose mistake (normals
not renormalised) shows only per pixel and which opens in pixel mode, and
lesson 5, whose mistake (no clamp on the diffuse term) shows per vertex too.
"""

from __future__ import annotations

from waiting import wait_for

SWITCH = ".phonglab-mistake-switch input"
NOTE = ".phonglab-mistake-note"


def steady_hash(app_page) -> int:
    """The view's pixel hash once it has not changed for 40 frames (the lesson has finished drawing)."""
    app_page.wait_settled(frames=40)
    return app_page.pixel_hash()


def pixel_src(app_page) -> str:
    images = app_page.page.locator(".phonglab-pixel img")
    return images.get_attribute("src") if images.count() else ""


def test_per_pixel_mistake_changes_the_per_pixel_picture_and_switching_off_restores_it(app_page):
    page = app_page.page
    app_page.open_lesson("Normals left unnormalised")
    correct = wait_for(lambda: (src := pixel_src(app_page)).startswith("data:image/png") and src,
                       "lesson 4's per-pixel picture")
    assert app_page.state("interpolation") == "pixel"
    assert not page.locator(NOTE).count(), f"a 'cannot show' note in pixel mode: {page.locator(NOTE).all_inner_texts()}"
    page.locator(SWITCH).click()
    wait_for(lambda: app_page.state("view__mistake") is True, "the mistake switch to turn on")
    wrong = wait_for(lambda: (src := pixel_src(app_page)) != correct and src,
                     "the per-pixel picture to change with the mistake on")
    assert wrong.startswith("data:image/png;base64,"), wrong[:60]
    assert not page.locator(NOTE).count(), "the note says the mistake cannot show, in pixel mode"
    page.locator(SWITCH).click()
    wait_for(lambda: pixel_src(app_page) == correct,
             "the per-pixel picture to be exactly the correct one again with the mistake off")
    # per vertex the same mistake cannot show: the page says why instead
    page.locator(SWITCH).click()
    app_page.set_state("interpolation", "'gouraud'")
    note = wait_for(lambda: page.locator(NOTE).all_inner_texts(), "the note that the mistake shows only per pixel")
    assert "per-pixel" in note[0] and "Gouraud" in note[0], note
    # one click under the note goes to where the mistake shows, with it on
    page.locator(".phonglab-mistake-pixel").click()
    wait_for(lambda: app_page.state("interpolation") == "pixel" and app_page.state("view__mistake") is True,
             "per-pixel shading with the mistake on, after the note's button")
    wait_for(lambda: not page.locator(NOTE).count(), "the note to go away in pixel mode")
    wait_for(lambda: pixel_src(app_page) == wrong, "the per-pixel picture with the mistake")


def test_gouraud_mistake_changes_the_view_and_switching_off_restores_it(app_page):
    page = app_page.page
    app_page.open_lesson("Diffuse without the clamp")
    assert app_page.state("interpolation") == "gouraud"
    correct = steady_hash(app_page)
    page.locator(SWITCH).click()
    wait_for(lambda: app_page.state("view__mistake") is True, "the mistake switch to turn on")
    app_page.wait_settled()
    wait_for(lambda: app_page.pixel_hash() != correct, "the view to change with the unclamped diffuse term")
    assert not page.locator(NOTE).count(), page.locator(NOTE).all_inner_texts()
    page.locator(SWITCH).click()
    wait_for(lambda: app_page.state("view__mistake") is False, "the mistake switch to turn off")
    app_page.wait_settled()
    wait_for(lambda: app_page.pixel_hash() == correct, "the view to show the correct shading again")
