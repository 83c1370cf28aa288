"""Every lesson's claims, executed on the lesson's own scene; and the claim language's guards."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from phonglab.accuracy.claims import FUNCTIONS, check_claim
from phonglab.scene import SceneError, SceneErrors, lesson_files, load_lesson
from phonglab.scene.claims import Claim, parse_check
from phonglab.scene.schema import CLAIM_FUNCTIONS

ROOT = Path(__file__).resolve().parents[1]
LESSONS = [load_lesson(p) for p in lesson_files(ROOT / "lessons")]
CASES = [(lesson, claim) for lesson in LESSONS for claim in lesson.claims]


@pytest.mark.parametrize("lesson, claim", CASES,
                         ids=[f"{lesson.number:02d}-{claim.index}" for lesson, claim in CASES])
def test_lesson_claim_holds(lesson, claim):
    result = check_claim(lesson, claim)
    assert result.passed, result.describe()


@pytest.mark.parametrize("lesson", LESSONS, ids=[f"{lesson.number:02d}" for lesson in LESSONS])
def test_every_experiment_has_a_claim(lesson):
    covered = {claim.experiment for claim in lesson.claims}
    missing = [i + 1 for i in range(len(lesson.experiments)) if i + 1 not in covered]
    assert not missing, f"{lesson.path}: experiments {missing} have no claim"
    assert any(claim.experiment is None for claim in lesson.claims), f"{lesson.path}: no claim about the start"


def test_the_measurements_are_the_functions_the_loader_allows():
    assert set(FUNCTIONS) == set(CLAIM_FUNCTIONS)


def test_a_false_claim_fails_with_the_sentence_and_the_value():
    lesson = next(lesson for lesson in LESSONS if lesson.number == 4)
    result = check_claim(lesson, Claim(says="the peak is above 2", check="peak('specular') > 2"))
    assert not result.passed
    text = result.describe()
    assert "the peak is above 2" in text and "peak('specular') = 0.5" in text, text


def test_a_claim_that_cannot_be_evaluated_fails_with_the_error():
    lesson = LESSONS[0]
    result = check_claim(lesson, Claim(says="x", check="sqrt(-1) > 0"))
    assert not result.passed and "ValueError" in result.error, result.describe()


@pytest.mark.parametrize("check", [
    "__import__('os').system('true')",  # an unknown function
    "x > 1",  # a bare name
    "peak('specular').real > 0",  # attribute access
    "[1][0] > 0",  # subscript, list
    "peak('nope') > 0",  # a word not in the function's list
    "peak(2) > 0",  # a number where a word belongs
    "probe('nl', 'r', 'g') > 0",  # too many arguments
    "pow(2) > 0",  # too few
    "(lambda: 1)() > 0",
    "'a' < 'b'",  # words outside a call
    "1 if 1 else 2",
    "pow(x=1, y=2) > 0",
    "1 +" ,  # not an expression
    "1 + " * 100 + "1 > 0",  # too long
])
def test_the_check_language_refuses(check):
    with pytest.raises(SceneError):
        parse_check(check)


def test_the_check_language_accepts_the_documented_forms():
    for check in ["abs(pow(0.9, 10) - 0.35) < 0.005", "0 < probe('nl') <= 1 and not peak('color', 'r') > 9",
                  "vertices(128) / vertices(16) > 60", "error('pixel', 16, 'rmse') < 2 * error('gouraud', 256, 'rmse')"]:
        parse_check(check)


def test_huge_powers_fail_instead_of_hanging():
    result = check_claim(LESSONS[0], Claim(says="x", check="9 ** 9 ** 9 > 0"))
    assert not result.passed and "OverflowError" in result.error, result.describe()


BAD = """\
+++
number = 1
title = "Bad claims"

[geometry]
kind = "sphere"

[material]
ka = 0.1
kd = 0.5
ks = 0.5
shininess = 10

[[lights]]
type = "point"
position = [1, 1, 1]

[[experiments]]
label = "one"
set = {{ "material.ks" = 0 }}

[[claims]]
says = "ok"
check = "peak('specular') >= 0"

[[claims]]
says = "bad"
check = "{check}"
experiment = {experiment}
+++
Text.
"""


@pytest.mark.parametrize("check, experiment, field, line", [
    ("os.system(1)", 1, "claims[1].check", 28),
    ("peak('specular') > 0", 2, "claims[1].experiment", 29),
])
def test_bad_claims_are_reported_with_file_and_line(tmp_path, check, experiment, field, line):
    path = tmp_path / "01-bad.md"
    path.write_text(BAD.format(check=check, experiment=experiment))
    with pytest.raises(SceneErrors) as info:
        load_lesson(path)
    shown = [str(e) for e in info.value.errors]
    assert any(f":{line}: {field}" in s for s in shown), shown
    out = subprocess.run([sys.executable, "-m", "phonglab.cli", "check", str(path)], capture_output=True, text=True,
                         cwd=ROOT)
    assert out.returncode == 1 and field in out.stdout, out.stdout + out.stderr


def test_claim_settings_are_checked_like_an_experiment(tmp_path):
    path = tmp_path / "01-bad.md"
    text = BAD.format(check="1 > 0", experiment=1).replace(
        "experiment = 1\n+++", 'experiment = 1\nset = { "material.shininess" = -3 }\n+++')
    path.write_text(text)
    with pytest.raises(SceneErrors) as info:
        load_lesson(path)
    assert any("claims[1].set" in str(e) for e in info.value.errors), [str(e) for e in info.value.errors]
