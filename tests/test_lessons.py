"""Walk every lesson: it loads, its maths converts, it shades, its experiments work, it exports.

The lessons make claims ("Gouraud shading misses this highlight", "a red light
on a green torus gives black"); the claims tests below check each one on the
lesson's own scene, so a change to a scene that breaks its story fails here.

Shading is checked the way the picture is made, with the core: per triangle
(flat), per vertex and blended (Gouraud) or with blended normals (per pixel),
at four sample points inside every triangle of the lesson's mesh.
"""

import re
from pathlib import Path

import numpy as np
import pytest
from latex2mathml.converter import convert
from PIL import Image

import phonglab as pl
from phonglab.render import build_mesh, figure
from phonglab.render.mesh import face_centroids_normals, triangles
from phonglab.render.objects import cell_objects, point_objects, scene_mesh
from phonglab.scene import lesson_files, list_lessons, load_lesson, plan
from phonglab.scene import shade as scene_shade
from phonglab.teaching import MISTAKES


def shade_scene(scene, points, normals, mistake=None, objects=None):
    """The scene's shading, correct or with the named mistake, each point with its object's material and shadows."""
    from phonglab.render.shadows import visibility

    shape = np.shape(points)[:-1]
    flat = None if objects is None else np.broadcast_to(objects, shape).reshape(-1)
    seen = visibility(scene, np.reshape(points, (-1, 3)), flat, full=True) if scene.shadows else None
    seen = None if seen is None else {i: v.reshape(shape) for i, v in seen.items()}
    return scene_shade(scene, points, normals, mistake=mistake, objects=objects, visibility=seen)


LESSONS_DIR = Path(__file__).resolve().parents[1] / "lessons"
#: every lesson file: each is loaded, shaded, exported and has its experiments applied
FILES = lesson_files(LESSONS_DIR)
IDS = [p.stem for p in FILES]
#: the course proper, lessons 1 to 10: held to the course's rules (2-3 experiments, each changing the picture)
COURSE = [p for p in FILES if int(re.match(r"\d+", p.name).group()) <= 10]
COURSE_IDS = [p.stem for p in COURSE]
TERMS = ("ambient", "diffuse", "specular", "color")

#: barycentric weights of the sample points in every triangle: the centroid and one near each corner
BARY = np.array([[1 / 3, 1 / 3, 1 / 3], [0.6, 0.2, 0.2], [0.2, 0.6, 0.2], [0.2, 0.2, 0.6]])


def bary_grid(k: int) -> np.ndarray:
    """Barycentric weights of a regular grid of (k + 1)(k + 2)/2 points over a triangle, centroid first."""
    grid = [(i / k, j / k, (k - i - j) / k) for i in range(k + 1) for j in range(k + 1 - i)]
    return np.array([(1 / 3, 1 / 3, 1 / 3)] + grid)


#: a dense grid, for highlights smaller than a triangle
DENSE = bary_grid(12)


def lesson(name: str):
    return load_lesson(LESSONS_DIR / f"{name}.md")


def surface_shading(scene, mistake=None, bary=BARY) -> dict:
    """Each term at the sample points of every triangle, as the scene's interpolation computes it.

    Parameters
    ----------
    scene : Scene
    mistake : str, optional
        Shade with this common-mistake variant instead of the core.
    bary : ndarray, shape (k, 3)
        Barycentric weights of the sample points; the first is the centroid.

    Returns
    -------
    dict of term -> ndarray, shape (n_triangles, k, 3)
    """
    mesh = scene_mesh(scene)  # every object, placed
    tri = triangles(mesh)
    points = np.asarray(mesh.points, dtype=np.float64)
    normals = np.asarray(mesh.point_data["Normals"], dtype=np.float64)
    on_vertex, on_face = point_objects(mesh), cell_objects(mesh)
    if scene.interpolation == "flat":
        # one shade per triangle, at its centroid with its face normal
        centroids, face_normals = face_centroids_normals(mesh)
        s = shade_scene(scene, centroids.astype(np.float64), face_normals.astype(np.float64), mistake, on_face)
        return {t: np.repeat(np.asarray(getattr(s, t))[:, None, :], len(bary), axis=1) for t in TERMS}
    if scene.interpolation == "gouraud":
        # shade the vertices, blend the colours
        s = shade_scene(scene, points, normals, mistake, on_vertex)
        return {t: np.einsum("kb,tbc->tkc", bary, np.asarray(getattr(s, t))[tri]) for t in TERMS}
    # per pixel: blend positions and normals, shade there (the core renormalises)
    p = np.einsum("kb,tbc->tkc", bary, points[tri])
    n = np.einsum("kb,tbc->tkc", bary, normals[tri])
    s = shade_scene(scene, p, n, mistake, None if on_face is None else on_face[:, None])
    return {t: np.asarray(getattr(s, t)) for t in TERMS}


