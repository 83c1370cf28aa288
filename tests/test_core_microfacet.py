"""Cook–Torrance's terms (GGX D, height-correlated Smith V, Schlick F) and the white furnace.

References are mpmath evaluations, at 50 digits, of the same formulas from
the same rounded inputs; the furnace is checked against the closed form at
α = 1 and against energy conservation everywhere.
"""

import math

import mpmath
import numpy as np
import pytest

from phonglab.core.furnace import directional_albedo, ggx_albedo_alpha1
from phonglab.core.microfacet import (
    MIN_ROUGHNESS,
    fresnel_f0,
    ggx_alpha,
    ggx_distribution,
    phong_normalisation,
    schlick_fresnel,
    smith_visibility,
    smith_visibility_nl,
)

mpmath.mp.dps = 50
F32, F64 = np.float32, np.float64


def mp_d(d_nh, alpha):
    d, a2 = mpmath.mpf(float(d_nh)), mpmath.mpf(alpha) ** 2
    nh = 1 - d
    return a2 / (mpmath.pi * (nh * nh * (a2 - 1) + 1) ** 2)


def mp_v(nl, nv, alpha):
    nl, nv, a2 = mpmath.mpf(float(nl)), mpmath.mpf(float(nv)), mpmath.mpf(alpha) ** 2
    return mpmath.mpf(0.5) / (nl * mpmath.sqrt(nv * nv * (1 - a2) + a2) + nv * mpmath.sqrt(nl * nl * (1 - a2) + a2))


def ulps(got, want, dtype):
    """|got − want| in units of the last place of want in dtype."""
    want = float(want)
    spacing = float(np.spacing(dtype(abs(want)))) if want else float(np.finfo(dtype).smallest_subnormal)
    return abs(float(got) - want) / spacing


def test_white_metal_head_on_at_roughness_half_is_one_over_four_alpha_squared():
    alpha = ggx_alpha(0.5)
    value = math.pi * float(ggx_distribution(F64(0), alpha)) * float(smith_visibility_nl(F64(1), F64(1), alpha)) \
        * float(schlick_fresnel(F64(0), fresnel_f0(1.0, 1.0))[0])
    assert value == pytest.approx(1 / (4 * alpha**2), rel=1e-15) and value == pytest.approx(4.0, rel=1e-15), \
        f"roughness 0.5: α = {alpha}, π D V F = {value}"


@pytest.mark.parametrize("dtype,max_ulps", [(F32, 8), (F64, 8)])
@pytest.mark.parametrize("roughness", [MIN_ROUGHNESS, 0.1, 0.5, 1.0])
@pytest.mark.parametrize("d_nh", [0.0, 1e-12, 1e-7, 1e-4, 0.01, 0.3, 1.0])
def test_distribution_matches_mpmath_at_the_peak_and_away(dtype, max_ulps, roughness, d_nh):
    alpha = ggx_alpha(roughness)
    d = dtype(d_nh)
    got = ggx_distribution(d, alpha)
    assert got.dtype == dtype
    want = mp_d(d, float(dtype(alpha)))
    assert ulps(got, want, dtype) <= max_ulps, f"D(1 − n·h = {d_nh}, roughness {roughness}) = {got}, mpmath {want}"


def test_distribution_peak_is_finite_at_roughness_zero_in_float32():
    got = ggx_distribution(F32(0), ggx_alpha(0.0))
    assert np.isfinite(got) and got == pytest.approx(1 / (math.pi * MIN_ROUGHNESS**4), rel=1e-6), got


@pytest.mark.parametrize("dtype,max_ulps", [(F32, 8), (F64, 8)])
@pytest.mark.parametrize("roughness", [MIN_ROUGHNESS, 0.3, 1.0])
@pytest.mark.parametrize("nl,nv", [(1.0, 1.0), (0.5, 0.9), (1e-3, 0.7), (0.7, 1e-3), (1e-6, 1e-6)])
def test_visibility_matches_mpmath_including_grazing(dtype, max_ulps, roughness, nl, nv):
    alpha = ggx_alpha(roughness)
    a_nl, a_nv = dtype(nl), dtype(nv)
    got = smith_visibility(a_nl, a_nv, alpha)
    want = mp_v(a_nl, a_nv, float(dtype(alpha)))
    assert ulps(got, want, dtype) <= max_ulps, f"V(n·l {nl}, n·v {nv}, roughness {roughness}) = {got}, mpmath {want}"
    got_nl = smith_visibility_nl(a_nl, a_nv, alpha)
    want_nl = want * mpmath.mpf(float(a_nl))
    assert ulps(got_nl, want_nl, dtype) <= max_ulps, f"(n·l)V at n·l {nl}, n·v {nv}: {got_nl}, mpmath {want_nl}"


