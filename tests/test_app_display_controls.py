"""Display controls and colour pickers: pickers show sRGB and store linear light; display and exposure edit the scene."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from phonglab.app import controls as ctl
from phonglab.app.control import ControlError, hex_to_rgb, rgb_to_hex
from phonglab.bench.scenes import red_sphere


@pytest.fixture(scope="module")
def scene():
    return red_sphere(16)


@pytest.fixture(scope="module")
def by_path(scene):
    return {c.path: c for c in ctl.controls_by_key(scene).values()}


def test_picker_shows_srgb_of_the_linear_value():
    # linear 0.5 is the sRGB swatch #bcbcbc (188), not #808080
    assert rgb_to_hex((0.5, 0.5, 0.5)) == "#bcbcbc"
    assert rgb_to_hex((1.0, 0.0, 2.0)) == "#ff00ff", "clipped to [0, 1]"
    assert hex_to_rgb("#bcbcbc") == pytest.approx((0.5029,) * 3, abs=1e-4)
    assert hex_to_rgb("#808080") == pytest.approx((0.2159,) * 3, abs=1e-4)


@given(st.tuples(*[st.integers(0, 255)] * 3))
def test_picker_round_trip_keeps_every_swatch(rgb):
    text = "#" + "".join(f"{c:02x}" for c in rgb)
    assert rgb_to_hex(hex_to_rgb(text)) == text, (text, hex_to_rgb(text))


def test_material_colour_picked_in_srgb_is_stored_linear(scene, by_path):
    colour, level = by_path["material.kd.color"], by_path["material.kd.level"]
    new, _ = colour.apply(scene, "#ffbc00", {})
    top = level.read(scene, {})
    assert new.material.kd == pytest.approx((top, top * 0.5029, 0.0), abs=1e-4), new.material.kd
    assert colour.read(new, {}) == "#ffbc00"


def test_light_colour_picked_in_srgb_is_stored_linear(scene, by_path):
    colour = by_path["lights[1].color"]
    new, _ = colour.apply(scene, "#bcbcbc", {})
    assert new.lights[1].color == pytest.approx((0.5029,) * 3, abs=1e-4)
    assert colour.read(new, {}) == "#bcbcbc"


def test_display_select_and_exposure_slider_edit_the_scene(scene, by_path):
    display, exposure = by_path["display"], by_path["exposure"]
    assert (display.kind, exposure.kind) == ("select", "slider")
    assert display.read(scene, {}) == "srgb" and exposure.read(scene, {}) == 1.0
    linear, _ = display.apply(scene, "linear", {})
    assert linear.display == "linear"
    dim, _ = exposure.apply(scene, 0.5, {})
    assert dim.exposure == 0.5
    with pytest.raises(ControlError, match="display: must be one of srgb, linear, got 'gamma'"):
        display.apply(scene, "gamma", {})
    with pytest.raises(ControlError, match="exposure: must be between 0.05 and 4, got 0"):
        exposure.apply(scene, 0, {})


def test_a_lesson_lists_display_and_exposure_in_its_controls(scene):
    chosen = ctl.lesson_controls(ctl.scene_controls(scene), ["display", "exposure"])
    assert [c.path for c in chosen] == ["display", "exposure"]
