"""The guard seen from a real browser: a full server says so on the page."""

from __future__ import annotations

import pytest

from phonglab.bench.ui import free_port, log_tail, serve_command, start_server, stop_server, wait_until_serving
from waiting import wait_for


@pytest.fixture(scope="module")
def one_seat(lesson_dir, tmp_path_factory):
    """``phonglab serve --max-sessions 1`` on a free port."""
    port = free_port()
    log_path = tmp_path_factory.mktemp("one-seat") / "serve.log"
    process = start_server(serve_command(lesson_dir / "01-sphere.md", port) + ["--max-sessions", "1"],
                           log_path=log_path)
    try:
        wait_until_serving(process, port, log_path=log_path)
    except RuntimeError as exc:
        stop_server(process)
        pytest.fail(f"phonglab serve did not start: {exc}")
    yield {"url": f"http://127.0.0.1:{port}/", "port": port, "log": log_path, "process": process}
    stop_server(process)


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
