"""The fast kernel agrees with the reference kernel, the model written one light at a time.

Tolerance, per term and channel, with ``scale`` the largest magnitude of that
term over the points and ``eps`` the machine epsilon of the working dtype:

    |shade − shade_reference| ≤ 8 (1 + α) eps · scale + tiny

(``tiny`` the smallest normal number: coefficients like 1e-45 are subnormal
in float32, where relative rounding means nothing).
The reference computes ``max(0, c)^α`` from the cosine ``c`` directly, so
its relative error grows like ``α`` ulps near the highlight; the fast kernel
stays within a few ulps there. Diffuse, ambient and emission agree within a
few ulps. A failure prints the scene, the seed and where the terms differ.
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import phonglab as pl

finite = st.floats(-4, 4, allow_nan=False, allow_infinity=False)
vec3 = st.tuples(finite, finite, finite)
coef = st.floats(0, 2, allow_nan=False)
TERMS = ("ambient", "diffuse", "specular", "emission", "color")


@st.composite
def lights(draw):
    out = []
    for kind in draw(st.lists(st.sampled_from(["point", "dir", "spot", "ambient"]), min_size=1, max_size=4)):
        rgb = (draw(coef), draw(coef), draw(coef))
        if kind == "ambient":
            out.append(pl.AmbientLight(color=rgb, intensity=draw(coef)))
            continue
        if kind == "point":
            out.append(pl.PointLight(position=draw(vec3), color=rgb,
                                     attenuation=(draw(st.floats(0.1, 2)), draw(coef), draw(coef))))
            continue
        direction = draw(vec3)
        assume(np.linalg.norm(direction) > 1e-3)
        if kind == "dir":
            out.append(pl.DirectionalLight(direction=direction, color=rgb, specular=(draw(coef),) * 3))
        else:
            out.append(pl.SpotLight(position=draw(vec3), direction=direction, color=rgb,
                                    cutoff=draw(st.sampled_from([5.0, 30.0, 60.0, 90.0, 180.0])),
                                    exponent=draw(st.floats(0, 60)),
                                    attenuation=(1.0, draw(coef), draw(coef))))
    return out


materials = st.builds(
    pl.Material,
    ka=st.tuples(coef, coef, coef), kd=st.tuples(coef, coef, coef), ks=st.tuples(coef, coef, coef),
    shininess=st.one_of(st.sampled_from([0.0, 1.0, 2.0, 5.0, 64.0, 128.0]), st.floats(0, 300)),
    emission=st.tuples(coef, coef, coef),
)
viewers = st.one_of(
    st.builds(lambda e: {"eye": e}, st.tuples(finite, finite, st.floats(4, 8))),
    st.builds(lambda d: {"view_direction": d}, vec3.filter(lambda d: np.linalg.norm(d) > 1e-3)),
)


def random_geometry(seed, dtype, n=96):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n, 3))
    normals = rng.normal(size=(n, 3)) * rng.uniform(0.2, 3.0, size=(n, 1))  # any length
    return points.astype(dtype), normals.astype(dtype)


def assert_agree(fast, ref, shininess, dtype, inputs):
    eps, tiny = np.finfo(dtype).eps, np.finfo(dtype).tiny
    for term in TERMS:
        a, b = np.asarray(getattr(fast, term)), np.asarray(getattr(ref, term))
        assert a.dtype == b.dtype == dtype, f"{term}: dtypes {a.dtype} {b.dtype}; {inputs}"
        assert np.isfinite(a).all() and np.isfinite(b).all(), f"{term}: not finite; {inputs}"
        scale = np.abs(b).max(axis=0)  # per channel
        allowed = 8 * (1 + shininess) * eps * scale + tiny
        diff = np.abs(a.astype(float) - b.astype(float))
        bad = diff > allowed
        if bad.any():
            i, ch = np.argwhere(bad)[0]
            raise AssertionError(
                f"{term} differs at point {i} channel {ch}: fast {a[i, ch]!r} reference {b[i, ch]!r}, "
                f"|diff| {diff[i, ch]:.3g} > allowed {allowed[ch]:.3g} (8(1+α)·eps·scale + tiny); {inputs}")


@settings(max_examples=100, deadline=None)
@given(lights=lights(), material=materials, viewer=viewers, model=st.sampled_from(pl.MODELS),
       two_sided=st.booleans(), plan=st.sampled_from(["auto", "full"]),
       dtype=st.sampled_from([np.float32, np.float64]), seed=st.integers(0, 2**32 - 1))
def test_fast_kernel_agrees_with_the_reference(lights, material, viewer, model, two_sided, plan, dtype, seed):
    points, normals = random_geometry(seed, dtype)
    args = dict(material=material, lights=lights, model=model, two_sided=two_sided, **viewer)
    inputs = f"seed={seed} dtype={dtype.__name__} plan={plan} args={args}"
    fast = pl.shade(points, normals, plan=plan, **args)
    ref = pl.shade_reference(points, normals, **args)
    assert_agree(fast, ref, material.shininess, dtype, inputs)


def test_the_tolerance_catches_a_wrong_kernel():
    # a reference with the n·l gate dropped must fail the same comparison
    from phonglab.core.reference import Steps

    p, n = random_geometry(7, np.float64)
    args = dict(material=pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10), eye=(0, 0, 5),
                lights=[pl.PointLight(position=(3, 1, 0))])
    ungated = Steps(specular_weight=lambda nl, c, a: np.where(c > 0, np.maximum(c, 0) ** a, 0))
    with pytest.raises(AssertionError, match="specular differs"):
        assert_agree(pl.shade(p, n, **args), pl.shade_reference(p, n, steps=ungated, **args), 10.0, np.float64,
                     "ungated")


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_reference_shades_a_table_row(dtype):
    # n = (0, 0, 1), light at (0, 3, 4): n·l = 0.8, r = (0, −0.6, 0.8); eye at (0, 0, 5): r·v = 0.8
    s = pl.shade_reference(np.zeros((1, 3), dtype), np.array([[0, 0, 1]], dtype), eye=(0, 0, 5),
                           material=pl.Material(ka=0, kd=1, ks=1, shininess=2),
                           lights=[pl.PointLight(position=(0, 3, 4), attenuation=(1, 0.1, 0.01))])
    f = 1 / (1 + 0.1 * 5 + 0.01 * 25)
    np.testing.assert_allclose(s.diffuse[0], f * 0.8, rtol=8 * np.finfo(dtype).eps)
    np.testing.assert_allclose(s.specular[0], f * 0.8**2, rtol=8 * np.finfo(dtype).eps)
    assert s.color.dtype == dtype


def test_reference_refuses_what_shade_refuses():
    mat = pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10)
    light = [pl.PointLight(position=(0, 0, 3))]
    with pytest.raises(pl.InvalidValue, match="exactly one of eye"):
        pl.shade_reference([[0, 0, 0]], [[0, 0, 1]], material=mat, lights=light)
    with pytest.raises(pl.InvalidValue, match="model"):
        pl.shade_reference([[0, 0, 0]], [[0, 0, 1]], material=mat, lights=light, eye=(0, 0, 5), model="gouraud")
    with pytest.raises(pl.InvalidValue, match="normals: must be finite"):
        pl.shade_reference([[0, 0, 0]], [[0, np.nan, 1]], material=mat, lights=light, eye=(0, 0, 5))
    with pytest.raises(pl.InvalidValue, match=r"lights\[0\]"):
        pl.shade_reference([[0, 0, 0]], [[0, 0, 1]], material=mat, lights=["lamp"], eye=(0, 0, 5))
