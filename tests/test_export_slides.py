"""Exports fit for slides: text kept as text, clear polar labels, readable panels, no stray files."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

pytest.importorskip("vtk")

from phonglab.render import figure  # noqa: E402
from phonglab.render import plots  # noqa: E402
from phonglab.scene import load_lesson  # noqa: E402

LESSON = "lessons/04-specular.md"


@pytest.fixture(scope="module")
def specular_scene():
    return load_lesson(LESSON).scene


# ---------------------------------------------------------------------------
# text stays text


@pytest.mark.parametrize("kind", ["lobe", "lambert"])
def test_plot_svg_keeps_its_words_as_text_elements(tmp_path, kind):
    out = figure(LESSON, tmp_path / f"{kind}.svg", plot=kind, size=(900, 450))
    svg = out.read_text()
    texts = re.findall(r"<text\b[^>]*>(.*?)</text>", svg, flags=re.S)
    words = " ".join(texts)
    # the title, the axis labels and the tick labels are editable text, not outlined paths
    assert len(texts) >= 15, (kind, len(texts), texts[:5])
    assert "90°" in words, (kind, words[:300])


def test_plot_pdf_embeds_truetype_fonts_not_type3(tmp_path):
    out = figure(LESSON, tmp_path / "lobe.pdf", plot="lobe", size=(900, 450))
    data = out.read_bytes()
    assert b"/FontFile2" in data, "no embedded TrueType (Type 42) font in the PDF"
    assert b"/Type3" not in data, "Type 3 fonts draw text as outlines"


# ---------------------------------------------------------------------------
# the polar panel's labels


def _gap(a, b) -> float:
    """Pixels between two boxes (negative when they overlap)."""
    return max(b.x0 - a.x1, a.x0 - b.x1, b.y0 - a.y1, a.y0 - b.y1)


@pytest.mark.parametrize("kind", ["lobe", "lambert"])
@pytest.mark.parametrize("size", [(1200, 600), (800, 800), (640, 480), (600, 900)])
def test_polar_angle_labels_keep_clear_of_the_radius_labels(specular_scene, kind, size):
    import matplotlib.pyplot as plt

    fig = plots.make_plot(kind, specular_scene, size)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        polar = next(a for a in fig.axes if a.name == "polar")
        angles = [t for t in polar.get_xticklabels() if t.get_text() and t.get_visible()]
        radii = [t for t in polar.get_yticklabels() if t.get_text() and t.get_visible()]
        assert any("90" in t.get_text() for t in angles) and radii
        for a in angles:
            for r in radii:
                gap = _gap(a.get_window_extent(renderer), r.get_window_extent(renderer))
                assert gap >= 4, (kind, size, a.get_text(), r.get_text(), gap)
    finally:
        plt.close(fig)


def test_the_gap_check_catches_crowded_labels(specular_scene):
    """The same measure flags the labels when the angle labels sit on the rim (the old layout)."""
    import matplotlib.pyplot as plt

    fig = plots.make_plot("lobe", specular_scene, (800, 800))
    try:
        polar = next(a for a in fig.axes if a.name == "polar")
        polar.tick_params(axis="x", pad=0)
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        gaps = [_gap(a.get_window_extent(renderer), r.get_window_extent(renderer))
                for a in polar.get_xticklabels() if a.get_text()
                for r in polar.get_yticklabels() if r.get_text()]
        assert min(gaps) < 4, gaps
    finally:
        plt.close(fig)


# ---------------------------------------------------------------------------
# bench accuracy writes a figure only when asked

TINY = {
    "interpolation": {"resolutions": (8, 16), "size": 32, "repeats": 1, "min_seconds": 0.0},
    "precision": {"points": 8, "timed_points": 1000, "repeats": 1},
    "models": {"alphas": (10.0,), "size": 32, "timed_points": 1000, "repeats": 1},
    "area_light": {"samples": (1, 4, 16), "seeds": 2, "side": 4, "repeats": 1},
}


def test_bench_accuracy_without_figure_writes_no_file(tmp_path, capsys, monkeypatch):
    import phonglab.accuracy as acc
    from phonglab.cli import main

    monkeypatch.setattr(acc, "QUICK", {**acc.QUICK, **TINY})
    monkeypatch.chdir(tmp_path)
    assert main(["bench", "accuracy", "--quick", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["figure"] is None, data["figure"]
    assert list(tmp_path.iterdir()) == [], list(tmp_path.iterdir())
