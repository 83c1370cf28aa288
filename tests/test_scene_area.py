"""The scene's optional area light: file format, plan and shading."""

import numpy as np
import pytest

import phonglab as pl
from phonglab.scene import SceneError, load_scene, plan, shade

SCENE = "tests/data/scenes/area_light.toml"
PTS = np.array([[0.0, 0.0, 0.0], [0.5, 0.2, 0.0], [3.0, 0.0, 0.0]])
UP = np.array([[0.0, 0.0, 1.0]] * 3)


def test_area_light_loads_and_adds_its_diffuse_light():
    scene = load_scene(SCENE)
    area = scene.area_light
    assert area.method == "stratified" and area.samples == 16, area
    s = shade(scene, PTS, UP)
    without = shade(scene.replace("area_light.intensity", 0), PTS, UP)
    expected = pl.area_diffuse(PTS, UP, material=scene.material, light=area.light, method="stratified",
                               samples=16, seed=0)
    np.testing.assert_allclose(s.diffuse - without.diffuse, expected, rtol=1e-12)
    np.testing.assert_allclose(s.color - without.color, expected, rtol=1e-12)
    assert (expected[:2] > 0).all(), expected


def test_full_evaluation_includes_the_area_light():
    scene = load_scene(SCENE)
    np.testing.assert_allclose(shade(scene, PTS, UP, full=True).color, shade(scene, PTS, UP).color, rtol=1e-12)


def test_plan_says_how_the_area_light_is_evaluated_or_why_it_is_skipped():
    scene = load_scene(SCENE)
    computed = dict(plan(scene).computed)
    assert "stratified" in computed["area light"] and "16" in computed["area light"], computed
    skipped = dict(plan(scene.replace("area_light.intensity", 0)).skipped)
    assert "area light" in skipped, skipped
    plain = scene.replace("area_light.method", "exact")
    assert "closed form" in dict(plan(plain).computed)["area light"]
    no_area = load_scene("assets/scenes/sphere.toml")
    assert dict(plan(no_area).skipped)["area light"] == "the scene has none"


def test_two_sided_flips_normals_for_the_area_light_too():
    scene = load_scene(SCENE).replace("two_sided", True)
    np.testing.assert_allclose(shade(scene, PTS, -UP).diffuse, shade(scene, PTS, UP).diffuse, rtol=1e-12)


@pytest.mark.parametrize("path,value,needle", [
    ("area_light.samples", 0, "area_light.samples"),
    ("area_light.method", "adaptive", "area_light.method"),
    ("area_light.edge_v", [1, 0, 0], "area_light.edge_v"),
    ("area_light.intensity", -1, "area_light.intensity"),
    ("area_light.colour", 1, "did you mean"),
])
def test_bad_area_light_values_name_the_field(path, value, needle):
    with pytest.raises(SceneError) as info:
        load_scene(SCENE).replace(path, value)
    assert needle in str(info.value), (path, value, str(info.value))
