"""The common-mistake variants: each differs from the core exactly where its bug bites.

Every variant runs the core's reference kernel with one step swapped. The
reference kernel itself must agree with the fast one (tests/test_core_reference.py
holds it to that; here on the teaching test's scenes); each mistake must then
differ from the core on the points its bug affects, by the amount the wrong
line predicts, and agree everywhere else.
"""

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import phonglab as pl
from phonglab.teaching import (
    MISTAKES,
    attenuated_ambient,
    get_mistake,
    no_clamp_diffuse,
    power_before_max,
    reflect_wrong_way,
    spot_cutoff_in_degrees,
    ungated_specular,
    unnormalised_light,
    unnormalised_normals,
    unnormalised_view,
    view_from_eye,
    zero_shininess,
)
from phonglab.teaching.mistakes import zero_to_the_zero

TERMS = ("ambient", "diffuse", "specular", "emission", "color")
MAT = pl.Material(ka=0.2, kd=(0.8, 0.5, 0.3), ks=0.6, shininess=20.0)
AMBIENT = pl.AmbientLight(intensity=0.25)
EYE = (0.0, 0.0, 5.0)


def sphere(n_theta=40, n_phi=20):
    """Points on the unit sphere (poles excluded) with their unit normals."""
    theta, phi = np.meshgrid(np.linspace(0, 2 * np.pi, n_theta, endpoint=False),
                             np.linspace(0.05, np.pi - 0.05, n_phi))
    p = np.stack([np.sin(phi) * np.cos(theta), np.cos(phi), np.sin(phi) * np.sin(theta)], axis=-1)
    return p.reshape(-1, 3), p.reshape(-1, 3).copy()


def assert_terms_close(got, want, where, what, terms=TERMS, atol=1e-12):
    for term in terms:
        a, b = np.asarray(getattr(got, term))[where], np.asarray(getattr(want, term))[where]
        assert np.allclose(a, b, rtol=1e-9, atol=atol), (
            f"{what}: {term} differs where it should agree; max |diff| = {np.abs(a - b).max():.3g}")


# ---------------------------------------------------------------------------
# the reference kernel, which every mistake changes in one step, is the correct model


LIGHT_SETS = {
    "point": [AMBIENT, pl.PointLight(position=(2, 2.5, 3))],
    "attenuated+directional": [AMBIENT, pl.PointLight(position=(-2, 1, 2), attenuation=(1, 0.2, 0.05)),
                               pl.DirectionalLight(direction=(1, -0.5, 0.4), color=(0.3, 0.5, 1.0))],
    "spot": [pl.SpotLight(position=(0, 0, 3), direction=(0.1, 0, -1), cutoff=35, exponent=4, intensity=2)],
}


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), lights=st.sampled_from(sorted(LIGHT_SETS)),
       model=st.sampled_from(["phong", "blinn-phong"]), two_sided=st.booleans(),
       infinite=st.booleans(), shininess=st.sampled_from([0.0, 1.0, 7.5, 40.0, 300.0]))
def test_reference_agrees_with_core(seed, lights, model, two_sided, infinite, shininess):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(64, 3))
    normals = rng.normal(size=(64, 3)) * rng.uniform(0.2, 3.0, size=(64, 1))  # any length
    material = pl.Material(ka=0.1, kd=(0.7, 0.4, 0.2), ks=0.5, shininess=shininess, emission=0.05)
    viewer = {"view_direction": (0.3, 0.2, 1.0)} if infinite else {"eye": EYE}
    args = dict(material=material, lights=LIGHT_SETS[lights], model=model, two_sided=two_sided, **viewer)
    assert_terms_close(pl.shade_reference(points, normals, **args), pl.shade(points, normals, **args), slice(None),
                       f"reference vs core, seed={seed} lights={lights} model={model} two_sided={two_sided} "
                       f"viewer={viewer} shininess={shininess}")


def test_reference_keeps_float32():
    p, n = sphere(8, 4)
    s = pl.shade_reference(p.astype(np.float32), n.astype(np.float32), material=MAT, lights=[AMBIENT], eye=EYE)
    assert s.color.dtype == np.float32 and s.diffuse.dtype == np.float32, s.color.dtype


@pytest.mark.parametrize("viewer", [{}, {"eye": EYE, "view_direction": (0, 0, 1)}], ids=["none", "both"])
def test_needs_exactly_one_viewer(viewer):
    p, n = sphere(8, 4)
    with pytest.raises(ValueError, match="exactly one of eye"):
        no_clamp_diffuse(p, n, material=MAT, lights=[AMBIENT], **viewer)


