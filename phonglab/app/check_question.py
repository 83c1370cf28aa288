"""The lesson's answerable check question on the page: answer, feedback, then the explanation.

A lesson with a ``[check]`` table (:mod:`phonglab.scene.check`) shows its
question under "Check yourself" with radio buttons (multiple choice) or a
number field, and a Check button. The answer goes to the server, which
validates it like any value from the browser (:func:`phonglab.scene.check.judge`)
and answers with feedback: right, or the misunderstanding a wrong choice or
a number too low or too high suggests. The explanation (the lesson's
``answer``) can be revealed only once an answer has been checked.

State keys: ``check`` (the question as the page shows it, or None),
``check_choice``, ``check_number`` (the student's input) and
``check_verdict`` (``{"right": bool, "html": str}`` or None).
"""

from __future__ import annotations

from trame.widgets import html
from trame.widgets import vuetify3 as v3

from phonglab.app import text
from phonglab.scene.check import MAX_ANSWER_CHARS, judge

__all__ = ["CheckPanel", "initial_state", "build", "verdict_html", "REVEAL_IF"]

#: the condition under which the page offers the explanation: no check question, or one answered
REVEAL_IF = "!check || check_verdict"


def initial_state() -> dict:
    """The check question's state keys before a lesson is open."""
    return {"check": None, "check_choice": None, "check_number": "", "check_verdict": None}


class CheckPanel:
    """The open lesson's check question, for one tab.

    Parameters
    ----------
    state : trame state
    """

    def __init__(self, state):
        self.state = state
        self.check = None
        state.update(initial_state())

    def open(self, lesson) -> None:
        """Show ``lesson``'s check question (None: a broken file or no lesson), unanswered."""
        self.check = getattr(lesson, "check", None)
        self.state.update(initial_state())
        if self.check is None:
            return
        c = self.check
        self.state.check = {
            "kind": c.kind,
            "question_html": text.inline(c.question),
            "choices": [{"value": i, "label": label} for i, label in enumerate(c.choices)],
        }

    def submit(self, answer=None, *_, **__) -> None:
        """Mark ``answer`` (an index or a number, as the browser sent it) and show the feedback."""
        if self.check is None:
            return
        try:
            verdict = judge(self.check, answer)
        except ValueError as exc:
            self.state.check_verdict = {"right": False, "invalid": True, "html": text.inline(_plain(exc))}
            return
        self.state.check_verdict = {"right": verdict.right, "invalid": False, "html": verdict_html(verdict)}


def verdict_html(verdict) -> str:
    """The feedback led by its verdict, in bold, said once.

    "Right." or "Not quite." goes before the lesson's feedback, unless the
    feedback begins with the verdict itself ("Right: cos 60° = 1/2."): then
    that word is the bold lead, and is not said twice.
    """
    word = "Right" if verdict.right else "Not quite"
    feedback = verdict.feedback.strip()
    if feedback.startswith(word) and feedback[len(word):len(word) + 1] in (":", ".", ",", "!", " ", ""):
        return f"<b>{word}</b>{text.inline(feedback[len(word):])}"
    return f"<b>{word}.</b> {text.inline(feedback)}"


def _plain(exc: ValueError) -> str:
    """The refusal in the page's words: what to enter."""
    message = str(exc)
    return "Pick one of the answers." if "must be a choice" in message else (
        "Enter a number, e.g. 0.25." if "finite number" in message else message)


def build(submit) -> None:
    """The check question's widgets, inside the page's "Check yourself" block.

    Parameters
    ----------
    submit : callable
        :meth:`CheckPanel.submit` of the tab's panel.
    """
    with html.Div(v_if="check", classes="phonglab-check"):
        html.Div(v_html=("check.question_html",), classes="phonglab-check-question")
        with v3.VRadioGroup(v_if="check.kind === 'choice'", v_model=("check_choice",), density="compact",
                            hide_details=True, classes="phonglab-check-choices"):
            v3.VRadio(v_for="c in check.choices", key="c.value", value=("c.value",), label=("c.label",),
                      classes="phonglab-check-choice")
        v3.VTextField(v_if="check.kind === 'numeric'", v_model=("check_number",), label="Your answer",
                      inputmode="decimal", density="compact", variant="outlined", hide_details=True,
                      maxlength=MAX_ANSWER_CHARS, style="max-width: 12em", classes="phonglab-check-number")
        v3.VBtn("Check", size="small", color="primary", variant="tonal", classes="phonglab-check-btn mt-1",
                click=(submit, "[check.kind === 'choice' ? check_choice : check_number]"))
        html.Div(v_if="check_verdict", v_html=("check_verdict.html",),
                 classes=("check_verdict && check_verdict.right ? 'phonglab-check-feedback phonglab-check-right' "
                          ": 'phonglab-check-feedback phonglab-check-wrong'",))
