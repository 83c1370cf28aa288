"""Fixtures for the browser tests: a ``phonglab serve`` server and headless Chromium.

The server runs the test lessons written below (small meshes, known lights)
on a free 127.0.0.1 port, in its own process group, and is killed by PID at
the end. Chromium is Debian's ``/usr/bin/chromium`` driven by Playwright; if
it is missing the tests fail (they never skip) and say how to install it.
"""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

import pytest

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

#: the lessons the browser tests run against: (file name, text)
LESSONS = {
    "01-sphere.md": """
        +++
        number = 1
        title = "A red sphere"
        goal = "Watch $k_s$ and $\\\\alpha$ shape the highlight."
        controls = ["material.ks", "material.shininess", "lights[1].position", "interpolation"]
        question = "Where is $n\\\\cdot l$ largest?"
        answer = "Where the normal points at the light: $n = l$."
        probe = [0.3, 0.4, 0.866]

        [geometry]
        kind = "sphere"
        resolution = 48

        [material]
        ka = 0.1
        kd = [0.8, 0.3, 0.2]
        ks = 0.6
        shininess = 20

        [[lights]]
        type = "ambient"
        intensity = 0.2

        [[lights]]
        type = "point"
        position = [2, 2.5, 3]

        [camera]
        eye = [0, 0, 4]

        [[experiments]]
        label = "Matte"
        text = "Set $k_s = 0$."
        set = {"material.ks" = 0}
        +++

        # A red sphere

        The diffuse term is $k_d I_d \\max(0, n\\cdot l)$ and the specular one

        $$k_s I_s \\max(0, r\\cdot v)^{\\alpha}.$$

        Costs \\$0.
        """,
    "02-spot.md": """
        +++
        number = 2
        title = "A spotlight on a floor"
        goal = "Open and close the cone."
        controls = ["lights[1].cutoff", "lights[1].exponent"]

        [geometry]
        kind = "plane"
        resolution = 24

        [material]
        ka = 0.1
        kd = 0.8
        ks = 0.2
        shininess = 10

        [[lights]]
        type = "ambient"
        intensity = 0.1

        [[lights]]
        type = "spot"
        position = [0, 0, 2]
        direction = [0, 0, -1]
        cutoff = 25
        exponent = 4

        [camera]
        eye = [0, -3, 3]
        up = [0, 0, 1]
        +++

        # A spotlight on a floor

        The spot factor is $\\cos^e\\theta$ inside the cone. With attenuation,

        $$I = \\frac{\\cos^e\\theta}{a + b\\,d + c\\,d^2} \\left[k_d I_d \\max(0, n\\cdot l) + k_s I_s (r\\cdot v)^{\\alpha}\\right],$$

        and the light a point receives from the whole hemisphere is

        $$L_o(\\mathbf{x}, \\omega_o) = L_e(\\mathbf{x}, \\omega_o) + \\int_{\\Omega} f_r(\\mathbf{x}, \\omega_i, \\omega_o)\\, L_i(\\mathbf{x}, \\omega_i)\\, (\\omega_i \\cdot \\mathbf{n})\\, d\\omega_i + \\sum_{j=1}^{N} \\frac{\\Phi_j \\cos\\theta_j}{4\\pi d_j^2}.$$

        The cone's edge is at $\\theta = $ cutoff.
        """,
    "03-broken.md": """
        +++
        number = 3
        title = "A broken lesson"
        controls = ["material.kd"]

        [geometry]
        kind = "sphere"

        [material]
        ka = 0.1
        kd = -3
        ks = 0.5
        shininess = 40

        [[lights]]
        type = "point"
        position = [2, 2, 2]
        +++

        # A broken lesson
        """,
    "04-raw-normals.md": """
        +++
        number = 4
        title = "Normals left unnormalised"
        controls = ["interpolation"]
        mistake = "unnormalised-normals"
        interpolation = "pixel"

        [geometry]
        kind = "sphere"
        resolution = 10

        [material]
        ka = 0.1
        kd = [0.8, 0.3, 0.2]
        ks = 0.8
        shininess = 60

        [[lights]]
        type = "ambient"
        intensity = 0.15

        [[lights]]
        type = "point"
        position = [2, 2.5, 3]

        [camera]
        eye = [0, 0, 4]
        +++

        # Normals left unnormalised

        Per pixel, the blended normal must be normalised again.
        """,
    "05-unclamped.md": """
        +++
        number = 5
        title = "Diffuse without the clamp"
        controls = ["material.kd"]
        mistake = "no-clamp-diffuse"

        [geometry]
        kind = "sphere"
        resolution = 32

        [material]
        ka = 0.6
        kd = 0.8
        ks = 0
        shininess = 10

        [[lights]]
        type = "ambient"
        intensity = 0.3

        [[lights]]
        type = "point"
        position = [-2.5, 2.0, 1.0]

        [camera]
        eye = [0, 0, 4]
        +++

        # Diffuse without the clamp

        Where $n\\cdot l < 0$ the diffuse term must be zero, not negative.
        """,
    "11-accuracy.md": """
        +++
        number = 11
        title = "Accuracy costs time"
        controls = ["interpolation", "geometry.resolution", "material.shininess"]
        interpolation = "gouraud"

        [geometry]
        kind = "sphere"
        resolution = 16

        [material]
        ka = 0.1
        kd = [0.8, 0.3, 0.2]
        ks = 0.8
        shininess = 200

        [[lights]]
        type = "ambient"
        intensity = 0.2

        [[lights]]
        type = "point"
        position = [2, 2.5, 3]

        [camera]
        eye = [0, 0, 4]
        +++

        # Accuracy costs time

        Pick a method and a mesh; compare with the exact sphere.
        """,
}


@pytest.fixture(scope="session")
def lesson_dir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("lessons")
    for name, text in LESSONS.items():
        (folder / name).write_text(textwrap.dedent(text).lstrip(), encoding="utf-8")
    return folder


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

