"""The page's check question and "Your code" panel, on the Python side (no browser)."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest

from phonglab.app.check_question import CheckPanel
from phonglab.app.student_code import MAX_CODE_BYTES, StudentCodePanel, check_code, grade_code
from phonglab.scene.check import CheckQuestion
from phonglab.teaching.grading import Limits

from grade_students import student_source

DATA = Path(__file__).resolve().parent / "data" / "grade"


class State(dict):
    """Enough of trame's state for a panel: attributes, update() and a flushing with-block."""

    def __getattr__(self, key):
        return self[key]

    def __setattr__(self, key, value):
        self[key] = value

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


class Lesson:
    def __init__(self, check):
        self.check = check


def test_check_panel_marks_an_answer_and_refuses_a_bad_one():
    state = State()
    panel = CheckPanel(state)
    assert state.check is None and state.check_verdict is None
    panel.open(Lesson(CheckQuestion("Which?", choices=("a", "b"), correct=1, feedback=("a is diffuse", "b: yes"))))
    assert state.check["kind"] == "choice" and [c["label"] for c in state.check["choices"]] == ["a", "b"]
    panel.submit(0)
    assert state.check_verdict["right"] is False and "a is diffuse" in state.check_verdict["html"]
    panel.submit(1)
    assert state.check_verdict["right"] is True and "Right." in state.check_verdict["html"]
    for bad in (None, 5, "<script>", {"x": 1}):
        panel.submit(bad)
        assert state.check_verdict == {"right": False, "invalid": True, "html": "Pick one of the answers."}, bad
    panel.open(None)  # a broken lesson: no question, and the old verdict is gone
    assert state.check is None and state.check_verdict is None
    panel.submit(1)
    assert state.check_verdict is None


def test_check_panel_numbers():
    state = State()
    panel = CheckPanel(state)
    panel.open(Lesson(CheckQuestion("n·l?", numeric=0.5, tolerance=0.01, feedback_low="low", feedback_high="sin?")))
    panel.submit("0.87")
    assert not state.check_verdict["right"] and "sin?" in state.check_verdict["html"]
    panel.submit("0.5")
    assert state.check_verdict["right"]
    panel.submit("1e999")
    assert state.check_verdict["invalid"] and "number" in state.check_verdict["html"]


def test_the_page_refuses_code_larger_than_the_limit():
    assert check_code("x = 1\n" * 10) == "x = 1\n" * 10
    at_limit = "#" * MAX_CODE_BYTES
    assert check_code(at_limit) is at_limit
    with pytest.raises(ValueError, match=r"student_code: must be at most 64 kB, got 64 kB"):
        check_code(at_limit + "#")
    with pytest.raises(ValueError, match="at most 64 kB"):
        check_code("é" * (MAX_CODE_BYTES // 2 + 1))  # bytes of UTF-8, not characters
    for bad in (None, 3, b"def shade(): pass", ["x"]):
        with pytest.raises(ValueError, match="must be the text of a Python file"):
            check_code(bad)
    with pytest.raises(ValueError, match="is empty"):
        check_code("  \n")


def test_the_panel_refuses_too_much_code_without_running_anything():
    state = State()
    panel = StudentCodePanel(state, enabled=True)
    panel.submit("#" * (MAX_CODE_BYTES + 1))
    assert "at most 64 kB" in state.student_result["error"] and state.student_busy is False
    assert panel._task is None


def test_a_panel_without_the_flag_runs_nothing():
    state = State()
    panel = StudentCodePanel(state)
    assert state.student_code_enabled is False
    panel.submit((DATA / "correct.py").read_text())
    assert state.student_result is None and state.student_busy is False and panel._task is None


def test_grading_pasted_code_in_a_thread_gives_the_report_and_the_picture():
    state = State()
    panel = StudentCodePanel(state, enabled=True)

    async def run():
        panel.submit((DATA / "correct.py").read_text())
        assert state.student_busy is True
        await panel._task

    asyncio.run(run())
    result = state.student_result
    assert state.student_busy is False
    assert result["score"] == result["max_score"] == 100 and result["passed"], result.get("report", result)
    assert result["picture"].startswith("data:image/png;base64,") and result["isolation"]
    assert "Total: 100/100" in result["report"] and "phonglab-student-" not in result["report"]


def test_pasted_code_with_a_mistake_is_diagnosed_and_broken_code_is_reported():
    wrong = grade_code(student_source("spot_cutoff_in_degrees.py"), Limits())
    assert wrong["score"] < 100 and wrong["diagnosis"] == ["spot-cutoff-in-degrees"], wrong["report"]
    broken = grade_code("def shade(:\n", Limits())
    assert broken["error"].startswith("The code cannot be loaded: SyntaxError"), broken


def test_serve_flag_is_off_by_default_and_its_help_says_code_runs_on_the_server(monkeypatch, capsys):
    import argparse

    from phonglab.cli import serve as serve_cli

    parser = argparse.ArgumentParser()
    serve_cli.add_parser(parser.add_subparsers())
    assert parser.parse_args(["serve"]).allow_student_code is False
    assert parser.parse_args(["serve", "--allow-student-code"]).allow_student_code is True
    help_text = " ".join(serve_cli.add_parser(argparse.ArgumentParser().add_subparsers()).format_help().split())
    for words in ("RUNS ON THIS SERVER", "remote code execution", "trusted classroom", "python -I", "audit hook"):
        assert words in help_text, (words, help_text)
    # the flag reaches the app
    seen = {}
    monkeypatch.setattr("phonglab.app.serve", lambda target, **kw: seen.update(kw))
    args = parser.parse_args(["serve", str(Path(__file__).resolve().parents[1] / "lessons"), "--allow-student-code"])
    assert serve_cli.run(args) == 0 and seen["allow_student_code"] is True
    assert "students' code runs on this server" in capsys.readouterr().err
