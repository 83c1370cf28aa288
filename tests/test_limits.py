"""Hostile files and flags are refused before the expensive step: one line, exit 1 or 2, nothing written.

Each case runs ``phonglab`` as a subprocess under a 4 GiB address-space
limit and a time limit, so a file that makes a reader allocate what it
announces, or a flag that makes the renderer run for minutes, fails the test
instead of the machine. The hostile files are written in ``tmp_path``.
"""

from __future__ import annotations

import os
import re
import resource
import struct
import subprocess
import sys
import time
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from phonglab import core
from phonglab.core.display import display_values
from phonglab.core.model import MAX_ATTENUATION, MAX_COEFFICIENT, MAX_EXPONENT, MAX_EXPOSURE, MAX_INTENSITY
from phonglab.render._files import clean_stale_temporaries, temp_name, write_atomically
from phonglab.scene import SceneError, load
from phonglab.scene.checks import nesting_depth
from phonglab.scene.errors import show_value
from phonglab.scene.meshsize import mesh_counts
from phonglab.scene.schema import MAX_COORDINATE, MAX_LIGHTS, MAX_MESH_BYTES, MAX_NESTING

ROOT = Path(__file__).resolve().parents[1]
SPHERE = ROOT / "assets" / "scenes" / "sphere.toml"
#: address space each phonglab run may use
ADDRESS_LIMIT = 4 * 1024**3
#: seconds each run may take (generous: the refusals come before any render)
TIME_LIMIT = 240

MATERIAL = "[material]\nka = 0.1\nkd = 0.6\nks = 0.5\nshininess = 20\n"
POINT_LIGHT = '[[lights]]\ntype = "point"\nposition = [2, 2, 2]\n'


def _limit_address_space():
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_LIMIT, ADDRESS_LIMIT))


