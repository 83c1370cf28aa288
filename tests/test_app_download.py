"""Exports from the page: PNG bytes for the browser, a server copy only when asked."""

from __future__ import annotations

import base64
import io

import pytest

pytest.importorskip("vtk")

from phonglab.app import download  # noqa: E402
from phonglab.scene import load_lesson  # noqa: E402


def _png_size(data: bytes):
    from PIL import Image

    assert data[:8] == b"\x89PNG\r\n\x1a\n", data[:16]
    with Image.open(io.BytesIO(data)) as img:
        return img.size


def test_terms_figure_bytes_and_data_url():
    scene = load_lesson("lessons/04-specular.md").scene
    data = download.render_png(scene, "terms")
    assert _png_size(data) == (1200, 900)
    url = download.data_url(data)
    assert url.startswith("data:image/png;base64,") and base64.b64decode(url.split(",", 1)[1]) == data


def test_mistake_comparison_needs_a_mistake_and_unknown_kinds_are_refused():
    from phonglab.render import FigureError

    scene = load_lesson("lessons/04-specular.md").scene
    with pytest.raises(FigureError, match="compare"):
        download.render_png(scene, "mistake", None)
    with pytest.raises(ValueError, match="render, terms, mistake"):
        download.render_png(scene, "gif")


def test_file_names_carry_the_kind():
    assert download.file_name("lesson-04", "terms", 0).startswith("lesson-04-terms-")
    assert download.file_name("lesson-04", "render", 0).endswith(".png")


# ---------------------------------------------------------------------------
# "preparing…" while an export is made


def two_step_figure(scene, kind, mistake, shown_mistake):
    """Stands in for the render job in a worker: two views, each reported, seconds apart."""
    import time

    from phonglab.app.worker import report

    for step in (1, 2):
        report(step, 2, f"view {step}")
        time.sleep(2.5)
    return b"\x89PNG\r\n\x1a\n-not-really"


class RecordedState(dict):
    """Enough of a trame state for Exports: keys, a ``with`` block, and every value each key was given."""

    def __init__(self):
        super().__init__()
        self.history = {}

    def __setitem__(self, key, value):
        self.history.setdefault(key, []).append(value)
        super().__setitem__(key, value)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return None


def test_the_page_says_preparing_with_the_steps_while_an_export_is_made(monkeypatch):
    import asyncio

    from phonglab.app import worker

    monkeypatch.setattr(download, "_render_job", two_step_figure)
    state, notices = RecordedState(), []
    exports = download.Exports(state, lambda kind, text: notices.append((kind, text)))

    async def scenario():
        exports.start("scene", "render", "lesson-01")
        for _ in range(1200):  # the workers start (not warmed up here), then the two steps
            if not exports.job.busy:
                break
            await asyncio.sleep(0.1)

    try:
        asyncio.run(scenario())
    finally:
        worker.shutdown()
    said = [text for text in state.history[download.PROGRESS_KEY] if text]
    assert said and all(text.startswith("Preparing… ") for text in said), said
    assert any("view 1 of 2" in text for text in said) and any("view 2 of 2" in text for text in said), said
    assert state[download.PROGRESS_KEY] == "", "the progress stayed after the download"
    assert state[download.STATE_KEY]["name"].startswith("lesson-01-"), (state.get(download.STATE_KEY), notices)


@pytest.mark.parametrize("progress, ready, words", [
    (None, 0, "starting the figure workers (0 of 2 ready)"),
    (None, 2, "waiting for a free figure worker"),
    ((0, 0, ""), 2, "rendering"),
    ((3, 4, "specular"), 2, "view 3 of 4"),
])
def test_progress_names_what_the_export_waits_for(progress, ready, words):
    text = download.progress_text(progress, ready, 2, 12.4)
    assert text == f"Preparing… {words}, 12 s", text
