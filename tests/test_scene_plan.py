"""The planner: what a scene computes and skips, and planned shading equal to the full evaluation."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import phonglab as pl
from phonglab.scene import Camera, Geometry, Scene, plan, shade

# ---------------------------------------------------------------------------
# helpers


def make_scene(material=None, lights=(), **options):
    camera = options.pop("camera", Camera())
    material = material or pl.Material(ka=0.1, kd=0.7, ks=0.5, shininess=20)
    return Scene(Geometry("sphere"), material, tuple(lights), camera, **options)


def effects(pairs):
    return [effect for effect, _ in pairs]


def sphere_points(n, seed=0, dtype=np.float64):
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(n, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return normals.astype(dtype), normals.astype(dtype)


def assert_within_ulp(planned, full, context):
    """Every entry of ``planned`` within 1 ulp of ``full``; the message shows the worst entry and the scene."""
    planned, full = np.asarray(planned), np.asarray(full)
    assert planned.shape == full.shape and planned.dtype == full.dtype, context
    spacing = np.spacing(np.maximum(np.abs(planned), np.abs(full)))
    excess = np.abs(planned.astype(np.float64) - full.astype(np.float64)) - spacing.astype(np.float64)
    if (excess > 0).any():
        i = np.unravel_index(np.argmax(excess), excess.shape)
        raise AssertionError(f"planned {planned[i]!r} vs full {full[i]!r} at {i}, more than 1 ulp apart\n{context}")


# ---------------------------------------------------------------------------
# what the plan says


def test_ambient_only_scene_does_no_per_light_work():
    scene = make_scene(
        pl.Material(ka=0.3, kd=0, ks=0, shininess=10),
        [pl.AmbientLight(intensity=0.5), pl.PointLight(position=(1, 2, 3))],
    )
    p = plan(scene)
    assert "ambient" in effects(p.computed), p
    assert {"diffuse", "specular"} <= set(effects(p.skipped)), p
    assert p.core.lights == (), f"no light should be evaluated per point: {p.core.lights}"


def test_diffuse_only_skips_specular_with_reason():
    scene = make_scene(pl.Material(ka=0, kd=0.8, ks=0, shininess=10), [pl.PointLight(position=(1, 2, 3))])
    p = plan(scene)
    reasons = dict(p.skipped)
    assert "specular" in reasons and "k_s" in reasons["specular"], p.skipped
    assert "diffuse" in effects(p.computed), p.computed


def test_no_light_reaches_means_no_diffuse_or_specular():
    scene = make_scene(lights=[pl.AmbientLight(intensity=1)])
    skipped = dict(plan(scene).skipped)
    assert "light" in skipped.get("diffuse", "") and "light" in skipped.get("specular", ""), skipped


def test_directional_light_with_infinite_viewer_uses_constants():
    camera = Camera(eye=(0, 0, 4), infinite_viewer=True)
    scene = make_scene(lights=[pl.DirectionalLight(direction=(0, 1, 1))], camera=camera, model="blinn-phong")
    p = plan(scene)
    names = effects(p.computed)
    assert "constant V" in names and any("constant L" in n for n in names), names
    assert p.core.constant_view and all(lp.constant_l for lp in p.core.lights), p.core


def test_attenuation_and_spot_cone_only_when_needed():
    lights = [
        pl.PointLight(position=(0, 0, 3)),
        pl.SpotLight(position=(0, 0, 3), direction=(0, 0, -1), cutoff=180, attenuation=(1, 0.5, 0)),
        pl.SpotLight(position=(0, 0, 3), direction=(0, 0, -1), cutoff=30),
    ]
    p = plan(make_scene(lights=lights))
    by_index = {lp.index: lp for lp in p.core.lights}
    assert not by_index[0].attenuation and not by_index[0].spot, by_index[0]
    assert by_index[1].attenuation and not by_index[1].spot, by_index[1]
    assert by_index[2].spot and not by_index[2].attenuation, by_index[2]


def test_two_sided_flip_only_when_asked():
    light = [pl.PointLight(position=(1, 1, 1))]
    assert "two-sided flip" in effects(plan(make_scene(lights=light)).skipped)
    assert "two-sided flip" in effects(plan(make_scene(lights=light, two_sided=True)).computed)


@pytest.mark.parametrize(
    "interpolation, effect, skips_pixel",
    [("flat", "flat shading", True), ("gouraud", "per-vertex shading", True), ("pixel", "per-pixel shading", False)],
)
def test_interpolation_line(interpolation, effect, skips_pixel):
    p = plan(make_scene(lights=[pl.PointLight(position=(1, 1, 1))], interpolation=interpolation))
    assert effect in effects(p.computed), p.computed
    assert ("per-pixel shading" in effects(p.skipped)) == skips_pixel, p.skipped


def test_plan_as_dict_round_trips_the_pairs():
    p = plan(make_scene(lights=[pl.PointLight(position=(1, 1, 1))]))
    d = p.as_dict()
    assert [(x["effect"], x["reason"]) for x in d["computed"]] == list(p.computed)
    assert [(x["effect"], x["reason"]) for x in d["skipped"]] == list(p.skipped)


def test_shade_uses_the_scene_viewer():
    """An infinite viewer shades with the camera's constant view direction, a local one with the eye."""
    light = [pl.PointLight(position=(1, 2, 3))]
    points, normals = sphere_points(50)
    local = make_scene(lights=light, camera=Camera(eye=(0, 0, 4)))
    infinite = make_scene(lights=light, camera=Camera(eye=(0, 0, 4), infinite_viewer=True))
    mat = local.material
    expected_local = pl.shade(points, normals, material=mat, lights=light, eye=(0, 0, 4))
    expected_inf = pl.shade(points, normals, material=mat, lights=light, view_direction=(0, 0, 1))
    np.testing.assert_array_equal(shade(local, points, normals).color, expected_local.color)
    np.testing.assert_array_equal(shade(infinite, points, normals).color, expected_inf.color)
    assert not np.array_equal(expected_local.specular, expected_inf.specular), "the viewer should matter"