def summary(shading: dict) -> np.ndarray:
    """Mesh-independent figures of a shading: mean, max and percentiles of each term and channel."""
    rows = []
    for t in TERMS:
        v = shading[t].reshape(-1, 3)
        rows += [v.mean(axis=0), v.max(axis=0), *np.percentile(v, [10, 50, 90], axis=0)]
    return np.concatenate(rows)


def shading_change(before: dict, after: dict) -> float:
    """How much a shading changed: max |difference| at the samples, or of the summaries if the mesh differs."""
    a, b = before["color"], after["color"]
    if a.shape == b.shape:
        return float(np.abs(a - b).max())
    return float(np.abs(summary(before) - summary(after)).max())


# ---------------------------------------------------------------------------
# the course as a whole


def test_lessons_are_numbered_1_to_10():
    lessons = list_lessons(LESSONS_DIR)
    numbers = [les.number for les in lessons]
    assert numbers[:10] == list(range(1, 11)), f"the course is lessons 1..10, each once; got {numbers}"
    assert numbers == list(range(1, len(numbers) + 1)), f"lesson numbers must be unique and consecutive: {numbers}"
    for les in lessons:
        name = Path(les.path).name
        assert name.startswith(f"{les.number:02d}-"), f"{name}: the file name must start with {les.number:02d}-"


def test_every_mistake_is_shown_by_some_lesson():
    shown = {les.mistake for les in list_lessons(LESSONS_DIR)} - {None}
    # the mistakes students make writing the model themselves are taught by the grader's report
    # (phonglab grade) and by `phonglab figure --mistake`; a lesson may show them too
    exercise = {"reflect-wrong-way", "unnormalised-light", "unnormalised-view", "view-from-eye",
                "attenuated-ambient", "spot-cutoff-in-degrees", "power-before-max", "zero-to-the-zero"}
    assert shown <= set(MISTAKES) and set(MISTAKES) - shown <= exercise, f"mistakes never shown: {set(MISTAKES) - shown}"


# ---------------------------------------------------------------------------
# each lesson


@pytest.mark.parametrize("path", COURSE, ids=COURSE_IDS)
def test_lesson_is_complete(path):
    les = load_lesson(path)
    where = path.name
    assert les.title and les.scene.title == les.title, f"{where}: title {les.title!r}"
    goal = les.goal.strip()
    assert goal.endswith(".") and ". " not in goal, f"{where}: the goal must be one sentence, got {goal!r}"
    assert les.question.strip().endswith("?") and les.answer.strip(), f"{where}: question {les.question!r}"
    assert 2 <= len(les.experiments) <= 4, f"{where}: {len(les.experiments)} experiments"
    for e in les.experiments:
        assert e.label and e.text and e.settings, f"{where}: experiment {e}"
    assert 1 <= len(les.controls) <= 6, f"{where}: controls {les.controls} (the ones that matter, not all)"
    assert les.mistake is None or les.mistake in MISTAKES, f"{where}: unknown mistake {les.mistake!r}"
    assert "$$" in les.body, f"{where}: the explanation has no displayed formula"
    assert not re.search(r"^# ", les.body, re.MULTILINE), f"{where}: the title belongs in the front matter"


