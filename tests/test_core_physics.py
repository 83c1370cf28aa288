"""The named physics helpers: each guard at the input it guards, and one formula for every caller.

face_forward, attenuation and spot_factor are written once in
phonglab.core.physics; these tests pin each guard with eps-sized inputs
and check that the fast kernel, vectors() and the reference kernel all
give the helper's value.
"""

import math

import numpy as np
import pytest

import phonglab as pl
from phonglab.core.physics import SPOT_SLACK_ULPS

DTYPES = [np.float32, np.float64]
MAT_DIFFUSE = pl.Material(ka=0, kd=1, ks=0, shininess=1)


# ---------------------------------------------------------------------------
# face-forward


@pytest.mark.parametrize("dtype", DTYPES)
def test_face_forward_flips_at_the_smallest_negative_n_dot_v(dtype):
    tiny = np.finfo(dtype).tiny  # the smallest normal number: n·v is -tiny, 0 or +tiny
    v = np.array([1.0, 0.0, 0.0], dtype)
    n = np.array([[-tiny, 0, 1], [0, 0, 1], [tiny, 0, 1], [-1, 0, 0]], dtype)
    got = pl.face_forward(n, v)
    want = np.array([[tiny, 0, -1], [0, 0, 1], [tiny, 0, 1], [1, 0, 0]], dtype)
    assert got.dtype == dtype and np.array_equal(got, want), f"n={n.tolist()} v={v.tolist()} got {got.tolist()}"
    assert pl.facing_away(n, v).tolist() == [True, False, False, True], n.tolist()


def test_face_forward_keeps_a_zero_normal_and_a_zero_view():
    # n·v = 0 exactly: not facing away, nothing to flip (and never NaN)
    n = np.array([[0.0, 0, 0], [0, 0, -1]])
    v = np.array([[0.0, 0, 1], [0, 0, 0]])
    assert np.array_equal(pl.face_forward(n, v), n), pl.face_forward(n, v).tolist()


def test_face_forward_components_first_is_the_same_function():
    rng = np.random.default_rng(3)
    n, v = rng.normal(size=(50, 3)), rng.normal(size=(50, 3))
    rows = pl.face_forward(n, v)
    columns = pl.face_forward(n.T.copy(), v.T.copy(), axis=0)
    assert np.array_equal(rows, columns.T)
    # and in place, as the fast kernel calls it
    inplace = n.T.copy()
    out = pl.face_forward(inplace, v.T, axis=0, out=inplace)
    assert out is inplace and np.array_equal(inplace.T, rows)


def test_face_forward_negates_exactly():
    rng = np.random.default_rng(4)
    n, v = rng.normal(size=(200, 3)), rng.normal(size=(200, 3))
    away = np.einsum("ij,ij->i", n, v) < 0
    assert away.any() and (~away).any()
    assert np.array_equal(pl.face_forward(n, v), np.where(away[:, None], -n, n))


# ---------------------------------------------------------------------------
# distance attenuation


@pytest.mark.parametrize("dtype", DTYPES)
def test_attenuation_floors_an_eps_sized_distance(dtype):
    # a light on the point, or an eps-sized distance below the floor: d = DISTANCE_FLOOR
    eps = np.finfo(dtype).eps
    dist = np.array([0.0, eps, pl.DISTANCE_FLOOR / 2], dtype)
    a, b, c = 1.0, 2.0, 3.0
    f = pl.attenuation(dist, (a, b, c))
    d = dtype(pl.DISTANCE_FLOOR)
    want = dtype(1) / (dtype(a) + d * (dtype(b) + dtype(c) * d))
    assert f.dtype == dtype and (f == want).all(), f"dist={dist} got {f} want {want}"


@pytest.mark.parametrize("dtype", DTYPES)
def test_attenuation_is_capped_at_attenuation_max(dtype):
    # inverse square at the floor would be 1e12 exactly; a smaller c or a pure linear b goes past the cap
    f = pl.attenuation(np.array([0.0, 0.0], dtype), (0, 0, 1e-3))
    assert (f == dtype(pl.ATTENUATION_MAX)).all() and np.isfinite(f).all(), f
    g = pl.attenuation(np.array([0.0], dtype), (0, 1e-9, 0))
    assert g[0] == dtype(pl.ATTENUATION_MAX), g


@pytest.mark.parametrize("dtype", DTYPES)
def test_attenuation_skips_zero_terms_at_an_infinite_distance(dtype):
    # 0·inf would be NaN: a term whose coefficient is 0 is left out of the sum
    inf = np.array([np.inf], dtype)
    assert pl.attenuation(inf, (2, 0, 0))[0] == dtype(0.5)
    assert pl.attenuation(inf, (1, 0, 1))[0] == 0
    assert pl.attenuation(inf, (1, 1, 0))[0] == 0
    huge = np.array([np.finfo(dtype).max], dtype)
    with np.errstate(all="raise"):  # c·d² overflows to inf on purpose, silently
        assert pl.attenuation(huge, (1, 0, 1))[0] == 0


