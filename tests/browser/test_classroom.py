"""The page in a classroom: figures exported from the page arrive as downloads in the student's browser."""

from __future__ import annotations

import io
import re

from PIL import Image


def _saved_png(download, folder):
    path = folder / download.suggested_filename
    download.save_as(path)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", (download.suggested_filename, data[:16])
    with Image.open(io.BytesIO(data)) as img:
        img.load()
        return img.size


def test_export_arrives_as_a_browser_download(app_page, tmp_path):
    page = app_page.page
    with page.expect_download(timeout=120_000) as info:
        page.locator(".phonglab-export").click()
    download = info.value
    assert re.fullmatch(r"lesson-01-\d{8}-\d{6}\.png", download.suggested_filename), download.suggested_filename
    assert _saved_png(download, tmp_path) == (1200, 900)
    # the per-term figure, from the menu beside the button
    page.locator(".phonglab-export-more").click()
    with page.expect_download(timeout=120_000) as info:
        page.locator(".phonglab-export-terms").click()
    download = info.value
    assert re.fullmatch(r"lesson-01-terms-\d{8}-\d{6}\.png", download.suggested_filename), download.suggested_filename
    assert _saved_png(download, tmp_path) == (1200, 900)


def _lesson_title(page) -> str:
    return page.locator(".phonglab-lesson-title").first.inner_text()


def test_the_address_carries_the_lesson_through_reload_and_a_fresh_tab(app_page, browser, server):
    from waiting import wait_for

    page = app_page.page
    wait_for(lambda: page.url.endswith("?lesson=01-sphere"), f"the address of lesson 1, got {page.url}")
    app_page.open_lesson("A spotlight on a floor")
    wait_for(lambda: page.url.endswith("?lesson=02-spot"), f"the address of lesson 2, got {page.url}")
    link = page.url
    # a reload keeps the lesson
    page.reload()
    page.wait_for_function(
        "() => { const e = document.querySelector('.phonglab-lesson-title'); return e && e.innerText.endsWith('A spotlight on a floor'); }",
        timeout=60_000)
    assert page.url == link, page.url
    # the link pasted into a fresh tab (its own session) opens the same lesson
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        other = context.new_page()
        other.goto(link)
        other.wait_for_function(
            "() => { const e = document.querySelector('.phonglab-lesson-title'); return e && e.innerText.endsWith('A spotlight on a floor'); }",
            timeout=60_000)
        # a bad lesson name is refused with a notice; the page stays usable on its first lesson
        other.goto(server["url"] + "?lesson=no-such-lesson")
        other.wait_for_selector(".phonglab-notice", timeout=60_000)
        notice = other.locator(".phonglab-notice").first.inner_text()
        assert "no lesson 'no-such-lesson'" in notice, notice
        assert _lesson_title(other).endswith("A red sphere"), _lesson_title(other)
    finally:
        context.close()


def test_after_a_server_restart_the_tab_comes_back_to_the_same_lesson(browser, lesson_dir, tmp_path):
    from phonglab.bench.ui import free_port, serve_command, start_server, stop_server, wait_until_serving

    port = free_port()
    command = serve_command(lesson_dir, port)
    process = start_server(command, log_path=tmp_path / "first.log")
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        wait_until_serving(process, port, log_path=tmp_path / "first.log")
        page = context.new_page()
        page.goto(f"http://127.0.0.1:{port}/?lesson=02-spot")
        title = ("() => { const e = document.querySelector('.phonglab-lesson-title');"
                 " return e && e.innerText.endsWith('A spotlight on a floor'); }")
        page.wait_for_function(title, timeout=60_000)
        stop_server(process)
        # the page says it is reconnecting ...
        page.wait_for_selector(".phonglab-reconnecting", state="visible", timeout=30_000)
        assert "Reconnecting" in page.locator(".phonglab-reconnecting").inner_text()
        # ... and, once the server is back on the same port, shows the same lesson again by itself
        process = start_server(command, log_path=tmp_path / "second.log")
        wait_until_serving(process, port, log_path=tmp_path / "second.log")
        page.wait_for_function(title, timeout=60_000)
        page.wait_for_selector(".phonglab-reconnecting", state="detached", timeout=30_000)
        assert page.url.endswith("?lesson=02-spot"), page.url
    finally:
        context.close()
        stop_server(process)
