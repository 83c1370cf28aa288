"""`phonglab check` and `phonglab plan`: output and exit status."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

from phonglab.cli import main

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "scenes"
GOOD = [DATA / "good_scene.toml", DATA / "03-good-lesson.md"]
BAD = [DATA / "bad_many.toml", DATA / "bad_malformed.toml", DATA / "bad_missing_mesh.toml", DATA / "04-no-front-matter.md"]


def run(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_check_good_files_prints_ok_and_exits_0(capsys):
    status, out, err = run(capsys, "check", *GOOD)
    assert status == 0, (out, err)
    assert out.splitlines() == [f"ok {GOOD[0]}", f"ok {GOOD[1]} (2 claims hold)"], out


def test_check_lists_every_problem_in_every_file(capsys):
    status, out, err = run(capsys, "check", *GOOD, *BAD)
    assert status == 1, (out, err)
    lines = out.splitlines()
    for path in BAD:
        assert any(line.startswith(f"{path}:") for line in lines), f"{path} missing from:\n{out}"
    assert sum(line.startswith(f"{DATA / 'bad_many.toml'}:") for line in lines) == 8, out
    assert f"ok {GOOD[0]}" in lines and f"ok {GOOD[1]} (2 claims hold)" in lines, out
    assert "11 problems in 4 of 6 files" in err, err


def test_check_a_folder_expands_to_scenes_and_lessons(tmp_path, capsys):
    shutil.copy(DATA / "good_scene.toml", tmp_path / "a.toml")
    shutil.copy(DATA / "03-good-lesson.md", tmp_path / "03-good-lesson.md")
    (tmp_path / "README.md").write_text("not a lesson")
    status, out, _ = run(capsys, "check", tmp_path)
    assert status == 0 and out.splitlines() == [f"ok {tmp_path / 'a.toml'}",
                                                 f"ok {tmp_path / '03-good-lesson.md'} (2 claims hold)"], out


def test_check_missing_file(tmp_path, capsys):
    status, out, _ = run(capsys, "check", tmp_path / "absent.toml")
    assert status == 1 and out.strip() == f"{tmp_path / 'absent.toml'}: no such file", out


def test_plan_prints_computed_and_skipped_with_reasons(capsys):
    status, out, err = run(capsys, "plan", DATA / "good_scene.toml")
    assert status == 0, err
    text = out.splitlines()
    assert text[0].endswith("blinn-phong, pixel interpolation, 5 lights"), out
    computed, skipped = text.index("computed:"), text.index("skipped:")
    assert computed < skipped
    computed_lines = text[computed + 1 : skipped]
    assert any(line.split()[0] == "specular" for line in computed_lines), out
    assert any("light 3: attenuation" in line and "(1, 0, 0)" in line for line in text[skipped + 1 :]), out


def test_plan_json_with_set(capsys):
    status, out, err = run(capsys, "plan", "--json", DATA / "03-good-lesson.md", "--set", "material.ks=0")
    assert status == 0, err
    data = json.loads(out)
    skipped = {item["effect"]: item["reason"] for item in data["skipped"]}
    assert "k_s is 0" in skipped["specular"], data
    assert data["file"] == str(DATA / "03-good-lesson.md")
    assert all(set(item) == {"effect", "reason"} for item in data["computed"] + data["skipped"]), data


def test_plan_bad_file_exits_1_with_the_errors(capsys):
    status, out, err = run(capsys, "plan", DATA / "bad_many.toml")
    assert status == 1 and out == "", out
    assert err.count(str(DATA / "bad_many.toml")) == 8, err


def test_plan_bad_set_is_a_usage_error(capsys):
    status, _, err = run(capsys, "plan", DATA / "good_scene.toml", "--set", "material.ks=-1")
    assert status == 2, err
    assert "--set material.ks=-1: material.ks: must be a finite number >= 0" in err, err
    status, _, err = run(capsys, "plan", DATA / "good_scene.toml", "--set", "material.ks")
    assert status == 2 and "PATH=VALUE" in err, err


def test_check_and_plan_do_not_import_vtk():
    code = (
        "import sys; from phonglab.cli import main;"
        f"main(['check', {str(GOOD[0])!r}]); main(['plan', {str(GOOD[1])!r}]);"
        "bad = [m for m in ('pyvista', 'vtk', 'vtkmodules', 'trame') if m in sys.modules];"
        "print('IMPORTED', bad); sys.exit(1 if bad else 0)"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0 and "IMPORTED []" in done.stdout, (done.stdout, done.stderr)
