"""``phonglab export``: figures from the command line; every bad input is one line, exit 2, no file."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("vtk")

from phonglab.bench import scenes  # noqa: E402
from phonglab.cli import main  # noqa: E402

SCENE = 'title = "CLI sphere"\nprobe = [0.35, 0.45, 0.82]\n' + scenes.red_sphere_tables(12, shininess=40)


@pytest.fixture
def scene_file(tmp_path) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    return path


@pytest.fixture
def out_dir(tmp_path) -> Path:
    folder = tmp_path / "out"
    folder.mkdir()
    return folder


def export(*args):
    return main(["export", *[str(a) for a in args]])


def test_export_writes_the_png_and_prints_its_path(scene_file, out_dir, capsys):
    out = out_dir / "sphere.png"
    assert export(scene_file, "-o", out, "--size", "160x120", "--supersample", "1") == 0
    from PIL import Image

    with Image.open(out) as img:
        assert img.size == (160, 120)
    assert capsys.readouterr().out.strip() == str(out)
    assert sorted(p.name for p in out_dir.iterdir()) == ["sphere.png"]


def test_sweep_reports_progress_on_stderr(scene_file, out_dir, capsys):
    out = out_dir / "grid.png"
    code = export(scene_file, "-o", out, "--size", "240x200", "--supersample", "1",
                  "--sweep", "material.ks=0.1,0.9", "--sweep", "material.shininess=4,64")
    err = capsys.readouterr().err
    assert code == 0, err
    lines = [line for line in err.splitlines() if "rendered" in line]
    assert len(lines) == 4 and "4/4" in lines[-1], err


def test_plot_to_svg(scene_file, out_dir):
    out = out_dir / "lobe.svg"
    assert export(scene_file, "-o", out, "--plot", "lobe", "--size", "500x300") == 0
    assert out.read_bytes().lstrip().startswith(b"<?xml")


BAD = [
    # (extra arguments, output name, words the error must contain)
    (["--set", "material.kz=1"], "x.png", ["material.kz"]),
    (["--set", "material.ks=banana"], "x.png", ["material.ks", "banana"]),
    (["--set", "material.shininess=-5"], "x.png", ["material.shininess", "-5"]),
    (["--set", "material.ks"], "x.png", ["PATH=VALUE"]),
    (["--size", "12x"], "x.png", ["size", "12x"]),
    (["--size", "100000x10"], "x.png", ["size", "100000x10"]),
    (["--vectors", "NQ"], "x.png", ["Q", "N, L, R, V, H"]),
    (["--sweep", "material.ks"], "x.png", ["sweep", "material.ks"]),
    (["--sweep", "material.ks=0.1,oops"], "x.png", ["material.ks", "oops"]),
    (["--sweep", "material.ks=1", "--terms"], "x.png", ["terms", "sweep"]),
    ([], "x.jpg", ["x.jpg", ".jpg", ".png"]),
    ([], "noext", ["noext", "no extension"]),
    (["--supersample", "9"], "x.png", ["supersample", "9"]),
    (["--mistake", "no-clamp"], "x.png",
     ["no-clamp", "no-clamp-diffuse", "ungated-specular", "unnormalised-normals", "zero-shininess", "lesson"]),
    (["--mistake", "lesson"], "x.png", ["lesson", "scene", "no-clamp-diffuse"]),
    (["--compare"], "x.png", ["--compare", "--mistake"]),
    (["--mistake", "zero-shininess", "--plot", "lobe"], "x.png", ["mistake", "plot"]),
    (["--mistake", "zero-shininess", "--compare", "--terms"], "x.png", ["compare", "terms"]),
    (["--mistake", "zero-shininess", "--compare", "--sweep", "material.ks=0,1"], "x.png", ["compare", "sweeps"]),
]


@pytest.mark.parametrize("extra, name, words", BAD, ids=[" ".join(b[0]) or b[1] for b in BAD])
def test_bad_input_is_one_line_exit_2_and_no_file(scene_file, out_dir, capsys, extra, name, words):
    code = export(scene_file, "-o", out_dir / name, *extra)
    err = capsys.readouterr().err
    assert code == 2, f"{extra} {name}: exit {code}, stderr {err!r}"
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("phonglab export: error: "), f"{extra}: stderr {err!r}"
    for word in words:
        assert word in lines[0], f"{extra} {name}: {word!r} missing from {lines[0]!r}"
    assert list(out_dir.iterdir()) == [], f"{extra}: left {list(out_dir.iterdir())}"


def test_missing_output_folder(scene_file, tmp_path, capsys):
    target = tmp_path / "nowhere" / "x.png"
    assert export(scene_file, "-o", target) == 2
    err = capsys.readouterr().err
    assert "does not exist" in err and "nowhere" in err, err
    assert not target.parent.exists()


def test_output_folder_is_a_file(scene_file, tmp_path, capsys):
    blocker = tmp_path / "blocker"
    blocker.write_text("a file, not a folder")
    assert export(scene_file, "-o", blocker / "x.png") == 2
    err = capsys.readouterr().err
    assert "not a folder" in err, err
    assert blocker.read_text() == "a file, not a folder"


def test_output_is_a_folder(scene_file, out_dir, capsys):
    folder = out_dir / "shots.png"
    folder.mkdir()
    assert export(scene_file, "-o", folder) == 2
    assert "is a folder" in capsys.readouterr().err
    assert list(folder.iterdir()) == []


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder(scene_file, out_dir, capsys):
    out_dir.chmod(0o555)
    try:
        assert export(scene_file, "-o", out_dir / "x.png") == 2
        assert "not writable" in capsys.readouterr().err
    finally:
        out_dir.chmod(0o755)


def test_missing_scene_file(out_dir, capsys):
    assert export(out_dir / "absent.toml", "-o", out_dir / "x.png") == 2
    err = capsys.readouterr().err
    assert "absent.toml" in err and len(err.strip().splitlines()) == 1, err
    assert list(out_dir.iterdir()) == []


def test_broken_scene_file_reports_its_first_problem_on_one_line(tmp_path, out_dir, capsys):
    broken = tmp_path / "broken.toml"
    broken.write_text(SCENE.replace("shininess = 40", "shininess = -1").replace("ks = 0.6", "ks = -2"))
    assert export(broken, "-o", out_dir / "x.png") == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "broken.toml" in err, err
    assert list(out_dir.iterdir()) == []


def test_failure_while_writing_leaves_no_partial_file(scene_file, out_dir, capsys, monkeypatch):
    from PIL import Image

    def half_then_fail(self, fp, *args, **kwargs):
        with open(fp, "wb") as handle:
            handle.write(b"\x89PNG half a file")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", half_then_fail)
    assert export(scene_file, "-o", out_dir / "x.png", "--size", "64x48", "--supersample", "1") == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and len(err.strip().splitlines()) == 1, err
    assert list(out_dir.iterdir()) == [], f"left {list(out_dir.iterdir())}"


def test_failed_export_keeps_the_previous_file(scene_file, out_dir, capsys):
    out = out_dir / "keep.png"
    out.write_bytes(b"previous figure")
    assert export(scene_file, "-o", out, "--set", "material.ks=-1") == 2
    assert out.read_bytes() == b"previous figure"


def test_the_installed_command_runs(scene_file, out_dir):
    out = out_dir / "cmd.png"
    result = subprocess.run(
        [sys.executable, "-m", "phonglab.cli", "export", str(scene_file), "-o", str(out), "--size", "120x90"],
        capture_output=True, text=True, timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert out.stat().st_size > 1000
    assert "WARN" not in result.stderr, f"VTK noise on stderr: {result.stderr!r}"


LESSON = """\
+++
title = "CLI lesson"
goal = "see the mistake"
mistake = "no-clamp-diffuse"
probe = [-0.5, 0.4, 0.7]
[geometry]
kind = "sphere"
resolution = 16
[material]
ka = 0.3
kd = 0.8
ks = 0
shininess = 10
[[lights]]
type = "ambient"
intensity = 0.4
[[lights]]
type = "point"
position = [-3, 1, 1]
[camera]
eye = [0, 0, 5]
+++
# CLI lesson

