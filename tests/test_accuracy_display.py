"""The accuracy panel's images and the grader's picture are encoded for the display.

The core computes linear light; every picture the app shows or writes goes
through the core's display encoding (exposure, clip, sRGB curve by default,
raw with ``display = "linear"``), as in tests/test_render_display.py: a 50 %
grey patch (radiance 0.5) is 188/255 encoded as sRGB and 128/255 raw.
"""

from __future__ import annotations

import base64
import concurrent.futures
import io

import numpy as np
import pytest
from PIL import Image

from phonglab.accuracy import grade_picture, interpolation
from phonglab.accuracy.images import display_image
from phonglab.app import accuracy_panel as panel
from phonglab.app.lesson_app import LessonApp
from phonglab.bench.scenes import LESSONS
from phonglab.teaching.sandbox import Limits

GREY = 0.5
#: the display value of a 50 % grey for each encoding (IEC 61966-2-1: 0.7354 x 255 = 187.5 -> 188)
EXPECTED = {"srgb": 188, "linear": 128}


def decode(data) -> np.ndarray:
    if isinstance(data, str):
        assert data.startswith("data:image/png;base64,"), data[:40]
        data = base64.b64decode(data.split(",", 1)[1])
    with Image.open(io.BytesIO(data)) as image:
        return np.asarray(image.convert("RGB")).astype(int)


@pytest.mark.parametrize("encoding", ["srgb", "linear"])
def test_display_image_encodes_a_half_grey_patch_and_keeps_the_background(encoding):
    grey = np.full((4, 6, 3), GREY)
    grey[0, 0] = np.nan  # no colour: black, not NaN in a PNG
    mask = np.ones((4, 6), bool)
    mask[:, 5] = False
    out = display_image(grey, mask, background=(26, 26, 30), encoding=encoding)
    assert out.dtype == np.uint8 and out.shape == (4, 6, 3)
    assert np.all(out[1:, :5] == EXPECTED[encoding]), (encoding, out[1:, :5, 0].tolist())
    assert out[0, 0].tolist() == [0, 0, 0], out[0, 0]
    assert np.all(out[:, 5] == (26, 26, 30)), out[:, 5].tolist()


def test_display_image_applies_exposure_before_the_curve():
    # 0.5 x 0.5 = 0.25: sRGB 137; 0.5 x 2 = 1: white, and over-exposure clips
    patch = np.full((2, 2, 3), GREY)
    mask = np.ones((2, 2), bool)
    assert np.all(display_image(patch, mask, background=(0, 0, 0), exposure=0.5) == 137)
    assert np.all(display_image(patch * 3, mask, background=(0, 0, 0), exposure=2.0) == 255)


@pytest.fixture
def grey_study(monkeypatch):
    """The interpolation study with every method's image replaced by a 50 % grey (the errors stay real)."""
    measure = interpolation.measure

    def grey(*args, **kwargs):
        row, image = measure(*args, **kwargs)
        return row, np.full_like(image, GREY)

    monkeypatch.setattr(interpolation, "measure", grey)


@pytest.mark.parametrize("encoding", ["srgb", "linear"])
def test_error_images_encode_the_render_for_the_display(grey_study, encoding):
    view = interpolation.error_images("gouraud", 8, size=32, repeats=1, encoding=encoding)
    covered = np.any(view.render != interpolation.BACKGROUND, axis=-1)
    assert covered.sum() > 100, "the sphere covers almost nothing"
    assert np.all(view.render[covered] == EXPECTED[encoding]), (encoding, np.unique(view.render[covered]))


def test_error_images_reference_is_the_study_reference_through_the_display_curve():
    srgb = interpolation.error_images("flat", 8, size=32, repeats=1)
    raw = interpolation.error_images("flat", 8, size=32, repeats=1, encoding="linear")
    setup = interpolation.default_setup(32, 200.0)
    ref = interpolation.reference(setup, repeats=1)
    expected = display_image(ref.color, ref.mask, background=interpolation.BACKGROUND)
    assert np.array_equal(srgb.reference, expected)
    assert np.array_equal(raw.reference, display_image(ref.color, ref.mask, background=interpolation.BACKGROUND,
                                                       encoding="linear"))
    # mid-tones are brighter encoded: the raw x255 picture is not what the default shows
    mid = ref.mask & np.all((ref.color > 0.1) & (ref.color < 0.9), axis=-1)
    assert mid.sum() > 50 and np.all(srgb.reference[mid] > raw.reference[mid])


