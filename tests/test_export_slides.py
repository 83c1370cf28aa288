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


# ---------------------------------------------------------------------------
# --vectors none: a clean picture, no light markers over the surface


def _directional_scene():
    import phonglab as pl
    from phonglab.scene import Camera, Geometry, Scene

    return Scene(geometry=Geometry("sphere", 24),
                 material=pl.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.5, shininess=30),
                 lights=(pl.AmbientLight(intensity=0.2), pl.DirectionalLight(direction=(0.3, 0.4, 1.0))),
                 camera=Camera(eye=(0.0, 0.0, 5.0)), probe=(0.35, 0.45, 0.82), title="directional")


def _view_image(scene, size, *, markers):
    from phonglab.render import figures

    view = figures.SceneView(scene, size=(size[0] * 2, size[1] * 2), vectors="", vtk_text=False, markers=markers)
    try:
        return figures.downsample(view.annotate(view.screenshot(annotate=False), legend=True), 2)
    finally:
        view.close()


def test_no_vectors_means_no_directional_marker_over_the_surface():
    from phonglab.render import figures

    scene, size = _directional_scene(), (200, 150)
    image = figures.render(scene, size, vectors=None).astype(int)
    with_markers = _view_image(scene, size, markers=True).astype(int)
    without = _view_image(scene, size, markers=False).astype(int)
    # the marker shows in this scene (so the check can fail) ...
    assert (np.abs(with_markers - without).max(axis=-1) > 16).sum() > 50
    # ... and the render without vectors is the picture without it
    off = (np.abs(image - without).max(axis=-1) > 16).sum()
    assert off == 0, f"{off} pixels differ from the marker-free render"


# ---------------------------------------------------------------------------
# the terms figure: labels above the renders, every panel readable


def _record_terms(monkeypatch, tmp_path, source, size, **options):
    from phonglab.render import figures

    placed, labels = [], []
    real_place, real_labels = figures.place, figures.cell_labels

    def place(fig, image, box, fig_size):
        placed.append((image, box))
        return real_place(fig, image, box, fig_size)

    def cell_labels(*args, **kwargs):
        boxes = real_labels(*args, **kwargs)
        labels.extend(boxes)
        return boxes

    monkeypatch.setattr(figures, "place", place)
    monkeypatch.setattr(figures, "cell_labels", cell_labels)
    out = figure(source, tmp_path / "terms.png", size=size, terms=True, **options)
    return out, placed, labels


@pytest.mark.parametrize("size", [(800, 700), (1200, 400), (480, 360)])
def test_terms_labels_sit_above_the_renders_and_every_panel_reads(monkeypatch, tmp_path, size):
    from phonglab.render.layout import MIN_CONTRAST, subject_contrast

    out, placed, labels = _record_terms(monkeypatch, tmp_path, LESSON, size)
    assert len(placed) == len(labels) == 4, (size, len(placed), len(labels))
    for (image, (x, y, w, h)), (lx0, ly0, lx1, ly1) in zip(placed, labels):
        # the label's box ends above the render it names, inside the same column
        assert ly1 <= y + 0.5 and x - 1 <= lx0 and lx1 <= x + w + 1, (size, (x, y, w, h), (lx0, ly0, lx1, ly1))
        background = image[-1, 0] / 255.0  # a corner of the render is background
        contrast = subject_contrast(image, background)
        assert contrast >= MIN_CONTRAST, (size, (x, y), tuple(image[-1, 0]), contrast)


def test_the_contrast_check_fails_the_ambient_panel_on_the_dark_background(specular_scene):
    """Lesson 4's ambient panel (dark navy) on the renders' dark grey: the reason for the rule."""
    from phonglab.render import figures
    from phonglab.render.layout import MIN_CONTRAST, subject_contrast

    image = figures.render(specular_scene, (160, 120), vectors=None, term="ambient", legend=False)
    contrast = subject_contrast(image, figures.BACKGROUND)
    assert contrast < MIN_CONTRAST, contrast
    light = figures.render(specular_scene, (160, 120), vectors=None, term="ambient", legend=False,
                           background=figures.PAPER)
    assert subject_contrast(light, figures.PAPER) >= MIN_CONTRAST


def test_contrast_ratio_matches_wcag():
    from phonglab.render.layout import contrast_ratio, relative_luminance

    white, black = relative_luminance([1.0, 1.0, 1.0]), relative_luminance([0.0, 0.0, 0.0])
    assert white == pytest.approx(1.0) and black == 0.0
    assert contrast_ratio(white, black) == pytest.approx(21.0)
    # #777777 on white is the classic 4.48:1
    grey = relative_luminance([0x77 / 255] * 3)
    assert contrast_ratio(grey, white) == pytest.approx(4.48, abs=0.01)
