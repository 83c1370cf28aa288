"""The numerical contract: each guard tested with the case it guards.

References are computed with mpmath at 50 significant digits from the very
same (already rounded) inputs the core receives.
"""

import math

import mpmath
import numpy as np
import pytest

import phonglab as pl
from phonglab.core.model import MAX_EXPONENT

mpmath.mp.dps = 50
F32, F64 = np.float32, np.float64
DTYPES = [F32, F64]


def mp_unit(v):
    v = [mpmath.mpf(float(x)) for x in v]
    norm = mpmath.sqrt(sum(x * x for x in v))
    return [x / norm for x in v]


def mp_dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def mp_specular(p, n, light, eye, alpha, model):
    """max(0, r·v)^α or max(0, n·h)^α, from the float inputs, in 50 digits."""
    n = mp_unit(n)
    l = mp_unit([mpmath.mpf(float(a)) - mpmath.mpf(float(b)) for a, b in zip(light, p)])
    v = mp_unit([mpmath.mpf(float(a)) - mpmath.mpf(float(b)) for a, b in zip(eye, p)])
    nl = mp_dot(n, l)
    if nl <= 0:
        return mpmath.mpf(0)
    if model == "phong":
        r = [2 * nl * a - b for a, b in zip(n, l)]
        c = mp_dot(r, v)
    else:
        c = mp_dot(n, mp_unit([a + b for a, b in zip(l, v)]))
    return max(c, 0) ** alpha


def rotate_towards(d, axis_hint, theta):
    """Unit vector at angle theta from unit d, in the plane of d and axis_hint."""
    d = np.asarray(d, float)
    w = np.cross(d, axis_hint)
    w /= np.linalg.norm(w)
    return math.cos(theta) * d + math.sin(theta) * w


@pytest.mark.parametrize("dtype,rtol", [(F32, 1e-3), (F64, 1e-9)])
@pytest.mark.parametrize("model", pl.PHONG_MODELS)
def test_alpha_1e6_near_the_highlight_matches_mpmath(dtype, rtol, model):
    alpha = 1e6
    p = np.array([0.1, -0.2, 0.0])
    n = np.array([0.05, 0.02, 1.0])
    n_unit = n / np.linalg.norm(n)
    light = p + 3 * np.array([0.6, 0.0, 0.8])
    l = (light - p) / 3
    r = 2 * (n_unit @ l) * n_unit - l
    # Blinn-Phong peaks where h = n, i.e. at the same mirror direction
    for t in [0.0, 0.01, 0.5, 1.0, 2.0, 3.0]:
        theta = math.sqrt(2 * t / alpha) * (0.5 if model == "blinn-phong" else 1.0)
        eye = p + 4 * rotate_towards(r, [0.3, 1.0, 0.2], theta)
        pp, nn, ll, ee = (np.asarray(x, dtype) for x in (p, n, light, eye))
        s = pl.shade(pp[None], nn[None], eye=ee, model=model,
                     material=pl.Material(ka=0, kd=0, ks=1, shininess=alpha),
                     lights=[pl.PointLight(position=ll)]).specular[0, 0]
        ref = mp_specular(pp, nn, ll, ee, alpha, model)
        inputs = dict(dtype=dtype.__name__, model=model, t=t, p=pp, n=nn, light=ll, eye=ee)
        assert ref > 0.01, inputs  # near the highlight, by construction
        assert s.dtype == dtype
        assert abs(float(s) - float(ref)) <= rtol * float(ref), (inputs, float(s), float(ref))


@pytest.mark.parametrize("dtype,scales", [
    (F32, [1e20, 1e-20, 1e30, 1e-30, 2e38]),
    (F64, [1e160, 1e-160, 1e300, 1e-300, 1.4e308]),
])
def test_normalize_extreme_lengths(dtype, scales):
    base = np.array([0.3, -0.4, 1.2])
    for s in scales:
        v = (base * s).astype(dtype)
        u = pl.normalize(v)
        ref = [float(x) for x in mp_unit(v)]
        assert u.dtype == dtype
        np.testing.assert_allclose(u, ref, rtol=4 * np.finfo(dtype).eps, err_msg=f"scale={s} v={v}")


