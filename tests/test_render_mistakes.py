"""Common mistakes rendered through the render code: figure(), SceneView.set_mistake, shading.

Each mistake is shown on a scene built so that its bug bites in part of the
picture. The checks are physical: the mistaken picture must differ from the
correct one exactly where the bug bites (worked out per pixel from the
G-buffer, per vertex or per face from the mesh) and agree elsewhere.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("vtk")

import phonglab as pl  # noqa: E402
from phonglab.render import figures, glyphs, options, shading  # noqa: E402
from phonglab.render import FigureError, figure  # noqa: E402
from phonglab.render.mesh import face_centroids_normals  # noqa: E402
from phonglab.render.view import SceneView  # noqa: E402
from phonglab.scene import Camera, Geometry, Scene  # noqa: E402
from phonglab.teaching import MISTAKES  # noqa: E402

#: size of a comparison figure: two cells of about 160 x 110 pixels under the band
COMPARE_SIZE = (340, 190)


def base(**fields) -> Scene:
    values = dict(
        geometry=Geometry("sphere", 24),
        material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=30),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(2, 2.5, 3))),
        camera=Camera(eye=(0.0, 0.0, 5.0)),
        interpolation="pixel",
        title="Mistake test",
    )
    values.update(fields)
    return Scene(**values)


#: per mistake, a scene where its bug bites in part of the picture
SCENES = {
    # a light from the side: half the visible sphere has n·l < 0, lit by the ambient light only
    "no-clamp-diffuse": base(
        material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.0, shininess=30),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(-3, 1, 1))),
    ),
    # a sheet seen from its back, the lamp behind the viewer (out of the picture): n·l < 0 everywhere, yet r·v > 0
    "ungated-specular": base(
        geometry=Geometry("plane", 16),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(1.5, 1.2, -6.0))),
        camera=Camera(eye=(0.5, 0.4, -3.5)),
    ),
    # a coarse sphere with a tight highlight: the raw interpolated normals are up to 7% short
    "unnormalised-normals": base(
        geometry=Geometry("sphere", 12),
        material=pl.Material(ka=0.2, kd=(0.8, 0.2, 0.15), ks=0.8, shininess=100),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(2.8, 2.7, 4.45))),
    ),
    # a plastic sphere: α = 0 puts k_s I_s on every lit point
    "zero-shininess": base(),
    # the same sphere at α = 0: 0 ** 0 = 1 lights the lit points where r·v < 0 too
    "zero-to-the-zero": base(material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=0)),
    # the lamp near the eye, a broad highlight (α = 4): −r·v lights the rim instead of the middle
    "reflect-wrong-way": base(
        material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=4),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(0.5, 0.5, 5))),
    ),
    "view-from-eye": base(
        material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=4),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(0.5, 0.5, 5))),
    ),
    # the same with an even α = 2: (r·v)² > 0 at the rim, where r·v < 0
    "power-before-max": base(
        material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=2),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(0.5, 0.5, 5))),
    ),
    # a dim lamp about 4 units away: n·l four times too large on the lit side
    "unnormalised-light": base(
        material=pl.Material(ka=0.3, kd=(0.3, 0.1, 0.1), ks=0.0, shininess=30),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(2, 2.5, 3), intensity=0.3)),
    ),
    # the eye 5 units away and α = 4: the highlight 5⁴ times too bright
    "unnormalised-view": base(material=pl.Material(ka=0.3, kd=(0.8, 0.3, 0.2), ks=0.02, shininess=4)),
    # an inverse-square lamp: the ambient floor of the dark side fades with the distance to it
    "attenuated-ambient": base(
        material=pl.Material(ka=0.6, kd=(0.8, 0.3, 0.2), ks=0.6, shininess=30),
        lights=(pl.AmbientLight(intensity=0.4), pl.PointLight(position=(2, 2.5, 3), attenuation=(0, 0, 0.08))),
    ),
    # a 30° spot straight down on the sphere: nothing inside its cone passes "cos >= 30"
    "spot-cutoff-in-degrees": base(
        lights=(pl.AmbientLight(intensity=0.4),
                pl.SpotLight(position=(0.5, 3, 3), direction=(-0.5, -3, -3), cutoff=25, exponent=1)),
    ),
}

#: the lamp's distance and the spot cone, for the mistakes that use them
def lamp_terms(scene, points):
    lamp = scene.lights[1]
    to_point = np.asarray(points, float) - np.asarray(lamp.position)
    d = np.linalg.norm(to_point, axis=-1)
    axis = np.asarray(getattr(lamp, "direction", (0, 0, -1)), float)
    cos_axis = to_point @ (axis / np.linalg.norm(axis)) / d
    inside = cos_axis >= np.cos(np.radians(getattr(lamp, "cutoff", 180)))
    return d, inside


def bites(mistake, scene, points, nl, rv):
    """Where the mistake must change the colour, and where it must not (boolean masks)."""
    lit, dark = nl > 0.05, nl < -0.05
    d, inside = lamp_terms(scene, points)
    if mistake in ("reflect-wrong-way", "view-from-eye"):
        return lit & ((rv > 0.9) | (rv < -0.8)), dark
    if mistake == "power-before-max":
        return lit & (rv < -0.8), rv > 0
    if mistake == "zero-to-the-zero":
        return lit & (rv < -0.05), (rv > 0.05) | dark
    if mistake == "unnormalised-light":
        return lit, dark
    if mistake == "unnormalised-view":
        return lit & (rv > 0.3), dark
    if mistake == "attenuated-ambient":
        return dark & (d > 4.3), np.zeros_like(dark)
    if mistake == "spot-cutoff-in-degrees":
        return lit & inside & (np.abs(nl) > 0.2), ~inside
    raise AssertionError(f"no bite mask for {mistake}")


def test_every_mistake_has_a_scene_here():
    assert sorted(SCENES) == sorted(MISTAKES), f"scenes for {sorted(SCENES)}, mistakes {sorted(MISTAKES)}"


# ---------------------------------------------------------------------------
# helpers


def geometry_terms(scene, points, normals):
    """n·l and r·v for the scene's point light (lights[1]) and eye, computed here from their definitions."""
    p = np.asarray(points, float)
    n = np.asarray(normals, float)
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    l = np.asarray(scene.lights[1].position) - p
    l /= np.linalg.norm(l, axis=-1, keepdims=True)
    v = np.asarray(scene.camera.eye) - p
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    nl = np.sum(n * l, axis=-1)
    r = 2 * nl[..., None] * n - l
    return nl, np.sum(r * v, axis=-1)


