"""The page in a classroom: figures exported from the page arrive as downloads in the student's browser."""

from __future__ import annotations

import io
import re

import pytest
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


def _address(page) -> str:
    """The tab's address now (``page.url`` follows ``replaceState`` only when Playwright next hears from the page)."""
    return page.evaluate("() => window.location.href")


SPOT = "A spotlight on a floor"


def _settled_view(tab, title, ks, interpolation):
    """Wait until ``tab`` shows lesson ``title`` with k_s = ``ks`` and ``interpolation``; its slider text and readout."""
    from waiting import wait_for

    tab.page.wait_for_function(
        "(t) => { const e = document.querySelector('.phonglab-lesson-title');"
        " return window.trame && window.trame.state && e && e.innerText.endsWith(t); }", arg=title, timeout=60_000)
    wait_for(lambda: tab.state("material__ks__level") == pytest.approx(ks)
             and tab.state("interpolation") == interpolation,
             f"k_s = {ks} and {interpolation} on the page, got {tab.state('material__ks__level')!r}, "
             f"{tab.state('interpolation')!r}", timeout=60)
    wait_for(lambda: tab.state("readout"), "the readout")
    return tab.state("control_values")["material__ks__level"], tab.readout()


def test_the_address_carries_the_lesson_and_its_settings_through_reload_and_a_fresh_tab(app_page, browser, server):
    from waiting import wait_for

    page = app_page.page
    history = page.evaluate("() => window.history.length")
    wait_for(lambda: _address(page).endswith("?lesson=01-sphere"), "the address of lesson 1")
    app_page.open_lesson(SPOT)
    wait_for(lambda: _address(page).endswith("?lesson=02-spot"), "the address of lesson 2")
    # the address follows the student's work: only the settings that differ from the lesson's
    app_page.set_state("material__ks__level", "0.8")
    app_page.set_state("interpolation", "'flat'")
    link = wait_for(lambda: ("interpolation=flat" in _address(page) and "material.ks=0.8" in _address(page)
                             and _address(page)), "the settings in the address")
    assert link.startswith(server["url"]) and "?lesson=02-spot&" in link, link
    assert sorted(link.split("?")[1].split("&")) == ["interpolation=flat", "lesson=02-spot", "material.ks=0.8"], link
    shown, readout = _settled_view(app_page, SPOT, 0.8, "flat")
    assert shown == "0.80", shown
    # replaceState only: the tab's history did not grow
    assert page.evaluate("() => window.history.length") == history, (history, page.evaluate("() => window.history.length"))
    # a reload shows the same lesson and values, on the page and in the readout
    page.reload()
    assert _settled_view(app_page, SPOT, 0.8, "flat") == (shown, readout), link
    assert _address(page) == link, _address(page)
    # the link pasted into a fresh tab (its own session) opens the same view
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        other = type(app_page)(context.new_page(), server)  # the fixture's tab helper
        other.page.goto(link)
        assert _settled_view(other, SPOT, 0.8, "flat") == (shown, readout), link
        # a bad value is dropped with a notice naming it; the lesson opens and the rest applies
        other.page.goto(server["url"] + "?lesson=02-spot&lights[1].exponent=-3&lights[1].cutoff=40&colour=red")
        other.page.wait_for_selector(".phonglab-notice", timeout=60_000)
        notice = other.text(".phonglab-notice")
        assert "(lights[1].exponent) = -3," in notice and "a number of 0 or more" in notice, notice
        assert "colour = " in notice and "no setting called that" in notice, notice
        assert _lesson_title(other.page).endswith(SPOT), _lesson_title(other.page)
        wait_for(lambda: other.state("lights_1__cutoff") == 40, "the good setting to apply")
        wait_for(lambda: _address(other.page).endswith("?lesson=02-spot&lights[1].cutoff=40"),
                 "the address without the dropped settings")
        # a bad lesson name is refused with a notice; the page stays usable on its first lesson
        other.page.goto(server["url"] + "?lesson=no-such-lesson")
        other.page.wait_for_selector(".phonglab-notice", timeout=60_000)
        notice = other.text(".phonglab-notice")
        assert "a lesson called no-such-lesson, but there is none" in notice, notice
        assert _lesson_title(other.page).endswith("A red sphere"), _lesson_title(other.page)
        assert not other.errors, other.errors
    finally:
        context.close()


def test_after_a_server_restart_the_tab_comes_back_to_the_same_lesson(browser, lesson_dir, tmp_path):
    from app_support import start_app

    from phonglab.bench.ui import stop_server

    served = start_app(lesson_dir, log_path=tmp_path / "first.log")
    process = served["process"]
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    try:
        page = context.new_page()
        page.goto(served["url"] + "?lesson=02-spot")
        title = ("() => { const e = document.querySelector('.phonglab-lesson-title');"
                 " return e && e.innerText.endsWith('A spotlight on a floor'); }")
        page.wait_for_function(title, timeout=60_000)
        # the student narrows the cone; the address follows
        page.evaluate("() => window.trame.state.set('lights_1__cutoff', 12)")
        page.wait_for_function("() => window.location.search.includes('cutoff=12')", timeout=30_000)
        stop_server(process)
        # the page says it is reconnecting ...
        page.wait_for_selector(".phonglab-reconnecting", state="visible", timeout=30_000)
        assert "Reconnecting" in page.locator(".phonglab-reconnecting").inner_text()
        # ... and, once the server is back on the same port, shows the same lesson again by itself
        process = start_app(lesson_dir, log_path=tmp_path / "second.log", port=served["port"])["process"]
        page.wait_for_function(title, timeout=60_000)
        page.wait_for_selector(".phonglab-reconnecting", state="detached", timeout=30_000)
        # the same settings in the address (a reload may hand the page its query percent-encoded,
        # lights%5B1%5D, until the page writes the server's query back)
        wanted = "?lesson=02-spot&lights[1].cutoff=12"
        try:
            page.wait_for_function(f"() => decodeURIComponent(window.location.search) === {wanted!r}", timeout=30_000)
        except Exception:
            raise AssertionError(f"address {_address(page)!r}, wanted it to end with {wanted!r}") from None
        page.wait_for_function("() => window.trame.state.get('lights_1__cutoff') === 12", timeout=30_000)
        assert page.evaluate("() => window.trame.state.get('control_values')['lights_1__cutoff']") == "12°"
    finally:
        context.close()
        stop_server(process)