Text.
"""


@pytest.fixture
def lesson_file(tmp_path) -> Path:
    path = tmp_path / "05-cli.md"
    path.write_text(LESSON)
    return path


def test_mistake_lesson_compare_writes_the_side_by_side_figure(lesson_file, out_dir, capsys, monkeypatch):
    from phonglab.render import figures

    texts, placed = [], []
    save, place = figures.save_figure, figures.place
    monkeypatch.setattr(figures, "save_figure", lambda fig, path, ext: (
        texts.extend(t.get_text() for t in fig.texts), save(fig, path, ext)))
    monkeypatch.setattr(figures, "place", lambda fig, image, box, size: (
        placed.append(image.copy()), place(fig, image, box, size)))
    out = out_dir / "compare.png"
    code = export(lesson_file, "-o", out, "--mistake", "lesson", "--compare", "--size", "320x180",
                  "--supersample", "1")
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.out.strip() == str(out) and "2/2" in captured.err, captured
    from PIL import Image

    with Image.open(out) as img:
        assert img.size == (320, 180)
    assert sorted(p.name for p in out_dir.iterdir()) == ["compare.png"]
    # the lesson's own mistake, labelled, and the two pictures differ (the dark side goes black)
    assert "correct" in texts and any(t.startswith("common mistake: Diffuse without max(0, ·)") for t in texts), texts
    assert len(placed) == 2 and (placed[0].astype(int) - placed[1].astype(int)).sum() > 0, \
        "the mistaken picture is not darker than the correct one"


def test_mistake_with_terms_shows_the_wrong_terms(scene_file, out_dir, capsys, monkeypatch):
    from phonglab.render import figures

    texts = []
    save = figures.save_figure
    monkeypatch.setattr(figures, "save_figure", lambda fig, path, ext: (
        texts.extend(t.get_text() for t in fig.texts), save(fig, path, ext)))
    out = out_dir / "terms.png"
    code = export(scene_file, "-o", out, "--mistake", "ungated-specular", "--terms", "--size", "400x200",
                  "--supersample", "1")
    assert code == 0, capsys.readouterr().err
    assert out.exists()
    wrong = [t.split()[0] for t in texts if "(wrong)" in t]
    assert wrong == ["specular", "sum"], texts
    assert any("Common mistake: Specular without the n·l gate" in t for t in texts), texts


def test_mistake_lesson_without_a_mistake_key(lesson_file, out_dir, capsys):
    lesson_file.write_text(LESSON.replace('mistake = "no-clamp-diffuse"\n', ""))
    code = export(lesson_file, "-o", out_dir / "x.png", "--mistake", "lesson")
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "no mistake key" in lines[0] and "zero-shininess" in lines[0], err
    assert list(out_dir.iterdir()) == []


#: run in a fresh interpreter: ``phonglab export`` of a bad scene, then which renderer modules had loaded
REFUSAL_IMPORTS = """
import sys
from phonglab.cli import main
try:
    status = main(["export", sys.argv[1], "-o", sys.argv[2], *sys.argv[3:]])