@pytest.mark.parametrize("dtype", DTYPES)
def test_normalize_subnormal_vectors(dtype):
    tiny = np.finfo(dtype).smallest_subnormal
    for v in ([1, 0, 0], [3, -4, 0], [1000, 2000, -2000]):
        vv = (np.array(v, float) * tiny).astype(dtype)
        assert np.all(np.abs(vv[vv != 0]) < np.finfo(dtype).tiny), vv  # really subnormal
        u = pl.normalize(vv)
        ref = [float(x) for x in mp_unit(vv)]
        np.testing.assert_allclose(u, ref, rtol=4 * np.finfo(dtype).eps, err_msg=f"v={vv!r}")


@pytest.mark.parametrize("dtype", DTYPES)
def test_zero_vector_normalizes_to_zero(dtype):
    u, length = pl.normalize(np.zeros((2, 3), dtype), return_length=True)
    assert (u == 0).all() and (length == 0).all() and u.dtype == dtype


MAT = pl.Material(ka=0.1, kd=0.7, ks=0.5, shininess=20)


def shade1(p, n, lights, dtype=F64, **kw):
    kw.setdefault("eye", (0, 0, 5))
    return pl.shade(np.asarray([p], dtype), np.asarray([n], dtype), material=kw.pop("material", MAT),
                    lights=lights, **kw)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", pl.MODELS)
def test_zero_normal_gives_no_direct_light(dtype, model):
    s = shade1((0, 0, 0), (0, 0, 0), [pl.PointLight(position=(0, 0, 3))], dtype, model=model)
    assert np.isfinite(s.color).all()
    assert (s.diffuse == 0).all() and (s.specular == 0).all(), s


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", pl.PHONG_MODELS)
@pytest.mark.parametrize("gap", [0.0, 1e-30])
def test_light_at_the_point_with_inverse_square(dtype, model, gap):
    light = pl.PointLight(position=(0, 0, gap), attenuation=(0, 0, 1))
    s = shade1((0, 0, 0), (0, 0, 1), [light], dtype, model=model)
    inputs = (dtype, model, gap)
    assert np.isfinite(s.color).all(), inputs
    if gap == 0:  # zero-length l: no direction, so no direct light
        assert (s.diffuse == 0).all() and (s.specular == 0).all(), inputs
    else:  # distance floored at 1e-6, factor capped at 1e12
        np.testing.assert_allclose(s.diffuse[0], 0.7 * pl.ATTENUATION_MAX, rtol=1e-5, err_msg=str(inputs))


def test_attenuation_floor_documented_values():
    assert pl.DISTANCE_FLOOR == 1e-6 and pl.ATTENUATION_MAX == 1e12


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", pl.MODELS)
@pytest.mark.parametrize("alpha", [0.0, 1.0, 40.0, 1e6])
@pytest.mark.parametrize("lz", [0.0, -1e-30, -1e-6, -0.5])
def test_specular_exactly_zero_where_n_dot_l_is_not_positive(dtype, model, alpha, lz):
    # the eye sits on the mirror ray, so r·v = 1 would light it without the gate
    l = np.array([1.0, 0.0, lz])
    r = np.array([-1.0, 0.0, lz])
    kw = dict(view_direction=r) if model == "phong" else dict(view_direction=(-l[0], 0.0, -lz + 1e-3))
    mat = pl.Material(ka=0, kd=1, ks=1, shininess=alpha)
    s = shade1((0, 0, 0), (0, 0, 1), [pl.DirectionalLight(direction=l)], dtype, model=model,
               material=mat, eye=None, **kw)
    inputs = dict(dtype=dtype, model=model, alpha=alpha, l=l)
    assert (s.specular == 0).all() and (s.diffuse == 0).all(), (inputs, s.specular)


