"""phonglab.render.figures: single renders, per-term views, sweeps, plots, formats and option checks."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("vtk")

from phonglab.render import FigureError, figure, render  # noqa: E402
from phonglab.render.layout import grid_layout  # noqa: E402
from phonglab.render.options import parse_size, parse_sweep, split_values  # noqa: E402
from phonglab.render.plots import half_width  # noqa: E402
from phonglab.bench import scenes  # noqa: E402
from phonglab.scene import Camera, Scene, SceneError  # noqa: E402

SMALL = (200, 150)


def scene(**changes) -> Scene:
    # the shared red sphere, seen from a little further away
    s = scenes.red_sphere(16, camera=Camera(eye=(0.0, 0.0, 5.0)), probe=(0.35, 0.45, 0.82), title="Test sphere")
    for path, value in changes.items():
        s = s.replace(path, value)
    return s


def read_png(path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as img:
        return np.asarray(img.convert("RGB"))


def test_single_render_png_has_the_requested_size(tmp_path):
    out = figure(scene(), tmp_path / "one.png", size=SMALL)
    image = read_png(out)
    assert image.shape == (150, 200, 3), image.shape
    assert [p.name for p in tmp_path.iterdir()] == ["one.png"], "temporary files left behind"


@pytest.mark.parametrize("ext, magic", [(".svg", b"<?xml"), (".pdf", b"%PDF")])
def test_vector_formats_embed_the_render(tmp_path, ext, magic):
    out = figure(scene(), tmp_path / f"one{ext}", size=SMALL)
    head = out.read_bytes()[:16]
    assert head.startswith(magic), f"{out.name} starts with {head!r}"


def test_settings_change_the_scene_before_rendering():
    # the blue channel: the red diffuse colour barely has any, a white highlight does
    dull = render(scene(**{"material.ks": 0.0, "interpolation": "pixel"}), SMALL, vectors=None)[..., 2]
    shiny = render(scene(**{"material.ks": 1.0, "interpolation": "pixel"}), SMALL, vectors=None)[..., 2]
    assert shiny.max() > dull.max() + 100, f"blue max {dull.max()} without specular, {shiny.max()} with"


def test_settings_given_as_text_are_parsed_like_toml(tmp_path):
    a = figure(scene(), tmp_path / "a.png", size=SMALL, vectors=None, settings=["material.shininess=4"])
    b = figure(scene(), tmp_path / "b.png", size=SMALL, vectors=None, settings={"material.shininess": 4})
    assert np.array_equal(read_png(a), read_png(b))


def test_vectors_default_to_all_on_a_single_render():
    plain = render(scene(), SMALL, vectors=None)
    arrows = render(scene(), SMALL, vectors="NLRVH")
    changed = np.any(plain != arrows, axis=-1).mean()
    assert changed > 0.01, f"only {changed:.2%} of pixels changed with the arrows on"


def test_sweep_grid_renders_every_cell_with_progress(tmp_path):
    calls = []
    size = (300, 260)
    out = figure(scene(), tmp_path / "grid.png", size=size,
                 sweep=["material.ks=0.0,0.9", ("material.shininess", [4, 128])],
                 progress=lambda done, total, label: calls.append((done, total, label)))
    assert [c[:2] for c in calls] == [(1, 4), (2, 4), (3, 4), (4, 4)], calls
    assert calls[0][2] == "material.ks=0, material.shininess=4", calls[0][2]
    image = read_png(out)
    boxes, _ = grid_layout(size, 2, 2, title=True, row_labels=True, col_labels=True)
    cells = [image[y:y + h, x:x + w] for row in boxes for (x, y, w, h) in row]
    # ks = 0: no highlight, the shininess makes no difference; ks = 0.9: it does
    assert np.array_equal(cells[0], cells[1]), "ks = 0 cells differ although specular is off"
    assert not np.array_equal(cells[2], cells[3]), "ks = 0.9 cells look the same for alpha 4 and 128"
    assert cells[2].max() > cells[0].max(), "the ks = 0.9 row is not brighter"


def test_one_sweep_is_a_row(tmp_path):
    calls = []
    figure(scene(), tmp_path / "row.png", size=(300, 120), sweep="interpolation=flat,gouraud,pixel",
           progress=lambda *a: calls.append(a))
    assert [c[2] for c in calls] == ["interpolation=flat", "interpolation=gouraud", "interpolation=pixel"]


def test_terms_figure_is_written(tmp_path):
    out = figure(scene(), tmp_path / "terms.png", size=(400, 300), terms=True)
    assert read_png(out).shape == (300, 400, 3)


@pytest.mark.parametrize(
    "changes, expected",
    [({}, "0.02"),  # k_a = 0.1 under an ambient light of intensity 0.2
     ({"material.ka": [0.3, 0.1, 0.05]}, "(0.06, 0.02, 0.01)"),
     ({"lights[0].intensity": 0.0}, "0")],
)
def test_ambient_panel_label_states_ka_ia(changes, expected):
    import matplotlib.pyplot as plt

    from phonglab.render import figures
    from phonglab.render.captions import ambient_value

    s = scene(**changes)
    assert ambient_value(s) == expected, f"{changes}: {ambient_value(s)!r}"
    fig = figures._terms_figure(s, (240, 180), "", 1, figures.BACKGROUND, None)
    try:
        labels = [t.get_text() for t in fig.texts]
    finally:
        plt.close(fig)
    ambient = [t for t in labels if t.startswith("ambient")]
    assert len(ambient) == 1 and ambient[0].endswith(f"= {expected}"), f"{changes}: labels {labels}"


@pytest.mark.parametrize("kind", ["lobe", "lambert", "incidence"])
@pytest.mark.parametrize("ext", [".png", ".svg", ".pdf"])
def test_plots_in_every_format(tmp_path, kind, ext):
    out = figure(scene(), tmp_path / f"{kind}{ext}", size=(600, 400), plot=kind)
    data = out.read_bytes()
    assert len(data) > 1000, f"{out.name}: {len(data)} bytes"
    if ext == ".png":
        assert read_png(out).shape == (400, 600, 3)


def content_boxes(fig):
    """Window extents (pixels) of every drawn text and axes area of a figure."""
    from matplotlib.text import Text

    renderer = fig.canvas.get_renderer()
    fig.draw(renderer)
    # tick labels: only those of ticks inside the axis' view (the others are not drawn)
    tick_labels, drawn_ticks = set(), []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                tick_labels.update({id(tick.label1), id(tick.label2)})
                if lo - 1e-9 <= tick.get_loc() <= hi + 1e-9:
                    drawn_ticks += [label for label in (tick.label1, tick.label2) if label.get_visible()]
    boxes = []
    texts = [t for t in fig.findobj(Text) if id(t) not in tick_labels] + drawn_ticks
    for artist in texts:
        if artist.get_visible() and artist.get_text().strip():
            patch = artist.get_bbox_patch()
            box = patch.get_window_extent(renderer) if patch is not None else artist.get_window_extent(renderer)
            boxes.append((artist.get_text()[:40], box))
    for ax in fig.axes:
        # the drawn area (a polar half disc is drawn in the middle of its square axes)
        boxes.append((f"axes {ax.name} {ax.get_title()[:30]!r}", ax.patch.get_window_extent(renderer)))
    return boxes


@pytest.mark.parametrize("kind", ["lobe", "lambert", "incidence"])
@pytest.mark.parametrize("size", [(1200, 900), (800, 600), (1600, 600), (600, 900), (400, 300)])
def test_plots_keep_their_text_inside_and_use_the_height(kind, size):
    import matplotlib.pyplot as plt

    from phonglab.render.plots import make_plot

    fig = make_plot(kind, scene(), size)
    try:
        boxes = content_boxes(fig)
    finally:
        plt.close(fig)
    width, height = size
    margin = 2.0  # pixels of white at least between any text and the figure's edge
    for name, box in boxes:
        inside = (box.x0 >= margin and box.y0 >= margin
                  and box.x1 <= width - margin and box.y1 <= height - margin)
        assert inside, f"{kind} at {size}: {name!r} spans x {box.x0:.1f}..{box.x1:.1f}, y {box.y0:.1f}..{box.y1:.1f}"
    # no empty band at the bottom: something reaches into the lowest sixth
    lowest = min(box.y0 for _, box in boxes)
    assert lowest < height / 6, f"{kind} at {size}: nothing below y = {lowest:.0f} px of {height}"


def test_incidence_plot_needs_a_directed_light(tmp_path):
    ambient_only = scene().replace("lights", [{"type": "ambient", "intensity": 0.5}])
    with pytest.raises(FigureError, match="incidence"):
        figure(ambient_only, tmp_path / "x.png", plot="incidence")
    assert list(tmp_path.iterdir()) == []


def test_lesson_file_is_rendered_from_its_scene(tmp_path):
    lesson = tmp_path / "01-test.md"
    lesson.write_text(
        '+++\ntitle = "Test lesson"\ngoal = "see"\n[geometry]\nkind = "sphere"\nresolution = 12\n'
        "[material]\nka = 0.1\nkd = 0.5\nks = 0.5\nshininess = 20\n"
        '[[lights]]\ntype = "point"\nposition = [2, 2, 3]\n[camera]\neye = [0, 0, 4]\n+++\n# Test lesson\n\nText.\n'
    )
    out = figure(str(lesson), tmp_path / "lesson.png", size=SMALL)
    assert read_png(out).shape == (150, 200, 3)


@pytest.mark.parametrize("kwargs, message", [
    ({"sweep": ["material.ks=1", "material.kd=1", "material.ka=1"]}, "at most two"),
    ({"terms": True, "sweep": "material.ks=1,2"}, "cannot be combined"),
    ({"plot": "lobe", "terms": True}, "cannot be combined"),
    ({"plot": "spiral"}, "spiral"),
    ({"vectors": "NX"}, "X"),
    ({"size": (5, 5)}, "16 to 8192"),
])
def test_bad_options_raise_before_rendering(tmp_path, kwargs, message):
    with pytest.raises(FigureError, match=message):
        figure(scene(), tmp_path / "bad.png", **kwargs)
    assert list(tmp_path.iterdir()) == [], f"{kwargs} left {list(tmp_path.iterdir())}"


def test_bad_setting_raises_scene_error_naming_the_path(tmp_path):
    with pytest.raises(SceneError, match="material.shininess"):
        figure(scene(), tmp_path / "bad.png", settings=[("material.shininess", -3)])
    with pytest.raises(SceneError, match="material.ks"):
        figure(scene(), tmp_path / "bad.png", sweep="material.ks=0.5,banana")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text, expected", [("1200x900", (1200, 900)), ("16X16", (16, 16)), ((640, 480), (640, 480))])
def test_parse_size_accepts(text, expected):
    assert parse_size(text) == expected


@pytest.mark.parametrize("text", ["1200", "x900", "12.5x9", "-4x5", "abcxdef", "9000x100", "0x0", (1, 2, 3)])
def test_parse_size_refuses(text):
    with pytest.raises(FigureError, match="size"):
        parse_size(text)


def test_sweep_values_split_outside_brackets():
    assert split_values("0.1, 0.5,0.9") == ["0.1", "0.5", "0.9"]
    assert split_values("[1,2,3],[4,5,6]") == ["[1,2,3]", "[4,5,6]"]
    assert parse_sweep("lights[1].position=[1,2,3],[0,0,3]") == ("lights[1].position", [[1, 2, 3], [0, 0, 3]])
    assert parse_sweep("model=phong,blinn-phong") == ("model", ["phong", "blinn-phong"])
    with pytest.raises(FigureError, match="comma-separated"):
        parse_sweep("material.ks=0.1,,0.3")


@pytest.mark.parametrize("alpha", [1, 4, 40, 256])
def test_half_width_is_where_the_lobe_halves(alpha):
    phi = math.radians(half_width(alpha))
    assert abs(math.cos(phi) ** alpha - 0.5) < 1e-12, f"alpha {alpha}: cos^a at {half_width(alpha)}°"


@pytest.mark.parametrize("lit", [True, False])
def test_the_incidence_plot_says_when_the_probe_is_in_the_lights_shadow(lit):
    """Lesson 14's probe lies in the ball's shadow; the plot gave n·l and the specular factor as if it were lit."""
    import matplotlib.pyplot as plt

    from phonglab.render.plots import make_plot
    from phonglab.scene import load

    shadowed = load(Path(__file__).resolve().parents[1] / "lessons" / "14-shadows.md").scene
    fig = make_plot("incidence", shadowed if not lit else shadowed.replace("shadows", False), (1200, 900))
    try:
        text = " ".join(t.get_text() for t in fig.texts)
    finally:
        plt.close(fig)
    said = "in shadow" in text and "adds\nno diffuse or specular light" in text
    assert said != lit, f"shadows {'off' if lit else 'on'}: the plot's text is {text!r}"


@pytest.mark.parametrize("path, value, label", [
    ("material.ks", 0.5, "$k_s$ = 0.5"),
    ("material.shininess", 32, r"$\alpha$ = 32"),
    ("material.roughness", 0.1, "roughness = 0.1"),
    ("lights[1].intensity", 0.5, "light 1 intensity = 0.5"),
    ("shadow_bias", 0.01, "shadow bias = 0.01"),
    ("interpolation", "pixel", "pixel"),
])
def test_a_sweeps_labels_name_fields_in_words_not_paths(path, value, label):
    """A roughness series was headed "material.roughness = 0.1" while k_s and α got their symbols."""
    from phonglab.render.captions import sweep_label

    assert sweep_label(path, value) == label, (path, value)