def phonglab(*args, cwd):
    """Run ``phonglab ARGS`` bounded in memory and time; (exit status, stdout, stderr)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run(
        [sys.executable, "-m", "phonglab.cli", *map(str, args)],
        capture_output=True, text=True, cwd=cwd, env=env, timeout=TIME_LIMIT, preexec_fn=_limit_address_space,
    )
    return done.returncode, done.stdout, done.stderr


def scene_file(folder: Path, name: str, *, geometry='kind = "sphere"', extra="", lights=POINT_LIGHT) -> Path:
    path = folder / name
    path.write_text(f"[geometry]\n{geometry}\n{MATERIAL}{lights}{extra}", encoding="utf-8")
    return path


def mesh_scene(folder: Path, mesh_name: str, content: bytes | str) -> Path:
    mesh = folder / mesh_name
    mesh.write_bytes(content.encode() if isinstance(content, str) else content)
    return scene_file(folder, mesh_name + ".toml", geometry=f'kind = "file"\npath = "{mesh_name}"')


def ply_header(vertices: int, faces: int) -> str:
    return ("ply\nformat binary_little_endian 1.0\n"
            f"element vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n"
            f"element face {faces}\nproperty list uchar int vertex_indices\nend_header\n")


# ---------------------------------------------------------------------------
# the hostile inputs, each a class of its own: name -> builder(folder) giving the scene file


def _huge_ply(folder):  # a 200-byte header claiming two billion vertices
    return mesh_scene(folder, "huge.ply", ply_header(2_000_000_000, 1))


def _huge_ply_faces(folder):  # bad_alloc class: few vertices, a billion faces
    return mesh_scene(folder, "faces.ply", ply_header(3, 1_000_000_000))


def _huge_stl(folder):  # a binary STL whose count claims far more than the file holds
    return mesh_scene(folder, "huge.stl", b"\0" * 80 + struct.pack("<I", 500_000_000) + b"\0" * 100)


def _huge_vtk(folder):  # a legacy VTK header announcing two billion points
    return mesh_scene(folder, "huge.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                                          "POINTS 2000000000 float\n0 0 0\n")


def _huge_obj_bytes(folder):  # larger than the byte limit (a sparse file: no disk used)
    mesh = folder / "big.obj"
    with open(mesh, "wb") as f:
        f.truncate(MAX_MESH_BYTES + 1)
    return scene_file(folder, "big.toml", geometry='kind = "file"\npath = "big.obj"')


def _nan_vertex(folder):
    return mesh_scene(folder, "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")


def _degenerate_obj(folder):  # every triangle of zero area
    return mesh_scene(folder, "flat.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n")


def _face_out_of_range(folder):
    return mesh_scene(folder, "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")


def _broken_stl(folder):  # VTK's reader fails on it and prints its own multi-line report
    return mesh_scene(folder, "broken.stl", "solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0 zz\n")


def _broken_vtk(folder):  # declares more data than it holds: VTK logs "Error reading ascii data"
    return mesh_scene(folder, "broken.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n"
                                            "POINTS 3 float\n0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n")


def _deep_toml(folder):
    path = folder / "deep.toml"
    path.write_text("x = " + "[" * 2000 + "]" * 2000 + "\n", encoding="utf-8")
    return path


def _deep_lesson(folder):
    path = folder / "01-deep.md"
    path.write_text("+++\nx = " + "{a = " * 1500 + "1" + "}" * 1500 + "\n+++\n# Deep\n", encoding="utf-8")
    return path


def _deep_markdown(folder):  # a list nested 2000 deep: the Markdown renderer recurses per level
    path = folder / "02-list.md"
    path.write_text(f"+++\n[geometry]\nkind = \"sphere\"\n{MATERIAL}+++\n# List\n\n" + "- " * 2000 + "x\n",
                    encoding="utf-8")
    return path


def _big_scene_file(folder):
    path = folder / "big.toml"
    path.write_text("# " + "x" * (2 * 1024 * 1024) + "\n", encoding="utf-8")
    return path


def _far_light(folder):
    return scene_file(folder, "far.toml", lights='[[lights]]\ntype = "point"\nposition = [1e300, 0, 0]\n')


def _far_eye(folder):
    return scene_file(folder, "eye.toml", extra="[camera]\neye = [0, 0, -1e308]\n")


def _many_lights(folder):
    return scene_file(folder, "lights.toml", lights=POINT_LIGHT * (MAX_LIGHTS + 1))


def _many_samples(folder):
    return scene_file(folder, "area.toml", geometry='kind = "sphere"\nresolution = 1024',
                      extra='[area_light]\nposition = [0, 2, 0]\nmethod = "uniform"\nsamples = 4096\n')


def _huge_coefficient(folder):  # 1e308 overflows float32 in the shading sum
    path = folder / "bright.toml"
    path.write_text(f"[geometry]\nkind = \"sphere\"\n{MATERIAL.replace('ka = 0.1', 'ka = 1e308')}{POINT_LIGHT}",
                    encoding="utf-8")
    return path


def _long_mesh_path(folder):  # longer than any file name the system takes
    return scene_file(folder, "long.toml", geometry=f'kind = "file"\npath = "{"m" * 5000}.ply"')


def _fifo_scene(folder):  # reading a FIFO waits for a writer that never comes
    path = folder / "pipe.toml"
    os.mkfifo(path)
    return path


def _fifo_mesh(folder):
    os.mkfifo(folder / "pipe.ply")
    return scene_file(folder, "pipe-mesh.toml", geometry='kind = "file"\npath = "pipe.ply"')


#: file cases: builder, words the one-line error must contain
FILE_CASES = {
    "huge PLY header": (_huge_ply, "too many vertices"),
    "PLY with a billion faces": (_huge_ply_faces, "too many triangles"),
    "STL count past its size": (_huge_stl, "not an STL file"),
    "legacy VTK with 2e9 points": (_huge_vtk, "too many vertices"),
    "mesh past the byte limit": (_huge_obj_bytes, "too large a mesh file"),
    "NaN vertex": (_nan_vertex, "not a finite number"),
    "degenerate OBJ": (_degenerate_obj, "zero area"),
    "face index out of range": (_face_out_of_range, "vertex it does not have"),
    "STL that VTK cannot read": (_broken_stl, "holds no surface"),
    "legacy VTK shorter than declared": (_broken_vtk, "holds no surface"),
    "TOML nested 2000 deep": (_deep_toml, f"at most {MAX_NESTING} allowed"),
    "lesson front matter nested 1500 deep": (_deep_lesson, f"at most {MAX_NESTING} allowed"),
    "lesson text with a list nested 2000 deep": (_deep_markdown, "lists or quotes 2000 deep"),
    "scene file over 1 MB": (_big_scene_file, "too large"),
    "light at 1e300": (_far_light, "lights[0].position"),
    "eye at -1e308": (_far_eye, "camera.eye"),
    "too many lights": (_many_lights, f"at most {MAX_LIGHTS} allowed"),
    "4096 area samples at resolution 1024": (_many_samples, "area_light.samples"),
    "ka of 1e308": (_huge_coefficient, "material.ka: must be a finite number in [0, 1000]"),
    "mesh path of 5000 characters": (_long_mesh_path, "geometry.path: is too long"),
    "FIFO named .toml": (_fifo_scene, "is a FIFO (named pipe), not a regular file"),
    "FIFO named .ply": (_fifo_mesh, "geometry.path: must name a regular mesh file"),
}


def _assert_clean(status, out, err, expected_status, words, output=None, *, one_line=True):
    shown = f"status {status}\nstdout: {out[-2000:]}\nstderr: {err[-2000:]}"
    assert status == expected_status, shown
    assert "Traceback" not in out + err, shown
    assert words in out + err, f"expected {words!r}:\n{shown}"
    if one_line:
        assert len(err.strip().splitlines()) == 1, f"expected one line on stderr:\n{shown}"
    if output is not None:
        assert not output.exists(), f"{output} was written:\n{shown}"
        leftovers = [p.name for p in output.parent.iterdir() if p.name.startswith(".")]
        assert not leftovers, f"temporary files left: {leftovers}\n{shown}"


@pytest.fixture(scope="module")
def hostile_files(tmp_path_factory):
    """Every hostile file, each in its own folder: case -> scene or lesson file."""
    made = {}
    for i, (case, (build, _)) in enumerate(FILE_CASES.items()):
        folder = tmp_path_factory.mktemp(f"hostile{i}")
        made[case] = build(folder)
    return made


def test_check_reports_each_hostile_file_in_one_line(hostile_files, tmp_path):
    """One ``phonglab check`` over all of them: each file's problem on its own line, exit 1."""
    status, out, err = phonglab("check", *hostile_files.values(), cwd=tmp_path)
    shown = f"status {status}\nstdout: {out[-4000:]}\nstderr: {err[-2000:]}"
    assert status == 1 and "Traceback" not in out + err, shown
    assert f"in {len(hostile_files)} of {len(hostile_files)} files" in err, shown
    for case, path in hostile_files.items():
        words = FILE_CASES[case][1]
        lines = [line for line in out.splitlines() if line.startswith(str(path))]
        assert lines and any(words in line for line in lines), f"{case}: expected {words!r} for {path}\n{shown}"


