"""In a real browser: a check question marks an answer before the explanation, and the "Your code" panel
grades a pasted shade() only when the server was started with --allow-student-code.

The server here serves the test lessons with a [check] table added to lesson 1 and the flag on; the
shared server of conftest.py (no flag) shows no panel.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from waiting import wait_for

from phonglab.bench.scenes import write_lessons

from conftest import open_tab

CORRECT = Path(__file__).resolve().parents[1] / "data" / "grade" / "correct.py"
CHECK = """
[check]
question = "What is n·l where the normal points straight at the light?"
choices = ["0", "1", "-1"]
correct = 1
feedback = ["0 is where the light grazes the surface.", "Right: cos 0 = 1.", "-1: the light would be behind."]
"""


@pytest.fixture(scope="module")
def code_server(serve_app, tmp_path_factory):
    folder = write_lessons(tmp_path_factory.mktemp("lessons-check"))
    first = folder / "01-sphere.md"
    lines = first.read_text().splitlines(keepends=True)
    closing = [i for i, line in enumerate(lines) if line.strip() == "+++"][1]
    first.write_text("".join(lines[:closing]) + CHECK + "".join(lines[closing:]))
    return serve_app(first, "--allow-student-code")


@pytest.fixture
def code_page(browser, code_server):
    with open_tab(browser, code_server, height=900) as page:
        yield page


def test_check_question_gives_feedback_then_offers_the_explanation(code_page):
    page = code_page.page
    page.wait_for_selector(".phonglab-check-choice", timeout=30_000)
    assert not page.locator(".phonglab-answer-btn").count(), "the explanation is offered before any answer"
    # one question to answer: the check's first; the lesson's open question after it, labelled apart
    block = page.locator(".phonglab-question").inner_text()
    check_at, think_at = block.find("What is n·l where"), block.find("Think about it")
    assert 0 <= check_at < think_at, block
    page.locator(".phonglab-check-choice", has_text="-1").locator("input").check()
    page.locator(".phonglab-check-btn").click()
    feedback = wait_for(lambda: page.locator(".phonglab-check-feedback").all_inner_texts(), "the feedback")
    assert "Not quite." in feedback[0] and "behind" in feedback[0], feedback
    assert page.locator(".phonglab-check-wrong").count() == 1
    page.locator(".phonglab-check-choice", has_text="1").first.locator("input").check()
    page.locator(".phonglab-check-btn").click()
    wait_for(lambda: page.locator(".phonglab-check-right").count() == 1, "the answer to be marked right")
    assert "cos 0 = 1" in page.locator(".phonglab-check-feedback").inner_text()
    page.locator(".phonglab-answer-btn").click()
    wait_for(lambda: page.locator(".phonglab-answer").count() == 1, "the explanation")


def test_the_feedback_is_scrolled_into_sight_when_the_check_button_was_at_the_columns_foot(browser, code_server):
    with open_tab(browser, code_server, height=600) as tab:
        page = tab.page
        page.wait_for_selector(".phonglab-check-choice", timeout=30_000)
        # the Check button at the very foot of the lesson column, as a student who just read the question has it
        page.locator(".phonglab-check-btn").evaluate("b => b.scrollIntoView({block: 'end'})")
        page.locator(".phonglab-check-choice", has_text="-1").locator("input").check()
        page.locator(".phonglab-check-btn").click()
        wait_for(lambda: page.locator(".phonglab-check-feedback").count() == 1, "the feedback")
        seen = """f => { const r = f.getBoundingClientRect();
                          let c = f.parentElement; while (c && getComputedStyle(c).overflowY !== 'auto') c = c.parentElement;
                          const box = c ? c.getBoundingClientRect() : {top: 0, bottom: innerHeight};
                          return [r.top, r.bottom, box.top, Math.min(box.bottom, innerHeight)]; }"""
        feedback = page.locator(".phonglab-check-feedback")
        last = []

        def in_sight():
            last[:] = feedback.evaluate(seen)
            top, bottom, column_top, column_bottom = last
            return column_top <= top and bottom <= column_bottom + 1

        if not wait_for_quietly(in_sight, timeout=10):
            pytest.fail(f"the feedback is out of sight: feedback top, bottom and column top, bottom {last}")


def wait_for_quietly(predicate, timeout):
    """True once ``predicate()`` is, False after ``timeout`` seconds."""
    import time

    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return False


def test_pasting_a_correct_shade_gets_full_marks(code_page):
    page = code_page.page
    page.locator(".phonglab-student-code-text textarea").fill(CORRECT.read_text())
    page.locator(".phonglab-student-code-btn").click()
    score = wait_for(lambda: page.locator(".phonglab-student-score").all_inner_texts(), "the grade", timeout=240)
    assert score == ["Score: 100/100"], score
    assert "Total: 100/100" in page.locator(".phonglab-student-report").inner_text()
    picture = page.locator(".phonglab-student-picture")
    src = picture.get_attribute("src")
    assert src.startswith("data:image/png;base64,"), src[:40]
    # fitted to the column its captions are a few pixels tall; a click shows it at its own size, another fits it
    sizes = "e => [e.getBoundingClientRect().width, e.naturalWidth, e.parentElement.clientWidth]"
    shown, natural, column = picture.evaluate(sizes)
    assert shown <= column < natural, (shown, natural, column)
    picture.click()
    wait_for(lambda: picture.evaluate(sizes)[0] == natural or None, "the picture at its own size")
    picture.click()
    wait_for(lambda: picture.evaluate(sizes)[0] <= column or None, "the picture fitted to the column again")


def test_without_the_flag_there_is_no_panel(app_page):
    assert app_page.state("student_code_enabled") is False
    assert not app_page.page.locator(".phonglab-student-code").count()
    assert not app_page.page.locator(".phonglab-student-code-text").count()
