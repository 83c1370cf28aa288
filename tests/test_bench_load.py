"""``phonglab bench load``: its students read the page as a browser does, and its report counts what it measured."""

from __future__ import annotations

import subprocess
import sys

import pytest

from phonglab.bench import load
from phonglab.bench.load_student import _carries_picture, page_calls
from phonglab.bench.scenes import lesson, red_sphere_tables

TEMPLATE = (
    '<VSlider v-model="material__ks__level" :min="0.0" :max="1.0" :step="0.01" hideDetails />'
    '<VSlider v-model="material__shininess__log" :min="0.0" :max="3.0" :step="0.01" />'
    '<VSlider v-model="broken" :min="x" :max="1" />'
    '<VtkLocalView @click="trigger(\'trigger__6\', [$event])" '
    '@Animation="trigger(\'trigger__7\', [trame.refs.phonglab_view.getCamera()])" '
    '@EndAnimation="trigger(\'trigger__8\', [trame.refs.phonglab_view.getCamera()])" />'
    '<VBtn @click="trigger(\'trigger__2\')" />'
)


def test_a_student_finds_the_sliders_and_the_views_triggers_in_the_template():
    calls = page_calls({"trame__template_main": "<VBtn @click=\"trigger('trigger__1')\" />",
                        "trame__template_phonglab_controls": TEMPLATE, "other": TEMPLATE})
    assert calls.sliders == [("material__ks__level", 0.0, 1.0, 0.01), ("material__shininess__log", 0.0, 3.0, 0.01)]
    assert (calls.click, calls.turn, calls.turn_end) == ("trigger__6", "trigger__7", "trigger__8"), calls


@pytest.mark.parametrize("result, carries", [
    ({"view_colors": {"data": b"x"}}, True), ([{"pixel_src": "data:"}], True),
    ({"readout": {}}, False), ([{"readout": 1}], False), (None, False)])
def test_a_pushed_picture_is_recognised(result, carries):
    assert _carries_picture(result) is carries, result


def _round(clients, p95, achieved, lost=0):
    return load.Round(clients=clients, asked=4.0 * clients, achieved=achieved, reply_ms=(1, p95, p95),
                      picture_ms=(1, p95, p95), wait_p95_ms=p95, lost=lost, cpu_cores=None, pss_mb=None, open_s=1.0)


def test_capacity_is_the_largest_class_within_the_target_with_nothing_lost():
    rounds = [_round(1, 20, 4), _round(2, 60, 8), _round(4, 90, 14, lost=1), _round(8, 150, 20)]
    assert load.capacity(rounds) == 2
    assert load.kept_pace(rounds) == 2  # 14 of 16 asked is under 90 %, and one was lost
    assert load.capacity([_round(1, 120, 4)]) == 0
    assert load.class_sizes(12) == [1, 2, 4, 8, 12] and load.class_sizes(1) == [1]


def test_the_bench_runs_against_a_server_it_starts(tmp_path):
    path = tmp_path / "01-sphere.md"
    path.write_text(lesson('title = "A small sphere"\ncontrols = ["material.ks"]', red_sphere_tables(12),
                           "# A small sphere"), encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "bench", "load", "--lesson", str(path),
                           "--clients", "2", "--seconds", "2", "--address", ""],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    rows = [line.split() for line in done.stdout.splitlines() if line.strip()[:1].isdigit()]
    assert [int(row[0]) for row in rows] == [1, 2], done.stdout
    assert all(float(row[2]) > 0 and row[9] == "0" for row in rows), done.stdout  # answered, nothing lost
    assert "largest class with p95 <= 100 ms" in done.stdout, done.stdout


def test_a_bad_flag_is_one_line():
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "bench", "load", "--clients", "0"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "--clients" in done.stderr and "at least 1" in done.stderr, done.stderr