def lesson_texts(les) -> list[tuple[str, str]]:
    """Every text of a lesson that may hold maths, with where it comes from."""
    texts = [("body", les.body), ("goal", les.goal), ("question", les.question), ("answer", les.answer)]
    texts += [(f"experiment {e.label!r}", e.text) for e in les.experiments]
    return texts


def formulas(text: str, where: str) -> list[tuple[str, str]]:
    """The ``$$...$$`` (display) and ``$...$`` (inline) formulas of a text, as (latex, display|inline)."""
    found = [(m, "block") for m in re.findall(r"\$\$(.+?)\$\$", text, re.DOTALL)]
    rest = re.sub(r"\$\$(.+?)\$\$", " ", text, flags=re.DOTALL)
    found += [(m, "inline") for m in re.findall(r"\$([^$\n]+?)\$", rest)]
    for latex, kind in found:
        # the page takes $...$ for maths only when no space follows the opening $ or precedes the closing one
        assert kind == "block" or latex == latex.strip(), f"{where}: ${latex}$ starts or ends with a space"
    rest = re.sub(r"\$([^$\n]+?)\$", " ", rest)
    assert "$" not in rest, f"{where}: an unmatched $ near {rest[max(0, rest.find('$') - 40):rest.find('$') + 40]!r}"
    return found


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_formulas_convert_to_mathml(path):
    les = load_lesson(path)
    count = 0
    for where, text in lesson_texts(les):
        for latex, display in formulas(text, f"{path.name} {where}"):
            mathml = convert(latex, display=display)
            count += 1
            # latex2mathml passes unknown commands through as text: none may survive
            assert "\\" not in mathml, f"{path.name} {where}: ${latex}$ has a command MathML cannot show: {mathml}"
            assert mathml.startswith("<math") and len(mathml) > 60, f"{path.name} {where}: ${latex}$ -> {mathml}"
    assert count >= 3, f"{path.name}: only {count} formulas"


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_lesson_scene_shades(path):
    les = load_lesson(path)
    scene_plan = plan(les.scene)
    assert scene_plan.computed, f"{path.name}: the plan computes nothing"
    s = surface_shading(les.scene)
    assert s["color"].max() > 0.1, f"{path.name}: the scene is black (max {s['color'].max():.3g})"
    for label, scene in [("the start", les.scene)] + [(repr(e.label), e.apply(les.scene)) for e in les.experiments]:
        for term, values in surface_shading(scene).items():
            assert np.isfinite(values).all(), f"{path.name}, {label}: {term} is not finite"
            assert (values >= 0).all(), f"{path.name}, {label}: {term} is negative"


@pytest.mark.parametrize("path", COURSE, ids=COURSE_IDS)
def test_each_experiment_changes_the_shading(path):
    les = load_lesson(path)
    before = surface_shading(les.scene)
    for e in les.experiments:
        change = shading_change(before, surface_shading(e.apply(les.scene)))
        assert change > 0.02, f"{path.name}: experiment {e.label!r} ({e.settings}) changes the shading by only {change:.3g}"


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_experiments_give_the_same_picture_in_any_order(path):
    # a student clicks the experiments in any order: each must set everything it relies on
    les = load_lesson(path)
    for first in les.experiments:
        after_first = first.apply(les.scene)
        for second in les.experiments:
            direct = surface_shading(second.apply(les.scene))
            chained = surface_shading(second.apply(after_first))
            for t in TERMS:
                assert direct[t].shape == chained[t].shape and np.allclose(direct[t], chained[t]), (
                    f"{path.name}: {second.label!r} looks different after {first.label!r} ({t})")


