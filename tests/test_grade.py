"""`phonglab grade`: grading a student's shade() in a sandbox, diagnosis, reports and their limits.

The student files live in tests/data/grade: an independent, correct textbook
loop (it does not call phonglab.shade), files that raise, return NaN or the
wrong shape, loop forever, fail to load, or try to leave the sandbox. The
same loop with one catalogue mistake each is made from the correct one by
tests/grade_students.py.
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import phonglab as pl
from phonglab.cli import main
from phonglab.teaching import MISTAKES
from phonglab.teaching.grading import (
    GROUPS,
    encode_scene,
    Limits,
    LoadError,
    expected,
    format_report,
    grade,
    grade_file,
    gradescope_results,
    starter_text,
    within,
)
from phonglab.teaching.grading import wording
from phonglab.teaching.sandbox import Outcome, Sandbox

from grade_students import STUDENTS, student_path

DATA = Path(__file__).resolve().parent / "data" / "grade"

#: the student file that makes each catalogue mistake
MISTAKE_FILES = {
    "no-clamp-diffuse": "no_clamp_diffuse.py",
    "ungated-specular": "ungated_specular.py",
    "zero-shininess": "zero_shininess.py",
    "unnormalised-normals": "unnormalised_normals.py",
    "reflect-wrong-way": "reflect_wrong_way.py",
    "unnormalised-light": "unnormalised_light.py",
    "unnormalised-view": "unnormalised_view.py",
    "view-from-eye": "view_from_eye.py",
    "attenuated-ambient": "attenuated_ambient.py",
    "spot-cutoff-in-degrees": "spot_cutoff_in_degrees.py",
    "power-before-max": "power_before_max.py",
    "zero-to-the-zero": "zero_to_the_zero.py",
}

#: mistakes that one-sided Phong with a local viewer cannot tell apart: −r·v either way
SAME_NUMBERS = {"reflect-wrong-way": {"view-from-eye"}, "view-from-eye": {"reflect-wrong-way"}}

#: quick limits for the files that fail on purpose
QUICK = Limits(time_limit=1.0, total_limit=20.0)


@functools.lru_cache(maxsize=None)
def graded(name: str, limits: Limits = Limits()):
    """Grade a student file once per test session (each run starts a worker process)."""
    return grade_file(student_path(name), limits)


def run_cli(capsys, *argv):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def by_key(report):
    return {g.group.key: g for g in report.groups}


# ---------------------------------------------------------------------------
# the cases themselves


def test_groups_are_worth_100_points_with_stated_tolerances():
    assert sum(g.points for g in GROUPS) == 100
    assert [g.key for g in GROUPS] == ["ambient", "diffuse", "specular", "reflection", "shininess",
                                       "attenuation", "directional", "spot", "many", "hard"]
    for g in GROUPS:
        assert g.cases and 0 < g.rtol <= 1e-6 and 0 < g.atol <= 1e-12 and g.why, g


def test_shininess_cases_cover_0_to_1e6():
    alphas = {c.material.shininess for c in by_key_groups()["shininess"].cases}
    assert min(alphas) == 0 and max(alphas) == 1e6 and {1, 2} <= alphas, alphas


def rv_of(case) -> float:
    """r·v of a case's one point light, from the definitions (unit n, l, v; r = 2(n·l)n − l)."""
    n = np.asarray(case.normal) / np.linalg.norm(case.normal)
    light = next(lt for lt in case.lights if hasattr(lt, "position"))
    l = np.asarray(light.position) - case.point
    l /= np.linalg.norm(l)
    v = np.asarray(case.eye) - case.point
    v /= np.linalg.norm(v)
    return float((2 * (n @ l) * n - l) @ v)


def test_alpha_zero_is_graded_on_both_sides_of_the_mirror_direction():
    """At α = 0 the weight is 1 where r·v > 0 and 0 where r·v < 0 (not 0 ** 0 = 1) on a lit point."""
    zero = [c for c in by_key_groups()["shininess"].cases if c.material.shininess == 0]
    signs = sorted(rv_of(c) > 0 for c in zero)
    assert signs == [False, True], [(c.what, rv_of(c)) for c in zero]
    for c in zero:
        ks_is = 1.0 * np.asarray(c.lights[0].specular_rgb) * (1.0 if rv_of(c) > 0 else 0.0)
        diffuse = expected(c) - ks_is
        assert np.all(diffuse > 0.05) and np.all(diffuse < 0.1 + 1e-12), (c.what, expected(c))


