"""The page's check question and "Your code" panel, on the Python side (no browser)."""

from __future__ import annotations

import asyncio
import os
import time
from pathlib import Path

import numpy as np

import pytest

from phonglab.app.check_question import CheckPanel
from phonglab.app.student_code import MAX_CODE_BYTES, StudentCodePanel, check_code, grade_code, grading_slots
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


async def until(condition, seconds: float) -> bool:
    """Wait in the loop until ``condition()`` holds (True) or ``seconds`` pass (False)."""
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            return False
        await asyncio.sleep(0.01)
    return True


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
    assert not panel.busy


def test_a_panel_without_the_flag_runs_nothing():
    state = State()
    panel = StudentCodePanel(state)
    assert state.student_code_enabled is False
    panel.submit((DATA / "correct.py").read_text())
    assert state.student_result is None and state.student_busy is False and not panel.busy


def test_grading_pasted_code_in_a_thread_gives_the_report_and_the_picture():
    state = State()
    panel = StudentCodePanel(state, enabled=True)

    async def run():
        panel.submit((DATA / "correct.py").read_text())
        assert state.student_busy is True
        assert await until(lambda: not panel.busy, 240), "the grading did not end"

    asyncio.run(run())
    result = state.student_result
    assert state.student_busy is False
    assert result["score"] == result["max_score"] == 100 and result["passed"], result.get("report", result)
    assert result["picture"].startswith("data:image/png;base64,") and result["isolation"]
    assert "Total: 100/100" in result["report"] and "phonglab-student-" not in result["report"]
    assert "bubblewrap" in " ".join(result["isolation"])


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
    for words in ("RUNS ON THIS SERVER", "bubblewrap sandbox", "seccomp", "Refuses to start when bwrap"):
        assert words in help_text, (words, help_text)
    # the flag reaches the app
    seen = {}
    monkeypatch.setattr("phonglab.app.serve", lambda target, **kw: seen.update(kw))
    args = parser.parse_args(["serve", str(Path(__file__).resolve().parents[1] / "lessons"), "--allow-student-code"])
    assert serve_cli.run(args) == 0 and seen["allow_student_code"] is True
    err = capsys.readouterr().err
    assert f"students' code runs on this server in a bubblewrap sandbox, {grading_slots()} at a time" in err, err


SLEEPER = "import time\n\ndef shade(point, normal, eye, material, lights):\n    time.sleep(100)\n"


class QuickJob:
    """A per-pixel picture whose NumPy half is instant: it shows only whether a thread was free for it."""

    def finish(self):
        return np.zeros((2, 2, 3), np.uint8)


def test_sleeping_gradings_leave_another_tabs_per_pixel_picture_alone_and_end_with_their_tabs():
    """As many tabs as asyncio's default pool has threads paste a shade that sleeps; another tab's picture.

    Run in that pool, the gradings (a case may take 60 s here) hold every thread and the picture waits for
    a whole grading. On their own pool it comes at once; the gradings wait their turn with their place
    shown, a second paste cancels the first, and closing the tabs kills what runs.
    """
    from phonglab.app.pixel_picture import PixelPicture

    tabs = min(32, (os.cpu_count() or 1) + 4)  # the threads of asyncio's default executor
    limits = Limits(time_limit=60.0, total_limit=120.0)
    shown = []

    class PictureState(dict):
        def __setitem__(self, key, value):
            shown.append(value)

        def flush(self):
            pass

    async def scenario():
        from phonglab.app import student_code

        panels = [StudentCodePanel(State(), True, limits) for _ in range(tabs)]
        for panel in panels:
            panel.submit(SLEEPER)
        for _ in range(3):  # let the loop run the tabs' submissions first, as a busy server would have
            await asyncio.sleep(0)
        pictures = PixelPicture(PictureState(), lambda kind, text: shown.append(text))
        pictures.request(QuickJob)
        came = await until(lambda: bool(shown), 60)
        assert came and all(p.busy for p in panels), (
            f"the per-pixel picture {'came only after' if came else 'waited behind'} the gradings")
        slots = student_code.queue().slots
        assert slots == grading_slots() and student_code.queue().running == slots
        places = [p.state.student_status for p in panels]
        assert places[:slots] == ["Grading your code…"] * slots, places
        assert places[slots:] == [f"Waiting for a free grader: number {i} in the queue"
                                  for i in range(1, tabs - slots + 1)], places
        # a second paste cancels the first: its slot goes to the next tab, and it queues again at the end
        panels[0].submit(SLEEPER)
        assert await until(lambda: panels[slots].state.student_status == "Grading your code…", 30), (
            [p.state.student_status for p in panels])
        assert panels[0].state.student_status.endswith(f"number {tabs - slots} in the queue"), (
            panels[0].state.student_status)
        # closing the tabs cancels every grading: the sandboxes are killed, the pool is free again
        for panel in panels:
            panel.close()
        assert await until(lambda: student_code.queue().running == 0, 30), "a grading still runs"
        assert student_code.queue().waiting == 0
        assert all(p.state.student_result is None for p in panels)

    asyncio.run(scenario())
