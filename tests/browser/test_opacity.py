"""A half-transparent sphere in a real browser: the page shows it blended in linear light.

A server of its own serves one lesson, the red sphere Gouraud-shaded at
opacity 0.5. The browser's own copy of the scene (vtk.js) must carry the
opacity on the mesh's actor, and the picture the page shows (the server's
image over the view, as in pixel mode: vtk.js would blend the encoded
colours) must have, at its centre, the front pole over the back pole over
the background, blended in linear light (within 2/255).
"""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest
from conftest import Page
from waiting import wait_for

from phonglab.bench.scenes import red_sphere, red_sphere_tables
from phonglab.bench.ui import free_port, log_tail, serve_command, start_server, stop_server, wait_until_serving
from phonglab.core.blend import composite_closed
from phonglab.core.display import display_bytes, srgb_decode
from phonglab.render.shading import shade
from phonglab.render.view import BACKGROUND

GLASS = """+++
number = 1
title = "A glass sphere"
goal = "See through a sphere."
probe = [0.35, 0.45, 0.82]
""" + red_sphere_tables(48, shininess=40).replace("shininess = 40\n", "shininess = 40\nopacity = 0.5\n") + """+++

A sphere of opacity 0.5.
"""


@pytest.fixture(scope="module")
def glass_server(tmp_path_factory):
    folder = tmp_path_factory.mktemp("glass-lessons")
    (folder / "01-glass.md").write_text(GLASS, encoding="utf-8")
    port = free_port()
    log_path = tmp_path_factory.mktemp("glass-server") / "serve.log"
    process = start_server(serve_command(folder, port), log_path=log_path)
    try:
        wait_until_serving(process, port, log_path=log_path)
    except RuntimeError as exc:
        stop_server(process)
        pytest.fail(f"phonglab serve did not start: {exc}")
    yield {"url": f"http://127.0.0.1:{port}/", "process": process, "log": log_path, "port": port}
    stop_server(process)


def shown_image(page) -> np.ndarray:
    from PIL import Image

    src = page.locator(".phonglab-pixel img").get_attribute("src") or ""
    assert src.startswith("data:image/png;base64,"), src[:40]
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1]))).convert("RGB")).astype(int)


def test_a_half_transparent_sphere_is_blended_in_linear_light(browser, glass_server):
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    tab = Page(context.new_page(), glass_server)
    try:
        tab.open()
        page = tab.page
        assert "opacity = 0.5" in GLASS
        # the browser's copy of the mesh carries the material's opacity
        actors_js = ("() => { const v = window.phonglabView; return v && v.renderer ? "
                     "v.renderer.getActors().map((a) => a.getProperty().getOpacity()) : null; }")
        opacities = wait_for(lambda: (o := page.evaluate(actors_js)) and 0.5 in o and o,
                             "an actor of opacity 0.5 in the local view")
        assert 0.5 in opacities and all(o in (0.5, 1) for o in opacities), opacities
        # the page shows the server's blend
        wait_for(lambda: tab.state("pixel_mode") is True, "the page to show the blended picture")
        image = wait_for(lambda: [img for img in [shown_image(page)] if img.shape[0] > 100], "the picture")[0]
        h, w, _ = image.shape
        got = image[h // 2, w // 2]
        scene = red_sphere(48)
        points = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
        front, back = np.clip(shade(scene, points, points).color, 0.0, 1.0)
        expected = display_bytes(composite_closed(front, back, srgb_decode(np.array(BACKGROUND)), 0.5)).astype(int)
        assert np.abs(got - expected).max() <= 2, ("centre", got, "expected", expected, "size", (w, h))
        assert not tab.errors, f"JavaScript errors on the page: {tab.errors}"
        assert glass_server["process"].poll() is None, f"the server died:\n{log_tail(glass_server['log'])}"
    finally:
        context.close()
