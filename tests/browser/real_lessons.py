"""Tabs on the real lessons (``lessons/``), for the browser tests that look at them as a student does.

:func:`lesson_tab` is a tab (its own server session) on ``phonglab serve
lessons/``, with the page's pixels readable (:data:`~phonglab.bench.ui.LAZY_MEASURE_JS`); :func:`visit` opens
an address in it and waits until the view has drawn and stopped changing.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

from conftest import Page, new_page

from phonglab.bench.ui import LAZY_MEASURE_JS

LESSONS = Path(__file__).resolve().parents[2] / "lessons"


@contextlib.contextmanager
def lesson_tab(browser, serve_app, width: int = 1280, height: int = 800):
    """A tab (:class:`conftest.Page`) on the real lessons' server; on leaving, it fails on JavaScript errors."""
    tab = Page(new_page(browser, width=width, height=height), serve_app(LESSONS))
    tab.page.add_init_script(LAZY_MEASURE_JS)
    try:
        yield tab
        assert not tab.errors, f"JavaScript errors on the page: {tab.errors}"
    finally:
        tab.close()


def visit(tab, query: str) -> None:
    """Open ``?query`` (``lesson=04-specular&…``) in ``tab`` and wait until its view has drawn and settled."""
    tab.page.goto(f"{tab.server['url']}?{query}")
    drawn(tab)


#: true once no newer per-pixel picture is on its way and the one shown was made for the view's size (the
#: server follows the view's size once it is drawn: a picture, a camera and letters for it come after)
PICTURE_FITS = """() => {
  const state = window.trame && window.trame.state;
  if (!state || state.get('pixel_pending')) return false;
  if (!state.get('pixel_mode')) return true;
  const img = document.querySelector('.phonglab-pixel img'), view = document.querySelector('.phonglab-view');
  return !!(img && img.complete && view
            && img.naturalWidth === Math.min(1600, Math.round(view.getBoundingClientRect().width)));
}"""


def drawn(tab) -> None:
    """Wait until the page's view is there, has drawn, shows the picture for its size and has stopped changing."""
    tab.page.wait_for_selector(".phonglab-view canvas", timeout=90_000)
    tab.page.evaluate("() => { window.__phonglabBench.selector = '.phonglab-view canvas'; }")
    tab.page.wait_for_function(PICTURE_FITS, timeout=90_000)
    tab.wait_settled()
