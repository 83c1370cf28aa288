"""The display encoding: linear light → exposure → clip → sRGB curve → bytes."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from phonglab.core.display import (
    DISPLAY_ENCODINGS,
    display_bytes,
    display_values,
    srgb_decode,
    srgb_encode,
)
from phonglab.core.model import InvalidValue


def test_half_grey_is_188_in_srgb_and_128_linear():
    assert display_bytes(0.5).item() == 188
    assert display_bytes(0.5, encoding="linear").item() == 128


@pytest.mark.parametrize("value, expected", [
    # reference values of the IEC 61966-2-1 curve, worked by hand
    (0.0, 0.0), (1.0, 1.0), (0.0031308, 0.0031308 * 12.92),
    (0.18, 1.055 * 0.18 ** (1 / 2.4) - 0.055), (0.5, 0.735356983),
])
def test_srgb_encode_matches_the_standard(value, expected):
    got = float(srgb_encode(np.float64(value)))
    assert got == pytest.approx(expected, abs=1e-9), f"srgb_encode({value}) = {got}, expected {expected}"


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_the_two_pieces_meet_at_the_threshold(dtype):
    # eps-sized steps either side of the threshold: no jump between the linear and power segments
    t = dtype(0.0031308)
    below, above = np.nextafter(t, dtype(0)), np.nextafter(t, dtype(1))
    values = srgb_encode(np.array([below, t, above], dtype))
    assert values.dtype == dtype
    # the standard's two pieces differ by about 3e-8 at the threshold: far below one 8-bit step
    assert np.all(np.diff(values) >= -1e-7), f"steps back at the threshold: {values}"
    assert np.ptp(values) < 1e-6, f"jump at the threshold: {values}"


@settings(max_examples=200, deadline=None)
@given(st.floats(0, 1, allow_nan=False))
def test_decode_inverts_encode(x):
    back = float(srgb_decode(srgb_encode(np.float64(x))))
    assert back == pytest.approx(x, abs=1e-12, rel=1e-9), f"x = {x!r}: decode(encode(x)) = {back!r}"


@settings(max_examples=200, deadline=None)
@given(st.floats(0, 1, allow_nan=False), st.floats(0, 1, allow_nan=False))
def test_encode_is_monotonic(a, b):
    lo, hi = sorted((a, b))
    assert float(srgb_encode(np.float64(lo))) <= float(srgb_encode(np.float64(hi))), (lo, hi)


def test_exposure_clip_and_nan():
    values = display_values(np.array([-1.0, 0.25, 0.5, 4.0, np.nan, np.inf]), encoding="linear", exposure=2.0)
    assert values.tolist() == [0.0, 0.5, 1.0, 1.0, 0.0, 1.0]


def test_float32_stays_float32():
    assert display_values(np.ones(3, np.float32)).dtype == np.float32
    assert display_bytes(np.ones((2, 3), np.float32)).dtype == np.uint8


@pytest.mark.parametrize("kwargs, field", [
    ({"encoding": "gamma"}, "display"), ({"exposure": 0.0}, "exposure"),
    ({"exposure": float("nan")}, "exposure"), ({"exposure": -1.0}, "exposure"),
])
def test_bad_options_name_the_field(kwargs, field):
    with pytest.raises(InvalidValue, match=f"^{field}: "):
        display_values([0.5], **kwargs)


def test_encodings_listed():
    assert DISPLAY_ENCODINGS == ("srgb", "linear")
