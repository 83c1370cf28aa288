"""The fast kernel agrees with the reference kernel, the model written one light at a time.

Tolerance, per term and channel, with ``scale`` the largest magnitude of that
term over the points and ``eps`` the machine epsilon of the working dtype:

    |shade − shade_reference| ≤ 8 (1 + α) eps · scale + tiny

(``tiny`` the smallest normal number: coefficients like 1e-45 are subnormal
in float32, where relative rounding means nothing).

For 0 < α < 1 the specular weight ``c^α`` is ill-conditioned near ``c = 0``:
a rounding ``δc`` of the cosine (a few eps, however it is computed) moves it
by ``α c^(α−1) δc``, without bound as ``c → 0``. There the specular and
colour terms may differ by a further ``16 α eps Σ_l S_l / c_l`` at each point,
with ``S_l`` light l's specular term and ``c_l`` its cosine (measured on the
reference, light by light: ``S_l / c_l = S_l(α) · S_l(0) / S_l(1)``).
The reference computes ``max(0, c)^α`` from the cosine ``c`` directly, so
its relative error grows like ``α`` ulps near the highlight; the fast kernel
stays within a few ulps there. Diffuse, ambient and emission agree within a
few ulps. A failure prints the scene, the seed and where the terms differ.
"""

import dataclasses

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


def power_conditioning(points, normals, args):
    """Σ_l S_l / c_l per point and channel (see the module docstring); zeros for α ≥ 1."""
    material = args["material"]
    total = np.zeros(points.shape, dtype=float)
    if material.shininess >= 1:
        return total
    for light in args["lights"]:
        one = dict(args, lights=[light])
        s = {a: np.asarray(pl.shade_reference(points, normals, **dict(one, material=dataclasses.replace(material, shininess=a))
                                              ).specular, dtype=float)
             for a in (0.0, 1.0, material.shininess)}
        lit = s[1.0] > 0
        total[lit] += s[material.shininess][lit] * s[0.0][lit] / s[1.0][lit]
    return total


def assert_agree(fast, ref, shininess, dtype, inputs, conditioning=0.0):
    eps, tiny = np.finfo(dtype).eps, np.finfo(dtype).tiny
    for term in TERMS:
        a, b = np.asarray(getattr(fast, term)), np.asarray(getattr(ref, term))
        assert a.dtype == b.dtype == dtype, f"{term}: dtypes {a.dtype} {b.dtype}; {inputs}"
        assert np.isfinite(a).all() and np.isfinite(b).all(), f"{term}: not finite; {inputs}"
        scale = np.abs(b).max(axis=0)  # per channel
        allowed = 8 * (1 + shininess) * eps * scale + tiny
        if term in ("specular", "color"):
            allowed = allowed + 16 * shininess * eps * conditioning
        diff = np.abs(a.astype(float) - b.astype(float))
        bad = diff > allowed
        if bad.any():
            i, ch = np.argwhere(bad)[0]
            allowed = np.broadcast_to(allowed, bad.shape)
            raise AssertionError(
                f"{term} differs at point {i} channel {ch}: fast {a[i, ch]!r} reference {b[i, ch]!r}, "
                f"|diff| {diff[i, ch]:.3g} > allowed {allowed[i, ch]:.3g} (8(1+α)·eps·scale + tiny"
                f" [+ 16α·eps·Σ S_l/c_l for α < 1]); {inputs}")


@settings(max_examples=100, deadline=None)
@given(lights=lights(), material=materials, viewer=viewers, model=st.sampled_from(pl.PHONG_MODELS),
       two_sided=st.booleans(), plan=st.sampled_from(["auto", "full"]),
       dtype=st.sampled_from([np.float32, np.float64]), seed=st.integers(0, 2**32 - 1))
def test_fast_kernel_agrees_with_the_reference(lights, material, viewer, model, two_sided, plan, dtype, seed):
    points, normals = random_geometry(seed, dtype)
    args = dict(material=material, lights=lights, model=model, two_sided=two_sided, **viewer)
    inputs = f"seed={seed} dtype={dtype.__name__} plan={plan} args={args}"
    fast = pl.shade(points, normals, plan=plan, **args)
    ref = pl.shade_reference(points, normals, **args)
    assert_agree(fast, ref, material.shininess, dtype, inputs, power_conditioning(points, normals, args))


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


