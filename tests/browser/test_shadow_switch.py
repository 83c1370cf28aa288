"""The shadow switch in a real browser: it takes the ball's shadow off the floor and puts it back.

A server of its own serves one lesson: the ball over the floor
(``assets/scenes/ball-over-floor.toml``) with the shadow switch and the
offset among its controls. Per vertex, the browser draws the colours itself
(vtk.js): turning shadows off brightens the canvas, and on again gives the
same pixels as before. Per pixel, the page shows the server's picture: with
shadows off no pixel is darker and the floor under the ball is much brighter.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import open_tab
from waiting import wait_for

ROOT = Path(__file__).resolve().parents[2]
SWITCH = ".phonglab-control-shadows:not(.phonglab-control-all) input"

#: the mean of the canvas's RGB (its WebGL drawing buffer, kept by MEASURE_JS), 0..255
CANVAS_MEAN = """() => {
    const c = document.querySelector(window.__phonglabBench.selector);
    const gl = c.getContext("webgl2") || c.getContext("webgl");
    const px = new Uint8Array(c.width * c.height * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let sum = 0;
    for (let i = 0; i < px.length; i += 4) sum += px[i] + px[i + 1] + px[i + 2];
    return sum / (3 * c.width * c.height);
}"""


def pixel_src(page) -> str:
    """The per-pixel picture's data URL, or "" while the page has none."""
    images = page.locator(".phonglab-pixel img")
    src = images.get_attribute("src") if images.count() else ""
    return src if (src or "").startswith("data:image/png;base64,") else ""


def lesson_text() -> str:
    scene = (ROOT / "assets" / "scenes" / "ball-over-floor.toml").read_text(encoding="utf-8")
    scene = scene.replace('title = "A ball over a floor"\n', "")
    head = ('number = 1\ntitle = "Shadows on"\ngoal = "See the ball\'s shadow."\n'
            'controls = ["shadows", "shadow_bias"]\n')
    return "+++\n" + head + scene + "+++\n\nThe ball over the floor.\n"


@pytest.fixture(scope="module")
def shadow_server(serve_app, tmp_path_factory):
    folder = tmp_path_factory.mktemp("shadow-lessons")
    (folder / "01-shadows.md").write_text(lesson_text(), encoding="utf-8")
    return serve_app(folder)


def test_the_shadow_switch_toggles_the_shadow_on_the_floor(browser, shadow_server):
    with open_tab(browser, shadow_server) as tab:
        page = tab.page
        assert tab.state("shadows") is True and tab.state("interpolation") == "gouraud"
        tab.wait_settled(frames=30)
        shadowed, dark = tab.pixel_hash(), page.evaluate(CANVAS_MEAN)
        page.locator(SWITCH).click()
        wait_for(lambda: tab.state("shadows") is False, "the shadow switch to turn off")
        wait_for(lambda: tab.pixel_hash() != shadowed, "the view to change with shadows off")
        tab.wait_settled(frames=30)
        bright = page.evaluate(CANVAS_MEAN)
        assert bright > dark + 0.5, ("the canvas did not brighten with shadows off", dark, bright)
        page.locator(SWITCH).click()
        wait_for(lambda: tab.state("shadows") is True, "the shadow switch to turn on again")
        tab.wait_settled(frames=30)
        wait_for(lambda: tab.pixel_hash() == shadowed, "the same shadowed pixels as before")

        # per pixel: the server's picture, compared pixel by pixel
        tab.set_state("interpolation", "'pixel'")
        first = wait_for(lambda: pixel_src(page), "the per-pixel picture")
        on = tab.pixel_image()
        page.locator(SWITCH).click()
        wait_for(lambda: tab.state("shadows") is False, "the shadow switch to turn off per pixel")
        wait_for(lambda: pixel_src(page) not in ("", first), "the per-pixel picture without shadows")
        off = tab.pixel_image()
        assert off.shape == on.shape, (off.shape, on.shape)
        darker = (off < on).any(axis=-1)
        assert not darker.any(), ("pixels darker with shadows off", np.argwhere(darker)[:5])
        lifted = (off - on).max(axis=-1) >= 40
        assert lifted.mean() > 0.02, ("the floor under the ball did not brighten", lifted.mean())
