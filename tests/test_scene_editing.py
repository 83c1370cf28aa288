"""Editing a scene: one way to retype a light, values checked once, the lesson list."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.scene import SceneError, catalog, load_scene, scene_from_dict
from phonglab.scene.editing import RETYPE_MIN_DISTANCE, SPOT_DEFAULTS, retype_light, retyped_light_table

LESSONS = Path(__file__).resolve().parent.parent / "lessons"
MATERIAL = {"ka": 0.1, "kd": 0.5, "ks": 0.5, "shininess": 10}


def table(**extra):
    return {"geometry": {"kind": "sphere", "resolution": 8}, "material": dict(MATERIAL), **extra}


@pytest.mark.parametrize("eye, distance", [((0.0, 0.0, 2.0), RETYPE_MIN_DISTANCE), ((0.0, 0.0, 7.5), 7.5)])
def test_a_directional_light_becomes_a_point_light_at_the_eye_distance_or_the_minimum(eye, distance):
    scene = scene_from_dict(table(lights=[{"type": "directional", "direction": [0, 3, 4]}],
                                  camera={"eye": list(eye)}))
    point = scene.replace("lights[0].type", "point").lights[0]
    assert type(point) is pl.PointLight, point
    np.testing.assert_allclose(point.position, np.array([0, 0.6, 0.8]) * distance, rtol=1e-12, err_msg=str(point))


def test_scene_replace_and_the_retype_function_give_the_same_spot():
    scene = load_scene("assets/scenes/sphere.toml")
    by_path = scene.replace("lights[1].type", "spot").lights[1]
    by_function = retype_light(scene, 1, "spot").lights[1]
    assert by_path == by_function, (by_path, by_function)
    assert (by_path.cutoff, by_path.exponent) == (SPOT_DEFAULTS["cutoff"], SPOT_DEFAULTS["exponent"]), by_path
    aim = np.subtract(scene.camera.focal_point, by_path.position)
    assert np.dot(aim, by_path.direction) == pytest.approx(np.linalg.norm(aim) * np.linalg.norm(by_path.direction))


def test_retyping_understands_a_homogeneous_light_table():
    point = {"homogeneous": [2.0, 4.0, 6.0, 2.0], "color": [1, 0, 0]}
    spot = retyped_light_table(point, "spot", (0, 0, 0), (0, 0, 4))
    assert spot["position"] == [1.0, 2.0, 3.0] and spot["color"] == [1, 0, 0], spot
    sun = retyped_light_table({"homogeneous": [0.0, 0.0, 2.0, 0.0]}, "point", (0, 0, 0), (0, 0, 4))
    assert sun["position"] == [0.0, 0.0, 4.0], sun
    assert retyped_light_table(point, "point", (0, 0, 0), (0, 0, 4)) is point, "same type: unchanged"


def test_text_is_not_a_number_even_where_the_core_would_convert_it():
    assert pl.Material(ka=0, kd=0, ks=0, shininess="3").shininess == 3.0, "the core converts text"
    with pytest.raises(SceneError) as info:
        scene_from_dict(table(material=dict(MATERIAL, shininess="3")))
    assert str(info.value) == 'material.shininess: must be a finite number >= 0, got "3"', str(info.value)


def test_every_bad_value_of_one_light_is_reported_from_the_core():
    light = {"type": "spot", "position": [0, 0, 3], "direction": [0, 0, 0], "cutoff": 95, "intensity": -1}
    with pytest.raises(SceneError) as info:
        scene_from_dict(table(lights=[light]))
    fields = sorted(e.field for e in info.value)
    assert fields == ["lights[0].cutoff", "lights[0].direction", "lights[0].intensity"], str(info.value)


def test_a_zero_homogeneous_direction_is_blamed_on_homogeneous():
    with pytest.raises(SceneError) as info:
        scene_from_dict(table(lights=[{"homogeneous": [0, 0, 0, 0]}]))
    assert info.value.field == "lights[0].homogeneous" and "w >= 0" in info.value.problem, str(info.value)


def test_editing_a_scene_does_not_look_at_its_mesh_file_again(tmp_path):
    mesh = tmp_path / "tri.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = scene_from_dict(table(geometry={"kind": "file", "path": "tri.obj"}), base_dir=tmp_path)
    mesh.unlink()
    assert scene.replace("material.ks", 0.2).geometry == scene.geometry
    with pytest.raises(SceneError, match="no such mesh file"):
        scene.replace("geometry.path", str(tmp_path / "other.obj"))


def test_the_lesson_list_keeps_title_and_number_of_a_broken_lesson(tmp_path):
    (tmp_path / "04-broken.md").write_text(textwrap.dedent("""\
        +++
        ka = = 1
        +++
        # Broken heading
        """), encoding="utf-8")
    (tmp_path / "05-numbered.md").write_text("+++\nnumber = 9\ntitle = 'Given'\n[geometry]\nkind = 'cone'\n+++\n",
                                             encoding="utf-8")
    (tmp_path / "06-no-front-matter.md").write_text("text\n", encoding="utf-8")
    entries, first = catalog(tmp_path)
    got = [(e.number, e.title, e.ok, len(e.errors)) for e in entries]
    assert got == [(4, "Broken heading", False, 1), (9, "Given", False, 2), (6, "No front matter", False, 1)], got
    assert first == 0


def test_area_light_problems_are_each_reported_once():
    area = {"position": [0, 0, 1], "edge_u": [0, 0, 1], "edge_v": [0, 0, 1], "intensity": -1}
    with pytest.raises(SceneError) as info:
        scene_from_dict(table(area_light=area))
    fields = sorted(e.field for e in info.value)
    assert fields == ["area_light.edge_v", "area_light.intensity"], str(info.value)


#: edits inside one part (the page's sliders), good and refused ones; each is compared with the whole build
ONE_PART_EDITS = [
    ("material.shininess", 55.5), ("material.ks", [0.2, 0.3, 0.4]), ("material.kd", 0.5), ("material.opacity", 0.5),
    ("material.shininess", -1), ("material.ks", "bright"), ("material.opacity", 2), ("material.kd", [1, 2]),
    ("camera.eye", [1.0, 2.0, 6.0]), ("camera.infinite_viewer", True), ("camera.eye", [0.0, 0.0, 0.0]),
    ("camera.view_angle", 400), ("camera.up", [0, 0, 0]),
    ("lights[1].position", [1.0, 2.0, 3.0]), ("lights[1].intensity", 0.25), ("lights[1].color", [1, 0.5, 0]),
    ("lights[1]", {"type": "point", "position": [0.5, 1.5, 2.5]}), ("lights[1].type", "spot"),
    ("lights[1].type", "directional"), ("lights[1].homogeneous", [0.0, 1.0, 0.0, 0.0]),
    ("lights[1].position", [1e12, 0.0, 0.0]), ("lights[1].intensity", -1), ("lights[1].attenuation", [0, 0, 0]),
    ("lights[0].intensity", 0.5), ("lights[1].cutoff", 30),
]


def _whole_build(scene, path, value):
    """``scene.replace(path, value)`` the way a file is read: every part built again from the table."""
    from phonglab.scene.editing import _assign, _build
    from phonglab.scene.fieldpath import scene_to_dict

    data = scene_to_dict(scene)
    _assign(data, path, value)
    return _build(scene, data)


def _outcome(make):
    try:
        return "scene", make()
    except SceneError as exc:
        return "refused", str(exc)


@pytest.mark.parametrize("lesson", sorted(p.name for p in LESSONS.glob("[0-9]*.md")))
def test_an_edit_inside_one_part_gives_what_the_whole_build_gives(lesson):
    from phonglab.scene import load_lesson

    scene = load_lesson(LESSONS / lesson).scene
    for path, value in ONE_PART_EDITS:
        if path.startswith("lights[1]") and len(scene.lights) < 2:
            continue
        fast, whole = _outcome(lambda: scene.replace(path, value)), _outcome(lambda: _whole_build(scene, path, value))
        assert fast == whole, (lesson, path, value, fast, whole)


def test_an_edit_inside_one_part_keeps_the_other_parts_as_they_are():
    scene = load_scene("assets/scenes/sphere.toml")
    shinier = scene.replace("material.shininess", 80)
    assert shinier.material.shininess == 80 and shinier.camera is scene.camera and shinier.lights is scene.lights
    moved = scene.replace("lights[1].position", [1, 2, 3])
    assert moved.lights[1].position == (1.0, 2.0, 3.0) and moved.lights[0] is scene.lights[0], moved.lights
    assert moved.material is scene.material and moved.camera is scene.camera
