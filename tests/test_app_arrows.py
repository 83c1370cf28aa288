"""The arrows at the probe can be hidden, to see the surface under them, and shown again.

Lesson 13's "Smooth" and "Gold" ask about a highlight that lies under the
arrows and the V marker at the probe: the view's "arrows" switch takes the
arrows out of the browser's scene, the per-pixel picture, the letters and the
legend, and the address keeps the choice.
"""

from __future__ import annotations

import base64
import io
from pathlib import Path

import numpy as np

from app_support import open_app
from phonglab.app import address

LESSON = Path(__file__).resolve().parents[1] / "lessons" / "13-physically-based.md"
KEY = "view__arrows_hidden"


def _picture(app) -> np.ndarray:
    from PIL import Image

    url = app.state.pixel_src
    assert url.startswith("data:image/png;base64,"), url[:40]
    return np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB"))


def _letters(app) -> tuple[list, list]:
    return [v["letter"] for v in app.state.legend], [t["letter"] for t in app.state.arrow_tips]


def test_hiding_the_arrows_takes_them_from_the_scene_the_picture_and_the_legend_and_showing_brings_them_back(
        tmp_path, monkeypatch):
    app = open_app(tmp_path, LESSON.name, LESSON.read_text(encoding="utf-8"), "arrows")
    try:
        app._later.run_waiting()
        assert app.state.pixel_mode, "lesson 13 is shaded per pixel"
        scene, legend, tips = app.scene, *_letters(app)
        with_arrows = _picture(app)
        assert legend and tips, (legend, tips)
        synced = []
        monkeypatch.setattr(app.html_view, "update", lambda *a, **k: synced.append(True))

        app._on_control(KEY, True)
        app._later.run_waiting()
        assert app.scene == scene, "hiding the arrows changed the scene"
        assert app.view.arrow_tips() == [] and _letters(app) == ([], []), (app.view.arrow_tips(), _letters(app))
        assert synced, "the browser's copy of the scene was not sent again: its arrows would stay"
        without = _picture(app)
        differ = np.argwhere(np.any(without != with_arrows, axis=-1))
        assert len(differ), "the per-pixel picture still shows the arrows"
        query = app.state[address.QUERY_KEY]
        assert "view.arrows_hidden=" in query, query
        # the address opens the view with the arrows hidden (a link a teacher hands out)
        app.open_lesson(0)
        assert _letters(app) == (legend, tips), "a lesson opened again should show its arrows"
        app.state[address.REQUEST_KEY] = query
        app._on_address()
        app._later.run_waiting()
        assert app.state.notice is None, (query, app.state.notice)
        assert _letters(app) == ([], []) and np.array_equal(_picture(app), without), (query, _letters(app))

        app._on_control(KEY, False)
        app._later.run_waiting()
        assert _letters(app) == (legend, tips), (_letters(app), legend, tips)
        again = _picture(app)
        assert np.array_equal(again, with_arrows), (
            f"{int(np.any(again != with_arrows, axis=-1).sum())} pixels differ from the picture before the arrows hid")
        assert "arrows_hidden" not in app.state[address.QUERY_KEY], app.state[address.QUERY_KEY]
    finally:
        app.close()
