"""The grader's picture keeps each caption within its own panel: the difference map's title is wrapped, not cut
at the picture's edge ("(log 1e-4..1" was all a student saw of it)."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image, ImageDraw, ImageFont

from phonglab.accuracy import grade_picture
from phonglab.teaching.sandbox import Limits


def picture_off_by(monkeypatch, error):
    """The grader's picture (PNG bytes) of a student whose square of colour is ``error`` off the core's everywhere."""
    def spheres(file, limits):
        mask = np.zeros((grade_picture.PICTURE_SIZE,) * 2, bool)
        mask[20:70, 20:70] = True
        core = np.where(mask[..., None], np.full(mask.shape + (3,), 0.4), np.nan)
        return core, core + error, mask, 0

    monkeypatch.setattr(grade_picture, "sphere_images", spheres)
    data, _ = grade_picture.picture_png("unused.py", Limits())
    return data


@pytest.mark.parametrize("error", [0.0012, 0.35, 1.0])
def test_every_caption_stays_within_its_panel(monkeypatch, error):
    data = picture_off_by(monkeypatch, error)
    image = np.asarray(Image.open(io.BytesIO(data)).convert("L"))
    panel, gap = grade_picture.PICTURE_SIZE * 2, 8
    top = int(np.argmax(image[:, gap + panel - 3] < 100))  # the first panel's dark background begins
    ink = image[:top] < 128  # the caption band above the panels
    inside = np.zeros(image.shape[1], bool)
    for i in range(3):
        inside[gap + i * (panel + gap):gap + i * (panel + gap) + panel] = True
    stray = np.argwhere(ink[:, ~inside])
    assert len(stray) == 0, (error, f"caption ink outside the panels' columns, {len(stray)} pixels")
    # the third caption's words are all drawn: its ink reaches well into a second line or within its panel
    assert ink[:, inside].any(), error


def test_captions_wrap_at_spaces_within_the_width():
    font = ImageFont.load_default(size=12)
    draw = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    measure = lambda t: draw.textlength(t, font=font)  # noqa: E731
    text = "|difference| max 0.0012 (log scale 0.0001 to 1)"
    lines = grade_picture.caption_lines(text, 192, measure)
    assert " ".join(lines) == text and len(lines) == 2, lines
    assert all(measure(line) <= 192 for line in lines), [(line, measure(line)) for line in lines]
    long = grade_picture.caption_lines("word " * 80, 100, measure)
    assert len(long) == grade_picture.CAPTION_LINES and long[-1].endswith("…"), long
    assert all(measure(line) <= 100 for line in long), long


@pytest.mark.parametrize("error", [0.0005, 0.03, 0.4])
def test_the_difference_map_has_a_colour_scale_a_reader_can_look_its_colours_up_on(monkeypatch, error):
    """Under the difference panel a bar runs over the map's range in its colours, its ends and middle labelled."""
    data = picture_off_by(monkeypatch, error)
    image = np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)
    panel, gap, caption = grade_picture.PICTURE_SIZE * 2, 8, grade_picture.CAPTION_HEIGHT
    x0 = gap + 2 * (panel + gap)
    bar_y = caption + gap + panel + grade_picture.SCALE_TOP + grade_picture.SCALE_HEIGHT // 2
    assert image.shape[0] > bar_y + grade_picture.SCALE_HEIGHT, (error, "no room for a scale under the panels", image.shape)
    bar = image[bar_y, x0:x0 + panel]
    lo, hi = grade_picture.DIFFERENCE_RANGE
    mid = 10 ** ((np.log10(lo) + np.log10(hi)) / 2)
    ends = grade_picture.difference_colours(np.array([lo, mid, hi])).astype(int)
    for where, seen, wanted in (("low end", bar[0], ends[0]), ("middle", bar[panel // 2], ends[1]),
                                ("high end", bar[-1], ends[2])):
        assert np.abs(seen - wanted).max() <= 12, (error, where, seen.tolist(), wanted.tolist())
    # the panel's colour for this difference is on the bar, where the log scale puts it
    shown = image[caption + gap + panel // 2, x0 + panel // 2]
    nearest = int(np.argmin(np.abs(bar - shown).sum(axis=1)))
    where = (np.log10(error) - np.log10(lo)) / (np.log10(hi) - np.log10(lo))
    assert np.abs(bar[nearest] - shown).max() <= 12, (error, shown.tolist(), bar[nearest].tolist())
    assert abs(nearest / (panel - 1) - where) < 0.05, (error, nearest, where)
    # the labels: dark ink under the bar, at both ends and in the middle
    labels = image[bar_y + grade_picture.SCALE_HEIGHT:, x0:x0 + panel].min(axis=2) < 100
    for part, columns in (("left", slice(0, panel // 4)), ("middle", slice(3 * panel // 8, 5 * panel // 8)),
                          ("right", slice(3 * panel // 4, panel))):
        assert labels[:, columns].any(), (error, f"no label at the bar's {part}")