# ---------------------------------------------------------------------------
# each mistake, where it bites and where it does not


def test_no_clamp_diffuse_is_negative_exactly_where_the_light_is_behind():
    p, n = sphere()
    light = pl.PointLight(position=(3, 1, 0))
    args = dict(material=MAT, lights=[AMBIENT, light], eye=EYE)
    wrong, right = no_clamp_diffuse(p, n, **args), pl.shade(p, n, **args)
    nl = pl.dot(n, pl.normalize(np.asarray(light.position) - p))
    behind = nl < 0
    assert behind.sum() > 100 and (~behind).sum() > 100, "the test sphere must have both sides"
    # where the bug bites: diffuse = k_d I_d (n·l) < 0, and the colour drops below the ambient light
    expected = np.asarray(MAT.kd) * nl[behind, None]
    assert np.allclose(wrong.diffuse[behind], expected, atol=1e-12), "diffuse must be k_d·(n·l) where n·l < 0"
    assert (wrong.diffuse[behind] < 0).all()
    assert (wrong.color[behind] < right.color[behind]).all()
    assert (right.diffuse[behind] == 0).all()
    # everywhere else, and for the other terms, the same as the core
    assert_terms_close(wrong, right, ~behind, "no-clamp-diffuse on the lit side")
    assert_terms_close(wrong, right, slice(None), "no-clamp-diffuse", terms=("ambient", "specular", "emission"))


def test_no_clamp_diffuse_cancels_a_second_light():
    # two lamps on opposite sides: the point facing one is darkened by the other
    p, n = np.array([[0.0, 0, 0]]), np.array([[1.0, 0, 0]])
    lights = [pl.DirectionalLight(direction=(1, 0, 0)), pl.DirectionalLight(direction=(-1, 0, 0))]
    wrong = no_clamp_diffuse(p, n, material=MAT, lights=lights, eye=(0, 0, 5))
    right = pl.shade(p, n, material=MAT, lights=lights, eye=(0, 0, 5))
    assert np.allclose(right.diffuse, [MAT.kd]), right.diffuse
    assert np.allclose(wrong.diffuse, 0, atol=1e-15), f"+k_d and -k_d should cancel, got {wrong.diffuse}"


def test_ungated_specular_lights_points_the_light_cannot_reach():
    # the hand-worked case: n·l = -0.8 and still r·v = 0.8
    p, n = np.array([[0.0, 0, 0]]), np.array([[0.0, 0, 1]])
    args = dict(material=MAT, lights=[pl.PointLight(position=(0, 3, -4))], eye=(0, 0, -5))
    wrong, right = ungated_specular(p, n, **args), pl.shade(p, n, **args)
    assert np.all(right.specular == 0), right.specular
    assert np.allclose(wrong.specular, 0.6 * 0.8**20, rtol=1e-12), f"want k_s·0.8^20, got {wrong.specular}"


@pytest.mark.parametrize("model", ["phong", "blinn-phong"])
def test_ungated_specular_differs_only_on_the_unlit_side(model):
    p, n = sphere(64, 32)
    light = pl.PointLight(position=(-3, 2, -3))  # behind and to the left: a lit crescent
    material = pl.Material(ka=0.1, kd=0.5, ks=0.6, shininess=5)
    args = dict(material=material, lights=[light], eye=EYE, model=model)
    wrong, right = ungated_specular(p, n, **args), pl.shade(p, n, **args)
    nl = pl.dot(n, pl.normalize(np.asarray(light.position) - p))
    unlit = nl <= 0
    extra = wrong.specular[..., 0] - right.specular[..., 0]
    assert (extra[unlit] > 0.05).sum() > 5, f"{model}: no highlight leaked onto the unlit side"
    assert np.all(right.specular[unlit] == 0)
    assert_terms_close(wrong, right, ~unlit, f"ungated-specular ({model}) on the lit side")
    assert_terms_close(wrong, right, slice(None), "ungated-specular", terms=("ambient", "diffuse", "emission"))


def test_unnormalised_normals_agree_for_unit_normals():
    p, n = sphere()
    args = dict(material=MAT, lights=LIGHT_SETS["attenuated+directional"], eye=EYE)
    assert_terms_close(unnormalised_normals(p, n, **args), pl.shade(p, n, **args), slice(None),
                       "unnormalised-normals with unit normals")


