"""Letters drawn on exported pictures sit at their own arrow tips, in every lesson and for a turned eye.

:func:`phonglab.render.annotate.draw_labels` places each letter about its own tip
(:func:`~phonglab.render.annotate.place_labels`). Every letter is checked against the tips the view
projects: within its third ring of places, and nearer its own tip than any other arrow's (a reader
takes a letter for its nearest tip's), unless two tips are one place (:data:`SAME_TIP`) or share a
label, "N, L, R" (tips nearer than :data:`TOGETHER` font sizes: lesson 3's probe). The page's own
letters are checked in a browser: ``tests/browser/test_letters.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from phonglab.render import SceneView
from phonglab.render.annotate import LABEL_RINGS, SAME_TIP, font, label_layout, place_labels
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
ENTRIES = [e for e in catalog(LESSONS)[0] if e.ok]
SIZE = (480, 360)


def _problems(labels, size, what) -> list[str]:
    tips = {text: np.asarray(xy, dtype=float) for text, xy, _, _ in labels}
    height = size[1]
    font_px = max(12, round(height / 24))
    problems = []
    for label in label_layout(labels, size):
        # a letter of a shared label stands up to half the label's width off its centre
        aside = 0.5 * font(font_px, bold=True).getlength(label.text) if len(label.letters) > 1 else 0.0
        for text, (left, top, right, bottom) in label.boxes.items():
            centre = np.array([(left + right) / 2, (top + bottom) / 2])
            extent = max(font(font_px, bold=True).getbbox(text, anchor="mm")[2:])
            own = float(np.hypot(*(centre - tips[text])))
            reach = 0.45 * font_px + 0.6 * extent + (LABEL_RINGS - 1) * (extent + 1) + 1 + 2 * aside
            if own > reach:
                problems.append(f"{what}: {text} is {own:.1f} px from its tip (at most {reach:.1f})")
            for other, tip in tips.items():
                apart = float(np.hypot(*(tip - tips[text])))
                if (other not in label.letters and apart >= SAME_TIP
                        and float(np.hypot(*(centre - tip))) <= own):
                    problems.append(f"{what}: {text} is nearer {other}'s tip than its own ({own:.1f} px)")
    return problems


@pytest.mark.parametrize("entry", ENTRIES, ids=lambda e: e.path.stem)
def test_every_lessons_exported_letters_sit_at_their_own_tips(entry):
    view = SceneView(entry.scene, size=SIZE)
    problems = []
    try:
        for degrees in (0.0, 35.0, -70.0):
            c = entry.scene.camera
            a = np.radians(degrees)
            up = np.asarray(c.up, dtype=float) / np.linalg.norm(c.up)
            offset = np.subtract(c.eye, c.focal_point)
            # the eye turned about the camera's up axis (Rodrigues)
            turned = (offset * np.cos(a) + np.cross(up, offset) * np.sin(a) + up * (up @ offset) * (1 - np.cos(a)))
            view.update(entry.scene.replace("camera.eye", (np.asarray(c.focal_point) + turned).tolist()))
            view.render()
            labels, _ = view.image_labels(SIZE[1])
            problems += _problems(labels, SIZE, f"{entry.path.stem}, eye turned {degrees:g}°")
    finally:
        view.close()
    assert not problems, "\n".join(problems)


def test_crowded_tips_keep_their_letters():
    # three arrows nearly along one line (the floor under lesson 7's spot), and two exactly on one tip
    labels = [("N", (100.0, 100.0), (0.0, -1.0), (0, 0, 0)), ("L", (104.0, 98.0), (0.2, -1.0), (0, 0, 0)),
              ("R", (96.0, 99.0), (-0.3, -1.0), (0, 0, 0)), ("V", (100.0, 100.0), (0.0, -1.0), (0, 0, 0))]
    assert _problems(labels, SIZE, "crowded") == []
    centres = place_labels([(50.0, 50.0)] * 3, [(1.0, 0.0)] * 3, [10.0] * 3, [6.0] * 3, SIZE)
    for i in range(3):
        for j in range(i):
            assert np.max(np.abs(centres[i] - centres[j])) >= 12.0, ("letters on one tip cover each other", centres)


def test_a_letter_is_not_put_on_another_arrow():
    # two arrows from one probe along one line, one shorter: just past the short one's tip is the long one's
    # shaft (lesson 4 as it opens put H over L so); the short one's letter turns off the line
    base = np.array([100.0, 100.0])
    tips = [(200.0, 100.0), (150.0, 100.0)]
    directions = [tuple(np.subtract(t, base)) for t in tips]
    centres = place_labels(tips, directions, [10.0, 10.0], [6.0, 6.0], SIZE)
    short = centres[1]
    # off the long arrow's line by more than half a letter's box, and still nearest its own tip
    assert abs(short[1] - 100.0) > 6.0 or short[0] > 200.0 + 6.0, ("the letter lies on the long arrow", centres)
    assert np.hypot(*(short - tips[1])) < np.hypot(*(short - tips[0])), centres


