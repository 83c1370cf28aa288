"""Invariants of the model, checked on random inputs with hypothesis."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import phonglab as pl

finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
vec3 = st.tuples(finite, finite, finite)
coef = st.floats(0, 2, allow_nan=False)
unit_scale = st.floats(0.0, 1.0)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


@st.composite
def unit_vectors(draw):
    v = np.array(draw(vec3))
    assume(np.linalg.norm(v) > 1e-3)
    return unit(v)


@st.composite
def scenes(draw):
    mat = pl.Material(ka=draw(coef), kd=(draw(coef), draw(coef), draw(coef)), ks=draw(coef),
                      shininess=draw(st.floats(0, 500)))
    lights = []
    for kind in draw(st.lists(st.sampled_from(["point", "dir", "spot", "ambient"]), min_size=1, max_size=4)):
        if kind == "point":
            lights.append(pl.PointLight(position=draw(vec3), attenuation=(1, draw(coef), draw(coef))))
        elif kind == "dir":
            d = draw(vec3)
            assume(any(d))
            lights.append(pl.DirectionalLight(direction=d, color=(draw(coef), draw(coef), draw(coef))))
        elif kind == "spot":
            d = draw(vec3)
            assume(any(d))
            lights.append(pl.SpotLight(position=draw(vec3), direction=d,
                                       cutoff=draw(st.sampled_from([10.0, 45.0, 90.0, 180.0])),
                                       exponent=draw(st.floats(0, 50))))
        else:
            lights.append(pl.AmbientLight(intensity=draw(coef)))
    return mat, lights


def random_points(seed, n=64):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(n, 3)), rng.normal(size=(n, 3))


@settings(max_examples=60, deadline=None)
@given(scenes(), st.integers(0, 2**32 - 1), st.sampled_from(pl.MODELS), st.booleans())
def test_terms_are_nonnegative_and_finite(scene, seed, model, two_sided):
    mat, lights = scene
    p, n = random_points(seed)
    s = pl.shade(p, n, eye=(0, 0, 6), material=mat, lights=lights, model=model, two_sided=two_sided)
    for name in ("ambient", "diffuse", "specular", "emission", "color"):
        arr = getattr(s, name)
        assert np.isfinite(arr).all() and (arr >= 0).all(), (name, mat, lights, seed, model)


@settings(max_examples=100, deadline=None)
@given(unit_vectors(), unit_vectors())
def test_reflection_is_unit_and_an_involution(l, n):
    r = pl.reflect(l, n)
    assert abs(np.linalg.norm(r) - 1) < 1e-12, (l, n, r)
    np.testing.assert_allclose(pl.reflect(r, n), l, atol=1e-12, err_msg=f"l={l} n={n}")


@settings(max_examples=100, deadline=None)
@given(unit_vectors(), unit_vectors(), st.floats(1, 1000), st.sampled_from(pl.PHONG_MODELS))
def test_specular_peak_sits_at_r_equals_v_and_is_bounded(l, v, alpha, model):
    n = np.array([0.0, 0.0, 1.0])
    assume(l @ n > 1e-3)
    mat = pl.Material(ka=0, kd=0, ks=0.7, shininess=alpha)
    light = pl.DirectionalLight(direction=l, intensity=1.5)
    r = pl.reflect(l, n)
    peak = pl.shade([[0, 0, 0]], [n], view_direction=r, material=mat, lights=[light], model=model).specular[0, 0]
    other = pl.shade([[0, 0, 0]], [n], view_direction=v, material=mat, lights=[light], model=model).specular[0, 0]
    bound = 0.7 * 1.5
    assert peak == pytest.approx(bound, rel=1e-9), (l, alpha, model)  # r = v: (r·v)^α = 1; n·h = 1
    assert 0 <= other <= peak * (1 + 1e-12), (l, v, alpha, model, other, peak)


@settings(max_examples=100, deadline=None)
@given(st.floats(0.0, 1.5), st.floats(0.0, 1.5), st.floats(20, 400))
def test_phong_alpha_matches_blinn_4alpha_in_plane(theta_l, theta_v, alpha):
    # n, l, v coplanar: the r-v angle is twice the n-h angle, so (r·v)^α ≈ (n·h)^(4α)
    l = np.array([np.sin(theta_l), 0, np.cos(theta_l)])
    v = np.array([-np.sin(theta_v), 0, np.cos(theta_v)])
    n = np.array([0.0, 0, 1])
    light = pl.DirectionalLight(direction=l)
    phong = pl.shade([[0, 0, 0]], [n], view_direction=v, lights=[light],
                     material=pl.Material(ka=0, kd=0, ks=1, shininess=alpha)).specular[0, 0]
    blinn = pl.shade([[0, 0, 0]], [n], view_direction=v, lights=[light], model="blinn-phong",
                     material=pl.Material(ka=0, kd=0, ks=1, shininess=4 * alpha)).specular[0, 0]
    # the two lobes differ by O(α θ⁴) in the exponent, i.e. by a few per cent at the most
    assert abs(phong - blinn) <= 0.06, (theta_l, theta_v, alpha, phong, blinn)


@settings(max_examples=60, deadline=None)
@given(scenes(), st.integers(0, 2**32 - 1), st.sampled_from(pl.MODELS))
def test_float32_agrees_with_float64(scene, seed, model):
    mat, lights = scene
    assume(mat.shininess <= 200)
    p, n = random_points(seed)
    s64 = pl.shade(p, n, eye=(0, 0, 6), material=mat, lights=lights, model=model).color
    s32 = pl.shade(p.astype(np.float32), n.astype(np.float32), eye=(0, 0, 6), material=mat,
                   lights=lights, model=model).color
    assert s32.dtype == np.float32
    # inputs rounded to float32 move cosines by ~1e-7; α ≤ 200 amplifies that 200-fold
    np.testing.assert_allclose(s32, s64, rtol=2e-3, atol=2e-4, err_msg=f"{mat} {lights} seed={seed}")


@settings(max_examples=60, deadline=None)
@given(scenes(), st.integers(0, 2**32 - 1), st.sampled_from(pl.MODELS), st.booleans(), st.booleans())
def test_planned_equals_full_evaluation(scene, seed, model, two_sided, infinite):
    mat, lights = scene
    p, n = random_points(seed)
    view = dict(view_direction=(0.2, 0.1, 1)) if infinite else dict(eye=(0, 0, 6))
    kw = dict(material=mat, lights=lights, model=model, two_sided=two_sided, **view)
    planned = pl.shade(p, n, **kw)
    full = pl.shade(p, n, plan="full", **kw)
    for name in ("ambient", "diffuse", "specular", "emission", "color"):
        np.testing.assert_array_max_ulp(getattr(planned, name), getattr(full, name), maxulp=1)