def pixel_geometry(scene, size):
    """The G-buffer of ``scene`` at ``size`` and n·l, r·v, |raw normal| for its covered pixels."""
    view = SceneView(scene, size=size, vectors=None)
    try:
        g = view.gbuffer()
    finally:
        view.close()
    nl, rv = geometry_terms(scene, g.positions[g.mask], g.normals[g.mask])
    raw = np.linalg.norm(g.raw_normals[g.mask].astype(float), axis=-1)
    return g, nl, rv, raw


def compare_through_figure(monkeypatch, tmp_path, scene, mistake, **options):
    """Export a comparison figure; return the PNG, the two placed cell images with their boxes, and the texts."""
    placed, texts = [], []
    place, save = figures.place, figures.save_figure

    def record_place(fig, image, box, size):
        placed.append((np.array(image), box))
        place(fig, image, box, size)

    def record_save(fig, path, ext):
        texts.extend(t.get_text() for t in fig.texts)
        save(fig, path, ext)

    monkeypatch.setattr(figures, "place", record_place)
    monkeypatch.setattr(figures, "save_figure", record_save)
    out = figure(scene, tmp_path / f"{mistake}.png", size=COMPARE_SIZE, supersample=1, mistake=mistake,
                 compare=True, **options)
    from PIL import Image

    with Image.open(out) as img:
        png = np.asarray(img.convert("RGB"))
    assert len(placed) == 2, f"{mistake}: {len(placed)} images placed, expected correct + mistaken"
    return png, placed, texts


def changed(a, b, levels: int = 1) -> np.ndarray:
    """Where two uint8 colour arrays differ by more than ``levels`` in some channel."""
    return np.abs(a.astype(int) - b.astype(int)).max(axis=-1) > levels