@pytest.mark.parametrize("dtype", DTYPES)
def test_tiny_positive_n_dot_l_is_lit(dtype):
    l = np.array([1.0, 0.0, 1e-30])
    s = shade1((0, 0, 0), (0, 0, 1), [pl.DirectionalLight(direction=l)], dtype,
               material=pl.Material(ka=0, kd=1, ks=1, shininess=1), eye=None, view_direction=(-1, 0, 1e-30))
    assert np.isfinite(s.color).all() and s.specular[0, 0] > 0.99, (dtype, s.specular)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("local", [True, False])
def test_zero_half_vector_gives_no_specular(dtype, local):
    # l = -v: h = normalize(0) = 0
    l = np.array([0.6, 0.0, 0.8])
    view = dict(eye=-5 * l) if local else dict(eye=None, view_direction=-l)
    s = shade1((0, 0, 0), (0, 0, 1), [pl.DirectionalLight(direction=l)], dtype, model="blinn-phong", **view)
    assert np.isfinite(s.color).all() and (s.specular == 0).all(), (dtype, local, s.specular)
    assert s.diffuse[0, 0] == pytest.approx(0.7 * 0.8, rel=1e-6)


@pytest.mark.parametrize("dtype", DTYPES)
def test_point_exactly_on_the_spot_cone_is_inside(dtype):
    spot = pl.SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=45, exponent=1)
    p = np.array([1.0, 0.0, -1.0], dtype)
    # the computed cosine falls just below cos(45°): the slack is what keeps it inside
    c = float(-(pl.normalize(-p) @ np.array([0, 0, -1], dtype)))
    assert c <= math.cos(math.radians(45)) + np.finfo(dtype).eps
    s = shade1(p, (0, 0, 1), [spot], dtype, material=pl.Material(ka=0, kd=1, ks=0, shininess=1))
    assert s.diffuse[0, 0] > 0.4, (dtype, c, s.diffuse)
    outside = shade1(np.array([1.0, 0, -0.99], dtype), (0, 0, 1), [spot], dtype,
                     material=pl.Material(ka=0, kd=1, ks=0, shininess=1))
    assert outside.diffuse[0, 0] == 0


@pytest.mark.parametrize("dtype", DTYPES)
def test_cutoff_180_lights_behind_the_light(dtype):
    spot = pl.SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=180, exponent=3)
    point = pl.PointLight(position=(0, 0, 0))
    behind, facing = (0, 0, 5), (0, 0, -1)
    s = shade1(behind, facing, [spot], dtype, eye=(0, 0, 0.5))
    ref = shade1(behind, facing, [point], dtype, eye=(0, 0, 0.5))
    assert np.isfinite(s.color).all() and s.diffuse[0, 0] > 0
    np.testing.assert_array_equal(s.color, ref.color)


@pytest.mark.parametrize("dtype", DTYPES)
def test_short_interpolated_normals_are_renormalised(dtype):
    light = [pl.PointLight(position=(1, 2, 3))]
    unit = shade1((0, 0, 0), (0.6, 0, 0.8), light, dtype)
    for scale in (0.5, 1e-3, 1e-20 if dtype == F32 else 1e-150):
        short = shade1((0, 0, 0), np.array([0.6, 0, 0.8]) * scale, light, dtype)
        np.testing.assert_allclose(short.color, unit.color, rtol=8 * np.finfo(dtype).eps,
                                   err_msg=f"scale={scale}")


@pytest.mark.parametrize("dtype", DTYPES)
def test_antipodal_normals_interpolate_to_no_light(dtype):
    n = (np.array([0, 0.6, 0.8]) + np.array([0, -0.6, -0.8])) / 2
    s = shade1((0, 0, 0), n, [pl.PointLight(position=(1, 2, 3))], dtype)
    assert np.isfinite(s.color).all()
    assert (s.diffuse == 0).all() and (s.specular == 0).all()
    assert (s.color == 0).all(), s.color  # no ambient light in this scene either


