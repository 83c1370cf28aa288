"""Loading scene files and lessons: good files load, each kind of bad input gets a located error."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import phonglab as pl
from phonglab.scene import (
    PYVISTA_MESHES,
    Camera,
    Lesson,
    Scene,
    SceneError,
    SceneErrors,
    list_lessons,
    load,
    load_lesson,
    load_scene,
    pyvista_mesh_path,
)
from phonglab.scene.toml_lines import KeyLines

DATA = Path(__file__).parent / "data" / "scenes"
ASSETS = Path(__file__).resolve().parents[1] / "assets"

MATERIAL = """
[material]
ka = 0.1
kd = 0.5
ks = 0.5
shininess = 10
"""
SPHERE = '[geometry]\nkind = "sphere"\n'


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
    return path


def errors_of(path) -> list[SceneError]:
    with pytest.raises(SceneError) as info:
        load(path)
    return list(getattr(info.value, "errors", [info.value]))


def only_error(path) -> SceneError:
    errors = errors_of(path)
    assert len(errors) == 1, "expected one error, got:\n" + "\n".join(map(str, errors))
    return errors[0]


def line_of(path, needle) -> int:
    """The 1-based line of ``needle`` in the file, to check the reported line against."""
    for number, line in enumerate(Path(path).read_text().splitlines(), start=1):
        if needle in line:
            return number
    raise AssertionError(f"{needle!r} not in {path}")


# ---------------------------------------------------------------------------
# good files


def test_example_scene_loads_into_core_objects():
    scene = load_scene(DATA / "good_scene.toml")
    assert isinstance(scene, Scene)
    assert scene.geometry.kind == "torus" and scene.geometry.resolution == 32
    assert scene.material.kd == (0.7, 0.7, 0.7) and scene.material.emission == (0.01, 0.01, 0.01)
    types = [type(light).__name__ for light in scene.lights]
    assert types == ["AmbientLight", "PointLight", "DirectionalLight", "SpotLight", "DirectionalLight"], types
    assert scene.lights[1].attenuation == (1.0, 0.1, 0.01)
    assert scene.lights[2].diffuse == (0.4, 0.4, 0.5) and scene.lights[2].specular == (0.2, 0.2, 0.2)
    assert scene.lights[4].direction == (1.0, 1.0, 1.0), "homogeneous w = 0 is a directional light"
    assert scene.camera.infinite_viewer and scene.camera.view_angle == 35.0
    assert (scene.model, scene.interpolation, scene.two_sided) == ("blinn-phong", "pixel", True)
    assert scene.source == str(DATA / "good_scene.toml")


def test_defaults_fill_what_a_file_leaves_out(tmp_path):
    scene = load_scene(write(tmp_path, "s.toml", SPHERE + MATERIAL))
    assert scene.lights == () and scene.camera == Camera()
    assert (scene.model, scene.interpolation, scene.two_sided, scene.probe) == ("phong", "gouraud", False, None)
    assert scene.geometry.resolution == 48


def test_homogeneous_w1_is_a_point_light(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL + '[[lights]]\nhomogeneous = [2, 4, 6, 2]\ntype = "point"\n')
    light = load_scene(path).lights[0]
    assert isinstance(light, pl.PointLight) and light.position == (1.0, 2.0, 3.0), light


def test_every_example_asset_scene_loads():
    files = sorted((ASSETS / "scenes").glob("*.toml"))
    assert files, "assets/scenes should hold example scenes"
    for path in files:
        assert isinstance(load_scene(path), Scene), path


def test_lesson_front_matter_and_body():
    lesson = load_lesson(DATA / "03-good-lesson.md")
    assert isinstance(lesson, Lesson)
    assert (lesson.number, lesson.title) == (3, "Specular highlights")
    assert lesson.controls == ("material.ks", "material.shininess", "lights[1].position")
    assert lesson.body.startswith("\n# Specular highlights") and "$k_s I_s" in lesson.body
    assert [e.label for e in lesson.experiments] == ["Dull", "Matte"]
    assert lesson.experiments[0].settings == (("material.shininess", 5),)
    assert lesson.experiments[1].settings == (("material.ks", 0), ("lights[1].position", [0, 0, 3]))
    matte = lesson.experiments[1].apply(lesson.scene)
    assert matte.material.ks == (0.0, 0.0, 0.0) and matte.lights[1].position == (0.0, 0.0, 3.0)
    assert lesson.question.startswith("What happens") and lesson.answer and lesson.mistake is None


def test_lesson_number_and_title_default_from_file_name_and_heading(tmp_path):
    path = write(tmp_path, "07-diffuse.md", "+++\n" + SPHERE + MATERIAL + "+++\n\n# Diffuse light\n\nText.\n")
    lesson = load_lesson(path)
    assert (lesson.number, lesson.title) == (7, "Diffuse light")


def test_list_lessons_orders_by_number(tmp_path):
    for name, number in (("10-last.md", 10), ("2-first.md", 2)):
        write(tmp_path, name, f"+++\ntitle = 'L{number}'\n" + SPHERE + MATERIAL + "+++\ntext\n")
    write(tmp_path, "README.md", "not a lesson")
    assert [lesson.number for lesson in list_lessons(tmp_path)] == [2, 10]


# ---------------------------------------------------------------------------
# each kind of error, located


def test_malformed_toml_names_file_and_line():
    path = DATA / "bad_malformed.toml"
    error = only_error(path)
    assert str(error).startswith(f"{path}:6: is not valid TOML"), error


def test_malformed_front_matter_line_counts_from_file_start(tmp_path):
    path = write(tmp_path, "01-x.md", "+++\ntitle = 'x'\nka = = 1\n+++\ntext\n")
    error = only_error(path)
    assert error.line == 3 and "not valid TOML" in str(error), error


def test_lesson_without_front_matter():
    error = only_error(DATA / "04-no-front-matter.md")
    assert error.line == 1 and "+++" in error.problem, error


def test_front_matter_never_closed(tmp_path):
    error = only_error(write(tmp_path, "01-x.md", "+++\n" + SPHERE + MATERIAL + "\n# text\n"))
    assert "never closed" in error.problem, error


def test_missing_mesh_file():
    path = DATA / "bad_missing_mesh.toml"
    error = only_error(path)
    assert error.field == "geometry.path" and error.line == line_of(path, "no-such-mesh"), error
    assert "no such mesh file" in str(error) and '"meshes/no-such-mesh.ply"' in str(error), error


def test_mesh_file_resolves_next_to_the_scene(tmp_path):
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    scene = load_scene(write(tmp_path, "s.toml", '[geometry]\nkind = "file"\npath = "tri.obj"\n' + MATERIAL))
    assert scene.geometry.path == str((tmp_path / "tri.obj").resolve())


def test_mesh_file_with_an_unreadable_extension(tmp_path):
    (tmp_path / "mesh.txt").write_text("x")
    error = only_error(write(tmp_path, "s.toml", '[geometry]\nkind = "file"\npath = "mesh.txt"\n' + MATERIAL))
    assert error.field == "geometry.path" and ".ply" in error.problem, error


def test_wrong_type(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL.replace("shininess = 10", 'shininess = "shiny"'))
    error = only_error(path)
    assert str(error) == f'{path}:{line_of(path, "shiny")}: material.shininess: must be a finite number >= 0, got "shiny"'


def test_bool_is_not_a_number(tmp_path):
    error = only_error(write(tmp_path, "s.toml", SPHERE + MATERIAL + "[camera]\nview_angle = true\n"))
    assert error.field == "camera.view_angle" and error.value is True, error


def test_vector_of_wrong_length(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL + '[[lights]]\ntype = "point"\nposition = [1, 2]\n')
    error = only_error(path)
    assert error.field == "lights[0].position" and error.line == line_of(path, "position"), error
    assert "list of 3 finite numbers, got [1, 2]; 2 given" in str(error), error


def test_unknown_key_with_suggestion(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL + "shinyness = 4\n")
    error = only_error(path)
    assert error.field == "material.shinyness" and error.line == line_of(path, "shinyness"), error
    assert 'did you mean "shininess"?' in str(error), error


def test_unknown_top_level_key_and_light_key(tmp_path):
    path = write(tmp_path, "s.toml", 'titel = "x"\n' + SPHERE + MATERIAL + '[[lights]]\ntype = "point"\nposition = [1, 1, 1]\nattenuaton = [1, 0, 0]\n')
    errors = errors_of(path)
    text = "\n".join(map(str, errors))
    assert len(errors) == 2, text
    assert 'titel: unknown key; did you mean "title"?' in text, text
    assert 'lights[0].attenuaton: unknown key; did you mean "attenuation"?' in text, text


def test_out_of_range_value_matches_the_documented_message(tmp_path):
    lesson = write(tmp_path, "03-specular.md", "+++\ntitle = 'x'\n" + SPHERE + MATERIAL.replace("= 10", "= -3") + "+++\n")
    error = only_error(lesson)
    assert str(error) == f"{lesson}:{line_of(lesson, '= -3')}: material.shininess: must be a finite number >= 0, got -3", error


def test_core_validation_is_reported_with_file_line_and_path(tmp_path):
    path = write(
        tmp_path,
        "s.toml",
        SPHERE + MATERIAL + '[[lights]]\ntype = "point"\nposition = [1, 1, 1]\nattenuation = [0, 0, 0]\n',
    )
    error = only_error(path)
    assert error.field == "lights[0].attenuation" and error.line == line_of(path, "attenuation"), error
    assert "got [0, 0, 0]" in str(error), error


def test_unknown_choice_suggests(tmp_path):
    error = only_error(write(tmp_path, "s.toml", 'model = "blinn"\n' + SPHERE + MATERIAL))
    assert error.field == "model" and 'did you mean "blinn-phong"?' in str(error), error


def test_missing_required_tables_and_keys(tmp_path):
    errors = errors_of(write(tmp_path, "s.toml", '[[lights]]\ntype = "spot"\nposition = [0, 0, 1]\n'))
    fields = sorted(e.field for e in errors)
    assert fields == ["geometry", "lights[0].direction", "material"], "\n".join(map(str, errors))


def test_homogeneous_type_must_agree_with_w(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL + '[[lights]]\ntype = "point"\nhomogeneous = [0, 0, 1, 0]\n')
    error = only_error(path)
    assert error.field == "lights[0].type" and "w = 0 makes a directional light" in error.problem, error


def test_homogeneous_excludes_position(tmp_path):
    path = write(tmp_path, "s.toml", SPHERE + MATERIAL + "[[lights]]\nhomogeneous = [0, 0, 1, 1]\nposition = [1, 1, 1]\n")
    error = only_error(path)
    assert error.field == "lights[0].position" and "next to homogeneous" in error.problem, error


def test_a_table_where_a_value_belongs_and_back(tmp_path):
    errors = errors_of(write(tmp_path, "s.toml", 'material = 3\n' + SPHERE + '[lights]\ntype = "ambient"\n'))
    text = "\n".join(map(str, errors))
    assert {e.field for e in errors} == {"material", "lights"}, text
    assert "material: must be a table, got 3" in text and "lights: must be a list of [[lights]] tables" in text, text


def test_pyvista_mesh_name_is_checked(tmp_path):
    error = only_error(write(tmp_path, "s.toml", '[geometry]\nkind = "pyvista"\nname = "bunny"\n' + MATERIAL))
    assert error.field == "geometry.name" and '"ant"' in error.problem, error


def test_every_listed_pyvista_mesh_ships_with_pyvista():
    for name in PYVISTA_MESHES:
        path = pyvista_mesh_path(name)
        assert path.is_file() and path.stat().st_size > 0, (name, path)


def test_every_problem_is_listed_in_line_order():
    path = DATA / "bad_many.toml"
    errors = errors_of(path)
    got = [(e.line, e.field) for e in errors]
    expected = [
        (2, "model"),
        (6, "geometry.resolution"),
        (10, "material.kd"),
        (12, "material.shininess"),
        (13, "material.shinyness"),
        (17, "lights[0].position"),
        (23, "lights[1].cutoff"),
        (27, "camera.view_angle"),
    ]
    assert got == expected, "\n".join(map(str, errors))
    assert all(str(e).startswith(f"{path}:{e.line}: {e.field}: ") for e in errors), errors


def test_lesson_problems_in_controls_and_experiments(tmp_path):
    text = (DATA / "05-bad-lesson.md").read_text().replace('"bunny"', '"ant"')
    path = write(tmp_path, "05-bad-lesson.md", text)
    errors = errors_of(path)
    by_field = {e.field: e for e in errors}
    assert set(by_field) == {
        "controls[1]",
        "controls[2]",
        'experiments[0].set["material.shininess"]',
        'experiments[0].set["material.colour"]',
    }, "\n".join(map(str, errors))
    assert 'did you mean "shininess"' in str(by_field["controls[1]"])
    assert "no such light" in str(by_field["controls[2]"])
    assert "must be a finite number >= 0, got -1" in str(by_field['experiments[0].set["material.shininess"]'])
    assert all(e.line == line_of(path, "set =") for e in errors if e.field.startswith("experiments"))


def test_missing_file_and_unknown_extension(tmp_path):
    assert "no such file" in str(only_error(tmp_path / "absent.toml"))
    other = tmp_path / "scene.yaml"
    other.write_text("x: 1")
    assert ".toml" in only_error(other).problem


def test_scene_errors_is_a_scene_error_and_lists_all():
    with pytest.raises(SceneErrors) as info:
        load_scene(DATA / "bad_many.toml")
    assert isinstance(info.value, SceneError) and len(info.value) == 8
    assert str(info.value).count("\n") == 7


# ---------------------------------------------------------------------------
# the line index


def test_key_lines_follow_tables_arrays_and_multiline_values():
    text = textwrap.dedent(
        '''\
        title = "a # not a comment"
        answer = """
        [not_a_table]
        x = 1
        """
        [[lights]]
        type = "ambient"
        [[lights]]
        position = [
          1, 2, 3,
        ]
        attenuation = [1, 0, 0]
        [[experiments]]
        [experiments.set]
        "material.ks" = 0
        '''
    )
    lines = KeyLines(text)
    assert lines.line("answer") == 2
    assert "not_a_table" not in lines.lines and "x" not in lines.lines, lines.lines
    assert lines.line("lights[1]") == 8 and lines.line("lights[1].attenuation") == 12
    assert lines.line("lights[1].position[2]") == 9
    assert lines.line('experiments[0].set["material.ks"]') == 15
    assert lines.line("camera.eye") is None


# ---------------------------------------------------------------------------
# layering


def test_scene_layer_does_not_import_pyvista():
    code = (
        "import sys, phonglab.scene as s; s.load('tests/data/scenes/03-good-lesson.md');"
        "bad = [m for m in ('pyvista', 'vtk', 'vtkmodules', 'trame') if m in sys.modules];"
        "print(bad); sys.exit(1 if bad else 0)"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=Path(__file__).parents[1], capture_output=True, text=True)
    assert done.returncode == 0, f"phonglab.scene imported {done.stdout.strip()} {done.stderr}"


def test_error_message_shape():
    error = SceneError("must be a finite number >= 0", field="material.shininess", value=-3, file="lessons/03-specular.md", line=7)
    assert str(error) == "lessons/03-specular.md:7: material.shininess: must be a finite number >= 0, got -3"
    assert re.fullmatch(r"a: must be x", str(SceneError("must be x", field="a")))


def test_lesson_mistake_must_name_a_teaching_variant(tmp_path):
    from phonglab.scene import load_lesson

    text = Path("lessons/03-diffuse.md").read_text(encoding="utf-8")
    assert 'mistake = "no-clamp-diffuse"' in text
    bad = tmp_path / "03-diffuse.md"
    bad.write_text(text.replace('mistake = "no-clamp-diffuse"', 'mistake = "no-max"'), encoding="utf-8")
    with pytest.raises(SceneError) as info:
        load_lesson(bad)
    message = str(info.value)
    assert "mistake" in message and '"no-max"' in message and "no-clamp-diffuse" in message, message