@pytest.mark.parametrize("dtype", [F32, F64])
def test_visibility_times_cosine_stays_finite_as_the_cosines_reach_zero(dtype):
    tiny = np.finfo(dtype).smallest_subnormal
    nl = np.array([tiny, tiny, 1.0, 1e-30], dtype)
    nv = np.array([tiny, 1.0, tiny, 1e-30], dtype)
    got = smith_visibility_nl(nl, nv, ggx_alpha(MIN_ROUGHNESS))
    assert np.all(np.isfinite(got)) and np.all(got >= 0), f"(n·l)V at n·l {nl}, n·v {nv}: {got}"
    assert np.all(got <= 0.5 / ggx_alpha(MIN_ROUGHNESS) * (1 + 1e-6)), got


@pytest.mark.parametrize("d_vh", [0.0, 0.2, 0.5, 1.0])
def test_schlick_fresnel_matches_its_formula_and_ends(d_vh):
    f0 = fresnel_f0((0.9, 0.6, 0.3), 0.5)
    got = schlick_fresnel(F64(d_vh), f0)
    want = [float(mpmath.mpf(c) + (1 - mpmath.mpf(c)) * mpmath.mpf(d_vh) ** 5) for c in f0]
    assert got.tolist() == pytest.approx(want, rel=1e-15), f"F at 1 − v·h = {d_vh}, F0 = {f0}: {got}"
    assert np.all((got >= f0 - 1e-15) & (got <= 1 + 1e-15))


def test_f0_mixes_dielectric_and_metal_by_metallic():
    assert fresnel_f0((0.2, 0.4, 0.8), 0.25).tolist() == pytest.approx([0.08, 0.13, 0.23])


# ---------------------------------------------------------------------------
# the white furnace


@pytest.mark.parametrize("view_angle", [0.0, 30.0, 60.0, 80.0, 89.0])
def test_white_metal_albedo_at_alpha_one_matches_the_closed_form(view_angle):
    got = directional_albedo("cook-torrance", view_angle, roughness=1.0)
    want = ggx_albedo_alpha1(view_angle)
    assert got == pytest.approx(want, abs=1e-4), f"roughness 1, view {view_angle}°: {got}, closed form {want}"


def test_white_metal_albedo_head_on_at_alpha_one_is_one_minus_ln_2():
    assert directional_albedo("cook-torrance", 0.0, roughness=1.0) == pytest.approx(1 - math.log(2), abs=1e-5)


@pytest.mark.parametrize("roughness", [0.0, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0])
@pytest.mark.parametrize("view_angle", [0.0, 20.0, 45.0, 70.0, 85.0])
def test_white_metal_never_reflects_more_than_arrives(roughness, view_angle):
    got = directional_albedo("cook-torrance", view_angle, roughness=roughness)
    assert 0 < got <= 1 + 1e-6, f"roughness {roughness}, view {view_angle}°: albedo {got}"


def test_single_scattering_loses_more_energy_the_rougher_the_metal():
    head_on = [directional_albedo("cook-torrance", 0.0, roughness=r) for r in (0.1, 0.3, 0.5, 0.7, 1.0)]
    assert all(a > b for a, b in zip(head_on, head_on[1:])), head_on
    assert head_on[0] > 0.999, head_on


@pytest.mark.parametrize("shininess", [0.1, 0.5, 1.0, 5.0, 50.0])
def test_plain_phong_head_on_reflects_two_over_alpha_plus_one(shininess):
    got = directional_albedo("phong", 0.0, shininess=shininess)
    assert got == pytest.approx(2 / (shininess + 1), rel=1e-9), f"α = {shininess}: {got}"


def test_plain_phong_makes_light_at_low_shininess_and_normalised_phong_does_not():
    assert directional_albedo("phong", 0.0, shininess=0.5) > 1.3
    for shininess in (0.1, 0.5, 1.0, 10.0, 100.0):
        for view in (0.0, 30.0, 60.0, 85.0):
            got = directional_albedo("phong-normalised", view, shininess=shininess)
            assert got <= 1 + 1e-6, f"normalised Phong, α = {shininess}, view {view}°: {got}"
    assert directional_albedo("phong-normalised", 0.0, shininess=7.0) == pytest.approx(1.0, rel=1e-6)


def test_normalisation_integrates_the_lobe_to_one():
    # ∫ (α+2)/(2π) cos^α θ cos θ dω = (α+2) ∫₀¹ μ^(α+1) dμ = 1
    for shininess in (0.0, 1.0, 40.0):
        integral = mpmath.quad(lambda mu: phong_normalisation(shininess) * 2 * mpmath.pi * mu ** (shininess + 1),
                               [0, 1])
        assert float(integral) == pytest.approx(1.0, rel=1e-12), shininess


def test_furnace_refuses_unknown_model_and_angle():
    with pytest.raises(ValueError, match="model: must be one of"):
        directional_albedo("lambert", 0.0)
    with pytest.raises(ValueError, match="view_angle"):
        directional_albedo("phong", 90.0)