except SystemExit as exc:
    status = exc.code
loaded = [m for m in ("vtk", "vtkmodules", "pyvista", "phonglab.render.glyphs", "phonglab.render.view",
                      "phonglab.render.shading", "phonglab.render.figures") if m in sys.modules]
print(status, ",".join(loaded) or "-")
"""


def test_a_bad_scene_is_refused_before_the_renderer_loads(tmp_path):
    # every check runs before VTK and the render modules are imported: a refusal costs the reading of the file
    bad = tmp_path / "bad.toml"
    bad.write_text('geometry = {kind = "sphere", resolution = 1e300}\n', encoding="utf-8")
    run = subprocess.run([sys.executable, "-c", REFUSAL_IMPORTS, str(bad), str(tmp_path / "out.png")],
                         capture_output=True, text=True, timeout=300)
    status, loaded = run.stdout.split()
    assert status == "2" and "bad.toml" in run.stderr, (bad.read_text(), run.stdout, run.stderr)
    assert loaded == "-", f"the renderer loaded before {bad.name} was refused: {loaded}; stderr {run.stderr}"
    assert not (tmp_path / "out.png").exists()


def test_bad_vectors_are_refused_before_pyvista_loads(tmp_path):
    # the letters are checked with the other options: an unknown one costs no PyVista import
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE, encoding="utf-8")
    run = subprocess.run([sys.executable, "-c", REFUSAL_IMPORTS, str(scene), str(tmp_path / "out.png"),
                          "--vectors", "NQ"], capture_output=True, text=True, timeout=300)
    status, loaded = run.stdout.split()
    assert status == "2" and "vectors" in run.stderr and "Q" in run.stderr, (run.stdout, run.stderr)
    assert loaded == "-", f"the renderer loaded before --vectors NQ was refused: {loaded}; stderr {run.stderr}"


def test_the_letters_checked_are_the_letters_drawn():
    # parse_vectors lives with the options (no PyVista); the glyphs' colours and legend must name the same letters
    from phonglab.render.glyphs import VECTORS
    from phonglab.render.options import VECTOR_LETTERS, parse_vectors

    assert "".join(VECTORS) == VECTOR_LETTERS, (list(VECTORS), VECTOR_LETTERS)
    assert parse_vectors("h,v n") == "NVH"


@pytest.mark.parametrize("sweeps, shape", [
    (["material.shininess=5,50,500"], (1, 3)),
    (["material.ks=0.2,0.8", "material.shininess=10,100"], (2, 2)),
    (["material.shininess=" + ",".join(str(5 * k) for k in range(1, 9))], (1, 8)),
    (["material.ks=0.1,0.5,0.9"] + ["material.shininess=10,100,1000"], (3, 3)),
])
def test_a_sweep_without_a_size_gets_cells_of_four_by_three(scene_file, out_dir, sweeps, shape):
    """A row of three sweeps was 1200x900: three cells about 390 pixels wide and 800 tall."""
    from phonglab.render.figure_request import check_request
    from phonglab.render.layout import GRID_WIDTH, grid_layout

    args = [a for s in sweeps for a in ("--sweep", s)]
    request = check_request(scene_file, out_dir / "grid.png", size="auto", sweep=sweeps)
    rows, cols = shape
    boxes, _ = grid_layout(request.size, rows, cols, title=True, row_labels=rows > 1 and len(sweeps) == 2,
                           col_labels=True)
    _, _, w, h = boxes[0][0]
    assert len(boxes) == rows and len(boxes[0]) == cols, (args, request.size)
    assert abs(w / h - 4 / 3) < 0.02 and 300 <= w <= 600, (args, request.size, (w, h))
    assert cols * w <= max(GRID_WIDTH, 300 * cols), (args, request.size)
    # a size the user gives is the size drawn
    given = check_request(scene_file, out_dir / "grid.png", size="1000x700", sweep=sweeps)
    assert given.size == (1000, 700), (args, given.size)


def test_the_command_line_sweep_without_size_is_a_wide_row(scene_file, out_dir):
    from PIL import Image

    out = out_dir / "row.png"
    assert export(scene_file, "-o", out, "--sweep", "material.shininess=5,50,500", "--supersample", "1") == 0
    width, height = Image.open(out).size
    assert width > 3 * height, (width, height)
    out = out_dir / "single.png"  # one render keeps the 4:3 default
    assert export(scene_file, "-o", out, "--supersample", "1") == 0
    assert Image.open(out).size == (1200, 900)