@pytest.mark.parametrize("path", [p for p in FILES if load_lesson(p).mistake], ids=lambda p: p.stem)
def test_mistake_view_differs_from_the_lesson(path):
    les = load_lesson(path)
    scene = les.scene
    if MISTAKES[les.mistake].needs_raw_normals:
        # the bug lives in per-pixel shading, which blends the normals
        scene = scene.replace("interpolation", "pixel")
    right = np.clip(surface_shading(scene, bary=DENSE)["color"], 0, 1)
    wrong = np.clip(surface_shading(scene, les.mistake, bary=DENSE)["color"], 0, 1)
    diff = np.abs(right - wrong).max(axis=-1)
    assert diff.max() > 0.15, f"{path.name}: the {les.mistake} view is nowhere clearly different ({diff.max():.3f})"
    assert (diff > 0.02).mean() > 0.05, f"{path.name}: the {les.mistake} view changes only {(diff > 0.02).mean():.1%}"


@pytest.mark.parametrize("path", FILES, ids=IDS)
def test_lesson_exports_a_png(path, tmp_path):
    out = figure(load_lesson(path), tmp_path / f"{path.stem}.png", size=(160, 120), supersample=1)
    assert out.is_file(), f"{path.name}: no file written at {out}"
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size == (160, 120), f"{path.name}: {im.format} {im.size}"
        rgb = np.asarray(im.convert("RGB")).astype(int)
    background = rgb[0, 0]
    covered = (np.abs(rgb - background).sum(axis=-1) > 12).mean()
    assert covered > 0.1, f"{path.name}: the export is nearly blank ({covered:.1%} differs from the background)"
    assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 20, f"{path.name}: the export has almost no shading"


# ---------------------------------------------------------------------------
# what the lessons claim, checked on their own scenes


def test_ambient_alone_is_flat():
    les = lesson("02-ambient")
    alone = surface_shading(les.experiments[1].apply(les.scene))["color"]
    spread = np.ptp(alone.reshape(-1, 3), axis=0)
    assert np.all(spread < 1e-12), f"ambient light alone must be one colour, spread {spread}"


def test_diffuse_terminator_is_where_n_dot_l_is_zero():
    les = lesson("03-diffuse")
    scene = les.experiments[2].apply(les.scene)  # light at (5, 0, 0)
    mesh = build_mesh(scene.geometry)
    p, n = np.asarray(mesh.points, np.float64), np.asarray(mesh.point_data["Normals"], np.float64)
    d = shade_scene(scene, p, n).diffuse[:, 0]
    nl = pl.dot(n, pl.normalize(np.array([5.0, 0, 0]) - p))
    assert np.all(d[nl <= 0] == 0) and np.all(d[nl > 1e-3] > 0), "diffuse must be lit exactly where n·l > 0"


def test_specular_alpha_shrinks_the_highlight_and_the_eye_moves_it():
    les = lesson("04-specular")
    plastic, metal, walk = (surface_shading(e.apply(les.scene)) for e in les.experiments)
    area = {name: (s["specular"][..., 0] > 0.3).sum() for name, s in (("plastic", plastic), ("metal", metal))}
    assert area["metal"] < area["plastic"] / 4, f"alpha 100 should shrink the highlight a lot: {area}"
    start = surface_shading(les.scene)
    assert np.array_equal(walk["diffuse"], start["diffuse"]), "moving the eye must not change the diffuse term"
    assert np.abs(walk["specular"] - start["specular"]).max() > 0.3, "moving the eye must move the highlight"


def test_zero_shininess_mistake_washes_out_the_lit_side():
    les = lesson("04-specular")
    mesh = build_mesh(les.scene.geometry)
    p, n = np.asarray(mesh.points, np.float64), np.asarray(mesh.point_data["Normals"], np.float64)
    wrong, right = shade_scene(les.scene, p, n, "zero-shininess"), shade_scene(les.scene, p, n)
    lit = right.diffuse[:, 2] > 0
    assert np.allclose(wrong.specular[lit], 0.6), "every lit vertex should get the full k_s = 0.6"
    assert (right.specular[lit, 0] < 0.06).mean() > 0.5, "while most of the lit side has no highlight"


