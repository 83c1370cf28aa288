"""The picture tells the truth, in a real browser: display encoding and the mistake view.

A server of its own serves two lessons: a 50 % grey plane lit head-on (its
mesh pixels must show the sRGB value 188, not the raw 128) and lesson 9 of
the course, whose common mistake (specular without the n·l gate) paints a
highlight on the unlit side: with the mistake on, the readout must show that
highlight's specular and the view must carry the "deliberately wrong" banner.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from conftest import open_tab
from waiting import wait_for

LESSONS = Path(__file__).resolve().parents[2] / "lessons"

GREY = """+++
number = 1
title = "A grey card"
goal = "See a 50 % grey."
controls = ["display"]

[geometry]
kind = "plane"
resolution = 4

[material]
ka = 0
kd = 0.5
ks = 0
shininess = 10

[[lights]]
type = "directional"
direction = [0, 0, 1]

[camera]
eye = [0, 0, 3]
+++

A grey card, $k_d = 0.5$, lit head-on: $I = 0.5$.
"""
#: a point on lesson 9's sheet where the lamp is behind it and the ungated specular is bright
UNLIT = "[-0.1, 0.15, 0.0]"


@pytest.fixture(scope="module")
def truth_server(serve_app, tmp_path_factory):
    folder = tmp_path_factory.mktemp("truth-lessons")
    (folder / "01-grey.md").write_text(GREY, encoding="utf-8")
    (folder / "09-sheet.md").write_text((LESSONS / "09-two-sided-and-hard-cases.md").read_text("utf-8"), "utf-8")
    return serve_app(folder)


@pytest.fixture
def tab(browser, truth_server):
    with open_tab(browser, truth_server) as page:
        yield page


def view_pixels(tab) -> np.ndarray:
    """The 3D view as the browser shows it, RGB."""
    from PIL import Image

    png = tab.page.locator(".phonglab-view canvas").first.screenshot()
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def grey_patch(rgb: np.ndarray) -> np.ndarray:
    """Pixels of the plane away from the glyphs at the middle and the overlays at the bottom."""
    h, w, _ = rgb.shape
    return rgb[int(0.2 * h) : int(0.3 * h), int(0.45 * w) : int(0.55 * w)].reshape(-1, 3)


def test_half_grey_mesh_shows_188_and_128_with_the_linear_display(tab):
    tab.open_lesson("A grey card")
    assert tab.state("display") == "srgb"
    wait_for(lambda: bool(np.all(np.abs(grey_patch(view_pixels(tab)) - 188) <= 2)),
             "the grey plane's pixels to be sRGB 188 (today's raw encoding gives 128)")
    tab.set_state("display", "'linear'")
    wait_for(lambda: bool(np.all(np.abs(grey_patch(view_pixels(tab)) - 128) <= 2)),
             "the grey plane's pixels to be the raw 128 with display = linear")
    note = tab.text(".phonglab-display-note")
    assert "linear light" in note and "raw" in note, note


def test_mistake_readout_shows_the_unlit_highlight_and_the_view_carries_the_banner(tab):
    page = tab.page
    tab.open_lesson("Two-sided surfaces and hard cases")
    tab.set_state("probe", UNLIT)
    wait_for(lambda: np.allclose(tab.readout()["point"], [-0.1, 0.15, 0.0], atol=2e-3), "the probe to move")
    tab.wait_settled()
    assert tab.readout()["terms"].get("specular") == "(0.000, 0.000, 0.000)", tab.readout()
    assert not page.locator(".phonglab-wrong-banner").count(), "a banner while the picture is correct"
    before = tab.pixel_image()
    page.locator(".phonglab-mistake-switch input").click()
    wait_for(lambda: tab.state("view__mistake") is True, "the mistake switch to turn on")
    specular = wait_for(lambda: (t := tab.readout()["terms"].get("specular")) != "(0.000, 0.000, 0.000)" and t,
                        "the readout's specular to be the mistaken code's")
    values = [float(c) for c in specular.strip("()").split(",")]
    assert min(values) > 0.1, specular
    # beside it, the correct value and the wrong line of code next to the right one
    wrong = page.locator(".phonglab-term-wrong[data-wrong-term=specular]")
    assert "(0.000, 0.000, 0.000)" in wrong.inner_text() and "dot(n, l) > 0" in wrong.inner_text(), wrong.inner_text()
    # the picture has the highlight: much brighter pixels than without the mistake
    after = wait_for(lambda: [img for img in [tab.pixel_image()]
                              if img.shape == before.shape and not np.array_equal(img, before)],
                     "the per-pixel picture to change with the mistake")[0]
    def whitish(img):  # the grey-white highlight (the arrows are saturated colours; the lamp's white
        return int(np.count_nonzero(img.min(axis=2) > 190))  # marker is in both pictures)

    assert whitish(after) > whitish(before) + 200, (whitish(before), whitish(after))
    banner = page.locator(".phonglab-wrong-banner")
    assert banner.is_visible() and "Deliberately wrong: Specular without the n·l gate" in banner.inner_text()
    box, view = banner.bounding_box(), page.locator(".phonglab-view").bounding_box()
    assert view["y"] <= box["y"] and box["y"] + box["height"] <= view["y"] + view["height"], (box, view)
    # scroll the switch away: the banner over the view stays
    page.locator(".phonglab-mistake-switch").scroll_into_view_if_needed()
    assert banner.is_visible()
    page.locator(".phonglab-mistake-switch input").click()
    wait_for(lambda: not page.locator(".phonglab-wrong-banner").count(), "the banner to go with the mistake off")