# ---------------------------------------------------------------------------
# per pixel, through figure(): differs where the bug bites, and is labelled


@pytest.mark.parametrize("mistake", sorted(SCENES))
def test_pixel_mistake_through_figure_differs_where_the_bug_bites(monkeypatch, tmp_path, mistake):
    scene = SCENES[mistake]
    png, placed, texts = compare_through_figure(monkeypatch, tmp_path, scene, mistake)
    (correct, box), (wrong, wrong_box) = placed
    assert box[2:] == wrong_box[2:], f"{mistake}: cells {box} and {wrong_box} differ in size"
    g, nl, rv, raw = pixel_geometry(scene, box[2:])
    a, b = correct[g.mask].astype(int), wrong[g.mask].astype(int)
    darker = (a - b).sum(axis=-1)  # summed over RGB, in levels
    info = f"{mistake} in {scene.interpolation} mode, cell {box[2]}x{box[3]}"

    if mistake == "no-clamp-diffuse":
        # lit side untouched; every dark-side pixel darker (negative light subtracts from the ambient)
        lit, dark = nl > 0.05, nl < -0.05
        assert not changed(a[lit], b[lit]).any(), f"{info}: {changed(a[lit], b[lit]).sum()} lit pixels changed"
        assert np.all(darker[dark] > 0), f"{info}: {np.sum(darker[dark] <= 0)} of {dark.sum()} dark pixels not darker"
    elif mistake == "ungated-specular":
        # correct: ambient only (the lamp is behind every point); wrong: a highlight where r·v -> 1
        assert np.all(nl < 0), f"{info}: the scene should have n·l < 0 everywhere, max {nl.max():.3f}"
        assert np.ptp(a, axis=0).max() <= 1, f"{info}: the correct picture is not flat ambient: {np.ptp(a, axis=0)}"
        peak = rv > 0.99
        assert peak.sum() > 20 and np.all(darker[peak] < -100), \
            f"{info}: at r·v > 0.99 the wrong picture brightens by {-darker[peak].min()} levels at least"
        brightest = rv[np.argmax(b.sum(axis=-1))]
        assert brightest > 0.95, f"{info}: the brightest wrong pixel is at r·v = {brightest:.3f}"
    elif mistake == "unnormalised-normals":
        # the sharp highlight is lost ...
        peak = rv > 0.99
        assert peak.sum() > 5, f"{info}: only {peak.sum()} pixels at the highlight"
        assert darker[peak].mean() > 150, f"{info}: the highlight dims by only {darker[peak].mean():.0f} levels"
        # ... and the diffuse light dims most where the raw normal is shortest: the middle of the faces
        diffuse = (nl > 0.3) & (rv < 0.5)
        assert np.all(b[diffuse] <= a[diffuse] + 1), f"{info}: a diffuse pixel got brighter"
        short, long_ = np.quantile(raw[diffuse], [1 / 3, 2 / 3])
        in_faces, near_edges = darker[diffuse & (raw <= short)].mean(), darker[diffuse & (raw >= long_)].mean()
        assert in_faces > 3 and in_faces > 1.5 * near_edges, (
            f"{info}: darkening {in_faces:.2f} levels where |n| <= {short:.4f}, "
            f"{near_edges:.2f} where |n| >= {long_:.4f}"
        )
        assert raw.min() < 0.95, f"{info}: the pixel mode shading got renormalised normals (min |n| {raw.min():.4f})"
    elif mistake == "zero-shininess":
        # the dark side untouched; every lit pixel away from the highlight washed out
        dark, matte = nl < -0.05, (nl > 0.05) & (rv < 0.5)
        assert not changed(a[dark], b[dark]).any(), f"{info}: {changed(a[dark], b[dark]).sum()} dark pixels changed"
        assert np.all(darker[matte] < -30), f"{info}: lit pixels brighten by only {-darker[matte].max()} levels"
    else:
        # the pixels where the wrong line changes the sum change, and those where it cannot stay
        bite, same = bites(mistake, scene, g.positions[g.mask], nl, rv)
        assert bite.sum() > 10, f"{info}: only {bite.sum()} pixels where the bug bites"
        assert changed(a[bite], b[bite], 3).mean() > 0.9, \
            f"{info}: {changed(a[bite], b[bite], 3).mean():.0%} of the {bite.sum()} pixels where it bites changed"
        assert not changed(a[same], b[same]).any(), f"{info}: {changed(a[same], b[same]).sum()} pixels changed"

    # the picture in the file is the one rendered (below its label, inside its frame)
    inset = 4
    for image, (x, y, w, h) in placed:
        region = png[y + h // 2:y + h - inset, x + inset:x + w - inset]
        assert np.array_equal(region, image[h // 2:-inset, inset:-inset]), f"{info}: the file's cell at {x},{y} differs"
    # and it is labelled
    title = MISTAKES[mistake].title
    assert any(t.startswith("correct") for t in texts), f"{info}: no 'correct' label in {texts}"
    assert any(t.startswith(f"common mistake: {title}") and "deliberately wrong" in t for t in texts), \
        f"{info}: no mistake label in {texts}"
    assert any(MISTAKES[mistake].wrong in t for t in texts), f"{info}: the wrong line of code missing from {texts}"


# ---------------------------------------------------------------------------
# per vertex and per face


@pytest.mark.parametrize("mode", ["flat", "gouraud"])
@pytest.mark.parametrize("mistake", sorted(SCENES))
def test_vertex_and_face_colours_change_where_the_bug_bites(mode, mistake):
    scene = SCENES[mistake].replace("interpolation", mode)
    from phonglab.render.mesh import build_mesh

    mesh = build_mesh(scene.geometry)
    if mode == "flat":
        points, normals = face_centroids_normals(mesh)
        correct = shading.face_colors(scene, mesh)["color"]
        wrong = shading.face_colors(scene, mesh, mistake=mistake)["color"]
    else:
        points, normals = np.asarray(mesh.points), np.asarray(mesh.point_data["Normals"])
        correct = shading.vertex_colors(scene, mesh)["color"]
        wrong = shading.vertex_colors(scene, mesh, mistake=mistake)["color"]
    nl, rv = geometry_terms(scene, points, normals)
    diff = changed(correct, wrong)
    info = f"{mistake}, {mode}: {diff.sum()} of {len(diff)} colours changed"
    if mistake == "no-clamp-diffuse":
        assert not diff[nl > 0].any() and diff[nl < -0.05].all(), info
    elif mistake == "ungated-specular":
        assert diff[rv > 0.9].all() and not diff[rv < 0].any(), info
    elif mistake == "unnormalised-normals":
        # unit normals per vertex and per face: nothing to get wrong, and the caption says so
        assert np.array_equal(correct, wrong), info
        assert not shading.mistake_shows(mistake, mode)
        assert "per-pixel" in shading.mistake_note(mistake, mode), shading.mistake_note(mistake, mode)
    elif mistake == "zero-shininess":
        assert diff[(nl > 0.05) & (rv < 0.5)].all() and not diff[nl < 0].any(), info
    else:
        bite, same = bites(mistake, scene, points, nl, rv)
        assert bite.any() and diff[bite].mean() > 0.9 and not diff[same].any(), info


@pytest.mark.parametrize("mode", ["flat", "gouraud"])
@pytest.mark.parametrize("mistake", sorted(SCENES))
def test_flat_and_gouraud_mistakes_through_figure(monkeypatch, tmp_path, mode, mistake):
    scene = SCENES[mistake].replace("interpolation", mode)
    _, placed, texts = compare_through_figure(monkeypatch, tmp_path, scene, mistake)
    (correct, _), (wrong, _) = placed
    fraction = changed(correct, wrong).mean()
    joined = " ".join(texts)  # a long line is drawn as several texts
    if MISTAKES[mistake].needs_raw_normals:
        # the same picture, and the band says why rather than passing it off as the bug
        assert fraction == 0, f"{mistake}, {mode}: {fraction:.2%} of pixels changed"
        assert f"shows only with per-pixel shading: with {mode if mode == 'flat' else 'Gouraud'}" in joined, \
            f"{mistake}, {mode}: {texts}"
        assert "this picture is the correct one" in joined, f"{mistake}, {mode}: {texts}"
    else:
        assert fraction > 0.02, f"{mistake}, {mode}: only {fraction:.2%} of pixels changed"
        assert "per-pixel" not in joined, f"{mistake}, {mode}: a per-pixel note where the mistake shows: {texts}"


# ---------------------------------------------------------------------------
# labels: single render, per-term views, sweeps, and the errors


def figure_texts(monkeypatch, tmp_path, scene, **options) -> list[str]:
    texts = []
    save = figures.save_figure

    def record_save(fig, path, ext):
        texts.extend(t.get_text() for t in fig.texts)
        save(fig, path, ext)

    monkeypatch.setattr(figures, "save_figure", record_save)
    figure(scene, tmp_path / "f.png", supersample=1, **options)
    return texts


@pytest.mark.parametrize("mistake", sorted(SCENES))
def test_single_render_is_labelled_deliberately_wrong(monkeypatch, tmp_path, mistake):
    texts = figure_texts(monkeypatch, tmp_path, SCENES[mistake], size=(400, 300), mistake=mistake)
    joined = " ".join(texts)
    assert f"Common mistake: {MISTAKES[mistake].title}" in joined and "deliberately wrong" in joined, texts
    assert f"wrong: {MISTAKES[mistake].wrong}" in texts and f"right: {MISTAKES[mistake].right}" in texts, texts


def test_single_render_shows_the_mistake_inside_the_frame(monkeypatch, tmp_path):
    # the render placed under the band is the mistaken one: compare with render() at the same size
    placed = []
    place = figures.place
    monkeypatch.setattr(figures, "place", lambda fig, image, box, size: (placed.append((image, box)),
                                                                             place(fig, image, box, size)))
    scene = SCENES["zero-shininess"]
    figure(scene, tmp_path / "one.png", size=(240, 200), supersample=1, vectors=None, mistake="zero-shininess")
    (image, box), = placed
    wrong = figures.render(scene, box[2:], vectors=None, supersample=1, mistake="zero-shininess")
    right = figures.render(scene, box[2:], vectors=None, supersample=1)
    assert np.array_equal(image, wrong), "the figure's render is not the mistaken render"
    assert changed(image, right).mean() > 0.05, "the figure's render looks like the correct one"


def test_terms_show_the_wrong_terms(monkeypatch, tmp_path):
    # zero shininess changes the specular term (and the sum) only
    scene = SCENES["zero-shininess"]
    placed = []
    place = figures.place
    monkeypatch.setattr(figures, "place", lambda fig, image, box, size: (
        placed.append((np.array(image), box)), place(fig, image, box, size)))
    texts = figure_texts(monkeypatch, tmp_path, scene, size=(480, 200), terms=True, mistake="zero-shininess")
    assert len(placed) == 4, f"{len(placed)} panels"
    # the panels share the background that keeps them readable: the renders' own or the light one
    background = next(bg for bg in (figures.BACKGROUND, figures.PAPER)
                      if np.abs(placed[0][0][-1, 0] - np.round(np.array(bg) * 255)).max() <= 1)
    for (wrong, box), term in zip(placed, ["ambient", "diffuse", "specular", "color"]):
        right = figures.render(scene, box[2:], vectors=None, term=term, supersample=1, legend=False,
                               background=background)
        fraction = changed(right, wrong).mean()
        if term in ("ambient", "diffuse"):
            assert fraction == 0, f"{term} panel changed by zero shininess ({fraction:.2%})"
        else:
            assert fraction > 0.05, f"{term} panel unchanged by zero shininess ({fraction:.2%})"
    wrong_labels = [t for t in texts if "(wrong)" in t]
    assert [t.split()[0] for t in wrong_labels] == ["specular", "sum"], texts
    assert "^0" in wrong_labels[0], wrong_labels
    assert any("Common mistake" in t and "deliberately wrong" in t for t in texts), texts


def test_sweep_with_a_mistake_is_labelled(monkeypatch, tmp_path):
    texts = figure_texts(monkeypatch, tmp_path, SCENES["no-clamp-diffuse"], size=(360, 220),
                         sweep="material.kd=0.4,0.8", mistake="no-clamp-diffuse")
    assert any("deliberately wrong" in t for t in texts), texts


def test_lesson_mistake_is_looked_up(tmp_path):
    lesson = tmp_path / "05-test.md"
    front = ('+++\ntitle = "Test lesson"\ngoal = "see"\nmistake = "zero-shininess"\n[geometry]\nkind = "sphere"\n'
             'resolution = 12\n[material]\nka = 0.1\nkd = 0.5\nks = 0.5\nshininess = 20\n'
             '[[lights]]\ntype = "point"\nposition = [2, 2, 3]\n[camera]\neye = [0, 0, 4]\n'
             '+++\n# Test lesson\n\nText.\n')
    lesson.write_text(front)
    from phonglab.scene import load

    assert options.resolve_mistake("lesson", load(lesson)) == "zero-shininess"
    out = figure(str(lesson), tmp_path / "lesson.png", size=(200, 150), mistake="lesson", supersample=1)
    assert out.stat().st_size > 1000
    lesson.write_text(front.replace('mistake = "zero-shininess"\n', ""))
    with pytest.raises(FigureError, match="no mistake key"):
        figure(str(lesson), tmp_path / "none.png", mistake="lesson")
    assert not (tmp_path / "none.png").exists()


@pytest.mark.parametrize("options, words", [
    ({"mistake": "zero-shinines"}, ["zero-shinines", "no-clamp-diffuse", "ungated-specular", "did you mean"]),
    ({"mistake": "lesson"}, ["lesson", "scene"]),
    ({"compare": True}, ["compare", "mistake"]),
    ({"mistake": "zero-shininess", "plot": "lobe"}, ["mistake", "plot"]),
    ({"mistake": "zero-shininess", "compare": True, "terms": True}, ["compare", "terms"]),
])
def test_bad_mistake_options_raise_before_rendering(tmp_path, options, words):
    with pytest.raises(FigureError) as caught:
        figure(SCENES["zero-shininess"], tmp_path / "bad.png", **options)
    message = str(caught.value)
    assert "\n" not in message, f"{options}: {message!r}"
    for word in words:
        assert word in message, f"{options}: {word!r} missing from {message!r}"
    assert list(tmp_path.iterdir()) == [], f"{options} left {list(tmp_path.iterdir())}"


@pytest.mark.parametrize("ext", [".svg", ".pdf"])
def test_mistake_figures_in_vector_formats(tmp_path, ext):
    out = figure(SCENES["no-clamp-diffuse"], tmp_path / f"m{ext}", size=(300, 200), supersample=1,
                 mistake="no-clamp-diffuse", compare=True)
    assert out.stat().st_size > 1000 and [p.name for p in tmp_path.iterdir()] == [f"m{ext}"]


# ---------------------------------------------------------------------------
# SceneView.set_mistake


def actor_count(view) -> int:
    return view.renderer.GetViewProps().GetNumberOfItems()


@pytest.mark.parametrize("mode, data", [("flat", "cell_data"), ("gouraud", "point_data"), ("pixel", "point_data")])
def test_set_mistake_recolours_in_place_and_back_exactly(mode, data):
    scene = SCENES["no-clamp-diffuse"].replace("interpolation", mode)
    view = SceneView(scene, size=(96, 72))
    try:
        fields = getattr(view.mesh, data)
        array = fields.GetArray(glyphs.COLOR_ARRAY)
        address = array.GetAddressAsString("vtkDataArray")
        before, props = np.array(fields[glyphs.COLOR_ARRAY]), actor_count(view)
        stamp = array.GetMTime()

        view.set_mistake("no-clamp-diffuse")
        after = np.array(fields[glyphs.COLOR_ARRAY])
        same_array = fields.GetArray(glyphs.COLOR_ARRAY).GetAddressAsString("vtkDataArray") == address
        assert same_array, f"{mode}: the colour array was replaced, not overwritten"
        assert array.GetMTime() > stamp, f"{mode}: the colour array was not marked modified"
        fraction = changed(before, after).mean()
        assert fraction > 0.1, f"{mode}: only {fraction:.2%} of colours changed"
        assert actor_count(view) == props, f"{mode}: {actor_count(view)} props after set_mistake, {props} before"
        assert view.mistake == "no-clamp-diffuse" and view.mistake_shows and view.mistake_note == ""

        view.set_mistake(None)
        assert np.array_equal(np.array(fields[glyphs.COLOR_ARRAY]), before), f"{mode}: correct colours not restored"
        assert actor_count(view) == props and view.mistake is None
    finally:
        view.close()


def test_set_mistake_survives_updates_and_term_changes():
    scene = SCENES["zero-shininess"].replace("interpolation", "gouraud")
    view = SceneView(scene, size=(96, 72), mistake="zero-shininess")
    reference = SceneView(scene, size=(96, 72))
    try:
        def colours(v):
            return np.array(v.mesh.point_data[glyphs.COLOR_ARRAY])

        assert changed(colours(view), colours(reference)).any(), "mistake= at construction had no effect"
        # a slider moves: the mistake stays on
        moved = scene.replace("material.ks", 0.3)
        view.update(moved)
        expected = shading.vertex_colors(moved, view.mesh, mistake="zero-shininess")["color"]
        assert np.array_equal(colours(view), expected), "update() dropped the mistake"
        view.set_term("specular")
        expected = shading.vertex_colors(moved, view.mesh, ("specular",), mistake="zero-shininess")["specular"]
        assert np.array_equal(colours(view), expected), "set_term() dropped the mistake"
    finally:
        view.close()
        reference.close()


def test_set_mistake_refuses_unknown_names_and_keeps_the_view():
    view = SceneView(SCENES["zero-shininess"], size=(64, 48), mistake="zero-shininess")
    try:
        with pytest.raises(ValueError) as caught:
            view.set_mistake("zero-shine")
        for name in MISTAKES:
            assert name in str(caught.value), f"{name} missing from {caught.value}"
        assert view.mistake == "zero-shininess"
        with pytest.raises(ValueError, match="no-such"):
            SceneView(SCENES["zero-shininess"], size=(64, 48), mistake="no-such")
    finally:
        view.close()


def test_pixel_image_honours_the_mistake_with_raw_normals():
    scene = SCENES["unnormalised-normals"]
    view = SceneView(scene, size=(120, 90), vectors=None)
    try:
        correct = view.pixel_image()
        colours = np.array(view.mesh.point_data[glyphs.COLOR_ARRAY])
        view.set_mistake("unnormalised-normals")
        wrong = view.pixel_image()
        # per vertex (the window's preview) nothing changes; per pixel the raw normals darken the faces
        assert np.array_equal(np.array(view.mesh.point_data[glyphs.COLOR_ARRAY]), colours)
        assert changed(correct, wrong).mean() > 0.1, f"only {changed(correct, wrong).mean():.2%} of pixels changed"
        specular_wrong = view.pixel_image("specular").astype(int)
        view.set_mistake(None)
        assert np.array_equal(view.pixel_image(), correct), "pixel_image not restored after set_mistake(None)"
        specular_right = view.pixel_image("specular").astype(int)
        assert specular_wrong.max() < 0.7 * specular_right.max(), \
            f"the highlight's peak {specular_right.max()} only dims to {specular_wrong.max()}"
    finally:
        view.close()


def test_raw_normals_are_the_renormalised_ones_scaled():
    # the G-buffer's raw normals point the same way as the unit normals and are at most 1 long
    view = SceneView(SCENES["unnormalised-normals"], size=(80, 60), vectors=None)
    try:
        g = view.gbuffer()
    finally:
        view.close()
    raw, unit = g.raw_normals[g.mask].astype(float), g.normals[g.mask].astype(float)
    length = np.linalg.norm(raw, axis=-1)
    assert np.all(length <= 1 + 1e-5) and length.min() < 0.97, f"|raw n| from {length.min():.4f} to {length.max():.4f}"
    assert np.allclose(raw / length[:, None], unit, atol=1e-5), "raw and unit normals point different ways"
    assert np.isnan(g.raw_normals[~g.mask]).all(), "uncovered pixels should hold NaN"
