"""Fixtures for the browser tests: a ``phonglab serve`` server and headless Chromium.

The server runs the test lessons of :data:`phonglab.bench.scenes.LESSONS`
(small meshes, known lights) on a free 127.0.0.1 port, in its own process
group, and is killed by PID at the end. Chromium is Debian's ``/usr/bin/chromium`` driven by Playwright; if
it is missing the tests fail (they never skip) and say how to install it.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from phonglab.bench.scenes import write_lessons
from phonglab.bench.ui import (
    CHROMIUM,
    CHROMIUM_MISSING,
    MEASURE_JS,
    free_port,
    launch_chromium,
    log_tail,
    serve_command,
    start_server,
    stop_server,
    wait_until_serving,
)


@pytest.fixture(scope="session")
def lesson_dir(tmp_path_factory) -> Path:
    return write_lessons(tmp_path_factory.mktemp("lessons"))


@pytest.fixture(scope="session")
def export_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("exports")


@pytest.fixture(scope="session")
def server(lesson_dir, export_dir, tmp_path_factory):
    """``phonglab serve`` on a free 127.0.0.1 port; yields a dict with url, process and log path."""
    port = free_port()
    log_path = tmp_path_factory.mktemp("server") / "serve.log"
    command = serve_command(lesson_dir, port) + ["--export-dir", str(export_dir)]
    process = start_server(command, log_path=log_path)
    try:
        wait_until_serving(process, port, log_path=log_path)
    except RuntimeError as exc:
        stop_server(process)
        pytest.fail(f"phonglab serve did not start: {exc}")
    yield {"url": f"http://127.0.0.1:{port}/", "process": process, "log": log_path, "port": port}
    stop_server(process)


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium; fails (never skips) when it is not installed."""
    if not os.path.exists(CHROMIUM):
        pytest.fail(CHROMIUM_MISSING, pytrace=False)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = launch_chromium(playwright)
        yield chromium
        chromium.close()


class Page:
    """A browser tab on the app, with the helpers the tests share."""

    def __init__(self, page, server):
        self.page = page
        self.server = server
        self.errors = []
        self.external = []
        page.on("pageerror", lambda e: self.errors.append(str(e)))
        page.on("request", self._check_request)

    def _check_request(self, request):
        if not request.url.startswith(("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")):
            self.external.append(request.url)

    def open(self):
        self.page.add_init_script(MEASURE_JS)
        self.page.goto(self.server["url"])
        self.page.wait_for_selector(".phonglab-view canvas", timeout=60_000)
        self.page.evaluate("() => { window.__phonglabBench.selector = '.phonglab-view canvas'; }")
        self.wait_settled()
        return self

    def wait_settled(self, frames: int = 10):
        """Wait until the view has drawn something and stopped changing."""
        self.page.wait_for_function(
            f"() => {{ const b = window.__phonglabBench; return b.last !== 0 && b.stable >= {frames}; }}",
            timeout=30_000,
        )

    def pixel_hash(self) -> int:
        return self.page.evaluate("() => window.__phonglabBench.hash()")

    def state(self, key):
        return self.page.evaluate("(k) => window.trame.state.get(k)", key)

    def set_state(self, key, value_js: str):
        """Set a state key from the browser, the way a client message would (value as JavaScript)."""
        self.page.evaluate(f"() => window.trame.state.set({key!r}, {value_js})")

    def text(self, selector) -> str:
        return self.page.locator(selector).first.inner_text()

    def readout(self) -> dict:
        """The probe readout, read in one go: point, dots (name -> float) and terms (name -> text)."""
        raw = self.page.evaluate(
            """() => {
                const text = (s) => { const e = document.querySelector(s); return e ? e.innerText.trim() : null; };
                const dots = {}, terms = {};
                for (const e of document.querySelectorAll('[data-name]')) dots[e.dataset.name] = e.innerText.trim();
                for (const e of document.querySelectorAll('[data-term]')) terms[e.dataset.term] = e.innerText.trim();
                return { point: text('.phonglab-point'), dots, terms };
            }"""
        )
        assert raw["point"] and len(raw["dots"]) == 3, f"no readout on the page: {raw}"
        return {
            "point": [float(c) for c in raw["point"].strip("()").split(",")],
            "dots": {name: float(value) for name, value in raw["dots"].items()},
            "terms": raw["terms"],
        }

    def open_lesson(self, title: str):
        """Open a lesson from the drawer by its title and wait until the page shows it."""
        self.page.locator(".phonglab-menu").click()
        self.page.locator(".phonglab-lesson-item", has_text=title).click()
        self.page.wait_for_function(
            "(t) => { const e = document.querySelector('.phonglab-lesson-title'); return e && e.innerText.endsWith(t); }",
            arg=title, timeout=30_000,
        )
        self.page.wait_for_function("() => window.trame.state.get('drawer') === false", timeout=10_000)
        self.wait_settled()
        return self

    def slider(self, key):
        """The thumb of the lesson's slider for a state key."""
        return self.page.locator(f".phonglab-control-{key}:not(.phonglab-control-all) [role=slider]").first

    def close(self):
        self.page.close()


@pytest.fixture
def app_page(browser, server):
    """A fresh tab on the app (its own session); fails on page errors or internet requests."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    page = Page(context.new_page(), server)
    try:
        yield page.open()
        assert not page.errors, f"JavaScript errors on the page: {page.errors}"
        assert not page.external, f"the page asked the internet for: {page.external}"
        assert server["process"].poll() is None, f"the server died:\n{log_tail(server['log'])}"
    finally:
        context.close()


@pytest.fixture
def new_tab(browser, server):
    """A factory for more tabs, each in its own browser context (own session)."""
    contexts = []

    def make():
        context = browser.new_context(viewport={"width": 1280, "height": 800})
        contexts.append(context)
        return Page(context.new_page(), server).open()

    yield make
    for context in contexts:
        context.close()


def pytest_collection_modifyitems(items):
    for item in items:
        if "tests/browser" in str(item.fspath).replace(os.sep, "/"):
            item.add_marker(pytest.mark.browser)

