"""Every lesson's claims, executed on the lesson's own scene, and failing when their sentence is made false;
the claim language's guards; and ``phonglab check`` running the claims."""

from __future__ import annotations

import io
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from types import SimpleNamespace

import pytest

from phonglab.accuracy.claims import FUNCTIONS, check_claim, check_false_when
from phonglab.cli import main
from phonglab.scene import SceneError, SceneErrors, lesson_files, load_lesson
from phonglab.scene.claims import Claim, FalseWhen, parse_check
from phonglab.scene.schema import CLAIM_FUNCTIONS

ROOT = Path(__file__).resolve().parents[1]
LESSONS = [load_lesson(p) for p in lesson_files(ROOT / "lessons")]
CASES = [(lesson, claim) for lesson in LESSONS for claim in lesson.claims]


@pytest.mark.parametrize("lesson, claim", CASES,
                         ids=[f"{lesson.number:02d}-{claim.index}" for lesson, claim in CASES])
def test_lesson_claim_holds(lesson, claim):
    result = check_claim(lesson, claim)
    assert result.passed, result.describe()


@pytest.mark.parametrize("lesson, claim", CASES,
                         ids=[f"{lesson.number:02d}-{claim.index}" for lesson, claim in CASES])
def test_lesson_claim_fails_when_its_sentence_is_false(lesson, claim):
    # the claim's false_when changes the sentence's number or direction (or the scene it speaks of): a check
    # that still holds then cannot tell the sentence from its opposite
    result = check_false_when(lesson, claim)
    assert result.passed, "the check does not fail with the sentence made false:\n" + result.describe()


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
    result = check_claim(lesson, Claim(says="the peak is above 2", check="peak('specular') > 2",
                                       false_when=FalseWhen(replace=("> 2", "< 2"))))
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



def test_a_misspelled_function_is_named_with_the_one_meant():
    """'peek(...)' listed all thirty functions; a field's typo already got a did-you-mean."""
    with pytest.raises(SceneError) as caught:
        parse_check("peek('specular') > 0.5")
    assert str(caught.value).endswith('got "peek"; did you mean "peak"?'), str(caught.value)

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
set = {{ "material.shininess" = 20 }}

[[claims]]
says = "ok"
about = "model"
check = "peak('specular') >= 0"
false_when = {{ replace = [">=", "<"] }}