@pytest.mark.parametrize("case", list(FILE_CASES))
def test_hostile_file_is_refused_by_export(hostile_files, tmp_path, case):
    scene = hostile_files[case]
    output = tmp_path / "figure.png"
    status, out, err = phonglab("export", scene.name, "-o", output, cwd=scene.parent)
    _assert_clean(status, out, err, 2, FILE_CASES[case][1], output)


DEEP = "[" * 1000 + "]" * 1000

#: flag cases: arguments after ``export SCENE -o OUT``, words the error must contain
FLAG_CASES = {
    "--set nested 1000 deep": (["--set", f"material.ks={DEEP}"], "material.ks"),
    "--sweep value nested 1000 deep": (["--sweep", f"material.ks=0.5,{DEEP}"], f"at most {MAX_NESTING}"),
    "--set a light at 1e300": (["--set", "lights[1].position=[1e300, 0, 0]"], "lights[1].position"),
    "--set the eye past the bound": (["--set", f"camera.eye=[0, 0, {MAX_COORDINATE * 10:g}]"], "camera.eye"),
    "--set 4096 area samples": (["--set", "geometry.resolution=1024", "--set",
                                 'area_light={position = [0, 2, 0], method = "uniform", samples = 4096}'],
                                "area_light.samples"),
    "--size 8192x8192": (["--size", "8192x8192"], "pixels, at most"),
    "--size 8192x8192 --supersample 4": (["--size", "8192x8192", "--supersample", "4"], "pixels, at most"),
    "--supersample 9": (["--supersample", "9"], "supersample"),
    "sweep of 100 cells": (["--sweep", "material.ks=" + ",".join(["0.5"] * 100)], "cells, at most"),
    "9 x 8 sweep": (["--sweep", "material.ks=" + ",".join(["0.5"] * 9),
                     "--sweep", "material.shininess=" + ",".join(["8"] * 8)], "cells, at most"),
    "sweep too fine for its size": (["--size", "64x64", "--sweep", "material.ks=" + ",".join(["0.5"] * 8),
                                     "--sweep", "material.shininess=" + ",".join(["8"] * 8)], "too small"),
    "--set emission 1e308": (["--set", "material.emission=1e308"], "material.emission: must be a finite number in [0, 1000]"),
    "--set exposure 1e308": (["--set", "exposure=1e308"], "exposure: must be a finite number in (0, 1000]"),
}


