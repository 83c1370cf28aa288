"""Scenes of several objects: the [[objects]] form, its checks and limits, field paths, and where objects are placed."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from phonglab.scene import Geometry, SceneError, field_value, load_lesson, load_scene, scene_to_dict
from phonglab.scene.objects import MAX_OBJECTS, SHAPE_BOXES, object_box

ROOT = Path(__file__).resolve().parent.parent
BALL = load_scene(ROOT / "assets" / "scenes" / "ball-over-floor.toml")

OBJECT = """\
[[objects]]
name = "{name}"
geometry = {{ kind = "sphere", resolution = {resolution} }}
material = {{ ka = 0.1, kd = 0.8, ks = 0.3, shininess = 20 }}
"""


def write(tmp_path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_ball_over_the_floor_has_two_named_objects_placed_as_the_file_says():
    assert [o.name for o in BALL.objects] == ["ball", "floor"]
    assert BALL.geometry == BALL.objects[0].geometry and BALL.material == BALL.objects[0].material
    assert BALL.objects[0].geometry.center == (0.0, 0.0, 1.25) and BALL.objects[1].geometry.scale == 3.0
    assert BALL.shadows is True


def test_the_one_object_form_is_unchanged_and_means_one_unnamed_object():
    sphere = load_scene(ROOT / "assets" / "scenes" / "sphere.toml")
    assert sphere.objects == () and len(sphere.all_objects) == 1
    assert sphere.all_objects[0].label == "sphere" and sphere.geometry.center == (0.0, 0.0, 0.0)
    assert "objects" not in scene_to_dict(sphere) and not sphere.shadows


@pytest.mark.parametrize("text, message", [
    ('[geometry]\nkind = "sphere"\n' + OBJECT.format(name="a", resolution=8),
     r"scene.toml:1: geometry: cannot be given next to \[\[objects\]\]"),
    (OBJECT.format(name="a", resolution=8) + OBJECT.format(name="a", resolution=8),
     r"scene.toml:6: objects\[1\].name: must differ from objects\[0\].name, got \"a\""),
    (OBJECT.format(name=" ", resolution=8), r"scene.toml:2: objects\[0\].name: must not be empty"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere", scale = -2 }\nmaterial = { ka = 0, kd = 1, ks = 0, shininess = 1 }\n',
     r"scene.toml:3: objects\[0\].geometry.scale: must be a finite number in \[0.001, 1000\], got -2"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere", center = [0, 1] }\nmaterial = { ka = 0, kd = 1, ks = 0, shininess = 1 }\n',
     r"scene.toml:3: objects\[0\].geometry.center: must be a list of 3 finite numbers, got \[0, 1\]"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere", center = [0, 0, 1e9] }\nmaterial = { ka = 0, kd = 1, ks = 0, shininess = 1 }\n',
     r"objects\[0\].geometry.center: must have every coordinate within ±1,000,000"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere" }\nmaterial = { ka = 0, kd = 1, ks = 0, shininess = 1 }\ncolour = 1\n',
     r"scene.toml:5: objects\[0\].colour: unknown key; allowed: name, geometry, material"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere" }\n', r"objects\[0\].material: is required"),
    ('objects = 3\n', r"objects: must be a list of \[\[objects\]\] tables, got 3"),
    ('[[objects]]\nname = "a"\ngeometry = { kind = "sphere" }\nmaterial = { ka = 0, kd = 1, ks = 0, shininess = 1, opacity = 0.5 }\n'
     + OBJECT.format(name="b", resolution=8),
     r"objects\[0\].material.opacity: must be 1 in a scene of several objects.*got 0.5"),
])
def test_a_bad_object_is_reported_with_its_file_line_field_and_value(tmp_path, text, message):
    with pytest.raises(SceneError, match=message):
        load_scene(write(tmp_path, text))


def test_the_object_count_is_bounded_before_any_object_is_built(tmp_path, monkeypatch):
    from phonglab.scene import build

    built = []
    monkeypatch.setattr(build, "build_geometry", lambda *a, **k: built.append(a) or None)
    text = "".join(OBJECT.format(name=f"o{i}", resolution=8) for i in range(MAX_OBJECTS + 1))
    with pytest.raises(SceneError, match=rf"objects: has {MAX_OBJECTS + 1} objects, at most {MAX_OBJECTS} allowed"):
        load_scene(write(tmp_path, text))
    assert not built, "objects were built before their count was checked"


def test_the_triangles_of_all_objects_together_are_bounded_before_any_mesh_is_built(tmp_path):
    # three spheres of 1024 segments: about a million triangles each; the scene layer builds no mesh
    text = "".join(OBJECT.format(name=f"o{i}", resolution=1024) for i in range(3))
    with pytest.raises(SceneError, match=r"objects: the objects' meshes have about [\d,]+ triangles together, "
                                         r"at most 2,000,000 allowed; lower objects\[0\].geometry.resolution"):
        load_scene(write(tmp_path, text))
    load_scene(write(tmp_path, "".join(OBJECT.format(name=f"o{i}", resolution=512) for i in range(3))))


def test_field_paths_name_the_first_object_as_before_and_the_others_by_index():
    assert field_value(BALL, "material.ks") == [0.4, 0.4, 0.4]
    assert field_value(BALL, "objects[1].material.kd") == [0.7, 0.7, 0.7]
    edited = BALL.replace("material.kd", 0.5).replace("objects[1].geometry.scale", 2)
    assert edited.objects[0].material.kd == (0.5, 0.5, 0.5) and edited.objects[1].geometry.scale == 2.0
    assert edited.objects[1].material == BALL.objects[1].material  # the floor kept its own material
    with pytest.raises(SceneError, match=r"objects\[2\].material.kd: no such object: index must be below 2"):
        BALL.replace("objects[2].material.kd", 0.5)
    with pytest.raises(SceneError, match=r"objects\[1\].material.kx: no such field; allowed here: ka, kd, ks"):
        BALL.replace("objects[1].material.kx", 0.5)
    with pytest.raises(SceneError, match=r"objects\[1\].name: must differ from objects\[0\].name"):
        BALL.replace("objects[1].name", "ball")


def test_a_scene_given_objects_loses_its_geometry_and_material_tables_and_reads_back():
    sphere = load_scene(ROOT / "assets" / "scenes" / "sphere.toml")
    two = sphere.replace("objects", scene_to_dict(BALL)["objects"])
    assert [o.name for o in two.objects] == ["ball", "floor"] and two.geometry == BALL.geometry
    again = sphere.replace_many([("objects", scene_to_dict(two)["objects"])])
    assert again.objects == two.objects


@pytest.mark.parametrize("kind", sorted(set(SHAPE_BOXES) - {"file"}))
@pytest.mark.parametrize("resolution", [3, 8, 48, 200])
def test_every_mesh_lies_in_the_box_the_planner_bounds_it_by(kind, resolution):
    from phonglab.render.objects import scene_mesh
    from phonglab.scene import Scene

    geometry = Geometry(kind, resolution, name="ant" if kind == "pyvista" else None,
                        center=(0.3, -2.0, 5.0), scale=2.5)
    scene = Scene(geometry, BALL.material, (), BALL.camera)
    points = np.asarray(scene_mesh(scene).points, dtype=np.float64)
    lo, hi = (np.asarray(x) for x in object_box(geometry))
    slack = 1e-6 * (1 + np.abs(points).max())
    assert (points >= lo - slack).all() and (points <= hi + slack).all(), (
        kind, resolution, points.min(axis=0), points.max(axis=0), lo, hi)


def test_placing_a_shape_scales_it_about_its_origin_then_moves_it_and_keeps_its_normals():
    from phonglab.render.mesh import build_mesh
    from phonglab.render.objects import OBJECT_ARRAY, scene_mesh

    plane = build_mesh(Geometry("plane", 8))
    flat = np.asarray(plane.points)
    assert np.all(flat[:, 2] == 0) and np.allclose(plane.point_data["Normals"], [0, 0, 1])  # z = 0, normal +z
    mesh = scene_mesh(BALL)
    ids = np.asarray(mesh.point_data[OBJECT_ARRAY])
    ball = build_mesh(BALL.objects[0].geometry)
    assert np.allclose(np.asarray(mesh.points)[ids == 0], np.asarray(ball.points) + [0, 0, 1.25], atol=1e-6)
    floor = build_mesh(BALL.objects[1].geometry)
    assert np.allclose(np.asarray(mesh.points)[ids == 1], 3.0 * np.asarray(floor.points), atol=1e-6)
    assert np.array_equal(np.asarray(mesh.point_data["Normals"])[ids == 1], floor.point_data["Normals"])


def test_a_lesson_of_one_object_gets_exactly_the_mesh_it_always_had():
    from phonglab.render.mesh import build_mesh
    from phonglab.render.objects import scene_mesh

    for name in ("04-specular.md", "07-light-sources.md", "10-beyond-phong.md"):
        scene = load_lesson(ROOT / "lessons" / name).scene
        mine, before = scene_mesh(scene), build_mesh(scene.geometry)
        assert np.array_equal(mine.points, before.points) and np.array_equal(mine.faces, before.faces), name
        assert "ObjectId" not in mine.point_data, name


def test_check_reads_every_objects_mesh_file(tmp_path, capsys):
    from phonglab.cli import main

    (tmp_path / "broken.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                         "end_header\n0 0 0\n1 0 0\n")
    write(tmp_path, OBJECT.format(name="a", resolution=8)
          + '[[objects]]\nname = "b"\ngeometry = { kind = "file", path = "broken.ply" }\n'
            'material = { ka = 0.1, kd = 0.8, ks = 0.3, shininess = 20 }\n')
    assert main(["check", str(tmp_path / "scene.toml")]) == 1
    assert "objects[1].geometry.path: holds no surface" in capsys.readouterr().out


def test_an_area_lights_work_counts_every_objects_vertices(tmp_path):
    # 4096 samples × about 1,200 vertices a sphere: two spheres are under the limit of 50M rays, twelve are not
    panel = '[area_light]\nposition = [0, 2, 0]\nmethod = "uniform"\nsamples = 4096\n'
    text = "".join(OBJECT.format(name=f"o{i}", resolution=48) for i in range(2)) + panel
    load_scene(write(tmp_path, text))
    text = "".join(OBJECT.format(name=f"o{i}", resolution=48) for i in range(12)) + panel
    with pytest.raises(SceneError, match=r"area_light.samples: 4096 samples × 14,400 mesh vertices"):
        load_scene(write(tmp_path, text))
