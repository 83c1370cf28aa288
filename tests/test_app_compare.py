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

from phonglab.app.compare_panel import panel_size
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


def pictures(app) -> list[np.ndarray]:
    """The compare view's pictures, Phong's then Cook–Torrance's."""
    panels = app.state.compare_png["panels"]
    assert [p["model"] for p in panels] == ["phong", "cook-torrance"], app.state.compare_png
    decoded = []
    for p in panels:
        assert p["src"].startswith("data:image/png;base64,"), p["src"][:40]
        data = base64.b64decode(p["src"].split(",", 1)[1])
        decoded.append(np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), np.int16))
    return decoded


def test_the_switch_shows_both_models_and_the_picture_follows_the_roughness(app):
    assert app.state.compare_png["status"] == "idle" and not app.state.compare_png["panels"]
    app._on_control("view__compare", True)
    assert app.options["compare"] is True and app.state.compare_png["status"] == "ready", app.state.compare_png
    phong, ct = pictures(app)
    (width, height), stacked = panel_size(app.view.size)  # a share of the view less the panel's heading
    assert phong.shape == ct.shape == (height, width, 3), (phong.shape, ct.shape, app.view.size)
    assert app.state.compare_png["stacked"] is stacked
    # the captions are the page's text, the scene's own model named
    captions = [(p["caption"], p["own"]) for p in app.state.compare_png["panels"]]
    m = app.scene.material
    assert captions == [(f"Phong: α = {m.shininess:g}", app.scene.model == "phong"),
                        (f"Cook–Torrance: roughness {m.roughness:g}, metallic {m.metallic:g}", False)], captions
    app._on_control("material__roughness", 0.8)
    assert app.scene.material.roughness == 0.8
    phong_after, ct_after = pictures(app)
    phong_change = np.abs(phong - phong_after).max()
    ct_change = np.abs(ct - ct_after)
    assert phong_change == 0, f"the Phong picture changed by {phong_change} with the roughness"
    assert ct_change.max() >= 20 and ct_change.mean() > 0.2, "the Cook–Torrance picture did not follow the roughness"
    assert app.state.compare_png["panels"][1]["caption"].startswith("Cook–Torrance: roughness 0.8,"), \
        app.state.compare_png["panels"][1]["caption"]


@pytest.mark.parametrize("view, expected", [
    ((656, 358), ((312, 248), False)),  # a laptop's view: side by side, each under a caption's line
    ((500, 900), ((476, 376), True)),  # taller than wide: one above the other
    ((100, 100), ((120, 120), False)),  # never smaller than 120 px a side
])
def test_each_picture_takes_its_share_of_the_view(view, expected):
    assert panel_size(view) == expected, f"view {view}: {panel_size(view)}, expected {expected}"


def test_the_address_carries_the_switch_and_off_clears_the_picture(app):
    app._on_control("view__compare", True)
    app._refresh_panels()
    from phonglab.app.address import QUERY_KEY

    assert "view.compare=true" in app.state[QUERY_KEY], app.state[QUERY_KEY]
    app._on_control("view__compare", False)
    assert app.options["compare"] is False and app.state.compare_png["status"] == "idle"