@pytest.mark.parametrize("case", list(FLAG_CASES))
def test_hostile_flag_is_refused_before_rendering(tmp_path, case):
    flags, words = FLAG_CASES[case]
    output = tmp_path / "figure.png"
    status, out, err = phonglab("export", SPHERE, "-o", output, *flags, cwd=tmp_path)
    _assert_clean(status, out, err, 2, words, output)


# ---------------------------------------------------------------------------
# the pieces, in process


def test_mesh_counts_read_headers_without_reading_the_mesh(tmp_path):
    ply = tmp_path / "a.ply"
    ply.write_text(ply_header(12, 20))
    assert mesh_counts(ply) == (12, 20)
    obj = tmp_path / "a.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 3 4\n")
    assert mesh_counts(obj) == (4, 3), "a quad is two triangles"
    stl = tmp_path / "a.stl"
    stl.write_bytes(b"\0" * 80 + struct.pack("<I", 2) + b"\0" * 100)
    assert mesh_counts(stl) == (6, 2)


def test_a_shipped_mesh_passes_the_header_check():
    from phonglab.scene.paths import pyvista_mesh_path

    for name in ("airplane", "ant", "nut"):
        vertices, faces = mesh_counts(pyvista_mesh_path(name))
        assert 0 < vertices < 1_000_000 and 0 < faces < 2_000_000, (name, vertices, faces)


def test_nesting_depth_counts_lists_and_tables():
    assert nesting_depth("x = [[1, 2], {a = [3]}]") == 3
    assert nesting_depth("") == 0


@pytest.mark.parametrize("value", ["x" * 100_000, list(range(100_000)), [[[[[[[[[[[[1]]]]]]]]]]]]])
def test_shown_values_are_capped(value):
    shown = show_value(value)
    assert len(shown) < 120, shown


def test_editing_refuses_what_check_refuses():
    scene = load(SPHERE)
    with pytest.raises(SceneError, match=r"lights\[1\]\.position.*1,000,000"):
        scene.replace("lights[1].position", [-1e308, 0, 0])
    far = scene.replace("lights[1].position", [MAX_COORDINATE, 0, 0])
    assert far.lights[1].position[0] == MAX_COORDINATE


def test_stale_temporaries_are_cleared_and_fresh_ones_kept(tmp_path):
    target = tmp_path / "figure.png"
    stale, fresh = tmp_path / temp_name(target), tmp_path / temp_name(target)
    mine = tmp_path / ".notes-0123abcd.txt"  # not ours
    for p in (stale, fresh, mine):
        p.write_bytes(b"")
    old = time.time() - 3600
    os.utime(stale, (old, old))
    os.utime(mine, (old, old))
    assert clean_stale_temporaries(tmp_path) == [stale.name]
    assert fresh.exists() and mine.exists() and not stale.exists()
    os.utime(fresh, (old, old))
    write_atomically(target, lambda tmp: Path(tmp).write_bytes(b"png"))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([target.name, mine.name])


# ---------------------------------------------------------------------------
# the upper limits of coefficients, intensities and exponents


#: field path -> a value past its limit; every one of them overflowed float32 in an export before
PAST_LIMITS = {
    "material.ka": 1e308, "material.kd": [0.5, 1e308, 0.5], "material.ks": 1e308, "material.emission": 1e308,
    "material.shininess": 1e308, "lights[1].intensity": 1e308, "lights[1].color": [1e308, 1, 1],
    "lights[1].attenuation": [1, 0, 1e308], "exposure": 1e308,
}


@pytest.mark.parametrize("path", list(PAST_LIMITS))
def test_values_past_their_limit_are_refused_from_files_and_edits_alike(path, tmp_path):
    value = PAST_LIMITS[path]
    with pytest.raises(SceneError) as edited:
        load(SPHERE).replace(path, value)
    message = str(edited.value)
    assert message.startswith(f"{path}: must be") and len(message.splitlines()) == 1, (path, value, message)
    assert any(limit in message for limit in ("in [0, 1000]", "in [0, 1e6]", "±1e6", "in (0, 1000]")), message
    # the same scene written as a file is refused with the same words
    data = tomllib.loads(SPHERE.read_text(encoding="utf-8"))
    *tables, key = re.split(r"\.", path)
    table = data
    for name in tables:  # "material", "lights[1]"
        m = re.fullmatch(r"(\w+)\[(\d+)\]", name)
        table = table[m.group(1)][int(m.group(2))] if m else table[name]
    table[key] = value
    file = tmp_path / "past.toml"
    file.write_text(_toml(data), encoding="utf-8")
    with pytest.raises(SceneError) as loaded:
        load(file)
    assert message in str(loaded.value), (path, value, str(loaded.value))


