"""A half-transparent sphere in a real browser: the page shows it blended in linear light.

A server of its own serves one lesson, the red sphere Gouraud-shaded at
opacity 0.5. The browser's own copy of the scene (vtk.js) must carry the
opacity on the mesh's actor, and the picture the page shows (the server's
image over the view, as in pixel mode: vtk.js would blend the encoded
colours) must have, at its centre, the front pole over the back pole over
the background, blended in linear light (within 2/255).
"""

from __future__ import annotations


import numpy as np
import pytest
from conftest import open_tab
from waiting import wait_for

from phonglab.bench.scenes import red_sphere, red_sphere_tables
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
def glass_server(serve_app, tmp_path_factory):
    folder = tmp_path_factory.mktemp("glass-lessons")
    (folder / "01-glass.md").write_text(GLASS, encoding="utf-8")
    return serve_app(folder)


def test_a_half_transparent_sphere_is_blended_in_linear_light(browser, glass_server):
    with open_tab(browser, glass_server) as tab:
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
        image = wait_for(lambda: [img for img in [tab.pixel_image()] if img.shape[0] > 100], "the picture")[0]
        h, w, _ = image.shape
        got = image[h // 2, w // 2]
        scene = red_sphere(48)
        points = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
        front, back = np.clip(shade(scene, points, points).color, 0.0, 1.0)
        expected = display_bytes(composite_closed(front, back, srgb_decode(np.array(BACKGROUND)), 0.5)).astype(int)
        assert np.abs(got - expected).max() <= 2, ("centre", got, "expected", expected, "size", (w, h))