@pytest.mark.parametrize("length", [0.5, 0.87, 0.99])
def test_unnormalised_normals_scale_the_diffuse_light_by_the_normal_length(length):
    p, n = sphere()
    light = pl.DirectionalLight(direction=(1, 1, 2))
    args = dict(material=MAT, lights=[AMBIENT, light], eye=EYE)
    wrong, right = unnormalised_normals(p, n * length, **args), pl.shade(p, n * length, **args)
    lit = right.diffuse[..., 0] > 1e-3
    ratio = wrong.diffuse[lit] / right.diffuse[lit]
    assert np.allclose(ratio, length, rtol=1e-9), f"diffuse must shrink by |n| = {length}: {ratio.min()}..{ratio.max()}"
    assert_terms_close(wrong, right, slice(None), "unnormalised-normals", terms=("ambient", "emission"))


def test_unnormalised_normals_darken_the_middle_of_triangles():
    # a coarse octahedral patch: vertex normals 90° apart, blended at the centroid
    n0, n1, n2 = np.eye(3)
    corners = np.stack([n0, n1, n2])
    centroid_normal = corners.mean(axis=0)  # length 1/sqrt(3), not renormalised
    points = np.vstack([corners, centroid_normal[None, :]])  # positions do not matter for a directional light
    normals = np.vstack([corners, centroid_normal[None, :]])
    args = dict(material=MAT, lights=[pl.DirectionalLight(direction=(1, 1, 1))], view_direction=(1, 1, 1))
    wrong, right = unnormalised_normals(points, normals, **args), pl.shade(points, normals, **args)
    assert np.allclose(wrong.color[:3], right.color[:3]), "corners (unit normals) must agree"
    assert wrong.diffuse[3, 0] < 0.6 * right.diffuse[3, 0], (
        f"the centre must be darker: wrong {wrong.diffuse[3]}, right {right.diffuse[3]}")


def test_zero_shininess_washes_out_the_whole_lit_side():
    p, n = sphere()
    light = pl.PointLight(position=(2, 2.5, 3))
    args = dict(material=MAT, lights=[AMBIENT, light], eye=EYE)
    wrong, right = zero_shininess(p, n, **args), pl.shade(p, n, **args)
    nl = pl.dot(n, pl.normalize(np.asarray(light.position) - p))
    lit = nl > 0
    # the wrong line: max(0, r·v)^0 = 1 at every lit point, 0 elsewhere
    assert np.allclose(wrong.specular[lit], MAT.ks, atol=1e-15), "specular must be the full k_s on the lit side"
    assert np.all(wrong.specular[~lit] == 0)
    away = lit & (right.specular[..., 0] < 0.01)
    assert away.sum() > 100, "most of the lit side is far from the highlight"
    assert_terms_close(wrong, right, slice(None), "zero-shininess", terms=("ambient", "diffuse", "emission"))


def test_zero_shininess_is_the_core_at_alpha_0_where_r_v_is_positive():
    # the core's own convention for α = 0 is 1 where n·l > 0 and r·v > 0; the mistake also lights r·v <= 0
    p, n = sphere()
    light = pl.PointLight(position=(2, 2.5, 3))
    zero = pl.Material(ka=MAT.ka, kd=MAT.kd, ks=MAT.ks, shininess=0)
    core0 = pl.shade(p, n, material=zero, lights=[light], eye=EYE)
    wrong = zero_shininess(p, n, material=MAT, lights=[light], eye=EYE)
    rv = pl.dot(pl.reflect(pl.normalize(np.asarray(light.position) - p), n), pl.normalize(np.asarray(EYE) - p))
    nl = pl.dot(n, pl.normalize(np.asarray(light.position) - p))
    both = (nl > 0) & (rv > 0)
    only_mistake = (nl > 0) & (rv <= 0)
    assert np.allclose(wrong.specular[both], core0.specular[both])
    assert only_mistake.sum() > 0 and np.all(core0.specular[only_mistake] == 0)
    assert np.allclose(wrong.specular[only_mistake], MAT.ks)


# ---------------------------------------------------------------------------
# the seven mistakes students make writing the model themselves


def sides(light_position, p, n, eye=EYE):
    l = pl.normalize(np.asarray(light_position, float) - p)
    v = pl.normalize(np.asarray(eye, float) - p)
    nl = pl.dot(n, l)
    return nl, pl.dot(pl.reflect(l, n), v)


