"""``phonglab new lesson FILE`` writes a lesson that passes check, keeps its claims and opens in the app."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from phonglab.accuracy.claims import check_lesson
from phonglab.cli import main
from phonglab.scene import catalog, load_lesson

ROOT = Path(__file__).resolve().parents[1]


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "phonglab.cli", *args], capture_output=True, text=True, cwd=ROOT)


@pytest.fixture
def new_lesson(tmp_path):
    path = tmp_path / "lessons" / "12-my-first-lesson.md"
    done = run_cli("new", "lesson", str(path))
    assert done.returncode == 0 and path.exists(), done.stdout + done.stderr
    return path


def test_the_new_lesson_passes_check(new_lesson):
    done = run_cli("check", str(new_lesson))
    assert done.returncode == 0 and f"ok {new_lesson}" in done.stdout, done.stdout + done.stderr
    lesson = load_lesson(new_lesson)
    assert (lesson.number, lesson.title) == (12, "My first lesson")
    assert lesson.experiments and lesson.claims and lesson.question.endswith("?")


def test_the_new_lessons_claims_hold(new_lesson):
    results = check_lesson(load_lesson(new_lesson))
    assert results and all(r.passed for r in results), "\n".join(r.describe() for r in results)


def test_the_new_lesson_opens_in_the_app(new_lesson, tmp_path):
    from trame.app import get_server

    from phonglab.app.lesson_app import LessonApp

    entries, first = catalog(new_lesson)
    assert entries[first].ok, entries[first].errors
    server = get_server(f"test-new-{tmp_path.name}", client_type="vue3")
    app = LessonApp(server, target=new_lesson, export_dir=tmp_path / "exports")
    try:
        s = app.state
        assert s.lesson_title == "My first lesson" and s.lesson_errors == [], (s.lesson_title, s.lesson_errors)
        assert "<h2" in s.lesson_html and "<math" in s.lesson_html, s.lesson_html[:300]
        app.apply_experiment(0)
        assert app.scene.material.shininess == 100
    finally:
        app.close()


def test_new_refuses_to_overwrite_and_non_markdown(new_lesson, capsys):
    assert main(["new", "lesson", str(new_lesson)]) == 2
    assert "exists" in capsys.readouterr().err
    assert main(["new", "lesson", str(new_lesson.with_suffix(".toml"))]) == 2
    assert ".md" in capsys.readouterr().err
    assert main(["new", "lesson", "--force", str(new_lesson)]) == 0


def test_a_heading_that_is_not_the_title_is_shown(tmp_path):
    from phonglab.app.text import strip_title

    assert strip_title("# Intro\n\ntext", "My lesson").startswith("# Intro")
    assert strip_title("# My lesson\n\ntext", "My lesson").strip() == "text"
    assert strip_title("# Taken as title\n\ntext").strip() == "text"


def test_check_refuses_what_the_page_cannot_show(new_lesson):
    text = new_lesson.read_text(encoding="utf-8")
    new_lesson.write_text(text + "\n![a figure](figure.png)\n\n<img src='x.png'>\n\n$$x\n", encoding="utf-8")
    done = run_cli("check", str(new_lesson))
    lines = len(text.splitlines())
    assert done.returncode == 1, done.stdout
    assert f"{new_lesson}:{lines + 2}: text: an image" in done.stdout, done.stdout
    assert f"{new_lesson}:{lines + 4}: text: raw HTML" in done.stdout, done.stdout
    assert "$$ is never closed" in done.stdout, done.stdout


def test_a_new_lesson_under_a_number_already_taken_gets_a_note_and_check_reports_the_pair(tmp_path):
    """Copying 04-specular.md as 04-mine.md listed two lessons "4 · …" in the page, and check passed both."""
    folder = tmp_path / "lessons"
    folder.mkdir()
    (folder / "04-specular.md").write_text((ROOT / "lessons" / "04-specular.md").read_text(encoding="utf-8"),
                                           encoding="utf-8")
    done = run_cli("new", "lesson", str(folder / "04-mine.md"))
    assert done.returncode == 0 and "note: 04-specular.md starts with the same lesson number" in done.stdout, (
        done.stdout + done.stderr)
    done = run_cli("check", "--no-claims", str(folder))
    assert done.returncode == 1, done.stdout + done.stderr
    assert "04-specular.md: number: lesson 4 is also 04-mine.md" in done.stdout, done.stdout
    assert "1 problem in 1 of 2 files" in done.stderr, done.stderr
    (folder / "04-mine.md").rename(folder / "15-mine.md")
    done = run_cli("check", "--no-claims", str(folder))
    assert done.returncode == 1, done.stdout + done.stderr  # the file's own number = 4 line still says 4
    (folder / "15-mine.md").write_text((folder / "15-mine.md").read_text(encoding="utf-8").replace(
        "number = 4", "number = 15"), encoding="utf-8")
    done = run_cli("check", "--no-claims", str(folder))
    assert done.returncode == 0, done.stdout + done.stderr
