"""``phonglab serve --launcher`` in real browsers: a process per tab, closed with its tab; the address and
reconnecting work through the launcher as they do with one server."""

from __future__ import annotations

import os
import signal
from types import SimpleNamespace

import pytest
from conftest import Page
from test_app_launcher import free_range, sessions_of
from waiting import wait_for

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def launcher(serve_app, lesson_dir):
    first = free_range(3)
    served = serve_app(lesson_dir, "--launcher", "--max-sessions", "3", "--session-ports", str(first), timeout=120)
    return SimpleNamespace(**served, first=first)


def _tab(browser, launcher, query: str = ""):
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    page = Page(context.new_page(), {**launcher.__dict__, "url": launcher.url + query})
    page.open()
    return context, page


def test_two_browsers_get_two_processes_and_a_closed_tab_ends_its_own(browser, launcher):
    first_context, first = _tab(browser, launcher)
    second_context, second = _tab(browser, launcher, "index.html?interpolation=flat")
    try:
        both = wait_for(lambda: len(sessions_of(launcher)) == 2 and sessions_of(launcher),
                        "two session processes", timeout=60)
        assert len(set(both.values())) == 2, both
        # each tab is its own session: the second one's address applied there only
        wait_for(lambda: second.state("interpolation") == "flat", "the address's setting in the second tab", 60)
        assert first.state("interpolation") != "flat"
        assert not first.errors and not second.errors, (first.errors, second.errors)

        # reconnecting: the second tab's process dies; the page reloads into a new process, same view
        second_pid = _started_last(both)  # the tabs opened one after the other
        os.kill(second_pid, signal.SIGKILL)
        wait_for(lambda: second_pid not in sessions_of(launcher) and len(sessions_of(launcher)) == 2,
                 "a new process for the reloaded tab", timeout=120)
        second.page.wait_for_selector(".phonglab-view canvas", timeout=120_000)
        wait_for(lambda: second.state("interpolation") == "flat", "the same view after reconnecting", 120)

        # closing the first tab ends its process only
        kept = set(sessions_of(launcher))
        first_context.close()
        first_context = None
        left = wait_for(lambda: len(sessions_of(launcher)) == 1 and sessions_of(launcher),
                        "the closed tab's process to end", timeout=60)
        assert set(left) < kept, (kept, left)
        assert launcher.process.poll() is None
    finally:
        if first_context is not None:
            first_context.close()
        second_context.close()


def _started_last(pids) -> int:
    """The process of ``pids`` that started last (field 22 of /proc/PID/stat: its start time)."""
    def start(pid):
        text = open(f"/proc/{pid}/stat").read()
        return int(text[text.rfind(")") + 2:].split()[19])

    return max(pids, key=start)