# ---------------------------------------------------------------------------
# planned shading equals the full evaluation


def rgb(zero_chance=True):
    value = st.floats(0, 2, allow_nan=False)
    options = [value, st.tuples(value, value, value)]
    if zero_chance:
        options.append(st.just(0.0))
    return st.one_of(*options)


vec = st.tuples(*[st.floats(-5, 5, allow_nan=False)] * 3)
nonzero_vec = vec.filter(lambda v: sum(x * x for x in v) > 1e-6)
attenuation = st.one_of(
    st.just((1.0, 0.0, 0.0)),
    st.tuples(st.floats(0.1, 2), st.floats(0, 1), st.floats(0, 1)),
)
common = dict(color=rgb(), intensity=st.one_of(st.just(0.0), st.floats(0, 2)))

lights = st.one_of(
    st.builds(pl.AmbientLight, **common),
    st.builds(pl.PointLight, position=vec, attenuation=attenuation, **common),
    st.builds(pl.DirectionalLight, direction=nonzero_vec, **common),
    st.builds(
        pl.SpotLight,
        position=vec,
        direction=nonzero_vec,
        cutoff=st.one_of(st.just(180.0), st.floats(1, 90)),
        exponent=st.floats(0, 20),
        attenuation=attenuation,
        **common,
    ),
    st.builds(pl.PointLight, position=vec, diffuse=rgb(), specular=rgb()),
)
materials = st.builds(
    pl.Material,
    ka=rgb(),
    kd=rgb(),
    ks=rgb(),
    shininess=st.one_of(st.just(0.0), st.floats(0, 500)),
    emission=st.one_of(st.just(0.0), rgb()),
)
cameras = st.builds(
    Camera,
    eye=st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(2, 6)),
    focal_point=st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)),
    up=st.just((0.0, 1.0, 0.0)),
    infinite_viewer=st.booleans(),
).filter(lambda c: abs(c.view_direction[1]) < 0.999)
scenes = st.builds(
    make_scene,
    material=materials,
    lights=st.lists(lights, max_size=4),
    camera=cameras,
    model=st.sampled_from(["phong", "blinn-phong"]),
    two_sided=st.booleans(),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scene=scenes, seed=st.integers(0, 2**32 - 1), dtype=st.sampled_from([np.float64, np.float32]))
def test_planned_shading_equals_full_evaluation(scene, seed, dtype):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-1.5, 1.5, size=(64, 3)).astype(dtype)
    normals = rng.normal(size=(64, 3)).astype(dtype)
    normals[0] = 0  # a degenerate normal takes the guarded path in both
    planned = shade(scene, points, normals)
    full = shade(scene, points, normals, full=True)
    context = f"scene={scene!r}\nplan={plan(scene).computed!r}\nseed={seed}, dtype={np.dtype(dtype).name}"
    for term in ("ambient", "diffuse", "specular", "emission", "color"):
        assert_within_ulp(getattr(planned, term), getattr(full, term), f"term {term}\n{context}")


# ---------------------------------------------------------------------------
# the benchmark runs end to end (its timings are not checked: benchmarks are not tests)


def test_planner_benchmark_reports_every_case_with_a_verdict(capsys):
    import argparse

    from phonglab.bench import planner

    parser = argparse.ArgumentParser()
    planner.add_arguments(parser)
    assert planner.run(parser.parse_args(["--points", "3000", "--repeats", "1", "--shadow-vertices", "2000",
                                          "--shadow-picture", "64x48"])) == 0
    out = capsys.readouterr().out
    for name in planner.cases():
        assert name in out, f"{name} missing from:\n{out}"
    for name in planner.TARGETS:
        row = next(line for line in out.splitlines() if line.startswith(name + " "))
        assert row.split()[-1] in ("PASS", "MISS"), row
    from phonglab.bench import shadows

    for name in ("convex object: shadows on / off", "ball over floor: planned / every pair",
                 "ball over floor, per vertex: shadows on / off", "per-pixel view: shadows on / off"):
        assert f"  {name}" in out, f"{name} missing from:\n{out}"
    for name in shadows.TARGETS:
        row = next(line for line in out.splitlines() if line.strip().startswith(name))
        assert "PASS" in row or "MISS" in row, row


def test_benchmark_scenes_plan_what_their_names_say():
    from phonglab.bench.planner import cases

    scenes = cases()
    assert plan(scenes["ambient only"]).core.lights == ()
    assert not plan(scenes["diffuse only"]).core.specular
    directional = plan(scenes["directional + infinite viewer"]).core
    assert directional.constant_view and all(lp.constant_l for lp in directional.lights), directional
    spot = plan(scenes["spotlight with attenuation"]).core.lights
    assert spot and spot[0].spot and spot[0].attenuation, spot