def test_a_power_below_one_is_compared_with_its_conditioning():
    # α = 0.5 and a cosine of about 0.003 at some points: both kernels round the cosine by a few eps,
    # which c^0.5 amplifies to ~30 eps of the result; the plain tolerance refuses that, the conditioned one not
    args = dict(material=pl.Material(ka=0, kd=0, ks=(0, 0, 1), shininess=0.5), eye=(0.0, 0.0, 4.0),
                lights=[pl.DirectionalLight(color=0, specular=1, direction=(0.0, 1.75, 3.25)),
                        pl.SpotLight(color=0, position=(0, 0, 0), direction=(0, 0, 1), cutoff=5.0, exponent=0.0)],
                model="phong", two_sided=False)
    points, normals = random_geometry(271682, np.float64)
    fast, ref = pl.shade(points, normals, plan="auto", **args), pl.shade_reference(points, normals, **args)
    with pytest.raises(AssertionError, match="specular differs"):
        assert_agree(fast, ref, 0.5, np.float64, "unconditioned")
    assert_agree(fast, ref, 0.5, np.float64, "conditioned", power_conditioning(points, normals, args))
    # and the conditioning still catches a wrong kernel at α = 0.5
    from phonglab.core.reference import Steps
    ungated = Steps(specular_weight=lambda nl, c, a: np.where(c > 0, np.maximum(c, 0) ** a, 0))
    wrong = pl.shade_reference(points, normals, steps=ungated, **args)
    with pytest.raises(AssertionError, match="specular differs"):
        assert_agree(fast, wrong, 0.5, np.float64, "ungated", power_conditioning(points, normals, args))


ct_materials = st.builds(
    pl.Material,
    ka=st.tuples(coef, coef, coef), kd=st.tuples(coef, coef, coef), ks=st.tuples(coef, coef, coef),
    shininess=st.just(1.0), emission=st.tuples(coef, coef, coef),
    roughness=st.one_of(st.sampled_from([0.0, 0.05, 0.5, 1.0]), st.floats(0, 1)),
    metallic=st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0, 1)),
)


def peak_conditioning(points, normals, args):
    """``1/X`` per point, ``X = (n·h)²(α² − 1) + 1`` for each light (the largest over the lights).

    The reference writes ``D`` with ``X`` as the lesson does; near the peak of a
    sharp lobe ``X`` falls to ``α²`` while its rounding stays a few eps, so the
    reference's ``D`` is good to about ``4 eps / X`` relative (the fast kernel
    computes ``X`` from ``1 − n·h = |n − h|²/2`` and keeps full precision).
    """
    _, record = pl.shade_reference(points.astype(float), normals.astype(float), trace=True, **args)
    alpha2 = float(np.asarray(record["α_GGX"]).flat[0]) ** 2
    worst = np.zeros(points.shape[:-1])
    for lr in record.lights:
        nh = np.asarray(lr["n·h"], float)
        worst = np.maximum(worst, 1 / (nh * nh * (alpha2 - 1) + 1))
    return worst[..., None]


@settings(max_examples=100, deadline=None)
@given(lights=lights(), material=ct_materials, viewer=viewers, two_sided=st.booleans(),
       plan=st.sampled_from(["auto", "full"]), dtype=st.sampled_from([np.float32, np.float64]),
       seed=st.integers(0, 2**32 - 1))
def test_fast_cook_torrance_agrees_with_the_reference(lights, material, viewer, two_sided, plan, dtype, seed):
    """Per term and channel: ``|fast − reference| ≤ 64 eps (1 + 4/X) · scale + tiny`` (see :func:`peak_conditioning`)."""
    points, normals = random_geometry(seed, dtype)
    args = dict(material=material, lights=lights, model="cook-torrance", two_sided=two_sided, **viewer)
    inputs = f"seed={seed} dtype={dtype.__name__} plan={plan} args={args}"
    fast = pl.shade(points, normals, plan=plan, **args)
    ref = pl.shade_reference(points, normals, **args)
    eps, tiny = np.finfo(dtype).eps, np.finfo(dtype).tiny
    cond = 1 + 4 * peak_conditioning(points, normals, args)
    for term in TERMS:
        a, b = np.asarray(getattr(fast, term), float), np.asarray(getattr(ref, term), float)
        assert np.isfinite(a).all() and np.isfinite(b).all(), f"{term}: not finite; {inputs}"
        allowed = 64 * eps * np.abs(b).max(axis=0) * (cond if term in ("specular", "color") else 1) + tiny
        diff = np.abs(a - b)
        bad = diff > allowed
        if bad.any():
            i, ch = np.argwhere(bad)[0]
            raise AssertionError(f"{term} differs at point {i} channel {ch}: fast {a[i, ch]!r} reference "
                                 f"{b[i, ch]!r}, |diff| {diff[i, ch]:.3g} > allowed "
                                 f"{np.broadcast_to(allowed, bad.shape)[i, ch]:.3g}; {inputs}")
