"""The accuracy lesson on a server whose studies never finish: the page says so in words, offers "Try again",
and the rest of the lesson (view, controls, experiments) stays on the page.

The server is ``phonglab serve lessons/`` with the panel's worker calls replaced by results that never come
and its wait cut to 3 seconds (a module patched before the command runs).
"""

from __future__ import annotations

import sys

import pytest
from conftest import Page
from real_lessons import LESSONS, drawn
from waiting import wait_for

from phonglab.bench.ui import LAZY_MEASURE_JS, free_port, log_tail, start_server, stop_server, wait_until_serving

#: ``phonglab serve`` whose accuracy studies never finish, given up after 3 s
NEVER = """
import concurrent.futures, sys
import phonglab.app.accuracy_panel as panel
panel.TIMEOUT = 3.0
panel.submit = lambda *args, **kwargs: concurrent.futures.Future()
from phonglab.cli import main
sys.exit(main(["serve", sys.argv[1], "--host", "127.0.0.1", "--port", sys.argv[2]]))
"""
#: words of Python's, not a student's
RAW = ("Error", "Exception", "no result after", "Traceback")


@pytest.fixture(scope="module")
def stuck_server(tmp_path_factory):
    port = free_port()
    log = tmp_path_factory.mktemp("stuck") / "serve.log"
    process = start_server([sys.executable, "-c", NEVER, str(LESSONS), str(port)], log_path=log)
    try:
        wait_until_serving(process, port, log_path=log, timeout=90)
        yield {"url": f"http://127.0.0.1:{port}/", "port": port, "process": process, "log": log}
    finally:
        stop_server(process)


def test_a_study_that_cannot_finish_is_told_in_words_with_try_again(browser, stuck_server):
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    tab = Page(context.new_page(), stuck_server)
    tab.page.add_init_script(LAZY_MEASURE_JS)
    try:
        tab.page.goto(stuck_server["url"] + "?lesson=11-accuracy")
        drawn(tab)
        tab.page.wait_for_function("() => document.querySelectorAll('.phonglab-try-again').length === 2", timeout=60_000)
        texts = tab.page.locator(".phonglab-try-again").all_inner_texts()
        for text in texts:
            assert "did not finish within 3 seconds" in text and "try again" in text.lower(), texts
            assert not any(word in text for word in RAW), texts
        # the lesson is all there around it: its view, controls and experiments
        for part in (".phonglab-view canvas", ".phonglab-controls", ".phonglab-apply"):
            assert tab.page.locator(part).count() > 0, part
        # "Try again" asks once more: the images' words go while they are measured, and come back when not
        tab.page.locator(".phonglab-accuracy-images-failed .phonglab-try-again-btn").click()
        wait_for(lambda: not tab.state("accuracy_failed"), "the images to be asked for again")
        wait_for(lambda: tab.state("accuracy_failed"), "the second try to give up", timeout=60)
        assert not tab.errors, tab.errors
    except BaseException:
        print(log_tail(stuck_server["log"]))
        raise
    finally:
        context.close()