@pytest.mark.parametrize("dtype", DTYPES)
def test_output_finite_for_extreme_finite_geometry(dtype):
    big = float(np.finfo(dtype).max) / 4
    pts = np.array([[big, -big, big], [0, 0, 0], [1e-30, 0, 0]], dtype)
    nrm = np.array([[big, big, -big], [1e-40, 0, 0], [0, 0, 1]], dtype)
    lights = [pl.PointLight(position=(0, 0, 1), attenuation=(0, 1e-3, 1)),
              pl.SpotLight(position=(1, 1, 1), direction=(0, 0, -1), cutoff=90, exponent=5),
              pl.DirectionalLight(direction=(1e-300, 0, 1e-300)), pl.AmbientLight(intensity=0.3)]
    for model in pl.MODELS:
        s = shade1(pts[0], nrm[0], lights, dtype, model=model, two_sided=True)
        full = pl.shade(pts, nrm, eye=(0, 0, 5), material=MAT, lights=lights, model=model)
        assert np.isfinite(s.color).all() and np.isfinite(full.color).all(), (dtype, model, full.color)


@pytest.mark.parametrize("dtype", DTYPES)
def test_log1p_neg_matches_mpmath_including_where_1_minus_d_rounds_to_1(dtype):
    from phonglab.core.vectors import log1p_neg

    eps = np.finfo(dtype).eps
    d = np.concatenate([np.geomspace(1e-30, 1.0, 2000, endpoint=False), [eps / 4, eps / 2, eps, 0.5, 1 - eps]]).astype(dtype)
    got = log1p_neg(d)
    ref = np.array([float(mpmath.log1p(-mpmath.mpf(float(x)))) for x in d])
    rel = np.abs(got - ref) / np.abs(ref)
    worst = int(rel.argmax())
    assert rel.max() <= 3 * eps, (dtype, float(d[worst]), float(got[worst]), ref[worst])
    assert log1p_neg(np.array([1.0], dtype))[0] == -np.inf
    assert log1p_neg(np.array([0.0], dtype))[0] == 0


@pytest.mark.parametrize("alpha", [1e-300, 1e-50, MAX_EXPONENT])
def test_shininess_outside_float32_range_gives_no_nan(alpha):
    # 1e-300 rounds to 0 in float32, and the largest α a Material takes must not overflow: no 0·inf, no NaN
    mat = pl.Material(ka=0, kd=0, ks=1, shininess=alpha)
    rng = np.random.default_rng(3)
    p, n = rng.normal(size=(200, 3)).astype(F32), rng.normal(size=(200, 3)).astype(F32)
    s = pl.shade(p, n, eye=(0, 0, 6), material=mat, lights=[pl.PointLight(position=(1, 2, 3))])
    assert np.isfinite(s.color).all() and (s.specular >= 0).all(), alpha


def test_the_power_guard_keeps_an_exponent_past_float32_finite():
    # cos_power itself (the kernel's power) holds an α that rounds to inf in float32 below the largest float
    from phonglab.core.vectors import cos_power

    d_cos = np.array([0.0, 1e-30, 0.5, 1.0], F32)
    got = cos_power(d_cos.copy(), np.ones(4, bool), 1e300)
    assert np.isfinite(got).all() and got[0] == 1 and got[2] == 0 and got[3] == 0, got


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("model", pl.PHONG_MODELS)
def test_eye_exactly_on_the_shaded_point_gives_no_specular(dtype, model):
    # v = 0 there; the other point is shaded normally
    pts = np.array([[0, 0, 0], [0.5, 0, 0]], dtype)
    s = pl.shade(pts, np.array([[0, 0, 1]] * 2, dtype), eye=(0, 0, 0), model=model,
                 material=pl.Material(ka=0, kd=1, ks=1, shininess=1), lights=[pl.PointLight(position=(0, 0, 3))])
    assert np.isfinite(s.color).all()
    assert (s.specular[0] == 0).all() and s.diffuse[0, 0] == pytest.approx(1.0), (dtype, model, s.specular)


