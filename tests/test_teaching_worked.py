"""The grader's worked answer: the record of the model (or of the diagnosed mistake) at the worst case."""

from __future__ import annotations

import re

import numpy as np
import pytest

from phonglab.teaching import MISTAKES
from phonglab.teaching.grade_cases import GROUPS
from phonglab.teaching.grading import expected
from phonglab.teaching.worked import worked_lines

CASES = [case for group in GROUPS for case in group.cases]


def numbers(line: str, name: str) -> list[float]:
    """The value after ``name = `` in a worked line: one number or a triple."""
    m = re.search(rf"(?:^|, |: ){re.escape(name)} = (\([^)]*\)|[-\d.e+]+)", line)
    assert m, (name, line)
    return [float(x) for x in m.group(1).strip("()").split(",")]


@pytest.mark.parametrize("case", CASES, ids=[c.what for c in CASES])
def test_the_worked_answer_adds_up_to_the_expected_colour(case):
    lines = worked_lines(case)
    total = numbers(lines[-1], "total")
    assert total == pytest.approx(expected(case), rel=1e-5, abs=1e-6), (case.what, lines)
    # the ambient, emission and each light's two terms add up to the total shown
    parts = np.add(numbers(lines[0], "ambient"), numbers(lines[0], "emission"))
    for line in lines[1:-1]:
        parts = parts + numbers(line, "diffuse") + numbers(line, "specular")
    assert parts == pytest.approx(total, rel=1e-5, abs=1e-5), (case.what, lines)


def test_a_mistakes_worked_answer_shows_its_own_wrong_values():
    case = next(c for c in CASES if "n·l = −1" in c.what)
    right = worked_lines(case)
    wrong = worked_lines(case, MISTAKES["no-clamp-diffuse"])
    assert numbers(right[1], "n·l") == numbers(wrong[1], "n·l") == pytest.approx([-1.0]), right
    assert numbers(right[1], "diffuse weight") == [0.0] and numbers(wrong[1], "diffuse weight") == [-1.0], wrong
    assert min(numbers(wrong[1], "diffuse")) < 0 <= min(numbers(right[1], "diffuse")), wrong


def test_the_report_shows_the_worked_answers():
    from phonglab.teaching.grading import CaseResult, GroupResult, diagnose, group_text

    group = next(g for g in GROUPS if g.key == "diffuse")
    wrong = MISTAKES["no-clamp-diffuse"]
    results = []
    for case in group.cases:
        want = expected(case)
        got = wrong.shade(np.array([case.point]), np.array([case.normal]), material=case.material,
                          lights=list(case.lights), eye=case.eye).color[0]
        ok = bool(np.allclose(got, want, rtol=group.rtol, atol=group.atol))
        results.append(CaseResult(case, want, got, None, ok, 0.0 if ok else 10.0))
    text = group_text(GroupResult(group, tuple(results), diagnose(group, results)))
    assert "worked answer (what the model used):" in text, text
    assert "that mistake's answer to the worst case:" in text, text
    block = text.split("that mistake's answer to the worst case:")[1]
    assert "diffuse weight = -0." in block or "diffuse weight = -1" in block, block  # the unclamped n·l