@pytest.mark.parametrize("value, field", [("gamma", "encoding"), (0.0, "exposure"), (float("nan"), "exposure")])
def test_error_images_refuse_a_bad_display_naming_the_field(value, field):
    with pytest.raises(ValueError, match=field):
        interpolation.error_images("flat", 8, size=16, repeats=1, **{field: value})


@pytest.mark.parametrize("display", ["srgb", "linear"])
def test_the_panel_sends_the_encoded_images(grey_study, monkeypatch, display):
    monkeypatch.setattr(panel, "IMAGE_SIZE", 32)
    shown = panel.error_panel("pixel", 8, 200.0, display)
    render = decode(shown["render"])
    covered = np.any(render != interpolation.BACKGROUND, axis=-1)
    assert shown["display"] == display and covered.sum() > 100
    assert np.all(render[covered] == EXPECTED[display]), (display, np.unique(render[covered]))


def _inline(function, *args):
    future = concurrent.futures.Future()
    future.set_result(function(*args))
    return future


def test_the_panel_follows_the_scenes_display_and_exposure(tmp_path, monkeypatch):
    from trame.app import get_server

    made = []
    monkeypatch.setattr(panel, "submit", lambda function, *args: made.append(args) or _inline(function, *args))
    monkeypatch.setattr(panel, "IMAGE_SIZE", 32)
    monkeypatch.setattr(panel, "plot_data_url", lambda: "data:image/png;base64,cGxvdA==")
    monkeypatch.setattr(panel, "_plot", None)
    (tmp_path / "11-accuracy.md").write_text(LESSONS["11-accuracy.md"], encoding="utf-8")
    app = LessonApp(get_server(f"test-accuracy-display-{tmp_path.name}", client_type="vue3"),
                    target=tmp_path / "11-accuracy.md")
    try:
        s = app.state
        assert (s.accuracy_view["display"], s.accuracy_view["exposure"]) == ("srgb", 1.0), made
        srgb = decode(s.accuracy_view["reference"])
        for key, value, seen in (("display", "linear", ("linear", 1.0)), ("exposure", 0.5, ("linear", 0.5))):
            app._on_control(key, value)
            app._later.run_waiting()  # a refresh the app put off for a running event loop
            assert (s.accuracy_view["display"], s.accuracy_view["exposure"]) == seen, (key, value, made[-1])
        dim = decode(s.accuracy_view["reference"])
        lit = np.any(srgb != interpolation.BACKGROUND, axis=-1)
        assert np.all(dim[lit] <= srgb[lit]) and np.any(dim[lit] < srgb[lit]), "linear at half exposure is darker"
    finally:
        app.close()


@pytest.mark.parametrize("encoding", ["srgb", "linear"])
def test_the_graders_picture_is_encoded_for_the_display(monkeypatch, encoding):
    def grey_spheres(file, limits):
        mask = np.zeros((grade_picture.PICTURE_SIZE,) * 2, bool)
        mask[20:70, 20:70] = True
        core = np.where(mask[..., None], np.full(mask.shape + (3,), GREY), np.nan)
        return core, core.copy(), mask, 0

    monkeypatch.setattr(grade_picture, "sphere_images", grey_spheres)
    options = {} if encoding == "srgb" else {"encoding": encoding}  # sRGB is the default
    data, note = grade_picture.picture_png("unused.py", Limits(), **options)
    image = decode(data)
    size, gap, caption = grade_picture.PICTURE_SIZE * 2, 8, grade_picture.CAPTION_HEIGHT
    for panel_index in (0, 1):  # the student's sphere and the core's
        x, y = gap + panel_index * (size + gap) + size // 2, caption + gap + size // 2
        assert image[y, x].tolist() == [EXPECTED[encoding]] * 3, (encoding, panel_index, image[y, x])
    assert note == ""