def test_attenuation_formula_away_from_the_guards():
    d = np.array([0.5, 1.0, 5.0])
    np.testing.assert_allclose(pl.attenuation(d, (1, 0.1, 0.01)), 1 / (1 + 0.1 * d + 0.01 * d * d), rtol=1e-15)


# ---------------------------------------------------------------------------
# the spot factor


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("cutoff", [10.0, 45.0, 89.0])
def test_spot_cone_test_has_its_slack_and_no_more(dtype, cutoff):
    limit = pl.spot_cos_limit(cutoff, dtype)
    eps = np.finfo(dtype).eps
    assert limit == dtype(math.cos(math.radians(cutoff)) - SPOT_SLACK_ULPS * eps), (cutoff, limit)
    # a cosine a few eps below cos(cutoff), at the limit: inside; the next float down: outside
    on_cone = np.array([dtype(math.cos(math.radians(cutoff))), limit, np.nextafter(limit, dtype(-1))], dtype)
    f = pl.spot_factor(on_cone, cutoff=cutoff, exponent=2.0)
    assert f.dtype == dtype, f.dtype
    assert f[0] > 0 and f[1] > 0 and f[2] == 0, f"cos={on_cone.tolist()} limit={limit} factor={f.tolist()}"


@pytest.mark.parametrize("dtype", DTYPES)
def test_spot_clamps_before_the_power_at_cutoff_90(dtype):
    # just behind the light's plane, cos ≈ −eps passes the slackened test: max(0, ·) keeps 0^e finite
    eps = np.finfo(dtype).eps
    cos_axis = np.array([-eps, -0.0, 0.0], dtype)
    for exponent in (0.5, 3.0):
        f = pl.spot_factor(cos_axis, cutoff=90.0, exponent=exponent)
        assert np.isfinite(f).all() and (f == 0).all(), f"exponent={exponent} factor={f.tolist()}"
    # exponent 0: inside the cone the factor is 1, x^0 = 1 even at x = 0
    assert (pl.spot_factor(cos_axis, cutoff=90.0, exponent=0.0) == 1).all()


def test_spot_cutoff_180_is_one_everywhere_even_behind():
    cos_axis = np.array([1.0, 0.0, -1.0])
    assert (pl.spot_factor(cos_axis, cutoff=180.0, exponent=7.0) == 1).all()


def test_spot_factor_in_place_matches_the_fresh_result():
    rng = np.random.default_rng(5)
    c = rng.uniform(-1, 1, 1000).astype(np.float32)
    fresh = pl.spot_factor(c, cutoff=40.0, exponent=3.5)
    buf = c.copy()
    assert pl.spot_factor(buf, cutoff=40.0, exponent=3.5, out=buf) is buf
    assert np.array_equal(buf, fresh)
    inside = c >= np.cos(np.radians(40.0))
    np.testing.assert_allclose(fresh, np.where(inside, np.maximum(c, 0) ** 3.5, 0), rtol=1e-6)


# ---------------------------------------------------------------------------
# every caller uses the helper's value


@pytest.mark.parametrize("dtype", DTYPES)
def test_shade_vectors_and_reference_share_the_light_factor(dtype):
    # diffuse k_d = 1 and n = l make the diffuse term the light factor f_l itself
    spot = pl.SpotLight(position=(0, 0, 0), direction=(0, 0.2, -1), cutoff=30, exponent=3.5,
                        attenuation=(0.5, 0.3, 0.2))
    rng = np.random.default_rng(6)
    p = (rng.normal(size=(300, 3)) * (0.5, 0.5, 0.1) + (0, 0, -2)).astype(dtype)
    l, dist = pl.normalize(np.asarray(spot.position, dtype) - p, return_length=True)
    axis = pl.normalize(np.asarray(spot.direction, dtype))
    f = pl.attenuation(dist, spot.attenuation) * pl.spot_factor(-pl.dot(l, axis), cutoff=30, exponent=3.5)
    assert (f > 0).any() and (f == 0).any(), "the points must straddle the cone"
    fast = pl.shade(p, l, material=MAT_DIFFUSE, lights=[spot], eye=(0, 0, 5)).diffuse[:, 0]
    ref = pl.shade_reference(p, l, material=MAT_DIFFUSE, lights=[spot], eye=(0, 0, 5)).diffuse[:, 0]
    np.testing.assert_allclose(fast, f, rtol=4 * np.finfo(dtype).eps, err_msg=f"fast, {dtype}")
    np.testing.assert_allclose(ref, f, rtol=4 * np.finfo(dtype).eps, err_msg=f"reference, {dtype}")
    assert np.array_equal(fast == 0, f == 0) and np.array_equal(ref == 0, f == 0), "the same cone"
    if dtype == np.float64:
        for i in range(0, 300, 37):
            pv = pl.vectors(p[i], l[i], light=spot, eye=(0, 0, 5))
            assert pv.attenuation * pv.spot == pytest.approx(float(f[i]), rel=1e-15, abs=0), (p[i], pv)