def test_red_light_on_green_torus_is_black_but_for_a_red_highlight():
    les = lesson("05-whole-model")
    s = surface_shading(les.experiments[1].apply(les.scene))
    assert np.all(s["diffuse"][..., 1:] == 0), "no green or blue diffuse light from a red lamp"
    assert s["diffuse"][..., 0].max() <= 0.05 + 1e-12, f"red diffuse at most k_d,R = 0.05: {s['diffuse'][..., 0].max()}"
    assert np.all(s["specular"][..., 1:] == 0) and s["specular"][..., 0].max() > 0.25, "the highlight is red"


def test_blinn_phong_needs_four_times_the_exponent():
    les = lesson("06-blinn-phong")
    phong = surface_shading(les.scene)["specular"]
    same, four = (surface_shading(e.apply(les.scene))["specular"] for e in les.experiments[:2])
    err_same, err_four = np.abs(same - phong).max(), np.abs(four - phong).max()
    assert (same[..., 0] > 0.3).sum() > 2 * (phong[..., 0] > 0.3).sum(), "same alpha: a larger highlight"
    assert err_four < err_same / 3, f"4 alpha should match Phong far better: {err_four:.3g} vs {err_same:.3g}"


def test_blinn_phong_streak_on_the_lake():
    # the highlight on the lake is long along the view (y) and narrow across (x) for Blinn-Phong only
    les = lesson("06-blinn-phong")
    lake = les.experiments[2].apply(les.scene)
    mesh = build_mesh(lake.geometry)
    p = np.einsum("kb,tbc->tkc", BARY, np.asarray(mesh.points, np.float64)[triangles(mesh)]).reshape(-1, 3)

    def extent(scene):
        spec = surface_shading(scene)["specular"].reshape(-1, 3)[:, 0]
        bright = p[spec > 0.5 * spec.max()]
        return np.ptp(bright[:, 1]) / max(np.ptp(bright[:, 0]), 1e-9)

    blinn, phong = extent(lake), extent(lake.replace("model", "phong").replace("material.shininess", 40))
    assert blinn > 2 * phong, f"Blinn-Phong's highlight should be a streak: length/width {blinn:.2f} vs {phong:.2f}"


def test_spot_cutoff_180_is_a_point_light_and_the_sun_lights_evenly():
    les = lesson("07-light-sources")
    point_like = les.experiments[0].apply(les.scene)
    spot = point_like.lights[1]
    plain = point_like.replace("lights[1].type", "point")
    assert isinstance(spot, pl.SpotLight) and not isinstance(plain.lights[1], pl.SpotLight)
    a, b = surface_shading(point_like)["color"], surface_shading(plain)["color"]
    assert np.allclose(a, b, rtol=0, atol=1e-12), "a 180° spotlight must shade exactly like a point light"
    cone = surface_shading(les.scene)["diffuse"][..., 0]
    assert (cone == 0).mean() > 0.3 and cone.max() > 0.3, "the 25° spot lights a disc and leaves the rest dark"
    sun = surface_shading(les.experiments[2].apply(les.scene))["diffuse"]
    assert np.ptp(sun.reshape(-1, 3), axis=0).max() < 1e-9, "a directional light shades a flat floor evenly"


def test_inverse_square_fades_towards_the_corners():
    les = lesson("07-light-sources")
    scene = les.experiments[1].apply(les.scene)
    mesh = build_mesh(scene.geometry)
    p, n = np.asarray(mesh.points, np.float64), np.asarray(mesh.point_data["Normals"], np.float64)
    d = shade_scene(scene, p, n).diffuse[:, 0]
    light = np.asarray(scene.lights[1].position)
    dist = np.linalg.norm(p - light, axis=1)
    near, far = d[dist < np.percentile(dist, 10)].mean(), d[dist > np.percentile(dist, 90)].mean()
    assert near > 2 * far, f"inverse square: near {near:.3f} vs far {far:.3f}"


