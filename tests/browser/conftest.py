"""Fixtures for the browser tests: ``phonglab serve`` servers and headless Chromium.

``serve_app(target, *flags)`` starts a server for a lesson or folder on a free
127.0.0.1 port, in its own process group; a second call with the same target
and flags gets the same server, and every server it started is killed by PID
at the end of the session. ``server`` is the one most tests share: the test
lessons of :data:`phonglab.bench.scenes.LESSONS` (small meshes, known lights).
Chromium is Debian's ``/usr/bin/chromium`` driven by Playwright; if
it is missing the tests fail (they never skip) and say how to install it.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import os
from pathlib import Path

import pytest
from app_support import start_app

from phonglab.bench.scenes import write_lessons
from phonglab.bench.ui import (
    CHROMIUM,
    CHROMIUM_MISSING,
    LAZY_MEASURE_JS,
    launch_chromium,
    log_tail,
    stop_server,
)


@pytest.fixture(scope="session")
def lesson_dir(tmp_path_factory) -> Path:
    return write_lessons(tmp_path_factory.mktemp("lessons"))


@pytest.fixture(scope="session")
def export_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("exports")


@pytest.fixture(scope="session")
def serve_app(tmp_path_factory):
    """A factory: ``serve_app(target, *flags, timeout=60)`` is ``phonglab serve target *flags``, answering.

    It returns a dict with url, port, process and log path. The same target and
    flags give the same server (started once a session); all are stopped by PID
    when the session ends. A server that does not start fails the test with the
    end of its log.
    """
    started: dict[tuple, dict] = {}

    def serve(target, *flags, timeout: float = 60.0) -> dict:
        key = (os.fspath(target), tuple(str(f) for f in flags))
        if key not in started:
            log_path = tmp_path_factory.mktemp("server") / "serve.log"
            try:
                started[key] = start_app(target, *key[1], log_path=log_path, timeout=timeout)
            except RuntimeError as exc:
                pytest.fail(f"phonglab serve {' '.join((key[0], *key[1]))} did not start: {exc}", pytrace=False)
        return started[key]

    yield serve
    # all at once: each may take seconds to close its sessions, and the last test's teardown waits for them
    with concurrent.futures.ThreadPoolExecutor(max(1, len(started))) as pool:
        list(pool.map(stop_server, [running["process"] for running in started.values()]))


@pytest.fixture(scope="session")
def server(serve_app, lesson_dir, export_dir):
    """``phonglab serve`` of the test lessons; a dict with url, port, process and log path."""
    return serve_app(lesson_dir, "--export-dir", export_dir)


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium; fails (never skips) when it is not installed."""
    if not os.path.exists(CHROMIUM):
        pytest.fail(CHROMIUM_MISSING, pytrace=False)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        chromium = launch_chromium(playwright)
        yield chromium
        _CONTEXTS.pop(id(chromium), None)
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
        self.page.add_init_script(LAZY_MEASURE_JS)
        self.page.goto(self.server["url"])
        self.page.wait_for_selector(".phonglab-view canvas", timeout=60_000)
        self.page.evaluate("() => { window.__phonglabBench.selector = '.phonglab-view canvas'; }")
        self.wait_settled()
        return self

    def wait_settled(self, frames: int = 10):
        """Wait until the view has drawn something, and for ``frames`` frames neither changed nor heard the server.

        A view that has not changed for a while may still be waiting for the server's next update (a lesson's
        mesh on a loaded machine): a settled view is also one the server has said nothing to for as long.
        """
        self.page.wait_for_function(
            "(n) => { const b = window.__phonglabBench; return b.last !== 0 && b.stable >= n && b.quiet >= n; }",
            arg=frames, timeout=30_000,
        )

    def pixel_hash(self) -> int:
        return self.page.evaluate("() => window.__phonglabBench.hash()")

    def state(self, key):
        return self.page.evaluate("(k) => window.trame.state.get(k)", key)

    def set_state(self, key, value_js: str):
        """Set a state key from the browser, the way a client message would (value as JavaScript)."""
        self.page.evaluate(f"() => window.trame.state.set({key!r}, {value_js})")

    def pixel_image(self):
        """The per-pixel picture the page shows over the view (the server's PNG), as RGB ints."""
        import base64
        import io

        import numpy as np
        from PIL import Image

        src = self.page.locator(".phonglab-pixel img").get_attribute("src") or ""
        assert src.startswith("data:image/png;base64,"), src[:40]
        return np.asarray(Image.open(io.BytesIO(base64.b64decode(src.split(",", 1)[1]))).convert("RGB")).astype(int)

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
        assert raw["point"] and len(raw["dots"]) >= 3, f"no readout on the page: {raw}"  # Cook–Torrance shows 4
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
        self.page.wait_for_function("() => window.trame.state.get('drawer') === false", timeout=60_000)
        self.wait_settled()
        return self

    def slider(self, key):
        """The thumb of the lesson's slider for a state key."""
        return self.page.locator(f".phonglab-control-{key}:not(.phonglab-control-all) [role=slider]").first

    def close(self):
        self.page.close()


#: one browser context a worker, which the tabs share as a student's tabs share one browser: its cache keeps
#: the page's 3 MB of scripts compiled (a tab then costs Chromium about half the CPU time of a tab in a
#: context of its own). A session is a tab's own websocket, so tabs in one context are separate sessions.
_CONTEXTS: dict[int, object] = {}


def new_page(browser, *, width: int = 1280, height: int = 800):
    """A new Playwright page (a tab, its own session) of ``browser``'s shared context, at ``width`` × ``height``."""
    context = _CONTEXTS.get(id(browser))
    if context is None:
        context = _CONTEXTS[id(browser)] = browser.new_context(viewport={"width": 1280, "height": 800})
    page = context.new_page()
    page.set_viewport_size({"width": width, "height": height})
    return page


@contextlib.contextmanager
def open_tab(browser, server, *, width: int = 1280, height: int = 800):
    """A fresh tab on ``server`` (its own session), opened.

    On leaving the block without an error, it fails on JavaScript errors, requests
    to the internet or a server that died (with the end of the server's log).
    """
    page = Page(new_page(browser, width=width, height=height), server)
    try:
        yield page.open()
        assert not page.errors, f"JavaScript errors on the page: {page.errors}"
        assert not page.external, f"the page asked the internet for: {page.external}"
        assert server["process"].poll() is None, f"the server died:\n{log_tail(server['log'])}"
    finally:
        page.close()


@pytest.fixture
def app_page(browser, server):
    """A fresh tab on the app (its own session); fails on page errors or internet requests."""
    with open_tab(browser, server) as page:
        yield page


@pytest.fixture
def new_tab(browser, server):
    """A factory for more tabs, each its own session."""
    pages = []

    def make():
        pages.append(Page(new_page(browser), server))
        return pages[-1].open()

    yield make
    for page in pages:
        page.close()


def pytest_collection_modifyitems(items):
    for item in items:
        if "tests/browser" in str(item.fspath).replace(os.sep, "/"):
            item.add_marker(pytest.mark.browser)