@pytest.mark.parametrize("dtype", DTYPES)
def test_normalize_of_a_vector_does_not_depend_on_its_neighbours(dtype):
    # one extreme vector in a block must not change how the ordinary ones round
    ordinary = np.array([[0.3, -0.4, 1.2], [1.0, 2.0, 3.0]], dtype)
    extreme = np.array([[np.finfo(dtype).smallest_subnormal, 0, 0]], dtype)
    alone = pl.normalize(ordinary)
    mixed = pl.normalize(np.concatenate([ordinary, extreme]))
    np.testing.assert_array_equal(mixed[:2], alone)
    np.testing.assert_array_equal(mixed[2], [1, 0, 0])


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("alpha", [1, 2, 3, 7, 40, 64, 100, 127, pl.core.SQUARING_MAX])
def test_integer_shininess_by_squaring_stays_within_2_alpha_ulps(dtype, alpha):
    # repeated squaring of 1 − d: the rounding of 1 − d and of each product grow like α ulps
    from phonglab.core.vectors import cos_power

    eps = np.finfo(dtype).eps
    d = np.concatenate([np.geomspace(1e-12, 0.999, 400), [0.0, eps / 4, eps, 0.5]]).astype(dtype)
    got = cos_power(d.copy(), np.ones(d.shape, bool), alpha)
    ref = np.array([float((1 - mpmath.mpf(float(x))) ** alpha) for x in d])
    big = ref > np.finfo(dtype).tiny / eps  # away from gradual underflow
    rel = np.abs(got[big] - ref[big]) / ref[big]
    worst = int(rel.argmax())
    assert got.dtype == dtype
    assert rel.max() <= 2 * alpha * eps, (dtype, alpha, float(d[big][worst]), float(got[big][worst]), ref[big][worst])
    assert got[d == 0].tolist() == [1.0], (dtype, alpha)


@pytest.mark.parametrize("dtype", DTYPES)
def test_squaring_and_exp_log_agree_at_the_switch(dtype):
    # α = SQUARING_MAX is squared, α + 0.5 and α + 1 go through exp/log: the lobes are continuous
    from phonglab.core.vectors import SQUARING_MAX, cos_power

    d = np.geomspace(1e-9, 0.05, 300).astype(dtype)
    lit = np.ones(d.shape, bool)
    a, b = SQUARING_MAX, SQUARING_MAX + 1
    squared = cos_power(d.copy(), lit, a)
    via_log = cos_power(d.copy(), lit, a + 1e-9 * a)  # not an integer: exp/log, same power to 1e-9
    np.testing.assert_allclose(squared, via_log, rtol=2 * a * np.finfo(dtype).eps + 1e-7,
                               err_msg=f"{dtype.__name__} α={a}")
    # one step above the switch, the power still falls by the factor (1 − d)
    above = cos_power(d.copy(), lit, b)
    np.testing.assert_allclose(above, squared * (1 - d.astype(float)), rtol=2 * b * np.finfo(dtype).eps + 1e-7,
                               err_msg=f"{dtype.__name__} α={b}")


@pytest.mark.parametrize("alpha", [0, 1, 2, 40, 128, 40.5, 1e6])
def test_power_is_exactly_zero_where_unlit_or_cos_not_positive(alpha):
    from phonglab.core.vectors import cos_power

    d = np.array([0.0, 1e-7, 1.0, 1.5, 2.0, 0.2])
    lit = np.array([True, True, True, True, True, False])
    got = cos_power(d.copy(), lit, alpha)
    assert got[2:].tolist() == [0.0, 0.0, 0.0, 0.0], (alpha, got)  # cos ≤ 0, or n·l ≤ 0
    assert got[0] == 1.0 and 0 < got[1] <= 1, (alpha, got)