def test_a_shade_that_lights_every_lit_point_at_alpha_zero_loses_marks_and_is_named():
    report = graded("zero_to_the_zero.py")
    shininess = by_key(report)["shininess"]
    assert report.score < 100 and not shininess.passed, format_report(report)
    assert shininess.worst.case.material.shininess == 0 and rv_of(shininess.worst.case) < 0, format_report(report)
    assert shininess.diagnosis is not None and shininess.diagnosis.name == "zero-to-the-zero", format_report(report)
    assert report.diagnosis == ["zero-to-the-zero"], format_report(report)


def test_the_eye_on_the_point_is_specified_and_graded():
    """v of length 0: no specular light. A shade whose normalize divides by zero fails that case only."""
    on_point = [c for g in GROUPS for c in g.cases if np.array_equal(c.eye, c.point)]
    assert len(on_point) == 1 and on_point[0] in by_key_groups()["hard"].cases, [c.what for c in on_point]
    case = on_point[0]
    no_specular = pl.shade([case.point], [case.normal], material=replace(case.material, ks=(0.0, 0.0, 0.0)),
                           lights=case.lights, eye=case.eye).color[0]
    assert np.array_equal(expected(case), no_specular), (expected(case), no_specular)
    assert "eye exactly on the point" in starter_text() and "no specular" in starter_text()


def test_a_shade_dividing_by_a_zero_view_vector_fails_the_eye_on_the_point(tmp_path):
    source = tmp_path / "unguarded_view.py"
    text = (DATA / "correct.py").read_text()
    right = "    v, _ = unit(sub([float(x) for x in eye], p))\n"
    assert text.count(right) == 1
    source.write_text(text.replace(right, "    w = sub([float(x) for x in eye], p)\n"
                                          "    v = [c / math.sqrt(dot(w, w)) for c in w]  # no zero-length guard\n"))
    report = grade_file(source)
    failed = {g.group.key: [c.case.what for c in g.cases if not c.passed] for g in report.groups if not g.passed}
    assert list(failed) == ["hard"] and len(failed["hard"]) == 1 and "eye on the point" in failed["hard"][0], failed


def test_an_unnormalised_normal_is_named_in_the_students_terms():
    """The student never interpolated anything: the report speaks of the normal argument, not b0·n0 + …."""
    text = format_report(graded("unnormalised_normals.py"))
    assert 'mistake "unnormalised-normals" (The normal not normalised)' in text, text
    assert "wrong: n = normal" in text and "right: n = normalize(normal)" in text, text
    assert "b0" not in text and "nterpolated" not in text, text


def test_the_templates_returns_summary_states_the_contracts_specular_rule():
    """The starter's Returns line, written literally, must be the contract: the n·l and r·v gate, α = 0."""
    returns = starter_text().split("Returns\n    -------\n", 1)[1].split('"""', 1)[0]
    returns = " ".join(returns.replace("``", "").split())
    for words in ("S = max(0, r·v)^α", "where n·l > 0 and r·v > 0, else 0", "also at α = 0",
                  "eye on the point"):
        assert words in returns, (words, returns)


def by_key_groups():
    return {g.key: g for g in GROUPS}


def test_within_refuses_nan_and_inf_and_checks_each_channel():
    assert within([1, 2, 3], [1, 2, 3 + 1e-13], 1e-12, 0)
    assert not within([1, 2, 3], [1, 2, 3 + 1e-11], 1e-12, 0)
    assert not within([1, 2, 3], [1, np.nan, 3], 1, 1)
    assert not within([1, 2, 3], [1, 2, np.inf], 1, 1)