def test_reflect_wrong_way_flips_the_sign_of_r_v():
    p, n = sphere(64, 32)
    light = pl.PointLight(position=(0.5, 0.5, 5))  # near the eye: the true highlight in the middle
    material = pl.Material(ka=0.1, kd=0.5, ks=0.6, shininess=4)
    args = dict(material=material, lights=[light], eye=EYE)
    wrong, right = reflect_wrong_way(p, n, **args), pl.shade(p, n, **args)
    nl, rv = sides(light.position, p, n)
    lit = nl > 0
    # the wrong line: max(0, −r·v)^α where n·l > 0
    assert np.allclose(wrong.specular[..., 0], np.where(lit, material.ks[0] * np.maximum(-rv, 0) ** 4, 0),
                       atol=1e-12), "specular must be k_s max(0, −r·v)^α"
    peak, rim = lit & (rv > 0.95), lit & (rv < -0.5)
    assert peak.sum() > 3 and rim.sum() > 3, (peak.sum(), rim.sum())
    assert np.all(wrong.specular[peak] == 0) and np.all(wrong.specular[rim] > right.specular[rim] + 0.03)
    assert_terms_close(wrong, right, slice(None), "reflect-wrong-way", terms=("ambient", "diffuse", "emission"))
    # Blinn-Phong has no r: unchanged
    blinn = dict(args, model="blinn-phong")
    assert_terms_close(reflect_wrong_way(p, n, **blinn), pl.shade(p, n, **blinn), slice(None), "blinn")


def test_view_from_eye_is_the_reversed_r_v_one_sided_and_differs_in_blinn_phong():
    p, n = sphere(64, 32)
    args = dict(material=MAT, lights=[AMBIENT, pl.PointLight(position=(2, 2.5, 3))], eye=EYE)
    assert_terms_close(view_from_eye(p, n, **args), reflect_wrong_way(p, n, **args), slice(None),
                       "view-from-eye vs reflect-wrong-way (one-sided Phong: −r·v either way)")
    wrong, right = view_from_eye(p, n, **args), pl.shade(p, n, **args)
    assert np.abs(wrong.specular - right.specular).max() > 0.3, "the highlight must move"
    blinn = dict(args, model="blinn-phong")
    assert np.abs(view_from_eye(p, n, **blinn).specular - pl.shade(p, n, **blinn).specular).max() > 0.1
    # an infinite viewer has no eye position to get wrong
    far = dict(args, eye=None, view_direction=(0, 0, 1))
    assert_terms_close(view_from_eye(p, n, **far), pl.shade(p, n, **far), slice(None), "infinite viewer")


@pytest.mark.parametrize("distance", [0.5, 3.0])
def test_unnormalised_light_scales_the_diffuse_light_by_the_distance(distance):
    p, n = np.array([[0.0, 0, 0]]), np.array([[0.0, 0, 1]])
    light = pl.PointLight(position=(0, 0.6 * distance, 0.8 * distance))  # n·l = 0.8
    args = dict(material=MAT, lights=[AMBIENT, light], eye=EYE)
    wrong, right = unnormalised_light(p, n, **args), pl.shade(p, n, **args)
    assert np.allclose(wrong.diffuse, right.diffuse * distance, rtol=1e-12), (distance, wrong.diffuse, right.diffuse)
    # a directional light is unchanged
    sun = dict(args, lights=[pl.DirectionalLight(direction=(0, 3, 4))])
    assert_terms_close(unnormalised_light(p, n, **sun), pl.shade(p, n, **sun), slice(None), "directional")


def test_unnormalised_view_raises_the_highlight_by_the_eye_distance_to_the_alpha():
    p, n = np.array([[0.0, 0, 0]]), np.array([[0.0, 0, 1]])
    material = pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=3)
    args = dict(material=material, lights=[pl.DirectionalLight(direction=(0, 0, 1))], eye=(0, 0, 4))  # r·v = 1
    wrong, right = unnormalised_view(p, n, **args), pl.shade(p, n, **args)
    assert np.allclose(right.specular, 0.5) and np.allclose(wrong.specular, 0.5 * 4**3), wrong.specular
    assert_terms_close(wrong, right, slice(None), "unnormalised-view", terms=("ambient", "diffuse", "emission"))


