"""A lesson's answerable check question: the [check] table, its errors located, and marking answers."""

from __future__ import annotations

import math

import pytest

from phonglab.scene import SceneErrors
from phonglab.scene.check import MAX_ANSWER_CHARS, CheckQuestion, judge
from phonglab.scene.lessons import list_lessons, load_lesson

SCENE = """
[geometry]
kind = "sphere"
[material]
ka = 0.1
kd = 0.5
ks = 0.5
shininess = 10
[[lights]]
type = "ambient"
"""


def lesson(tmp_path, check: str, question: str = 'question = "Why?"\n'):
    path = tmp_path / "03-test.md"
    path.write_text("+++\ntitle = \"T\"\n" + question + SCENE + check + "+++\n\n# T\n")
    return path


CHOICE = """[check]
choices = ["a", "b", "c"]
correct = 1
feedback = ["not a", "yes b", "not c"]
"""
NUMERIC = """[check]
question = "How much?"
numeric = 0.5
tolerance = 0.01
feedback_low = "low"
feedback_high = "high"
"""


def test_a_choice_question_defaults_to_the_lesson_question(tmp_path):
    check = load_lesson(lesson(tmp_path, CHOICE)).check
    assert check == CheckQuestion("Why?", choices=("a", "b", "c"), correct=1, feedback=("not a", "yes b", "not c"))
    assert check.kind == "choice"


def test_a_numeric_question(tmp_path):
    check = load_lesson(lesson(tmp_path, NUMERIC)).check
    assert (check.kind, check.question, check.numeric, check.tolerance) == ("numeric", "How much?", 0.5, 0.01)


def test_no_check_table_is_no_check(tmp_path):
    assert load_lesson(lesson(tmp_path, "")).check is None


@pytest.mark.parametrize("table, field, words", [
    ('[check]\nchoices = ["a", "b"]\nfeedback = ["x", "y"]\n', "check.correct", "is required"),
    ('[check]\nchoices = ["a", "b"]\ncorrect = 2\nfeedback = ["x", "y"]\n', "check.correct", "0 to 1"),
    ('[check]\nchoices = ["a", "b"]\ncorrect = true\nfeedback = ["x", "y"]\n', "check.correct", "index"),
    ('[check]\nchoices = ["a", "b"]\ncorrect = 0\nfeedback = ["x"]\n', "check.feedback", "one text per choice (2)"),
    ('[check]\nchoices = ["a"]\ncorrect = 0\nfeedback = ["x"]\n', "check.choices", "2 to 8"),
    ('[check]\nchoices = ["a", "b"]\ncorrect = 0\nfeedback = ["x", "y"]\ntolerance = 1\n', "check.tolerance",
     "does not go with choices"),
    ('[check]\nnumeric = 1\ntolerance = -1\nfeedback_low = "l"\nfeedback_high = "h"\n', "check.tolerance", ">= 0"),
    ('[check]\nnumeric = nan\nfeedback_low = "l"\nfeedback_high = "h"\n', "check.numeric", "finite number"),
    ('[check]\nnumeric = 1\nfeedback_low = "l"\n', "check.feedback_high", "is required"),
    ('[check]\nnumeric = 1\nchoices = ["a", "b"]\n', "check", "either choices"),
    ('[check]\nnumber = 1\n', "check.number", "unknown key"),
])
def test_a_bad_check_table_is_reported_with_file_line_and_field(tmp_path, table, field, words):
    path = lesson(tmp_path, table)
    with pytest.raises(SceneErrors) as err:
        load_lesson(path)
    text = str(err.value)
    assert f"03-test.md:" in text and f"{field}:" in text and words in text, text
    line = int(text.split("03-test.md:")[1].split(":")[0])
    assert line > 10, f"the error should point into the [check] table, got line {line}: {text}"


def test_a_check_needs_a_question(tmp_path):
    with pytest.raises(SceneErrors, match="check.question: is required"):
        load_lesson(lesson(tmp_path, CHOICE, question=""))


def test_every_lesson_has_an_answerable_check_whose_right_answer_is_marked_right():
    from pathlib import Path

    lessons = list_lessons(Path(__file__).resolve().parents[1] / "lessons")
    assert lessons
    for one in lessons:
        check = one.check
        assert check is not None, f"lesson {one.number} has no [check]"
        if check.kind == "choice":
            assert judge(check, check.correct).right, one.number
            wrong = [i for i in range(len(check.choices)) if i != check.correct]
            for i in wrong:  # each wrong choice names a misunderstanding, not just "wrong"
                verdict = judge(check, i)
                assert not verdict.right and verdict.feedback != check.feedback[check.correct], (one.number, i)
        else:
            assert judge(check, check.numeric).right and judge(check, str(check.numeric)).right, one.number
            assert judge(check, check.numeric + 2 * check.tolerance + 1).feedback == check.feedback_high
            assert judge(check, check.numeric - 2 * check.tolerance - 1).feedback == check.feedback_low


def test_judge_marks_choices_and_numbers_with_their_feedback():
    choice = CheckQuestion("q", choices=("a", "b"), correct=1, feedback=("because a", "because b"))
    assert judge(choice, 1) == judge(choice, "1") and judge(choice, 1).right
    assert judge(choice, 0).feedback == "because a" and not judge(choice, 0).right
    number = CheckQuestion("q", numeric=0.5, tolerance=0.01, feedback_low="low", feedback_high="high")
    assert judge(number, 0.505).right and judge(number, " 0.49 ").right
    assert judge(number, 0.4).feedback == "low" and judge(number, "0.87").feedback == "high"
    assert judge(number, 0.5).feedback.startswith("Right")


@pytest.mark.parametrize("answer", [2, -1, True, None, "1.0", "x", 1.0, [0], "9" * 100])
def test_judge_refuses_a_choice_that_is_not_one(answer):
    choice = CheckQuestion("q", choices=("a", "b"), correct=1, feedback=("x", "y"))
    with pytest.raises(ValueError, match=r"check.answer: must be a choice, 0 to 1, got"):
        judge(choice, answer)


@pytest.mark.parametrize("answer", [math.nan, math.inf, "nan", "inf", "", "half", True, None, {"x": 1},
                                    "1" * (MAX_ANSWER_CHARS + 1)])
def test_judge_refuses_a_number_that_is_not_finite(answer):
    number = CheckQuestion("q", numeric=0.5, tolerance=0.01, feedback_low="low", feedback_high="high")
    with pytest.raises(ValueError, match="check.answer: must be a finite number, got"):
        judge(number, answer)
