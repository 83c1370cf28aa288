"""The guard seen from a real browser: a full server says so on the page."""

from __future__ import annotations

import pytest

from phonglab.bench.ui import log_tail
from waiting import wait_for


@pytest.fixture(scope="module")
def one_seat(serve_app, lesson_dir):
    """``phonglab serve --max-sessions 1`` on a free port."""
    return serve_app(lesson_dir / "01-sphere.md", "--max-sessions", "1")


def test_a_tab_past_max_sessions_shows_that_the_server_is_full(browser, one_seat):
    first = browser.new_context()
    second = browser.new_context()
    try:
        page = first.new_page()
        page.goto(one_seat["url"])
        page.wait_for_selector(".phonglab-view canvas", timeout=60_000)
        late = second.new_page()
        late.goto(one_seat["url"])
        alert = late.locator("#phonglab-refused")
        wait_for(lambda: alert.count() and alert.inner_text(), "the server-full message", timeout=30)
        assert "full" in alert.inner_text() and "try again later" in alert.inner_text(), alert.inner_text()
        # the first tab still works
        assert page.evaluate("() => window.trame.state.get('drawer')") is not None
        # once the first tab closes, a new tab gets the lesson
        first.close()

        def seated():
            retry = second.new_page()
            retry.goto(one_seat["url"])
            retry.wait_for_function("() => document.querySelector('.phonglab-view canvas')"
                                    " || document.querySelector('#phonglab-refused')", timeout=60_000)
            shown = retry.locator(".phonglab-view canvas").count() > 0
            retry.close()
            return shown

        wait_for(seated, "a seat once the first tab closed", timeout=60)
    finally:
        second.close()
        if first.pages:
            first.close()
    assert one_seat["process"].poll() is None, log_tail(one_seat["log"])
