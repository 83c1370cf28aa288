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