def test_every_mistake_that_changes_phong_is_caught_and_diagnosed():
    """Each catalogue mistake, run on the cases, loses marks and is named: new mistakes are picked up.

    A mistake that never changes one-sided Phong with a local viewer (on a
    random sample of scenes) has nothing to grade here and is skipped; one
    that does but slips through every case fails this test.
    """
    rng = np.random.default_rng(7)
    for name, mistake in MISTAKES.items():
        outcomes = []
        for group in GROUPS:
            answers = []
            for case in group.cases:
                s = mistake.shade(np.array([case.point]), np.array([case.normal]), material=case.material,
                                  lights=list(case.lights), eye=case.eye, model="phong")
                answers.append(Outcome(value=np.asarray(s.color, float).reshape(3)))
            outcomes.append(answers)
        report = grade(outcomes)
        if report.passed:
            p = rng.normal(size=(200, 3))
            n = rng.normal(size=(200, 3)) * rng.uniform(0.1, 3, size=(200, 1))
            lights = [pl.AmbientLight(intensity=0.2), pl.PointLight(position=(1, 2, 3)),
                      pl.DirectionalLight(direction=(-1, 0.5, -1))]
            material = pl.Material(ka=0.1, kd=0.6, ks=0.5, shininess=20)
            ref = pl.shade(p, n, material=material, lights=lights, eye=(0, 0, 6)).color
            got = mistake.shade(p, n, material=material, lights=lights, eye=(0, 0, 6), model="phong").color
            assert np.allclose(got, ref, rtol=1e-9, atol=1e-12), (
                f"mistake {name} changes one-sided Phong but passes every graded case: add a case where it bites")
            continue
        assert report.score < 100 and name in report.diagnosis, (name, report.score, report.diagnosis)


# ---------------------------------------------------------------------------
# students, graded in the sandbox


def test_an_independent_correct_implementation_gets_full_marks():
    report = graded("correct.py")
    assert report.passed and report.score == report.max_score == 100, format_report(report)
    assert report.diagnosis == []


def test_every_generated_student_file_makes_a_catalogue_mistake():
    orphans = sorted(set(STUDENTS) - set(MISTAKE_FILES.values()))
    assert not orphans, f"tests/grade_students.py makes {orphans}, which no catalogue mistake in MISTAKE_FILES uses"


@pytest.mark.parametrize("name", sorted(set(MISTAKES) | set(MISTAKE_FILES)))
def test_a_catalogue_mistake_loses_marks_and_is_named(name):
    if name not in MISTAKE_FILES:
        pytest.skip(f"no student file for the mistake {name!r}: add its lines to tests/grade_students.py and MISTAKE_FILES")
    report = graded(MISTAKE_FILES[name])
    assert report.score < 100, format_report(report)
    assert name in MISTAKES, f"{name}: a student file for a mistake the catalogue does not have"
    # named, and nothing else named but the mistakes giving the same numbers
    assert name in report.diagnosis, format_report(report)
    assert set(report.diagnosis) <= {name} | SAME_NUMBERS.get(name, set()), format_report(report)
    for g in report.groups:
        if g.diagnosis is not None:
            m = wording(g.diagnosis.name)
            assert (g.diagnosis.wrong, g.diagnosis.right, g.diagnosis.looks_like) == (m.wrong, m.right,
                                                                                     m.looks_like)
    text = format_report(report)
    assert f"wrong: {wording(name).wrong}" in text and f"right: {wording(name).right}" in text, text


def test_a_reversed_reflection_vector_fails_the_reflection_group():
    report = graded("reflect_wrong_way.py")
    reflection = by_key(report)["reflection"]
    assert not reflection.passed and reflection.score < reflection.group.points / 2, format_report(report)
    if "reflect-wrong-way" in MISTAKES:
        assert reflection.diagnosis is not None and reflection.diagnosis.name == "reflect-wrong-way"
        assert "reflect-wrong-way" in report.diagnosis


