"""Letters of arrows that meet do not cover each other: they share one label, side by side.

Lesson 3's probe lies 1.9° from the light's mirror direction, so N, L and R end within a few pixels
of each other on the screen. Each letter placed past its own tip would fall on the others', and
letters moved aside about their own tips read as belonging to any of the three. The view lays them out
as one label, "N, L, R" (:func:`phonglab.render.annotate.label_layout`), and
:meth:`~phonglab.render.SceneView.vector_marks` gives each letter's box where it is drawn. The
page's letters follow the same rule (``tests/browser/test_letters.py``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from phonglab.render import SceneView
from phonglab.render.options import DEFAULT_SIZE
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
LESSON_3 = next(e for e in catalog(LESSONS)[0] if e.ok and e.path.stem.startswith("03-"))
#: tips nearer than this many font sizes are one place for their letters
TOGETHER = 1.0


def _overlaps(marks) -> list[str]:
    """Pairs of letters whose boxes overlap, as sentences."""
    found = []
    letters = sorted(marks)
    for i, a in enumerate(letters):
        for b in letters[:i]:
            (al, at, ar, ab), (bl, bt, br, bb) = marks[a][1], marks[b][1]
            if al < br and bl < ar and at < bb and bt < ab:
                found.append(f"{a}'s box {tuple(round(c) for c in marks[a][1])} overlaps "
                             f"{b}'s {tuple(round(c) for c in marks[b][1])}")
    return found


@pytest.mark.parametrize("size", [(DEFAULT_SIZE[0] * 2, DEFAULT_SIZE[1] * 2), (563, 469), (480, 360)],
                         ids=["export", "page", "small"])
def test_lesson_3s_letters_do_not_cover_each_other_and_meeting_arrows_share_a_label(size):
    # lesson 3's probe is 1.9° from the light's mirror direction: N, L and R end within a few pixels of
    # each other, and their letters, each placed past its own tip, were drawn over one another
    scene = LESSON_3.scene
    view = SceneView(scene, size=size, vtk_text=False)
    try:
        view.render()
        marks = view.vector_marks()
    finally:
        view.close()
    font_px = max(12, round(size[1] / 24))
    tips = {letter: np.asarray(tip) for letter, (tip, _) in marks.items()}
    where = (f"lesson 3 (probe {scene.probe}, light {scene.lights[1].position}) at {size[0]}x{size[1]}: tips "
             f"{ {k: tuple(round(float(c), 1) for c in v) for k, v in tips.items()} }, boxes "
             f"{ {k: tuple(round(c) for c in box) for k, (_, box) in marks.items()} }")
    assert set(marks) == set("NLRVH"), where
    meeting = [(a, b) for a in "NLR" for b in "NLR" if a < b]
    assert all(np.hypot(*(tips[a] - tips[b])) < TOGETHER * font_px for a, b in meeting), (
        f"{where}: the case this test is about is gone: N, L and R no longer end together")
    problems = _overlaps(marks)
    for letter, (tip, (left, top, right, bottom)) in marks.items():
        # near its tip: a shared label's outer letters too stand within two and a half font sizes of it
        gap = max(left - tip[0], tip[0] - right, top - tip[1], tip[1] - bottom, 0.0)
        if gap > 2.5 * font_px:
            problems.append(f"{letter}'s box is {gap:.0f} px from its tip")
    # the letters of arrows that meet read as one label: on one line, side by side
    row = sorted("NLR", key=lambda letter: marks[letter][1][0])
    for a, b in zip(row, row[1:]):
        (_, (_, at, ar, ab)), (_, (bl, bt, _, bb)) = marks[a], marks[b]
        if abs((at + ab) / 2 - (bt + bb) / 2) > 1.0 or bl - ar > 1.5 * font_px:
            problems.append(f"{a} and {b} end together but their letters are not side by side in one label")
    assert not problems, f"{where}:\n" + "\n".join(problems)


def test_tips_share_a_label_when_chained_nearer_than_a_letter_and_lone_letters_keep_their_place():
    from phonglab.render.annotate import font, label_layout, place_labels, share_labels

    tips = [(0.0, 0.0), (10.0, 0.0), (20.0, 0.0), (100.0, 0.0), (112.5, 0.0)]
    assert share_labels(tips, 12.0) == [[0, 1, 2], [3]] + [[4]], tips
    assert share_labels(tips, 12.6) == [[0, 1, 2], [3, 4]], tips
    # a letter alone is placed as place_labels places it, whatever shares a label elsewhere
    size = (480, 360)
    labels = [("N", (200.0, 100.0), (0.0, -60.0), (1, 1, 1)), ("L", (203.0, 101.0), (3.0, -59.0), (2, 2, 2)),
              ("V", (300.0, 200.0), (40.0, -10.0), (3, 3, 3))]
    layout = label_layout(labels, size)
    assert [label.letters for label in layout] == [("N", "L"), ("V",)], [label.letters for label in layout]
    shared, alone = layout
    assert shared.text == "N, L" and shared.colours == ((1, 1, 1), (2, 2, 2)), (shared.text, shared.colours)
    assert shared.boxes["N"][2] < shared.boxes["L"][0], ("N should stand left of L, apart", shared.boxes)
    extent = max(font(15, bold=True).getbbox("V", anchor="mm")[2:])  # V's half extent at 360 px: 15 px letters
    lone = place_labels([(300.0, 200.0)], [(40.0, -10.0)], [0.45 * 15 + 0.6 * extent], [extent + 1], size)[0]
    assert np.allclose(alone.centre, lone, atol=0.01), (alone.centre, lone)
