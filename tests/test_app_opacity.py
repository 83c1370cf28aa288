"""The page shows a translucent mesh as the server blends it, in every interpolation mode.

vtk.js would blend the 8-bit encoded colours, so for opacity < 1 the page
shows the server's picture over the view (as in pixel mode), blended in
linear light; back at opacity 1 the browser's own view shows the mesh again.
"""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest

from phonglab.bench.scenes import lesson, red_sphere_tables

GLASS = lesson(
    """
number = 1
title = "Glass"
interpolation = "gouraud"
""",
    red_sphere_tables(24).replace("shininess = 20\n", "shininess = 20\nopacity = 0.5\n"),
    "# Glass\n",
)


@pytest.fixture
def app(lesson_app):
    return lesson_app("01-glass.md", GLASS, "test-opacity")


def shown(app) -> np.ndarray:
    from PIL import Image

    src = app.state.pixel_src
    assert src.startswith("data:image/png;base64,"), src[:40]
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1]))).convert("RGB"))


def test_a_translucent_gouraud_mesh_is_shown_as_the_servers_blend(app):
    assert "opacity = 0.5" in GLASS
    assert app.scene.material.opacity == 0.5 and app.scene.interpolation == "gouraud"
    assert app.state.pixel_mode is True
    # the view's caption says what the picture is: a blend, not per-pixel shading
    assert app.state.pixel_hint.startswith("Translucent"), app.state.pixel_hint
    # the picture is the view's own blended screenshot, and the actor carries the opacity for vtk.js
    assert np.array_equal(shown(app), app.view.screenshot(annotate=True))
    assert app.view.mesh_actor.GetProperty().GetOpacity() == pytest.approx(0.5)
    app._show_scene(app.scene.replace("material.opacity", 1.0))
    assert app.state.pixel_mode is False and app.state.pixel_src == ""
    assert app.view.mesh_actor.GetProperty().GetOpacity() == 1.0


def test_a_translucent_per_pixel_mesh_is_captioned_as_per_pixel_shading(app):
    app._show_scene(app.scene.replace("interpolation", "pixel"))
    assert app.state.pixel_mode is True
    assert app.state.pixel_hint == "Per-pixel shading by the core", app.state.pixel_hint