def test_each_mistake_fails_where_it_bites_and_passes_elsewhere():
    groups = {name: {g.group.key for g in graded(f).groups if not g.passed} for name, f in MISTAKE_FILES.items()}
    assert {"diffuse", "many"} <= groups["no-clamp-diffuse"] and "ambient" not in groups["no-clamp-diffuse"]
    assert "specular" in groups["ungated-specular"] and "diffuse" not in groups["ungated-specular"]
    assert {"shininess", "specular"} <= groups["zero-shininess"]
    assert groups["unnormalised-normals"] == {"hard"}, groups
    assert "reflection" in groups["reflect-wrong-way"] and "diffuse" not in groups["reflect-wrong-way"], groups
    assert {"diffuse", "attenuation"} <= groups["unnormalised-light"] and "ambient" not in groups["unnormalised-light"]
    assert "specular" in groups["unnormalised-view"] and "diffuse" not in groups["unnormalised-view"], groups
    assert "reflection" in groups["view-from-eye"] and "diffuse" not in groups["view-from-eye"], groups
    assert "attenuation" in groups["attenuated-ambient"], groups
    assert not {"ambient", "diffuse", "specular"} & groups["attenuated-ambient"], groups
    assert "spot" in groups["spot-cutoff-in-degrees"] and not {"diffuse", "attenuation"} & groups[
        "spot-cutoff-in-degrees"], groups
    # an even α with r·v < 0 (specular, shininess), and α = 0 where 0 ** 0 = 1 (shininess)
    assert groups["power-before-max"] == {"specular", "shininess"}, groups
    assert groups["zero-to-the-zero"] == {"shininess"}, groups


def test_equal_mistakes_are_named_together_and_the_right_answers_break_ties():
    """A reversed r and a reversed v give the same r·v: both are named; power-before-max is told apart."""
    for name in ("reflect_wrong_way.py", "view_from_eye.py"):
        report = graded(name)
        assert report.diagnosis == ["reflect-wrong-way", "view-from-eye"], format_report(report)
        assert 'or, with the same numbers in every case here, the mistake "view-from-eye"' in format_report(report)
    # its one wrong case is explained by a reversed r too, but the reversed r would get the right answers wrong
    specular = by_key(graded("power_before_max.py"))["specular"]
    assert specular.diagnosis.name == "power-before-max" and specular.diagnosis.equally == (), format_report(
        graded("power_before_max.py"))


def test_the_report_shows_the_worst_case_with_inputs_and_the_diagnosis():
    text = format_report(graded("no_clamp_diffuse.py"))
    block = text.split("FAIL Diffuse light")[1].split("\n\n")[0]
    for word in ("worst case:", "point=", "material:", "lights:", "expected", "got", "tolerance",
                 'mistake "no-clamp-diffuse"', "wrong: diffuse = kd * Id * dot(n, l)",
                 "right: diffuse = kd * Id * max(0, dot(n, l))", "what it looks like:"):
        assert word in block, (word, block)
    assert "PASS Ambient light and emission: 5/5 points" in text


@pytest.mark.parametrize("name, message", [
    ("raises.py", "ValueError: cannot shade"),
    ("returns_nan.py", "NaN or inf"),
    ("wrong_shape.py", "expected 3"),
])
def test_a_broken_shade_is_reported_case_by_case_not_fatal(name, message):
    report = graded(name, QUICK)
    assert report.score == 0, format_report(report)
    errors = [c.error for g in report.groups for c in g.cases]
    assert all(errors) and any(message in e for e in errors), errors[:5]
    assert all("\n" not in e for e in errors)
    if name == "raises.py":  # the line in the student's file, not the worker's traceback
        assert "(raises.py line 9)" in errors[0], errors[0]
    if name == "wrong_shape.py":  # RGBA, a single number and a string
        for marker in ("shape (4,)", "shape ()", "str of <U3"):
            assert any(marker in e for e in errors), (marker, set(errors))


def test_an_endless_loop_fails_by_time_limit_and_the_run_stays_bounded():
    limits = Limits(time_limit=0.5, total_limit=3.0)
    report = grade_file(DATA / "loops_forever.py", limits)
    errors = [c.error for g in report.groups for c in g.cases]
    timed_out = [e for e in errors if e.startswith("time limit")]
    not_run = [e for e in errors if "total time limit" in e]
    assert report.score == 0 and len(timed_out) + len(not_run) == len(errors), set(errors)
    # every time-out spends at least the per-case limit of the total: the run cannot outlast it
    assert 1 <= len(timed_out) <= limits.total_limit / limits.time_limit, len(timed_out)
    assert not_run, "the total limit should have stopped the remaining cases"


