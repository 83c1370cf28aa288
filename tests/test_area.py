"""Area lights: Lambert's closed form against brute force, known values and limits;
the point approximation; Monte Carlo (uniform and stratified) and its convergence."""

from __future__ import annotations

import math

import numpy as np
import pytest

from phonglab import core
from phonglab.core.area import AreaLight, area_diffuse, area_irradiance, polygon_irradiance, strata_shape

# a 1 x 1 panel at height 1 shining down (-z)
PANEL = AreaLight(position=(0.0, 0.0, 1.0), edge_u=(1.0, 0.0, 0.0), edge_v=(0.0, -1.0, 0.0), intensity=1.0)
UP = np.array([0.0, 0.0, 1.0])


def midpoint_irradiance(light: AreaLight, x, n, m: int = 1000) -> float:
    """Brute force: the midpoint rule on an m x m grid over the light's area."""
    s = (np.arange(m) + 0.5) / m - 0.5
    a, b = np.meshgrid(s, s)
    y = (np.asarray(light.position) + a.reshape(-1, 1) * np.asarray(light.edge_u)
         + b.reshape(-1, 1) * np.asarray(light.edge_v))
    d = y - np.asarray(x, float)
    dist2 = np.einsum("ij,ij->i", d, d)
    cos_x = np.maximum(d @ np.asarray(n, float), 0)
    cos_y = np.maximum(-(d @ light.normal), 0)
    kernel = cos_x * cos_y / dist2**2
    return float(light.radiance * light.area * kernel.mean())


def corner_form_factor(a: float, b: float, h: float) -> float:
    """Form factor from a point to an a x b rectangle parallel to it, one corner straight above.

    The textbook closed form for parallel planes (e.g. Howell's catalogue of
    configuration factors), independent of Lambert's edge sum.
    """
    x, y = a / h, b / h
    sx, sy = math.sqrt(1 + x * x), math.sqrt(1 + y * y)
    return (x / sx * math.atan(y / sx) + y / sy * math.atan(x / sy)) / (2 * math.pi)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


# ---------------------------------------------------------------------------
# the exact closed form


@pytest.mark.parametrize("point, normal", [
    ((0.0, 0.0, 0.0), (0, 0, 1)),          # centred below
    ((1.2, -0.4, 0.0), (0, 0, 1)),         # off to the side
    ((0.3, 0.2, 0.5), (0.3, -0.2, 1)),     # tilted normal, light fully above
    ((0.0, 0.0, 0.5), (1, 0, 0)),          # horizon cuts the light in half
    ((0.2, -0.1, 0.7), (1, 0.5, 0.3)),     # horizon cuts a corner off
    ((0.4, 0.4, 0.9), (-0.2, 0.1, -1)),    # facing mostly away: a sliver
])
def test_closed_form_matches_brute_force_integral(point, normal):
    n = unit(normal)
    exact = float(area_irradiance(PANEL, point, n))
    brute = midpoint_irradiance(PANEL, point, n, m=1200)
    assert exact == pytest.approx(brute, rel=2e-4, abs=1e-7), (
        f"point {point}, normal {normal}: Lambert {exact!r}, midpoint rule {brute!r}")


def test_closed_form_matches_monte_carlo_at_many_samples():
    points = np.array([[0.0, 0.0, 0.0], [0.8, 0.3, 0.2], [0.1, 0.0, 0.6]])
    normals = np.array([unit((0, 0, 1)), unit((0.2, 0.3, 1)), unit((1, 0, 0.1))])
    exact = area_irradiance(PANEL, points, normals)
    estimate = area_irradiance(PANEL, points, normals, method="stratified", samples=250_000, seed=11)
    np.testing.assert_allclose(estimate, exact, rtol=1e-4,
                               err_msg=f"points {points.tolist()}, normals {normals.tolist()}")


@pytest.mark.parametrize("half, height", [(0.5, 1.0), (1.0, 0.5), (0.1, 3.0)])
def test_square_centred_above_a_point_matches_the_form_factor_table(half, height):
    light = AreaLight(position=(0, 0, height), edge_u=(2 * half, 0, 0), edge_v=(0, -2 * half, 0), intensity=1.0)
    expected = light.radiance * math.pi * 4 * corner_form_factor(half, half, height)
    got = float(area_irradiance(light, (0.0, 0.0, 0.0), UP))
    assert got == pytest.approx(expected, rel=1e-12), f"square half-side {half} at height {height}"


def test_rectangle_with_a_corner_above_the_point_matches_the_form_factor_table():
    a, b, h = 0.7, 1.9, 0.8
    light = AreaLight(position=(a / 2, b / 2, h), edge_u=(a, 0, 0), edge_v=(0, -b, 0), intensity=2.0)
    expected = light.radiance * math.pi * corner_form_factor(a, b, h)
    got = float(area_irradiance(light, (0.0, 0.0, 0.0), UP))
    assert got == pytest.approx(expected, rel=1e-12), f"rectangle {a} x {b} at height {h}"


