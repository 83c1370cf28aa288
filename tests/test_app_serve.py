"""``phonglab serve`` arguments, the benchmark's helpers, and the missing-Chromium message."""

from __future__ import annotations

import socket
import subprocess
import sys

import pytest

from phonglab.bench import ui
from phonglab.cli import UsageError
from phonglab.cli import serve as serve_cli
from phonglab.scene import load_lesson


@pytest.fixture
def lessons(tmp_path, monkeypatch):
    folder = tmp_path / "lessons"
    folder.mkdir()
    for number in (1, 2, 12):
        (folder / f"{number:02d}-x.md").write_text("+++\n+++\n# X\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    return folder


def test_lesson_argument_forms(lessons):
    assert serve_cli.resolve_target(None).samefile(lessons)
    assert serve_cli.resolve_target("12").name == "12-x.md"
    assert serve_cli.resolve_target("2").name == "02-x.md"
    assert serve_cli.resolve_target(str(lessons / "01-x.md")).name == "01-x.md"
    assert serve_cli.resolve_target(str(lessons)).samefile(lessons)


@pytest.mark.parametrize("given, says", [("7", "no lesson number 7"), ("nothing.md", "no such lesson"),
                                         ("notes.txt", "must be a lesson")])
def test_unknown_lessons_are_usage_errors(lessons, given, says):
    (lessons.parent / "notes.txt").write_text("x", encoding="utf-8")
    with pytest.raises(UsageError, match=says):
        serve_cli.resolve_target(given)


@pytest.mark.parametrize("port", ["-1", "65536", "http", "80.5"])
def test_bad_ports_exit_with_status_2(port):
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "serve", "--port", port],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2, done.stderr
    assert "--port" in done.stderr and port in done.stderr, done.stderr


def test_a_port_in_use_is_a_one_line_error(lessons):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        done = subprocess.run([sys.executable, "-m", "phonglab.cli", "serve", str(lessons), "--port", str(port)],
                              capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stdout + done.stderr
    assert f"cannot listen on 127.0.0.1:{port}" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr, done.stderr


def test_only_loopback_counts_as_local():
    assert serve_cli._is_loopback("127.0.0.1") and serve_cli._is_loopback("::1")
    assert serve_cli._is_loopback("localhost")
    assert not serve_cli._is_loopback("0.0.0.0") and not serve_cli._is_loopback("192.168.1.2")


def test_missing_chromium_says_how_to_install_it(monkeypatch, tmp_path):
    monkeypatch.setattr(ui, "CHROMIUM", str(tmp_path / "no-chromium"))
    with pytest.raises(RuntimeError, match="apt-get install -y chromium"):
        ui.launch_chromium(object())


def test_percentile_interpolates_between_order_statistics():
    values = [5.0, 1.0, 3.0, 2.0, 4.0]
    assert ui.percentile(values, 50) == 3.0
    assert ui.percentile(values, 95) == pytest.approx(4.8)
    assert ui.percentile(values, 0) == 1.0 and ui.percentile(values, 100) == 5.0


def test_the_bench_lesson_is_a_valid_lesson_with_a_shininess_slider(tmp_path):
    lesson = load_lesson(ui.write_bench_lesson(tmp_path, 64))
    assert lesson.controls == ("material.shininess",)
    assert lesson.scene.geometry.resolution == 64


def test_free_ports_are_bindable_on_loopback():
    port = ui.free_port()
    with socket.socket() as s:
        s.bind(("127.0.0.1", port))


@pytest.mark.parametrize("whole_group", [True, False])
def test_sigterm_stops_the_server_while_the_accuracy_plot_is_measured(whole_group):
    # lesson 11 starts worker processes; a SIGTERM to the server, or to its whole
    # process group (docker stop, kill -- -PGID), must end it and its workers promptly
    import os
    import signal
    import time

    port = ui.free_port()
    proc = subprocess.Popen([sys.executable, "-m", "phonglab.cli", "serve", "lessons/11-accuracy.md", "--port",
                             str(port)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)
    try:
        assert "serving" in proc.stdout.readline(), "the server did not start"
        deadline = time.monotonic() + 60
        while not _children(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.2)  # the plot's workers start with the lesson
        workers = _children(proc.pid)
        assert workers, "lesson 11 should start its worker processes"
        time.sleep(3)  # let the workers take up the measurement: the hang needed work in flight
        (os.killpg if whole_group else os.kill)(proc.pid, signal.SIGTERM)
        status = proc.wait(timeout=20)
        assert status == 0, (whole_group, status)
        time.sleep(0.5)
        alive = [pid for pid in workers if _alive(pid)]
        assert not alive, (whole_group, "workers left running", alive)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _children(pid):
    from pathlib import Path

    found = []
    for status in Path("/proc").glob("[0-9]*/status"):
        try:
            fields = dict(line.split(":\t", 1) for line in status.read_text().splitlines() if ":\t" in line)
        except OSError:
            continue
        if fields.get("PPid", "").strip() == str(pid):
            found.append(int(status.parent.name))
    return found


def _alive(pid):
    import os

    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    state = open(f"/proc/{pid}/stat").read().split(") ", 1)[1][0]
    return state != "Z"