@pytest.mark.parametrize("name, reason", [
    ("syntax_error.py", "SyntaxError: "),
    ("no_shade.py", "defines no function shade(point, normal, eye, material, lights)"),
    ("import_error.py", "ModuleNotFoundError: No module named 'not_a_real_module_for_phonglab'"),
    ("escape_at_import.py", "FileNotFoundError: [Errno 2] No such file or directory: '/etc/passwd'"),
])
def test_a_file_that_cannot_be_loaded_exits_2_with_one_line(capsys, name, reason):
    status, out, err = run_cli(capsys, "grade", DATA / name)
    assert status == 2, (out, err)
    assert reason in err and err.count("\n") == 1 and "Traceback" not in err, err
    if name == "syntax_error.py":
        assert "(syntax_error.py line 4)" in err, err


def test_a_file_that_does_not_exist_cannot_be_loaded():
    with pytest.raises(LoadError, match="cannot read"):
        grade_file(DATA / "no_such_file.py")


# ---------------------------------------------------------------------------
# the sandbox


@pytest.fixture
def escape(tmp_path):
    """The escape file aimed at a folder outside the sandbox, holding a secret."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.txt").write_text("the answers to the exam")
    source = tmp_path / "escape.py"
    source.write_text((DATA / "escape.py").read_text().replace("@TARGET@", str(outside)))
    attempts = {}
    exec(compile(source.read_text(), str(source), "exec"), attempts)  # only to read ATTEMPTS
    return source, outside, attempts["ATTEMPTS"]


#: what each escape attempt meets in the sandbox: a path that is not there, a refused system call,
#: or (for calls that report a failed fork by their return value) nothing at all
ESCAPES = {
    "read": "FileNotFoundError", "read-passwd": "FileNotFoundError", "read-dotdot": "FileNotFoundError",
    "os-open": "FileNotFoundError", "numpy-fromfile": "FileNotFoundError", "listdir": "FileNotFoundError",
    "write": "PermissionError", "system": None, "subprocess": "PermissionError", "posixsubprocess": None,
    "fork": "PermissionError", "socket": "PermissionError", "ctypes": None, "remove": "PermissionError",
    "memory": "MemoryError", "exit": "exited with status 3",
}


def test_escape_attempts_are_refused_and_leave_no_trace(escape):
    source, outside, attempts = escape
    assert set(attempts) == set(ESCAPES), "every attempt of escape.py needs its expected outcome here"
    scene = encode_scene(pl.Material(ka=0.1, kd=0.5, ks=0.5, shininess=10), [])
    with Sandbox(source, Limits(time_limit=5.0, total_limit=60.0)) as box:
        results = {}
        for i, attempt in enumerate(attempts):
            (outcome,) = box.evaluate([[i, 0, 0]], [[0, 0, 1]], eye=[0, 0, 5], scene=scene)
            results[attempt] = outcome
        after = box.evaluate([[0.5, 0, 0]], [[0, 0, 1]], eye=[0, 0, 5], scene=scene)  # "read" again
    for attempt, outcome in results.items():
        want = ESCAPES[attempt]
        if want is None:  # the call ran and reported failure: nothing was read, made or started
            assert outcome.value is not None and not outcome.value.any(), (attempt, outcome)
        else:
            assert outcome.value is None and want in outcome.error, (attempt, outcome)
    refused = [a for a, want in ESCAPES.items() if want == "PermissionError"]
    for attempt in refused:
        assert "refused by the grader's sandbox" in results[attempt].error, (attempt, results[attempt])
    assert after[0].error and "FileNotFoundError" in after[0].error  # a fresh worker, still no such file
    # nothing was made, removed or changed outside
    assert sorted(p.name for p in outside.iterdir()) == ["secret.txt"]
    assert (outside / "secret.txt").read_text() == "the answers to the exam"


def test_the_sandbox_reports_what_isolates_it():
    with Sandbox(DATA / "correct.py") as box:
        isolation = " ".join(box.isolation)
    for words in ("bubblewrap", "PID, network", "uid 65534", "seccomp", "no phonglab", "empty private /tmp"):
        assert words in isolation, (words, isolation)


@pytest.mark.parametrize("cheat", [
    "from phonglab.core import shade_reference\n\n"
    "def shade(point, normal, eye, material, lights):\n"
    "    return shade_reference([point], [normal], material=material, lights=lights, eye=eye).color[0]\n",
    "import importlib\n\n"
    "def shade(point, normal, eye, material, lights):\n"
    "    import phonglab.core.shading\n"
    "    importlib.reload(phonglab.core.shading)\n"
    "    return phonglab.core.shading.shade([point], [normal], material=material, lights=lights, eye=eye).color[0]\n",
], ids=["import", "reload"])
def test_the_projects_shading_scores_nothing(tmp_path, cheat):
    source = tmp_path / "cheat.py"
    source.write_text(cheat)
    try:
        report = grade_file(source, QUICK, groups=GROUPS[:1])
    except LoadError as exc:  # imported at the top: the file does not load, which scores nothing either
        assert "phonglab is not available in a graded exercise" in str(exc), exc
        return
    assert report.score == 0, format_report(report)
    errors = {c.error for c in report.groups[0].cases}
    assert all(e and "phonglab is not available in a graded exercise" in e for e in errors), errors


# ---------------------------------------------------------------------------
# the command line: reports, JSON, picture, template


def check_gradescope(results: dict) -> None:
    """The fields of Gradescope's results.json that we write, with their types."""
    assert isinstance(results["score"], (int, float)) and isinstance(results["max_score"], (int, float))
    assert results["visibility"] in ("hidden", "after_due_date", "after_published", "visible")
    assert results["stdout_visibility"] in ("hidden", "after_due_date", "after_published", "visible")
    assert isinstance(results["output"], str) and isinstance(results["execution_time"], (int, float))
    assert isinstance(results["diagnosis"], list) and all(isinstance(d, str) for d in results["diagnosis"])
    assert results["extra_data"] == {"diagnosis": results["diagnosis"]}
    tests = results["tests"]
    assert isinstance(tests, list) and len(tests) == len(GROUPS)
    for t in tests:
        assert set(t) <= {"name", "number", "score", "max_score", "status", "output", "visibility", "tags"}, t
        assert isinstance(t["name"], str) and isinstance(t["output"], str) and isinstance(t["number"], str)
        assert isinstance(t["score"], (int, float)) and isinstance(t["max_score"], (int, float))
        assert 0 <= t["score"] <= t["max_score"] and t["status"] in ("passed", "failed")
        assert (t["status"] == "passed") == (t["score"] == t["max_score"]), t
    assert math.isclose(results["score"], sum(t["score"] for t in tests), abs_tol=0.011)
    assert results["max_score"] == sum(t["max_score"] for t in tests) == 100
    json.dumps(results, allow_nan=False)  # strict JSON: no NaN or inf