def test_attenuated_ambient_fades_the_ambient_light_with_the_lamp_distance():
    p, n = sphere()
    light = pl.PointLight(position=(3, 1, 0), attenuation=(0, 0, 1))
    args = dict(material=MAT, lights=[AMBIENT, light], eye=EYE)
    wrong, right = attenuated_ambient(p, n, **args), pl.shade(p, n, **args)
    d = np.linalg.norm(np.asarray(light.position) - p, axis=-1)
    assert np.allclose(wrong.ambient, right.ambient * (1 / d**2)[:, None], rtol=1e-12)
    far = d > 3
    assert far.sum() > 50 and np.all(wrong.color[far] < right.color[far])
    assert_terms_close(wrong, right, slice(None), "attenuated-ambient", terms=("diffuse", "specular", "emission"))
    # no positioned light, or f = 1: nothing to get wrong
    sun = dict(args, lights=[AMBIENT, pl.DirectionalLight(direction=(1, 1, 1))])
    assert_terms_close(attenuated_ambient(p, n, **sun), pl.shade(p, n, **sun), slice(None), "directional only")


@pytest.mark.parametrize("cutoff", [8.0, 30.0, 89.0])
def test_spot_cutoff_in_degrees_lights_nothing_but_a_point_light_still_lights(cutoff):
    p, n = sphere()
    spot = pl.SpotLight(position=(0, 0, 3), direction=(0, 0, -1), cutoff=cutoff)
    args = dict(material=MAT, lights=[AMBIENT, spot], eye=EYE)
    wrong, right = spot_cutoff_in_degrees(p, n, **args), pl.shade(p, n, **args)
    assert np.all(wrong.diffuse == 0) and np.all(wrong.specular == 0), "no cosine reaches the cutoff"
    assert (right.diffuse > 0.01).any(), f"cutoff {cutoff}: the correct spot lights something"
    plain = dict(args, lights=[AMBIENT, pl.SpotLight(position=(0, 0, 3), direction=(0, 0, -1), cutoff=180)])
    assert_terms_close(spot_cutoff_in_degrees(p, n, **plain), pl.shade(p, n, **plain), slice(None), "cutoff 180")


@pytest.mark.parametrize("alpha, bites", [(2.0, True), (4.0, True), (3.0, False), (2.5, False)])
def test_power_before_max_shows_a_ghost_highlight_for_an_even_alpha(alpha, bites):
    p, n = sphere(64, 32)
    light = pl.PointLight(position=(0.5, 0.5, 5))
    material = pl.Material(ka=0.1, kd=0.5, ks=0.6, shininess=alpha)
    args = dict(material=material, lights=[light], eye=EYE)
    wrong, right = power_before_max(p, n, **args), pl.shade(p, n, **args)
    nl, rv = sides(light.position, p, n)
    ghost = (nl > 0) & (rv < -0.5)
    assert ghost.sum() > 3, "the sphere's rim must have r·v < 0 on the lit side"
    assert_terms_close(wrong, right, ~ghost, f"power-before-max α={alpha} where r·v > −0.5", terms=("specular",),
                       atol=0.6 * 0.5**alpha)  # at most k_s |r·v|^α there
    assert_terms_close(wrong, right, (nl > 0) & (rv > 0), f"power-before-max α={alpha} where r·v > 0")
    if bites:  # (r·v)^α = |r·v|^α for an even α
        assert np.allclose(wrong.specular[ghost, 0], 0.6 * np.abs(rv[ghost]) ** alpha, rtol=1e-9)
    else:  # odd: negative, then clamped; fractional: not a real number, taken as 0
        assert np.all(wrong.specular[ghost] == 0)


# ---------------------------------------------------------------------------
# the registry and the scene helper


def test_registry_names_each_variant():
    expected = {"no-clamp-diffuse": no_clamp_diffuse, "ungated-specular": ungated_specular,
                "unnormalised-normals": unnormalised_normals, "zero-shininess": zero_shininess,
                "reflect-wrong-way": reflect_wrong_way, "unnormalised-light": unnormalised_light,
                "unnormalised-view": unnormalised_view, "view-from-eye": view_from_eye,
                "attenuated-ambient": attenuated_ambient, "spot-cutoff-in-degrees": spot_cutoff_in_degrees,
                "power-before-max": power_before_max, "zero-to-the-zero": zero_to_the_zero}
    assert set(MISTAKES) == set(expected)
    for name, mistake in MISTAKES.items():
        assert mistake.name == name and mistake.shade is expected[name], name
        assert mistake.title and mistake.looks_like and mistake.wrong != mistake.right, name
        doc = mistake.shade.__doc__
        assert "What is wrong" in doc and "correct line" in doc, f"{name}: docstring must say both"
    assert [m.name for m in MISTAKES.values() if m.needs_raw_normals] == ["unnormalised-normals"]


