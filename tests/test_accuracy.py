"""The accuracy studies: their references checked against known values, the
orderings that must hold, the lesson's images, the figure and the command.
No test asserts a time."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from phonglab import core
from phonglab.accuracy import arealight, interpolation, models, precision
from phonglab.accuracy.raycast import View, camera_rays, hit_mesh, hit_sphere

REPO = Path(__file__).resolve().parents[1]


# ---------------------------------------------------------------------------
# the references


def test_analytic_sphere_at_the_centre_pixel_matches_a_hand_worked_colour():
    # an odd image: the centre pixel's ray runs straight down -z onto (0, 0, 1)
    setup = interpolation.default_setup(33)
    ref = interpolation.reference(setup, repeats=1)
    points, normals, mask = hit_sphere(camera_rays(setup.view))
    np.testing.assert_allclose(points[16, 16], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(normals[16, 16], [0, 0, 1], atol=1e-15)
    # by hand: l = (2, 2.5, 2)/sqrt(14.25), n·l = 2/sqrt(14.25) = 0.529813;
    # r·v = n·l too (v = n), and 0.8 * 0.529813^200 is below 1e-50
    nl = 2 / math.sqrt(14.25)
    expected = 0.1 * 0.2 + np.array([0.8, 0.3, 0.2]) * nl
    np.testing.assert_allclose(ref.color[16, 16], expected, rtol=1e-14,
                               err_msg=f"centre pixel, n·l = {nl}")


def test_sphere_rays_hit_exactly_inside_the_tangent_cone():
    # from the eye at distance 4 the unit sphere fills a cone of half-angle asin(1/4)
    view = View(width=41, height=41)
    rays = camera_rays(view)
    points, _, mask = hit_sphere(rays)
    angle = np.arccos(np.clip(rays.directions @ np.array([0, 0, -1.0]), -1, 1))
    inside = angle < math.asin(0.25)
    assert np.array_equal(mask, inside), f"{np.sum(mask != inside)} pixels disagree with the cone"
    np.testing.assert_allclose(np.linalg.norm(points[mask], axis=1), 1.0, atol=1e-14)


def _brute_force_hits(view, points, tri):
    """Every pixel ray against every triangle: the nearest hit's triangle and distance."""
    rays = camera_rays(view)
    d = rays.directions.reshape(-1, 1, 3)
    a, b, c = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
    e1, e2 = b - a, c - a
    pvec = np.cross(d, e2)
    det = np.einsum("ptk,tk->pt", pvec, e1)
    tvec = rays.origin - a
    u = np.einsum("tk,ptk->pt", tvec, pvec) / det
    qvec = np.cross(tvec, e1)
    w = np.einsum("ptk,tk->pt", d, qvec) / det
    t = np.einsum("tk,tk->t", e2, qvec) / det
    ok = (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
    t = np.where(ok, t, np.inf)
    nearest = t.argmin(axis=1)
    return np.isfinite(t.min(axis=1)).reshape(view.height, view.width), nearest, t.min(axis=1)


def test_mesh_ray_cast_agrees_with_brute_force():
    setup = interpolation.default_setup(40)
    prep = interpolation.prepare(setup, 8)
    mask, nearest, dist = _brute_force_hits(setup.view, prep.points, prep.triangles)
    # pixels whose ray grazes an edge may go either way: compare where both agree on coverage
    assert np.sum(mask != prep.mask) <= 2, f"coverage differs at {np.argwhere(mask != prep.mask).tolist()}"
    both = (mask & prep.mask).ravel()
    hit_index = np.cumsum(prep.mask.ravel()) - 1
    ours = prep.triangle[hit_index[both]]
    theirs = nearest[both]
    # same triangle, or (on a shared edge) the same hit point
    hits = hit_mesh(setup.view, prep.points, prep.triangles)
    origin = np.asarray(setup.view.eye)
    ours_dist = np.linalg.norm(hits.points[hit_index[both]] - origin, axis=1)
    ray_dir = camera_rays(setup.view).directions.reshape(-1, 3)[both]
    theirs_dist = dist[both] * np.linalg.norm(ray_dir, axis=1)
    same = (ours == theirs) | np.isclose(ours_dist, theirs_dist, rtol=1e-12)
    assert same.all(), f"{np.sum(~same)} pixels hit another triangle than brute force"
    np.testing.assert_allclose(hits.weights.sum(axis=1), 1.0, atol=1e-12)
    assert (hits.weights >= 0).all()


def test_pixel_blend_reproduces_the_hit_point():
    # the barycentric weights are the 3-D ones: they rebuild the ray's hit point
    setup = interpolation.default_setup(32)
    prep = interpolation.prepare(setup, 16)
    hits = hit_mesh(setup.view, prep.points, prep.triangles)
    rebuilt = interpolation._blend(prep.points, prep)
    np.testing.assert_allclose(rebuilt, hits.points, atol=1e-12)


# ---------------------------------------------------------------------------
# orderings that must hold


@pytest.fixture(scope="module")
def interpolation_study():
    return interpolation.run((8, 16, 32, 64), size=64, repeats=1, min_seconds=0.0)


def _row(study, method, resolution):
    return next(r for r in study["rows"] if r["method"] == method and r["resolution"] == resolution)


@pytest.mark.parametrize("resolution", [16, 32, 64])
def test_pixel_shading_beats_gouraud_at_the_highlight(interpolation_study, resolution):
    pixel = _row(interpolation_study, "pixel", resolution)
    gouraud = _row(interpolation_study, "gouraud", resolution)
    assert pixel["highlight_rmse"] < gouraud["highlight_rmse"], f"resolution {resolution}: {pixel}, {gouraud}"
    assert pixel["peak_error"] < gouraud["peak_error"], f"resolution {resolution}: {pixel}, {gouraud}"


def test_pixel_shading_converges_as_the_mesh_refines(interpolation_study):
    errors = [_row(interpolation_study, "pixel", r)["rmse"] for r in (8, 16, 32, 64)]
    assert all(a > b for a, b in zip(errors, errors[1:])), f"pixel RMSE at 8, 16, 32, 64: {errors}"


def test_every_row_reports_its_figures(interpolation_study):
    for row in interpolation_study["rows"]:
        for key in ("rmse", "max_error", "highlight_rmse", "peak_error", "time"):
            assert math.isfinite(row[key]) and row[key] >= 0, f"{key} in {row}"
        assert row["rmse"] <= row["max_error"], row


def test_float64_is_closer_to_50_digits_than_float32():
    study = precision.run(points=30, timed_points=2000, repeats=1)
    for case in precision.CASES:
        err = {r["precision"]: r["max_rel_error"] for r in study["rows"] if r["case"] == case}
        assert err["float64"] < err["float32"], f"case {case}: {err}"
        assert err["float64"] < 1e-9, f"case {case}: {err}"


def test_mpmath_reference_matches_a_hand_value():
    # point (0, 0, 1) facing up, light straight above, eye straight above: n·l = r·v = 1
    m = core.Material(ka=0.1, kd=0.6, ks=0.5, shininess=1e6)
    got = precision.phong_mp((0, 0, 1), (0, 0, 1), (0, 0, 4), (0, 0, 3), m)
    assert float(got["color"]) == pytest.approx(1.2, rel=1e-15)


def test_blinn_phong_with_four_alpha_is_closer_to_phong():
    study = models.run(alphas=(20.0,), size=48, timed_points=2000, repeats=1)
    for setup in models.SETUPS:
        diff = {r["blinn_exponent"]: r["max_diff"] for r in study["rows"] if r["setup"] == setup}
        assert diff["4a"] < diff["a"] / 3, f"{setup}: max differences to Phong {diff}"


def test_monte_carlo_study_error_falls_with_the_expected_slopes():
    study = arealight.run(samples=(4, 16, 64, 256), seeds=4, side=8, repeats=1)
    for method in ("uniform", "stratified"):
        errors = [r["error"] for r in study["rows"] if r["method"] == method]
        assert all(a > b for a, b in zip(errors, errors[1:])), f"{method}: {errors}"
    assert -0.7 < study["slopes"]["uniform"] < -0.3, study["slopes"]
    assert study["slopes"]["stratified"] < -0.75, study["slopes"]


# ---------------------------------------------------------------------------
# the lesson's images


def test_error_images_are_rgb_uint8_and_match_the_study():
    view = interpolation.error_images("gouraud", 16, size=48, repeats=1)
    for name in ("render", "reference", "error"):
        image = getattr(view, name)
        assert image.shape == (48, 48, 3) and image.dtype == np.uint8, f"{name}: {image.shape} {image.dtype}"
    # the highlight is white-ish in the reference, and the error is brightest where Gouraud misses it
    setup = interpolation.default_setup(48)
    ref = interpolation.reference(setup, repeats=1)
    row, col = ref.peak
    assert view.reference[row, col].min() > 200, view.reference[row, col]
    assert view.error[row, col].sum() > view.error[ref.mask].reshape(-1, 3).sum(axis=1).mean()
    assert 0 < view.rmse <= view.max_error


def test_error_images_follow_the_shininess():
    # a broad highlight (α = 5) is easy for Gouraud shading; a tight one (α = 200) is not
    broad = interpolation.error_images("gouraud", 24, size=48, shininess=5.0, repeats=1)
    tight = interpolation.error_images("gouraud", 24, size=48, shininess=200.0, repeats=1)
    assert broad.peak_error < tight.peak_error, (broad.peak_error, tight.peak_error)


def test_pixel_error_image_is_darker_than_flat():
    flat = interpolation.error_images("flat", 16, size=32, repeats=1)
    pixel = interpolation.error_images("pixel", 16, size=32, repeats=1)
    assert pixel.rmse < flat.rmse
    assert pixel.error.astype(float).mean() < flat.error.astype(float).mean()


@pytest.mark.parametrize("kwargs, field", [
    ({"method": "phong", "resolution": 16}, "method"),
    ({"method": "pixel", "resolution": 2}, "resolution"),
    ({"method": "pixel", "resolution": 16, "size": 5000}, "size"),
    ({"method": "pixel", "resolution": 16, "size": 32, "shininess": -1}, "shininess"),
])
def test_error_images_refuse_bad_input_naming_the_field(kwargs, field):
    with pytest.raises(ValueError, match=f"^{field}:"):
        interpolation.error_images(**kwargs)


# ---------------------------------------------------------------------------
# the figure, the command and the lesson


TINY = {
    "interpolation": {"resolutions": (8, 16), "size": 32, "repeats": 1, "min_seconds": 0.0},
    "precision": {"points": 8, "timed_points": 1000, "repeats": 1},
    "models": {"alphas": (10.0,), "size": 32, "timed_points": 1000, "repeats": 1},
    "area_light": {"samples": (1, 4, 16), "seeds": 2, "side": 4, "repeats": 1},
}


@pytest.fixture(scope="module")
def tiny_results():
    import phonglab.accuracy as acc

    saved = dict(acc.QUICK)
    acc.QUICK.update(TINY)
    try:
        yield acc.run_studies(quick=True)
    finally:
        acc.QUICK.clear()
        acc.QUICK.update(saved)


@pytest.mark.parametrize("ext, magic", [("png", b"\x89PNG"), ("svg", b"<?xml"), ("pdf", b"%PDF")])
def test_figure_is_written_atomically_in_the_format_of_its_extension(tiny_results, tmp_path, ext, magic):
    from phonglab.accuracy import write_figure

    path = tmp_path / f"plot.{ext}"
    assert write_figure(tiny_results, path) == str(path)
    assert path.read_bytes()[: len(magic)] == magic
    assert [p.name for p in tmp_path.iterdir()] == [path.name], "a temporary file was left behind"


def test_figure_refuses_an_unknown_extension(tiny_results, tmp_path):
    from phonglab.accuracy import accuracy_plot_png, write_figure

    with pytest.raises(ValueError, match="png, .svg or .pdf"):
        write_figure(tiny_results, tmp_path / "plot.jpg")
    with pytest.raises(ValueError, match=r"\.png"):
        accuracy_plot_png(tmp_path / "plot.svg", results=tiny_results)
    assert list(tmp_path.iterdir()) == []


def test_report_names_every_study_and_its_reference(tiny_results):
    from phonglab.accuracy import format_report

    text = format_report(tiny_results)
    for study in tiny_results["studies"]:
        assert study["title"] in text and study["reference"] in text
    assert "fitted slope" in text


def test_bench_command_prints_json_and_writes_the_figure(tiny_results, tmp_path, capsys, monkeypatch):
    import phonglab.accuracy as acc
    from phonglab.cli import main

    monkeypatch.setattr(acc, "QUICK", {**acc.QUICK, **TINY})
    figure = tmp_path / "out.svg"
    assert main(["bench", "accuracy", "--quick", "--json", "--figure", str(figure)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [s["name"] for s in data["studies"]] == ["interpolation", "precision", "models", "area_light"]
    assert data["figure"] == str(figure) and figure.exists()


@pytest.mark.parametrize("path, message", [
    ("plot.gif", "must end in .png, .svg or .pdf"),
    ("no/such/folder/plot.png", "does not exist"),
])
def test_bench_command_refuses_a_bad_figure_path(tmp_path, capsys, monkeypatch, path, message):
    from phonglab.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["bench", "accuracy", "--quick", "--figure", path]) == 2
    err = capsys.readouterr().err
    assert "--figure" in err and message in err and path in err, err
    assert list(tmp_path.iterdir()) == []


def test_the_lesson_loads_with_its_number():
    from phonglab.scene import load_lesson

    lesson = load_lesson(REPO / "lessons" / "11-accuracy.md")
    assert lesson.number == 11
    assert "accuracy" in lesson.title.lower()
    for word in ("Gouraud", "float32", "Blinn", "Monte Carlo"):
        assert word in lesson.body, word
