"""``phonglab bench load``: its students read the page as a browser does, and its report counts what it measured."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from phonglab.app import page
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


def test_a_student_moves_the_all_controls_panels_sliders_only_when_the_lesson_has_none():
    # a control's box holds a head (its label and value) before its slider, as the page draws it
    block = '<div class="phonglab-control phonglab-control-{key}{extra}"><div class="phonglab-control-head">x</div>'
    own = block.format(key="ks", extra="") + '<VSlider v-model="ks" min="0.0" max="1.0" step="0.1" />'
    every = (block.format(key="kd", extra=" phonglab-control-all")
             + '<VSlider v-model="kd" min="0.0" max="1.0" step="0.1" />'
             + block.format(key="ks", extra=" phonglab-control-all")
             + '<VSlider v-model="ks" min="0.0" max="1.0" step="0.1" />')
    assert page_calls({"trame__template_c": own + every}).sliders == [("ks", 0.0, 1.0, 0.1)]
    assert page_calls({"trame__template_c": every}).sliders == [("kd", 0.0, 1.0, 0.1), ("ks", 0.0, 1.0, 0.1)]


def test_a_student_finds_the_sliders_and_the_views_triggers_in_the_template():
    calls = page_calls({"trame__template_main": "<VBtn @click=\"trigger('trigger__1')\" />",
                        "trame__template_phonglab_controls": TEMPLATE, "other": TEMPLATE})
    assert calls.sliders == [("material__ks__level", 0.0, 1.0, 0.01), ("material__shininess__log", 0.0, 3.0, 0.01)]
    assert (calls.click, calls.turn, calls.turn_end) == ("trigger__6", "trigger__7", "trigger__8"), calls


#: lesson 4's controls: the shininess, k_s, the eye and the second light's position
LESSON_4_SLIDERS = ["material__shininess__log", "material__ks__level", "camera__azimuth", "camera__elevation",
                    "camera__distance", "lights_1__azimuth", "lights_1__elevation", "lights_1__distance"]


def test_a_student_finds_the_sliders_of_the_page_a_lesson_really_draws(lesson_app):
    # the page writes a slider's range as plain attributes (min="0.0"): students that read only ":min"
    # found no slider, and every "action" of the bench was a lifecycle call
    lesson4 = (Path(__file__).resolve().parents[1] / "lessons" / "04-specular.md").read_text(encoding="utf-8")
    app = lesson_app("04-specular.md", lesson4, "bench-load-template")
    keys = ("trame__template_main", f"trame__template_{page.CONTROLS_TEMPLATE}")
    templates = {key: app.state[key] for key in keys}
    calls = page_calls(templates)
    sliders = [key for key, *_ in calls.sliders]
    # the lesson's own sliders, once each; not the "all controls" panel's (roughness moves nothing under Phong)
    assert sorted(sliders) == sorted(LESSON_4_SLIDERS), (sliders, templates)
    assert all(high > low for _, low, high, _ in calls.sliders), calls.sliders
    assert calls.click and calls.turn and calls.turn_end, calls


@pytest.mark.parametrize("result, carries", [
    ({"view_colors": {"data": b"x"}}, True), ([{"pixel_src": "data:"}], True),
    ({"scene_phonglab_view": {"id": "1"}, "readout": {}}, True), ({1: "x"}, False),
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
    assert all(int(row[13]) > 0 for row in rows), done.stdout  # the students moved the lesson's slider
    assert "largest class with p95 <= 100 ms" in done.stdout, done.stdout


def test_a_bad_flag_is_one_line():
    done = subprocess.run([sys.executable, "-m", "phonglab.cli", "bench", "load", "--clients", "0"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and "--clients" in done.stderr and "at least 1" in done.stderr, done.stderr