def test_unknown_mistake_names_the_allowed_ones():
    with pytest.raises(ValueError) as err:
        get_mistake("no-clamp-difuse")
    text = str(err.value)
    assert "no-clamp-difuse" in text and '"zero-shininess"' in text and 'did you mean "no-clamp-diffuse"' in text, text


@pytest.mark.parametrize("infinite", [False, True])
def test_scene_shade_runs_the_named_mistake_with_the_scene(infinite):
    from phonglab.scene import Camera, Geometry, Scene
    from phonglab.scene import shade as scene_shade

    scene = Scene(Geometry("sphere"), MAT, (AMBIENT, pl.PointLight(position=(3, 1, 0))),
                  Camera(eye=(0, 0, 5), infinite_viewer=infinite), model="blinn-phong", two_sided=True)
    p, n = sphere()
    viewer = {"view_direction": scene.camera.view_direction} if infinite else {"eye": scene.camera.eye}
    args = dict(material=MAT, lights=scene.lights, model="blinn-phong", two_sided=True, **viewer)
    assert_terms_close(scene_shade(scene, p, n, mistake=None), pl.shade(p, n, **args), slice(None), "no mistake")
    wrong = scene_shade(scene, p, n, mistake="no-clamp-diffuse")
    assert_terms_close(wrong, no_clamp_diffuse(p, n, **args), slice(None), "no-clamp-diffuse through scene.shade")
    assert (wrong.diffuse < 0).any()
    with pytest.raises(ValueError, match='did you mean "zero-shininess"'):
        scene_shade(scene, p, n, mistake="zero-shinyness")


def test_each_mistake_is_the_reference_kernel_with_one_step_changed():
    # the same call through the reference kernel with that one step swapped gives the same arrays
    from phonglab.core.reference import Steps
    from phonglab.teaching import mistakes

    p, n = sphere()
    n = n * np.linspace(0.3, 1.0, len(n))[:, None]  # interpolated normals, shorter than 1
    args = dict(material=MAT, lights=[AMBIENT, pl.PointLight(position=(3, 1, 0))], eye=EYE, two_sided=True)
    changed = {
        no_clamp_diffuse: Steps(diffuse_weight=mistakes.lambert_unclamped),
        ungated_specular: Steps(specular_weight=mistakes.specular_lobe_ungated),
        unnormalised_normals: Steps(normal=mistakes.raw_normal),
        zero_shininess: Steps(specular_weight=mistakes.specular_lobe_zero_exponent),
        reflect_wrong_way: Steps(mirror=mistakes.reflect_reversed),
        unnormalised_light: Steps(light=mistakes.light_vector_raw),
        unnormalised_view: Steps(view=mistakes.view_vector_raw),
        view_from_eye: Steps(view=mistakes.view_from_eye_step),
        attenuated_ambient: Steps(ambient=mistakes.ambient_attenuated),
        power_before_max: Steps(specular_weight=mistakes.specular_lobe_power_first),
    }
    spot_args = dict(args, lights=[AMBIENT, pl.SpotLight(position=(0, 0, 3), direction=(0, 0, -1), cutoff=40)])
    want = pl.shade_reference(p, n, steps=Steps(spot=mistakes.spot_cone_degrees), **spot_args)
    got = spot_cutoff_in_degrees(p, n, **spot_args)
    assert np.array_equal(got.color, want.color) and not np.array_equal(got.color,
                                                                        pl.shade_reference(p, n, **spot_args).color)
    args["lights"] = [AMBIENT, pl.PointLight(position=(3, 1, 0), attenuation=(0.5, 0.1, 0.05))]  # f != 1
    for variant, steps in changed.items():
        want = pl.shade_reference(p, n, steps=steps, **args)
        got = variant(p, n, **args)
        for term in TERMS:
            assert np.array_equal(getattr(got, term), getattr(want, term)), f"{variant.__name__}: {term}"
        # and it is not the model: the changed step shows somewhere
        assert not np.array_equal(got.color, pl.shade_reference(p, n, **args).color), variant.__name__


def test_core_never_imports_the_teaching_module():
    # scene imports it only when a mistake is asked for
    code = "import sys, phonglab.core, phonglab.scene; print(sorted(m for m in sys.modules if 'teaching' in m))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]", f"phonglab.core/scene pulled in {out}"