def _toml(data: dict) -> str:
    """``data`` (scalars, lists, tables and arrays of tables of them) as TOML text."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = [f"{k} = {value(v)}" for k, v in data.items() if not isinstance(v, (dict, list)) or
             (isinstance(v, list) and not any(isinstance(x, dict) for x in v))]
    for k, v in data.items():
        if isinstance(v, dict):
            lines += [f"[{k}]"] + [f"{kk} = {value(vv)}" for kk, vv in v.items()]
        elif isinstance(v, list) and any(isinstance(x, dict) for x in v):
            for table in v:
                lines += [f"[[{k}]]"] + [f"{kk} = {value(vv)}" for kk, vv in table.items()]
    return "\n".join(lines) + "\n"


def test_values_at_their_limits_shade_finite_in_float32_without_a_warning():
    top = MAX_COEFFICIENT
    material = core.Material(ka=top, kd=top, ks=top, emission=top, shininess=MAX_EXPONENT)
    # every light sits on the shaded point at the origin: its attenuation factor is at its cap
    lights = [core.AmbientLight(intensity=MAX_INTENSITY, color=top)]
    lights += [core.PointLight(position=(0, 0, 0), intensity=MAX_INTENSITY, color=top, attenuation=(0, 0, 1))
               for _ in range(MAX_LIGHTS - 2)]
    lights += [core.SpotLight(position=(0, 0, 0), direction=(0, 0, -1), cutoff=90, exponent=MAX_EXPONENT,
                              intensity=MAX_INTENSITY, color=top, attenuation=(MAX_ATTENUATION, 0, MAX_ATTENUATION))]
    points = np.array([[0, 0, 0], [0.5, 0, 0], [MAX_COORDINATE, -MAX_COORDINATE, MAX_COORDINATE]], np.float32)
    normals = np.array([[0, 0, 1]] * 3, np.float32)
    with warnings.catch_warnings(), np.errstate(all="raise"):
        warnings.simplefilter("error")
        colour = core.shade(points, normals, material=material, lights=lights, eye=(0, 0, 5)).color
        shown = display_values(colour, exposure=MAX_EXPOSURE)
    assert colour.dtype == np.float32 and np.isfinite(colour).all(), colour
    # the brightest value times the exposure, summed over the largest figure (2**23 pixels), stays finite
    assert float(colour.max()) * MAX_EXPOSURE * 2**23 < np.finfo(np.float32).max, colour.max()
    assert np.isfinite(shown).all(), shown


def test_the_page_refuses_a_value_past_its_limit_with_a_notice(lesson_app):
    from test_app_page import MISTAKE_LESSON

    app = lesson_app("01-limits.md", MISTAKE_LESSON, "test-limits")
    scene = app.scene
    app._on_control("material__kd", [1e308, 0.5, 0.5])
    assert app.scene is scene, "kd = 1e308 changed the scene"
    notice = app.state.notice
    assert notice["kind"] == "error" and "Refused" in notice["text"] and "1000" in notice["text"], notice


def test_a_mesh_name_the_system_refuses_is_a_scene_error(tmp_path):
    scene = scene_file(tmp_path, "part.toml", geometry=f'kind = "file"\npath = "{"m" * 300}.ply"')
    with pytest.raises(SceneError) as refused:
        load(scene)
    text = str(refused.value)
    assert "geometry.path: cannot be used as a file name" in text and len(text.splitlines()) == 1, text
    assert len(text) < 300, text


def test_check_echoes_hidden_characters_of_a_file_escaped(tmp_path):
    # a right-to-left override in the file's name and in a value, a NUL and an escape sequence in values and keys
    scene = tmp_path / "evil\u202elmth.toml"
    scene.write_text('model = "phong\\u202e\\u0000"\ntitle = 7\n[geometry]\nkind = "sphere\\u001b[2J"\n'
                     f'{MATERIAL}"ka\\u202e" = 1\n', encoding="utf-8")
    status, out, err = phonglab("check", scene, cwd=tmp_path)
    shown = f"status {status}\nstdout: {out!r}\nstderr: {err!r}"
    assert status == 1 and "Traceback" not in out + err, shown
    for hidden in ("\u202e", "\x00", "\x1b"):
        assert hidden not in out + err, shown
    assert out.count("\\u202e") >= 3 and "\\x00" in out and "\\x1b" in out, shown
