"""The words of every lesson agree with the page: lights named as the panel names them, one meaning per symbol."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from phonglab.app.controls import scene_controls
from phonglab.scene import lesson_files, load_lesson

ROOT = Path(__file__).resolve().parents[1]
LESSONS = [load_lesson(p) for p in lesson_files(ROOT / "lessons")]
IDS = [Path(lesson.path).stem for lesson in LESSONS]

#: a light named by its place in the list, as the panel never does ("the third light")
ORDINAL = re.compile(r"\bthe (first|second|third|fourth|fifth|sixth|seventh|eighth|last) (light|lamp)\b",
                     re.IGNORECASE)
#: a light named as the panel names it: "Light 2", "Light 2 (directional)", "Ambient light 0"
PANEL_NAME = re.compile(r"\b(Ambient light|Light) (\d+)(?: \((\w+)\))?")


def texts(lesson) -> list[tuple[str, str]]:
    """Everything a student reads in a lesson, as (where, text)."""
    found = [("text", lesson.body), ("goal", lesson.goal), ("question", lesson.question), ("answer", lesson.answer)]
    for i, experiment in enumerate(lesson.experiments):
        found += [(f"experiments[{i}].label", experiment.label), (f"experiments[{i}].text", experiment.text)]
    if lesson.check is not None:
        check = lesson.check
        found += [("check.question", check.question)] + [(f"check.choices[{i}]", c) for i, c in enumerate(check.choices)]
        found += [(f"check.feedback[{i}]", f) for i, f in enumerate(check.feedback)]
        found += [("check.feedback_low", check.feedback_low), ("check.feedback_high", check.feedback_high),
                  ("check.feedback_right", check.feedback_right)]
    return [(where, text) for where, text in found if text]


def panel_names(lesson) -> set[str]:
    """The names the control panel gives the lesson's lights, at the start and after each experiment."""
    scenes = [lesson.scene] + [lesson.scene.replace_many(e.settings) for e in lesson.experiments]
    names = set()
    for scene in scenes:
        for control in scene_controls(scene):
            if control.group.startswith(("Light ", "Ambient light ")):
                names.add(control.group)
                names.add(control.group.split(" (")[0])  # the name without its kind
    return names


def light_names_problems(lesson) -> list[str]:
    """Where a lesson names a light other than as its panel does, one line each."""
    names = panel_names(lesson)
    problems = []
    for where, text in texts(lesson):
        for match in ORDINAL.finditer(text):
            problems.append(f"{where}: {match.group(0)!r}: the panel counts lights from 0 and names them "
                            f"{sorted(n for n in names if '(' in n)}")
        for match in PANEL_NAME.finditer(text):
            if match.group(0) not in names:
                problems.append(f"{where}: {match.group(0)!r} is not a light the panel shows; it shows "
                                f"{sorted(n for n in names if '(' in n)}")
    return problems


@pytest.mark.parametrize("lesson", LESSONS, ids=IDS)
def test_a_light_named_by_number_is_named_as_the_panel_names_it(lesson):
    problems = light_names_problems(lesson)
    assert not problems, f"{lesson.path}:\n" + "\n".join(problems)


def test_the_light_names_check_catches_an_ordinal_and_a_wrong_number():
    from dataclasses import replace

    from phonglab.scene.model import Experiment

    lesson = next(lesson for lesson in LESSONS if lesson.number == 7)
    for text in ("Turn the third light into a directional one.", "Turn Light 3 into a directional one.",
                 "Turn Light 0 (point) off."):
        wrong = replace(lesson, experiments=(Experiment(label="x", text=text, settings=()),))
        assert light_names_problems(wrong), text


#: the course's α is the shininess (lessons 4 to 10); opacity must not borrow the symbol
ALPHA_SYMBOL = re.compile(r"\\alpha\b|α")
OPACITY = re.compile(r"opacity|transparen", re.IGNORECASE)


def alpha_as_opacity(text: str) -> list[str]:
    """The paragraphs that speak of opacity and use the shininess's symbol α."""
    return [paragraph.strip()[:80] for paragraph in re.split(r"\n\s*\n", text)
            if OPACITY.search(paragraph) and ALPHA_SYMBOL.search(paragraph)]


@pytest.mark.parametrize("lesson", LESSONS, ids=IDS)
def test_alpha_means_the_shininess_only(lesson):
    found = [f"{where}: {p!r}" for where, text in texts(lesson) for p in alpha_as_opacity(text)]
    found += [f"claims[{c.index}].says: {p!r}" for c in lesson.claims for p in alpha_as_opacity(c.says)]
    assert not found, f"{lesson.path}: α is the shininess, but these speak of opacity with it:\n" + "\n".join(found)


def test_the_alpha_check_sees_a_blend_written_with_alpha():
    assert alpha_as_opacity("The opacity blends: $C = \\alpha C_s + (1 - \\alpha) C_b$.")
    assert not alpha_as_opacity("The opacity $o$ blends: $C = o C_s + (1 - o) C_b$.\n\nThe shininess $\\alpha$.")


#: a coefficient's name left as typed (k_d), outside the page's formulas and code
RAW_SYMBOL = re.compile(r"\bk_[adse]\b")


def shown_as_html(where: str, text: str) -> str:
    """``text`` as the page writes it: the body and the answer as Markdown, every shorter text inline."""
    from phonglab.app import text as page_text

    if where == "text":
        return page_text.render_markdown(text)
    if where == "answer":
        return page_text.render_markdown(page_text.symbols_as_math(text))
    return page_text.inline(text)


@pytest.mark.parametrize("lesson", LESSONS, ids=IDS)
def test_no_coefficient_reaches_the_page_as_typed(lesson):
    # lesson 5's question and feedback and lesson 12's question showed "k_d" raw (student-eye review)
    raw = []
    for where, text in texts(lesson):
        shown = re.sub(r"<math.*?</math>|<code>.*?</code>", "", shown_as_html(where, text), flags=re.DOTALL)
        raw += [f"{where}: {m.group(0)!r} in {text[:80]!r}" for m in RAW_SYMBOL.finditer(shown)]
    assert not raw, "\n".join(raw)


#: the readout is always shown beside the view: a lesson that tells the student to turn it on (or open it)
#: sends them looking for a switch that is not there
READOUT_SWITCH = re.compile(r"\b(turn|switch) on the readout\b|\b(open|show) the readout\b|\breadout (on|off)\b",
                            re.IGNORECASE)


@pytest.mark.parametrize("lesson", LESSONS, ids=IDS)
def test_no_lesson_tells_the_student_to_turn_the_readout_on(lesson):
    found = [f"{where}: {m.group(0)!r}" for where, text in texts(lesson) for m in READOUT_SWITCH.finditer(text)]
    assert not found, f"{Path(lesson.path).name}: the readout has no switch, yet: {found}"