def test_unit_square_value_in_the_docstring():
    # 4 corner rectangles 0.5 x 0.5 at height 1: 0.752275 (hand-checked from the table formula)
    assert float(polygon_irradiance([0, 0, 0.0], UP, PANEL.vertices)) == pytest.approx(
        math.pi * 4 * corner_form_factor(0.5, 0.5, 1.0), rel=1e-12)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (3.0, -2.0)])
def test_small_far_light_tends_to_the_point_formula(offset):
    # a light of side s at distance ~D: exact / point -> 1 like (s/D)^2
    x = np.array([offset[0], offset[1], 0.0])
    ratios = []
    for side in (0.4, 0.1, 0.025):
        light = AreaLight(position=(0, 0, 4.0), edge_u=(side, 0, 0), edge_v=(0, -side, 0), intensity=1.0)
        exact = float(area_irradiance(light, x, UP))
        point = float(area_irradiance(light, x, UP, method="point"))
        ratios.append(abs(exact / point - 1))
    assert ratios[-1] < 1e-4, f"offset {offset}: relative gaps {ratios}"
    assert ratios[0] > ratios[1] > ratios[2], f"offset {offset}: gaps should shrink with the light, {ratios}"
    # quartering the side shrinks the gap about 16-fold
    assert 8 < ratios[1] / ratios[2] < 32, f"offset {offset}: gaps {ratios}"


def test_point_approximation_is_the_inverse_square_cosine_law():
    x = np.array([0.6, -0.3, 0.0])
    d = np.asarray(PANEL.position) - x
    dist = np.linalg.norm(d)
    cos_x = d[2] / dist
    cos_y = d[2] / dist  # the panel faces straight down
    expected = PANEL.intensity * cos_x * cos_y / dist**2
    assert float(area_irradiance(PANEL, x, UP, method="point")) == pytest.approx(expected, rel=1e-14)


# ---------------------------------------------------------------------------
# guards: one-sided emitter, horizon, degenerate positions


def test_points_behind_the_light_receive_nothing():
    above = np.array([[0.0, 0.0, 2.0], [0.3, 0.1, 1.5]])
    for method in ("exact", "point", "uniform", "stratified"):
        e = area_irradiance(PANEL, above, np.array([0.0, 0.0, -1.0]), method=method, samples=16, seed=0)
        assert np.all(e == 0), f"{method}: points above a downward panel got {e}"


def test_flipping_the_winding_flips_the_emitting_side():
    flipped = AreaLight(position=PANEL.position, edge_u=PANEL.edge_v, edge_v=PANEL.edge_u)
    below, above = np.array([0.0, 0.0, 0.0]), np.array([0.0, 0.0, 2.0])
    assert float(area_irradiance(flipped, below, UP)) == 0.0
    assert float(area_irradiance(flipped, above, -UP)) == pytest.approx(float(area_irradiance(PANEL, below, UP)), rel=1e-13)


def test_light_entirely_below_the_horizon_gives_zero():
    # the surface faces away from the light
    assert float(area_irradiance(PANEL, (0.0, 0.0, 0.0), -UP)) == 0.0
    # the light's corners are all below the tangent plane of a tilted surface
    n = unit((1.0, 0.0, -1.5))
    assert float(area_irradiance(PANEL, (-1.0, 0.0, 0.0), n)) == pytest.approx(
        midpoint_irradiance(PANEL, (-1.0, 0.0, 0.0), n, m=200), abs=1e-15)


def test_point_in_the_light_plane_outside_it_gets_nothing():
    e = float(area_irradiance(PANEL, (2.0, 0.0, 1.0), unit((-1, 0, 0.0))))
    assert e == pytest.approx(0.0, abs=1e-12), f"a point in the panel's plane got {e}"


def test_horizon_through_a_corner_is_continuous():
    # a vertex exactly on the tangent plane, and the same with the plane nudged by 1e-12
    x = np.array([0.5, 0.5, 0.0])  # the corner (0.5, 0.5, 1) lies straight above
    n_on = unit((1.0, 0.0, 0.0))  # tangent plane x = 0.5 passes through two corners
    n_near = unit((1.0, 0.0, 1e-12))
    e_on, e_near = float(area_irradiance(PANEL, x, n_on)), float(area_irradiance(PANEL, x, n_near))
    assert e_on == pytest.approx(e_near, abs=1e-10), f"on the plane {e_on}, nudged {e_near}"
    assert e_on == pytest.approx(0.0, abs=1e-10)  # the light lies entirely at x <= 0.5