def test_cli_writes_gradescope_results_and_exits_1_when_some_fail(capsys, tmp_path):
    out_json = tmp_path / "results.json"
    status, out, err = run_cli(capsys, "grade", student_path("zero_shininess.py"), "--json", out_json)
    assert status == 1, (out, err)
    results = json.loads(out_json.read_text())
    check_gradescope(results)
    assert results["diagnosis"] == ["zero-shininess"] and results["score"] < 100
    assert f"Total: {results['score']:g}/100" in out
    shininess = next(t for t in results["tests"] if t["name"].startswith("Shininess"))
    assert shininess["status"] == "failed" and 'mistake "zero-shininess"' in shininess["output"]


def test_cli_full_marks_exit_0_and_json(capsys, tmp_path):
    out_json = tmp_path / "results.json"
    status, out, err = run_cli(capsys, "grade", DATA / "correct.py", "--json", out_json)
    assert status == 0 and "Total: 100/100" in out, (out, err)
    results = json.loads(out_json.read_text())
    check_gradescope(results)
    assert results["score"] == 100 and results["diagnosis"] == []


def test_cli_json_for_a_file_that_cannot_be_loaded(capsys, tmp_path):
    out_json = tmp_path / "results.json"
    status, _, err = run_cli(capsys, "grade", DATA / "no_shade.py", "--json", out_json)
    assert status == 2, err
    results = json.loads(out_json.read_text())
    check_gradescope(results)
    assert results["score"] == 0 and all("defines no function shade" in t["output"] for t in results["tests"])


