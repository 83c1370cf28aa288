"""The compare view: the tab's scene under Phong and under Cook–Torrance, below the 3D view.

The switch is a view option (``view.compare``), so the address carries it; the picture follows the scene
(a roughness change redraws the Cook–Torrance panel, not the Phong one) and goes when the switch is off.
"""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest
from PIL import Image

from phonglab.app.compare_panel import picture_size
from phonglab.bench.scenes import lesson, red_sphere_tables

SPHERE = lesson(
    """
number = 1
title = "Compare"
interpolation = "gouraud"
controls = ["model", "material.roughness", "material.metallic"]
""",
    red_sphere_tables(24),
    "# Compare\n",
)


@pytest.fixture
def app(lesson_app):
    return lesson_app("01-compare.md", SPHERE, "test-compare")


def picture(app) -> np.ndarray:
    src = app.state.compare_png["src"]
    assert src.startswith("data:image/png;base64,"), app.state.compare_png
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1]))).convert("RGB"), np.int16)


def test_the_switch_shows_both_models_and_the_picture_follows_the_roughness(app):
    assert app.state.compare_png["status"] == "idle" and not app.state.compare_png["src"]
    app._on_control("view__compare", True)
    assert app.options["compare"] is True and app.state.compare_png["status"] == "ready", app.state.compare_png
    first = picture(app)
    width, height = picture_size(app.view.size)  # the view less the panel's heading
    assert first.shape == (height, width, 3), (first.shape, app.view.size)
    app._on_control("material__roughness", 0.8)
    assert app.scene.material.roughness == 0.8
    second = picture(app)
    half = width // 2
    phong_change = np.abs(first[:, :half] - second[:, :half]).max()
    ct_change = np.abs(first[:, half:] - second[:, half:])
    assert phong_change == 0, f"the Phong panel changed by {phong_change} with the roughness"
    assert ct_change.max() >= 20 and ct_change.mean() > 0.2, "the Cook–Torrance panel did not follow the roughness"


def test_the_address_carries_the_switch_and_off_clears_the_picture(app):
    app._on_control("view__compare", True)
    app._refresh_panels()
    from phonglab.app.address import QUERY_KEY

    assert "view.compare=true" in app.state[QUERY_KEY], app.state[QUERY_KEY]
    app._on_control("view__compare", False)
    assert app.options["compare"] is False and app.state.compare_png["status"] == "idle"
