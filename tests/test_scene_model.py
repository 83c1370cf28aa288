"""The scene dataclasses: checked on construction, and Scene.replace by field path."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.scene import (
    Camera,
    Experiment,
    Geometry,
    SceneError,
    field_value,
    load_scene,
    parse_path,
    parse_setting,
    scene_to_dict,
)
from phonglab.scene.loader import scene_from_dict

DATA = Path(__file__).parent / "data" / "scenes"


@pytest.fixture
def scene():
    return load_scene(DATA / "good_scene.toml")


# ---------------------------------------------------------------------------
# construction


def test_dataclasses_are_frozen():
    g = Geometry("sphere")
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.kind = "torus"


def test_camera_stores_float_tuples_and_a_unit_view_direction():
    cam = Camera(eye=[0, 3, 4], focal_point=np.array([0, 0, 0]))
    assert cam.eye == (0.0, 3.0, 4.0) and isinstance(cam.focal_point, tuple)
    assert cam.view_direction == pytest.approx((0.0, 0.6, 0.8))


@pytest.mark.parametrize(
    "kwargs, field, words",
    [
        ({"eye": (0, 0, 0)}, "eye", "must differ from camera.focal_point"),
        ({"up": (0, 0, 2)}, "up", "parallel"),
        ({"up": (0, 0, 0)}, "up", "not all zero"),
        ({"view_angle": 180}, "view_angle", "(0, 180)"),
        ({"infinite_viewer": 1}, "infinite_viewer", "true or false"),
        ({"eye": (0, 0, float("nan"))}, "eye", "finite"),
    ],
)
def test_camera_rejects(kwargs, field, words):
    with pytest.raises(SceneError) as info:
        Camera(**kwargs)
    assert info.value.field == field and words in str(info.value), (kwargs, str(info.value))


@pytest.mark.parametrize(
    "kwargs, field, words",
    [
        ({"kind": "sphere", "resolution": 2}, "resolution", "from 3 to 1024"),
        ({"kind": "sphere", "resolution": True}, "resolution", "whole number"),
        ({"kind": "cone"}, "kind", "must be one of"),
        ({"kind": "pyvista"}, "name", "required"),
        ({"kind": "file"}, "path", "required"),
        ({"kind": "torus", "path": "x.ply"}, "path", 'only used with kind = "file"'),
    ],
)
def test_geometry_rejects(kwargs, field, words):
    with pytest.raises(SceneError) as info:
        Geometry(**kwargs)
    assert info.value.field == field and words in str(info.value), (kwargs, str(info.value))


def test_mesh_files_are_checked_when_a_scene_is_built_not_by_geometry(tmp_path):
    missing = str(tmp_path / "mesh.stl")
    assert Geometry("file", path=missing).path == missing, "Geometry does not look at the disk"
    table = {"geometry": {"kind": "file", "path": missing}, "material": {"ka": 0, "kd": 0, "ks": 0, "shininess": 1}}
    with pytest.raises(SceneError) as info:
        scene_from_dict(table)
    assert info.value.field == "geometry.path" and "no such mesh file" in str(info.value), str(info.value)


def test_scene_files_refuse_parts_that_are_not_tables():
    table = {"geometry": {"kind": "sphere"}, "material": {"ka": 1}, "lights": ["sun"]}
    with pytest.raises(SceneError) as info:
        scene_from_dict(table)
    fields = {e.field for e in info.value}
    assert fields == {"material.kd", "material.ks", "material.shininess", "lights[0]"}, str(info.value)


def test_experiment_apply_runs_settings_in_order(scene):
    exp = Experiment("x", "y", settings=[("material.ks", 0), ("material.shininess", 3)])
    out = exp.apply(scene)
    assert out.material.ks == (0.0, 0.0, 0.0) and out.material.shininess == 3.0


# ---------------------------------------------------------------------------
# replace


def test_replace_returns_a_new_scene_and_keeps_the_old(scene):
    new = scene.replace("material.shininess", 100)
    assert new.material.shininess == 100.0 and scene.material.shininess == 25.0
    assert new.lights == scene.lights and new.source == scene.source


@pytest.mark.parametrize(
    "path, value, read",
    [
        ("model", "phong", lambda s: s.model),
        ("interpolation", "flat", lambda s: s.interpolation),
        ("two_sided", False, lambda s: s.two_sided),
        ("probe", [0, 0, 1], lambda s: s.probe),
        ("lights[2].specular[0]", 0.9, lambda s: s.lights[2].specular),
        ("camera.eye", [1, 2, 5], lambda s: s.camera.eye),
        ("camera.infinite_viewer", False, lambda s: s.camera.infinite_viewer),
        ("geometry.resolution", 12, lambda s: s.geometry.resolution),
        ("geometry.kind", "cube", lambda s: s.geometry.kind),
        ("material.kd", [0.1, 0.2, 0.3], lambda s: s.material.kd),
        ("material.kd[1]", 0.9, lambda s: s.material.kd),
        ("lights[1].position", (1, 1, 1), lambda s: s.lights[1].position),
        ("lights[1].position[0]", -2, lambda s: s.lights[1].position),
        ("lights[3].cutoff", 180, lambda s: s.lights[3].cutoff),
        ("lights[2].diffuse", None, lambda s: s.lights[2].diffuse),
        ("lights[0].intensity", np.float32(0.25), lambda s: s.lights[0].intensity),
    ],
)
def test_replace_sets_the_field(scene, path, value, read):
    new = scene.replace(path, value)
    got = read(new)
    old = field_value(scene, path.split("[")[0] if path.endswith("]") else path)
    assert got != read(scene), f"{path} = {value!r} changed nothing: {got!r}"
    if path.endswith("]"):
        index = int(path[path.rindex("[") + 1 : -1])
        assert got[index] == pytest.approx(float(value)), (path, value, got, old)
    elif value is None:
        assert got is None, (path, got)
    elif isinstance(value, (list, tuple)):
        assert got == tuple(float(v) for v in value), (path, value, got)
    else:
        assert got == pytest.approx(value) if not isinstance(value, str) else got == value, (path, value, got)


def test_replace_homogeneous_switches_the_light_kind(scene):
    directional = scene.replace("lights[1].homogeneous[3]", 0)
    assert isinstance(directional.lights[1], pl.DirectionalLight), directional.lights[1]
    assert directional.lights[1].direction == scene.lights[1].position
    point = directional.replace("lights[1].homogeneous", [2, 2, 2, 2])
    assert isinstance(point.lights[1], pl.PointLight) and point.lights[1].position == (1.0, 1.0, 1.0)


def test_replace_light_type_keeps_shared_fields(scene):
    point = scene.replace("lights[3].type", "point")  # spot -> point drops the cone
    assert type(point.lights[3]) is pl.PointLight and point.lights[3].position == scene.lights[3].position
    # a point light turned spot gets an axis towards the focal point (see the test below)
    assert type(scene.replace("lights[1].type", "spot").lights[1]) is pl.SpotLight


@pytest.mark.parametrize(
    "path, value, words",
    [
        ("material.shinyness", 3, 'no such field; did you mean "shininess"?'),
        ("materials.ks", 3, 'no such field; did you mean "material"?'),
        ("lights[9].position", [0, 0, 1], "no such light: index must be below 5 (5 lights)"),
        ("lights[0].position", [0, 0, 1], "no such field; allowed here: type, color, intensity"),
        ("lights.position", [0, 0, 1], "no such field"),
        ("camera.eye[3]", 1, "no such item"),
        ("material..ks", 1, "must be a field path"),
        ("probe[2]", 1, "probe[2]: is not set, so probe has no parts"),
        ("lights[x]", 1, "must be a field path"),
    ],
)
def test_replace_bad_field_path(scene, path, value, words):
    with pytest.raises(SceneError) as info:
        scene.replace(path, value)
    assert words in str(info.value), (path, str(info.value))


@pytest.mark.parametrize(
    "path, value, words",
    [
        ("material.shininess", -3, "material.shininess: must be a finite number >= 0, got -3"),
        ("material.ks", "high", 'material.ks: must be a finite number >= 0 or a list of 3 of them (RGB), got "high"'),
        ("camera.eye", [0, 0], "camera.eye: must be a list of 3 finite numbers, got [0, 0]; 2 given"),
        ("model", "phon", 'model: must be one of "phong", "blinn-phong", "cook-torrance", got "phon"; '
                           'did you mean "phong"?'),
        ("lights[3].cutoff", 95, "lights[3].cutoff: must be a half-angle in degrees in (0, 90], or 180"),
        ("geometry.resolution", 1.5, "geometry.resolution: must be a whole number from 3 to 1024, got 1.5"),
    ],
)
def test_replace_bad_value_names_path_value_and_rule(scene, path, value, words):
    with pytest.raises(SceneError) as info:
        scene.replace(path, value)
    assert words in str(info.value), (path, value, str(info.value))
    assert info.value.file is None, "a runtime value has no file location"


def test_scene_round_trips_through_its_dict(scene):
    again = scene_from_dict(scene_to_dict(scene), source=scene.source)
    assert again == scene


def test_parse_path_and_setting():
    assert parse_path("lights[1].position[2]") == ["lights", 1, "position", 2]
    assert parse_setting("material.shininess=100") == ("material.shininess", 100)
    assert parse_setting("camera.eye = [1, 2, 3]") == ("camera.eye", [1, 2, 3])
    assert parse_setting("model=blinn-phong") == ("model", "blinn-phong")
    assert parse_setting("two_sided=true") == ("two_sided", True)
    with pytest.raises(SceneError, match="PATH=VALUE"):
        parse_setting("material.shininess")


def test_changing_a_light_type_keeps_it_where_it_was():
    import numpy as np

    from phonglab.scene import load_scene

    scene = load_scene("assets/scenes/sphere.toml")
    point = scene.lights[1]
    assert type(point).__name__ == "PointLight", point
    spot = scene.replace("lights[1].type", "spot").lights[1]
    # same place, aimed at the camera's focal point, with a default cone
    assert spot.position == point.position and spot.cutoff == 25.0 and spot.exponent == 2.0, spot
    aim = np.subtract(scene.camera.focal_point, point.position)
    np.testing.assert_allclose(np.cross(spot.direction, aim), 0, atol=1e-12, err_msg=str(spot))
    directional = scene.replace("lights[1].type", "directional")
    towards = np.subtract(point.position, scene.camera.focal_point)
    np.testing.assert_allclose(np.cross(directional.lights[1].direction, towards), 0, atol=1e-12)
    back = directional.replace("lights[1].type", "point").lights[1]
    # back to a point light on the same side of the scene
    assert np.dot(np.subtract(back.position, scene.camera.focal_point), towards) > 0, back


def test_replace_many_validates_once_at_the_end():
    from phonglab.scene import load_scene

    scene = load_scene("assets/scenes/sphere.toml")
    # each step alone is fine here, but the point is the combined result
    spot = scene.replace_many([("lights[1].type", "spot"), ("lights[1].cutoff", 12), ("material.ks", 0.2)])
    assert spot.lights[1].cutoff == 12 and spot.material.ks == (0.2, 0.2, 0.2), spot
    # a state that is invalid half-way: an eye on the up axis, fixed by the next setting
    moved = scene.replace_many([("camera.eye", [0, 4, 0]), ("camera.up", [0, 0, 1])])
    assert moved.camera.eye == (0, 4, 0) and moved.camera.up == (0, 0, 1), moved.camera
    with pytest.raises(SceneError) as info:
        scene.replace("camera.eye", [0, 4, 0])
    assert "camera" in str(info.value), str(info.value)
    with pytest.raises(SceneError) as info:
        scene.replace_many([("material.ks", -1), ("material.kd", 0.5)])
    assert "material.ks" in str(info.value) and "-1" in str(info.value), str(info.value)
