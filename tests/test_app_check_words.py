"""The check question's feedback says its verdict once: "Right: 102/12 = 8.5 …", never "Right. Right: …"."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from phonglab.app.check_question import CheckPanel
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
CHECKS = [e for e in catalog(LESSONS)[0] if e.ok and e.lesson and e.lesson.check]


def _answers(check):
    """A right answer and the wrong ones of a check (choices by index, numbers around the right one)."""
    if check.kind == "choice":
        return [(i, i == check.correct) for i in range(len(check.choices))]
    return [(check.numeric, True), (check.numeric * 0.5 - 1, False), (check.numeric * 2 + 1, False)]


@pytest.mark.parametrize("entry", CHECKS, ids=lambda e: e.path.stem)
def test_every_lessons_feedback_says_its_verdict_once(entry):
    from trame.app import get_server

    panel = CheckPanel(get_server(f"check-words-{entry.path.stem}", client_type="vue3").state)
    panel.open(entry.lesson)
    for answer, right in _answers(entry.lesson.check):
        panel.submit(answer)
        verdict = panel.state.check_verdict
        words = re.sub(r"<[^>]+>", "", verdict["html"])
        lead = "Right" if right else "Not quite"
        assert verdict["right"] is right and words.startswith(lead), (entry.path.stem, answer, words)
        for word in ("Right", "Not quite"):
            assert len(re.findall(rf"\b{word}\b", words)) <= 1, (entry.path.stem, answer, words)
        assert verdict["html"].startswith(f"<b>{lead}"), (entry.path.stem, verdict["html"])