def test_gouraud_misses_the_highlight_that_per_pixel_shading_finds():
    les = lesson("08-interpolation")
    peak = {name: surface_shading(scene, bary=DENSE)["specular"].max()
            for name, scene in (("gouraud 12", les.scene), ("pixel 12", les.experiments[1].apply(les.scene)),
                                ("gouraud 64", les.experiments[2].apply(les.scene)))}
    assert peak["gouraud 12"] < 0.05, f"Gouraud at 12 segments should miss the highlight: {peak}"
    assert peak["pixel 12"] > 0.5, f"per-pixel shading should find it: {peak}"
    assert peak["gouraud 64"] > 0.3, f"64 segments should bring it back: {peak}"


def test_unnormalised_normals_darken_triangle_middles_and_lose_the_highlight():
    les = lesson("08-interpolation")
    scene = les.experiments[1].apply(les.scene)  # per pixel
    right, wrong = surface_shading(scene, bary=DENSE), surface_shading(scene, "unnormalised-normals", bary=DENSE)
    lit = right["diffuse"][:, 0, 0] > 0.1
    ratio = wrong["diffuse"][lit, 0, 0] / right["diffuse"][lit, 0, 0]  # at the centroids
    assert ratio.max() < 0.99 and ratio.min() < 0.97, f"the centres must be darker: ratio {ratio.min():.3f}..{ratio.max():.3f}"
    corners = (DENSE == 1).any(axis=1)
    assert np.allclose(wrong["color"][:, corners], right["color"][:, corners]), "at the vertices both agree"
    assert right["specular"].max() > 0.5 and wrong["specular"].max() < 0.05, (
        f"the highlight should vanish: {right['specular'].max():.3f} -> {wrong['specular'].max():.3f}")


def test_two_sided_lighting_of_the_sheet():
    les = lesson("09-two-sided-and-hard-cases")
    start = surface_shading(les.scene)
    assert np.all(start["diffuse"] == 0) and np.all(start["specular"] == 0), "one-sided from behind: ambient only"
    on = surface_shading(les.experiments[0].apply(les.scene))
    assert on["diffuse"].min() > 0 and on["specular"].max() > 0.3, "two-sided: lit, with a highlight"
    far = les.experiments[1].apply(les.scene)
    assert surface_shading(far)["diffuse"].min() > 0, "one-sided, lamp behind the sheet: wrongly lit"
    assert np.all(surface_shading(far.replace("two_sided", True))["diffuse"] == 0), "two-sided: correctly dark"
    grazing = surface_shading(les.experiments[2].apply(les.scene))
    assert 0 < grazing["diffuse"].max() < 0.5 * on["diffuse"].max(), "grazing light is faint"
    leak = surface_shading(les.scene, "ungated-specular")["specular"]
    assert leak.max() > 0.3, f"the ungated mistake should show a highlight on the unlit sheet: {leak.max():.3f}"


def test_phong_has_no_shadows_and_normalising_keeps_the_highlight_energy():
    les = lesson("10-beyond-phong")
    low = les.experiments[0].apply(les.scene)
    mesh = build_mesh(low.geometry)
    p, n = np.asarray(mesh.points, np.float64), np.asarray(mesh.point_data["Normals"], np.float64)
    # inner wall of the left half, facing the lamp on the right through the hole: the right half blocks it
    inner_left = (p[:, 0] < -0.3) & (n[:, 0] > 0.7)
    d = shade_scene(low, p, n).diffuse[inner_left, 0]
    assert inner_left.sum() > 10 and d.min() > 0.1, "the model lights the inner wall straight through the ring"

    def total(scene):
        return surface_shading(scene)["specular"][..., 0].sum()

    start, sharp, normalised = total(les.scene), total(les.experiments[1].apply(les.scene)), total(
        les.experiments[2].apply(les.scene))
    assert sharp < start / 4, f"same k_s, alpha 200: far less reflected light ({sharp:.2f} vs {start:.2f})"
    assert 0.5 < normalised / start < 2, f"energy-normalised: about the same total ({normalised:.2f} vs {start:.2f})"