def test_float32_stays_float32_and_agrees_with_float64():
    x = np.array([[0.2, 0.1, 0.0], [1.0, -0.5, 0.3]])
    n = np.array([UP, unit((0.1, 0.2, 1))])
    e32 = area_irradiance(PANEL, x.astype(np.float32), n.astype(np.float32))
    e64 = area_irradiance(PANEL, x, n)
    assert e32.dtype == np.float32 and e64.dtype == np.float64
    np.testing.assert_allclose(e32, e64, rtol=1e-5)


# ---------------------------------------------------------------------------
# Monte Carlo


def test_monte_carlo_is_reproducible_with_a_seed():
    x = np.zeros((4, 3))
    a = area_irradiance(PANEL, x, UP, method="uniform", samples=32, seed=5)
    b = area_irradiance(PANEL, x, UP, method="uniform", samples=32, seed=5)
    c = area_irradiance(PANEL, x, UP, method="uniform", samples=32, seed=6)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


@pytest.mark.parametrize("method", ["uniform", "stratified"])
def test_monte_carlo_error_falls_as_samples_grow(method):
    # RMS relative error over 64 floor points and 8 seeds, at N = 4, 64, 1024
    s = np.linspace(-1, 1, 8)
    gx, gy = np.meshgrid(s, s)
    x = np.stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)], axis=1)
    exact = area_irradiance(PANEL, x, UP)
    errors = []
    for n in (4, 64, 1024):
        per_seed = [np.linalg.norm(area_irradiance(PANEL, x, UP, method=method, samples=n, seed=seed) - exact)
                    / np.linalg.norm(exact) for seed in range(8)]
        errors.append(float(np.sqrt(np.mean(np.square(per_seed)))))
    assert errors[0] > errors[1] > errors[2], f"{method}: errors at N = 4, 64, 1024: {errors}"
    # 16x the samples: at least the 1/sqrt(N) factor of 4, within noise
    assert errors[0] / errors[1] > 2.5 and errors[1] / errors[2] > 2.5, f"{method}: {errors}"


def test_monte_carlo_is_unbiased():
    # the mean of many independent 16-sample estimates sits within 4 standard errors
    x = np.array([[0.4, -0.2, 0.0]])
    exact = float(area_irradiance(PANEL, x, UP)[0])
    many = np.repeat(x, 4000, axis=0)
    est = area_irradiance(PANEL, many, UP, method="uniform", samples=16, seed=3)
    stderr = est.std() / math.sqrt(est.size)
    assert abs(est.mean() - exact) < 4 * stderr, f"mean {est.mean()}, exact {exact}, standard error {stderr}"


def test_stratified_beats_uniform_at_the_same_samples():
    x = np.array([[0.0, 0.0, 0.0], [0.9, 0.4, 0.0]])
    exact = area_irradiance(PANEL, x, UP)
    err = {m: np.sqrt(np.mean([np.sum((area_irradiance(PANEL, x, UP, method=m, samples=256, seed=s) - exact) ** 2)
                               for s in range(10)])) for m in ("uniform", "stratified")}
    assert err["stratified"] < err["uniform"] / 3, f"RMS errors at N = 256: {err}"


def test_strata_cover_exactly_the_requested_count():
    for n in range(1, 200):
        rows, cols = strata_shape(n)
        assert rows * cols == n and rows <= cols, f"N = {n}: grid {rows} x {cols}"


# ---------------------------------------------------------------------------
# validation and the RGB term


def test_parallel_edges_are_refused_naming_the_field():
    with pytest.raises(core.InvalidValue, match=r"AreaLight\.edge_v.*parallel"):
        AreaLight(position=(0, 0, 1), edge_u=(1, 0, 0), edge_v=(2, 0, 0))
    with pytest.raises(core.InvalidValue, match=r"AreaLight\.edge_u"):
        AreaLight(position=(0, 0, 1), edge_u=(0, 0, 0))
    with pytest.raises(core.InvalidValue, match=r"AreaLight\.intensity"):
        AreaLight(position=(0, 0, 1), intensity=-1)


def test_bad_method_and_samples_are_refused():
    with pytest.raises(core.InvalidValue, match="method"):
        area_irradiance(PANEL, (0, 0, 0.0), UP, method="quasi")
    with pytest.raises(core.InvalidValue, match="samples"):
        area_irradiance(PANEL, (0, 0, 0.0), UP, method="uniform", samples=0)


def test_area_diffuse_is_kd_times_colour_times_irradiance():
    light = AreaLight(position=(0, 0, 1.0), edge_u=(1, 0, 0), edge_v=(0, -1, 0), color=(1.0, 0.5, 0.25),
                      intensity=3.0)
    material = core.Material(ka=0.1, kd=(0.8, 0.3, 0.2), ks=0.5, shininess=10)
    x = np.array([[0.1, 0.2, 0.0], [0.0, 0.0, 0.5]])
    e = area_irradiance(light, x, UP)
    got = area_diffuse(x, UP, material=material, light=light)
    np.testing.assert_allclose(got, e[:, None] * np.array([0.8, 0.15, 0.05]), rtol=1e-14)