[[claims]]
says = "{says}"
about = "{about}"
check = "{check}"
false_when = {false_when}
experiment = {experiment}
+++
Text.
"""

GOOD = {"says": "the highlight's peak is above 0.35", "about": "model", "check": "peak('specular') > 0.35",
        "false_when": '{ set = { "material.ks" = 0.3 } }', "experiment": 1}


def bad_lesson(tmp_path, **change) -> Path:
    path = tmp_path / "01-bad.md"
    path.write_text(BAD.format(**{**GOOD, **change}))
    return path


def run_check(*args, process: bool = False):
    """``phonglab check ARGS``: in this process (the pictures stay cached), or as a real process (its exit status)."""
    if process:
        return subprocess.run([sys.executable, "-m", "phonglab.cli", "check", *map(str, args)], capture_output=True,
                              text=True, cwd=ROOT)
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(["check", *map(str, args)])
    return SimpleNamespace(returncode=status, stdout=out.getvalue(), stderr=err.getvalue())


@pytest.mark.parametrize("change, field, line", [
    ({"check": "os.system(1)"}, "claims[1].check", 31),
    ({"experiment": 2}, "claims[1].experiment", 33),
    ({"about": "screen"}, "claims[1].about", 30),
    # a model claim may not measure the picture, a picture claim must
    ({"check": "shown_peak('color') > 0"}, "claims[1].about", 30),
    ({"about": "picture"}, "claims[1].about", 30),
    # a sentence about how the picture looks is a picture claim
    ({"says": "the far side is black"}, "claims[1].about", 30),
    ({"false_when": "{}"}, "claims[1].false_when", 32),
    ({"false_when": '{ replace = ["0.7", "0.8"] }'}, "claims[1].false_when.replace", 32),
    ({"false_when": '{ replace = ["0.5", "0.5"] }'}, "claims[1].false_when.replace", 32),
    ({"false_when": '{ replace = ["0.5)", "0.5))"] }'}, "claims[1].false_when.replace", 32),
    ({"false_when": '{ set = { "material.shininess" = -3 } }'}, "claims[1].false_when.set", 32),
    ({"false_when": '{ sett = { "material.ks" = 0 } }'}, "claims[1].false_when.sett", 32),
])
def test_bad_claims_are_reported_with_file_and_line(tmp_path, change, field, line):
    path = bad_lesson(tmp_path, **change)
    with pytest.raises(SceneErrors) as info:
        load_lesson(path)
    shown = [str(e) for e in info.value.errors]
    assert any(f":{line}: {field}" in s for s in shown), (change, shown)
    out = run_check(path)
    assert out.returncode == 1 and field in out.stdout, out.stdout + out.stderr


def test_claims_without_about_or_false_when_are_refused(tmp_path):
    path = tmp_path / "01-bad.md"
    path.write_text(BAD.format(**GOOD).replace('about = "model"\ncheck = "peak(\'specular\') >', 'check = "peak(\'specular\') >').replace(
        'false_when = { set = { "material.ks" = 0.3 } }\n', ""))
    with pytest.raises(SceneErrors) as info:
        load_lesson(path)
    shown = [str(e) for e in info.value.errors]
    for field in ("claims[1].about: is required", "claims[1].false_when: is required"):
        assert any(field in s for s in shown), shown


def test_a_sound_lesson_with_claims_passes_check(tmp_path):
    out = run_check(bad_lesson(tmp_path))
    assert out.returncode == 0 and "ok " in out.stdout and "2 claims hold" in out.stdout, out.stdout + out.stderr


def test_check_fails_on_a_false_claim_with_the_sentence_the_check_and_the_value(tmp_path):
    # the sentence is false of the lesson's scene: reported like a schema error, FILE:LINE: field: problem
    path = bad_lesson(tmp_path, says="the peak is 0.7", check="abs(peak('specular') - 0.7) < 0.01")
    out = run_check(path, process=True)
    assert out.returncode == 1, out.stdout + out.stderr
    line = next(line for line in out.stdout.splitlines() if "claims[1]" in line)
    assert line.startswith(f"{path}:31: claims[1].check: the sentence is false: \"the peak is 0.7\""), line
    assert "abs(peak('specular') - 0.7) < 0.01" in line and "peak('specular') = 0.38" in line, line
    skipped = run_check("--no-claims", path)
    assert skipped.returncode == 0 and f"ok {path}" in skipped.stdout, skipped.stdout + skipped.stderr


def test_check_fails_on_a_false_picture_claim(tmp_path):
    path = bad_lesson(tmp_path, says="on the screen the far side is black", about="picture",
                      check="shown_low('color') > 10", false_when='{ set = { "material.ka" = 0 } }')
    out = run_check(path)
    assert out.returncode == 1 and f"{path}:31: claims[1].check: the sentence is false" in out.stdout, out.stdout
    assert "shown_low('color') = " in out.stdout, out.stdout


def test_check_fails_on_a_claim_that_cannot_fail(tmp_path):
    # "the peak is above 0.35" checked as "the peak is at most 1" still holds with k_s = 0.3: too weak
    path = bad_lesson(tmp_path, check="peak('specular') <= 1")
    out = run_check(path)
    assert out.returncode == 1, out.stdout + out.stderr
    assert f"{path}:32: claims[1].false_when: the check cannot tell the sentence from its opposite" in out.stdout, \
        out.stdout
    assert "material.ks = 0.3" in out.stdout, out.stdout


def test_check_notes_an_experiment_without_a_claim(tmp_path):
    path = bad_lesson(tmp_path, experiment=1).read_text().replace("experiment = 1\n+++", "+++")
    (tmp_path / "01-bad.md").write_text(path)
    out = run_check(tmp_path / "01-bad.md")
    assert out.returncode == 0, out.stdout + out.stderr
    assert f"{tmp_path / '01-bad.md'}:18: experiments[0]: note: no claim checks" in out.stdout, out.stdout


def test_claim_settings_are_checked_like_an_experiment(tmp_path):
    path = bad_lesson(tmp_path)
    path.write_text(path.read_text().replace('experiment = 1\n+++',
                                             'experiment = 1\nset = { "material.shininess" = -3 }\n+++'))
    with pytest.raises(SceneErrors) as info:
        load_lesson(path)
    assert any("claims[1].set" in str(e) for e in info.value.errors), [str(e) for e in info.value.errors]
