"""Scene.changes: one table says what each scene field's change needs; the view and the page read it.

The table is :data:`phonglab.scene.schema.SCENE_FIELDS`. These tests hold
the table to the Scene dataclass and the file format (a field missing from
either fails here, naming it), hold each field's needs to what the view and
the page redid before the table existed, and check that the view redoes
exactly what a change needs.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from phonglab.scene import Scene, load_scene, scene_to_dict
from phonglab.scene.build import _OPTION_CHECKS
from phonglab.scene.schema import NEEDS, SCENE_DEFAULTS, SCENE_FIELD, SCENE_FIELDS, SCENE_KEYS, SceneField

ROOT = Path(__file__).resolve().parent.parent
SPHERE = load_scene(ROOT / "assets" / "scenes" / "sphere.toml")

#: one change of each field, as a field path and a value
EDITS = {
    "title": ("title", "another"),
    "model": ("model", "blinn-phong"),
    "interpolation": ("interpolation", "flat"),
    "two_sided": ("two_sided", True),
    "probe": ("probe", [0.0, 0.0, 1.0]),
    "display": ("display", "linear"),
    "exposure": ("exposure", 0.5),
    "geometry": ("geometry.resolution", 24),
    "material": ("material.ks", 0.2),
    "lights": ("lights[1].position", [1.0, 2.0, 3.0]),
    "camera": ("camera.eye", [0.5, 0.0, 4.0]),
    "area_light": ("area_light", {"position": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1]}),
    # the sphere itself, named, and a floor under it: the first object stays the scene's geometry and material
    "objects": ("objects", [{"name": "ball", "geometry": {"kind": "sphere", "resolution": 48},
                             "material": {"ka": 0.1, "kd": [0.8, 0.3, 0.2], "ks": 0.6, "shininess": 40}},
                            {"name": "floor", "geometry": {"kind": "plane", "center": [0, -1, 0], "scale": 3},
                             "material": {"ka": 0.1, "kd": 0.7, "ks": 0, "shininess": 1}}]),
    "shadows": ("shadows", True),
    "shadow_bias": ("shadow_bias", 0.01),
}

#: what the view and the page redid for each field before the table (the five hand-written sets)
BEFORE = {
    "title": set(),
    "model": {"colours"},
    "interpolation": {"colours", "array"},
    "two_sided": {"colours", "vectors"},
    "probe": {"probe", "vectors"},
    "display": {"colours"},
    "exposure": {"colours"},
    "geometry": {"mesh", "colours", "probe", "vectors"},
    "material": {"colours"},
    "lights": {"colours", "vectors", "markers"},
    "camera": {"camera", "colours", "default probe", "vectors", "markers", "eye"},
    "area_light": {"colours", "markers"},
    "objects": {"mesh", "colours", "probe", "vectors"},
    "shadows": {"colours"},
    "shadow_bias": {"colours"},
}


def edited(field: str) -> Scene:
    path, value = EDITS[field]
    return SPHERE.replace(path, value)


def test_the_table_is_the_scene_dataclass_and_the_file_format():
    fields = {f.name: f for f in dataclasses.fields(Scene) if f.name != "source"}
    assert set(fields) == set(SCENE_FIELD), ("fields of Scene without a SceneField entry in scene/schema.py: "
                                            f"{sorted(set(fields) - set(SCENE_FIELD))}; entries without a field: "
                                            f"{sorted(set(SCENE_FIELD) - set(fields))}")
    assert SCENE_KEYS == tuple(f.name for f in SCENE_FIELDS)
    for entry in SCENE_FIELDS:
        if entry.option:
            assert fields[entry.name].default == entry.default, (entry.name, fields[entry.name].default)
            assert entry.name in _OPTION_CHECKS, f"{entry.name}: no check of its file value in scene/build.py"
    assert SCENE_DEFAULTS == {f.name: f.default for f in SCENE_FIELDS if f.option}


@pytest.mark.parametrize("field", [f.name for f in SCENE_FIELDS])
def test_each_field_is_written_to_the_file_form_and_read_back(field):
    scene = edited(field)
    again = scene_to_dict(scene)
    assert field in again, f"{field}: not written by scene_to_dict"
    rebuilt = SPHERE.replace_many([(field, again[field])])
    assert not Scene.changes(scene, rebuilt).fields, (field, Scene.changes(scene, rebuilt))


@pytest.mark.parametrize("field", [f.name for f in SCENE_FIELDS])
def test_a_change_of_one_field_needs_what_it_always_needed(field):
    changes = Scene.changes(SPHERE, edited(field))
    assert changes.fields == {field}, (field, changes)
    assert changes.needs == BEFORE[field], (field, sorted(changes.needs), sorted(BEFORE[field]))
    # colours only: what the page sends as colour bytes alone (material, model, display, exposure; a title)
    assert changes.colours_only == (field in {"title", "material", "model", "display", "exposure", "shadows",
                                              "shadow_bias"}), field


def test_needs_add_up_and_an_unknown_need_is_refused():
    both = Scene.changes(SPHERE, edited("material").replace("camera.eye", [0.5, 0.0, 4.0]))
    assert both.fields == {"material", "camera"} and both.needs == BEFORE["camera"] | BEFORE["material"]
    assert not Scene.changes(SPHERE, SPHERE) and not Scene.changes(SPHERE, SPHERE).fields
    with pytest.raises(ValueError, match="unknown needs.*'reshade'"):
        SceneField("tone", {"reshade"})
    assert set().union(*(f.needs for f in SCENE_FIELDS)) == set(NEEDS), "a need nobody has"


@pytest.fixture(scope="module")
def view():
    from phonglab.render import SceneView

    v = SceneView(SPHERE, size=(160, 120), labels=False, vtk_text=False)
    yield v
    v.close()


@pytest.mark.parametrize("field", ["material", "probe", "camera", "geometry", "lights", "title"])
def test_the_view_redoes_what_the_change_needs(view, field, monkeypatch):
    view.update(SPHERE)
    done = []
    for method, need in (("_recolor", "colours"), ("_update_vectors", "vectors"), ("_update_markers", "markers"),
                         ("_update_eye_marker", "eye"), ("_set_mesh", "mesh")):
        original = getattr(view, method)
        monkeypatch.setattr(view, method, lambda *a, _o=original, _n=need, **k: (done.append(_n), _o(*a, **k))[1])
    colours = np.array(view.colour_array().values)
    view.update(edited(field))
    assert set(done) == BEFORE[field] & {"colours", "vectors", "markers", "eye", "mesh"}, (field, done)
    if field == "material":
        assert not np.array_equal(colours, view.colour_array().values), "the colours did not follow"
    monkeypatch.undo()
    view.update(SPHERE)


TWO = edited("objects")


@pytest.mark.parametrize("path, value, needs", [
    ("material.ks", 0.2, {"colours"}),  # the first object's, in a scene of several
    ("objects[1].material.kd", 0.3, {"colours"}),
    ("objects[1].name", "ground", {"vectors"}),
    ("objects[1].geometry.scale", 2.0, {"mesh", "colours", "probe", "vectors"}),
    ("geometry.center", [0.0, 0.5, 0.0], {"mesh", "colours", "probe", "vectors"}),
])
def test_a_change_of_one_object_needs_what_that_part_needs(path, value, needs):
    changes = Scene.changes(TWO, TWO.replace(path, value))
    assert changes.needs == needs, (path, sorted(changes.needs), sorted(needs))
    assert changes.colours_only == (needs == {"colours"}), path


def test_the_first_object_is_the_scenes_geometry_and_material():
    moved = TWO.replace("material.kd", 0.5)
    assert moved.material.kd == (0.5, 0.5, 0.5) and moved.objects[0].material == moved.material
    again = dataclasses.replace(TWO, material=moved.material)  # set in code: the first object follows
    assert again.objects[0].material == moved.material and again == moved
    assert scene_to_dict(TWO)["objects"][1]["name"] == "floor" and "geometry" not in scene_to_dict(TWO)
    assert [o.label for o in SPHERE.all_objects] == ["sphere"] and not SPHERE.objects
