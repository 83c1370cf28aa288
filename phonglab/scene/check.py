"""A lesson's answerable check question: the ``[check]`` table of its front matter.

A lesson's ``question`` and ``answer`` are an open question and its
explanation. A ``[check]`` table adds a question the page can mark, in one
of two forms:

multiple choice::

    [check]
    question = "Where is the highlight brightest?"      # optional: the lesson's question
    choices = ["where r points at the eye", "where n points at the light"]
    correct = 0                                          # index into choices
    feedback = ["Right: r·v = 1 there.",                 # one per choice: for a wrong choice,
                "That is the diffuse peak (n·l = 1)."]   # the misunderstanding it shows

a number::

    [check]
    question = "n·l for a light 60° from the normal?"
    numeric = 0.5
    tolerance = 0.01                                     # right when |answer − numeric| <= tolerance
    feedback_low = "Too small: ..."                      # what an answer below suggests
    feedback_high = "Too large: did you take sin, not cos?"
    feedback_right = "Right: cos 60° = 1/2."             # optional

The file's values are checked once, when the lesson is read
(:func:`build_check`, errors located by the lesson reader); a student's
answer comes from the browser and is checked by :func:`judge` before it is
marked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from phonglab.scene.build import Problems
from phonglab.scene.errors import SceneError, join_path
from phonglab.scene.schema import CHECK_CHOICE_KEYS, CHECK_KEYS, CHECK_NUMERIC_KEYS

__all__ = ["CheckQuestion", "Verdict", "build_check", "judge", "MAX_CHOICES", "MAX_ANSWER_CHARS"]

#: how many choices a multiple-choice question may have
MAX_CHOICES = 8
#: the longest typed number the page accepts
MAX_ANSWER_CHARS = 64


@dataclass(frozen=True)
class CheckQuestion:
    """An answerable question: multiple choice (``choices``) or a number (``numeric``).

    Attributes
    ----------
    question : str
    choices : tuple of str
        Empty for a numeric question.
    correct : int or None
        Index of the right choice.
    feedback : tuple of str
        One per choice: why it is right, or what misunderstanding it shows.
    numeric, tolerance : float or None
        The right number and how far an answer may be from it.
    feedback_low, feedback_high, feedback_right : str
        What an answer below, above or within the tolerance gets.
    """

    question: str
    choices: tuple = ()
    correct: int | None = None
    feedback: tuple = ()
    numeric: float | None = None
    tolerance: float = 0.0
    feedback_low: str = ""
    feedback_high: str = ""
    feedback_right: str = ""

    @property
    def kind(self) -> str:
        """``"choice"`` or ``"numeric"``."""
        return "choice" if self.choices else "numeric"


@dataclass(frozen=True)
class Verdict:
    """A marked answer: right or not, and the feedback for it."""

    right: bool
    feedback: str


def _texts(problems: Problems, where: str, value, *, low: int, high: int) -> tuple | None:
    if not isinstance(value, list) or not low <= len(value) <= high or not all(
            isinstance(v, str) and v.strip() for v in value):
        problems.add(SceneError(f"must be a list of {low} to {high} non-empty text strings", field=where,
                                value=value))
        return None
    return tuple(value)


def _number(problems: Problems, where: str, value, *, low=None) -> float | None:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or (low is not None and value < low):
        rule = "must be a finite number" + (f" >= {low:g}" if low is not None else "")
        problems.add(SceneError(rule, field=where, value=value))
        return None
    return float(value)


def _text(problems: Problems, where: str, value, *, required: bool) -> str | None:
    if value is None and not required:
        return ""
    if not isinstance(value, str) or not value.strip():
        problems.add(SceneError("must be a non-empty text string" if value is not None else "is required",
                                field=where, **({} if value is None else {"value": value})))
        return None
    return value


def build_check(raw, problems: Problems, *, question: str = "", where: str = "check") -> CheckQuestion | None:
    """Check a ``[check]`` table into a :class:`CheckQuestion`, recording every problem.

    Parameters
    ----------
    raw : object
        The table as TOML gave it.
    problems : Problems
        Where each problem goes, with its field path (``check.correct``).
    question : str
        The lesson's question, used when the table gives none.
    """
    table = problems.table(where, raw, CHECK_KEYS)
    if table is None:
        return None
    before = len(problems.errors)
    has_choices, has_numeric = "choices" in table, "numeric" in table
    if has_choices == has_numeric:
        problems.add(SceneError("must have either choices (with correct and feedback) or numeric "
                                "(with tolerance, feedback_low and feedback_high)", field=where,
                                value=sorted(table)))
        return None
    own, other = (CHECK_CHOICE_KEYS, CHECK_NUMERIC_KEYS) if has_choices else (CHECK_NUMERIC_KEYS, CHECK_CHOICE_KEYS)
    for key in table:
        if key in other and key not in own:
            form = "choices" if has_choices else "numeric"
            problems.add(SceneError(f"does not go with {form}", field=join_path(where, key), value=table[key],
                                    hint=f"a {form} question has {', '.join(own)}"))
    text = _text(problems, join_path(where, "question"), table.get("question", question or None), required=True)
    if has_choices:
        choices = _texts(problems, join_path(where, "choices"), table["choices"], low=2, high=MAX_CHOICES)
        n = len(choices) if choices else None
        correct = table.get("correct")
        if correct is None:
            problems.add(SceneError("is required with choices", field=join_path(where, "correct")))
        elif isinstance(correct, bool) or not isinstance(correct, int) or (n and not 0 <= correct < n):
            problems.add(SceneError(f"must be the index of the right choice, 0 to {(n or MAX_CHOICES) - 1}",
                                    field=join_path(where, "correct"), value=correct))
        feedback = table.get("feedback")
        if feedback is None:
            problems.add(SceneError("is required with choices: one text per choice", field=join_path(where, "feedback")))
        elif n and (not isinstance(feedback, list) or len(feedback) != n):
            problems.add(SceneError(f"must have one text per choice ({n})", field=join_path(where, "feedback"),
                                    value=feedback))
        else:
            feedback = _texts(problems, join_path(where, "feedback"), feedback, low=2, high=MAX_CHOICES)
        if len(problems.errors) > before:
            return None
        return CheckQuestion(text, choices=choices, correct=correct, feedback=feedback)
    numeric = _number(problems, join_path(where, "numeric"), table["numeric"])
    tolerance = _number(problems, join_path(where, "tolerance"), table.get("tolerance", 0.0), low=0)
    low = _text(problems, join_path(where, "feedback_low"), table.get("feedback_low"), required=True)
    high = _text(problems, join_path(where, "feedback_high"), table.get("feedback_high"), required=True)
    right = _text(problems, join_path(where, "feedback_right"), table.get("feedback_right"), required=False)
    if len(problems.errors) > before:
        return None
    return CheckQuestion(text, numeric=numeric, tolerance=tolerance, feedback_low=low, feedback_high=high,
                         feedback_right=right)


def judge(check: CheckQuestion, answer) -> Verdict:
    """Mark a student's answer (a value from the browser, checked here first).

    A choice is its index (an int, or a string of digits as a form sends
    it); a number is a finite int or float, or a string of at most
    :data:`MAX_ANSWER_CHARS` characters that reads as one.

    Raises
    ------
    ValueError
        Naming the value and what is allowed.
    """
    if check.kind == "choice":
        n = len(check.choices)
        index = answer
        if isinstance(answer, str) and answer.strip().isdigit() and len(answer) <= MAX_ANSWER_CHARS:
            index = int(answer)
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < n:
            raise ValueError(f"check.answer: must be a choice, 0 to {n - 1}, got {_shown(answer)}")
        return Verdict(index == check.correct, check.feedback[index])
    value = answer
    if isinstance(answer, str) and len(answer) <= MAX_ANSWER_CHARS:
        try:
            value = float(answer.strip().replace("−", "-"))
        except ValueError:
            value = None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"check.answer: must be a finite number, got {_shown(answer)}")
    # the edge counts as right: a typed 0.49 for 0.5 ± 0.01 differs from it by 0.010000000000000009
    if abs(value - check.numeric) <= check.tolerance + 1e-9 * max(1.0, abs(check.numeric)):
        return Verdict(True, check.feedback_right or f"Right: {check.numeric:g}.")
    return Verdict(False, check.feedback_low if value < check.numeric else check.feedback_high)


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