def test_cli_reports_a_refused_read_as_a_failed_case(capsys, escape):
    source, outside, _ = escape
    status, out, err = run_cli(capsys, "grade", source, "--time-limit", "1", "--total-limit", "30")
    assert status == 1, err
    assert "FileNotFoundError" in out and str(outside / "secret.txt") in out, out[:2000]


def test_cli_picture_shows_the_student_beside_the_core(capsys, tmp_path):
    from PIL import Image

    from phonglab.accuracy.grade_picture import CAPTION_HEIGHT, SCALE_BAND
    from phonglab.cli import grade as grade_cli

    png = tmp_path / "sphere.png"
    status, out, err = run_cli(capsys, "grade", DATA / "correct.py", "--picture", png)
    assert status == 0 and f"wrote {png}" in out, (out, err)
    assert [p.name for p in tmp_path.iterdir()] == ["sphere.png"]  # no temporary file left
    image = np.asarray(Image.open(png).convert("RGB")).astype(int)
    size, gap, caption = grade_cli.PICTURE_SIZE * 2, 8, CAPTION_HEIGHT
    assert image.shape == (size + caption + 2 * gap + SCALE_BAND, 3 * size + 4 * gap, 3)
    panels = [image[caption + gap: caption + gap + size, gap + i * (size + gap): gap + i * (size + gap) + size]
              for i in range(3)]
    # the correct student's sphere is the core's, to the last grey level
    assert np.abs(panels[0] - panels[1]).max() <= 1
    # a mistake shows in the picture
    core, wrong, mask, failures = grade_cli.sphere_images(student_path("no_clamp_diffuse.py"), Limits())
    assert failures == 0 and np.max(np.abs(wrong[mask] - core[mask])) > 0.1


def test_template_is_written_once_and_grades_to_zero(capsys, tmp_path):
    path = tmp_path / "shade.py"
    status, out, _ = run_cli(capsys, "grade", "--template", path)
    assert status == 0 and path.read_text() == starter_text(), out
    path.write_text(path.read_text() + "\n# my work\n")
    status, _, err = run_cli(capsys, "grade", "--template", path)
    assert status == 2 and "exists: not overwritten" in err
    assert path.read_text().endswith("# my work\n")
    report = grade_file(path, QUICK, groups=GROUPS[:2])
    assert report.score == 0 and "NotImplementedError: write the Phong model here" in report.groups[0].cases[0].error


def test_template_and_grader_state_the_same_contract():
    from phonglab.teaching import grading

    starter, doc = (" ".join(text.replace("``", "").split()) for text in (starter_text(), grading.__doc__))
    for phrase in ("ONE surface point", "unclamped", "float64", "ambient_rgb", "diffuse_rgb", "specular_rgb",
                   "Only ambient lights add ambient light", "edge included", "cutoff", "also for α = 0",
                   "n·l > 0 and r·v > 0", "0 ** 0", "eye exactly on the point", "shade_helpers"):
        assert phrase.lower() in starter.lower() and phrase.lower() in doc.lower(), phrase


def test_cli_usage_errors_exit_2(capsys):
    assert run_cli(capsys, "grade")[0] == 2
    assert run_cli(capsys, "grade", DATA / "correct.py", "--template")[0] == 2
    status, _, err = run_cli(capsys, "grade", DATA / "correct.py", "--time-limit", "0")
    assert status == 2 and "--time-limit" in err


def test_expected_is_the_core_in_float64():
    case = GROUPS[1].cases[1]
    want = expected(case)
    assert want.dtype == np.float64 and want.shape == (3,)
    assert np.array_equal(want, pl.shade([case.point], [case.normal], material=case.material,
                                         lights=case.lights, eye=case.eye).color[0])


def test_gradescope_results_without_a_report_score_zero():
    results = gradescope_results(None, load_error="SyntaxError: invalid syntax (x.py line 1)", execution_time=0.1)
    check_gradescope(results)
    assert results["score"] == 0 and "SyntaxError" in results["output"]
