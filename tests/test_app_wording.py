"""Controls and rules in plain words: a slider's spoken name, what a field takes."""

from __future__ import annotations

from pathlib import Path

import pytest

from phonglab.app import controls as ctl
from phonglab.app.slider_access import key_step_handler, slider_attributes
from phonglab.app import wording
from phonglab.app.wording import plain_rule, spoken_label
from phonglab.scene import schema
from phonglab.scene.lessons import catalog

LESSONS = Path(__file__).resolve().parents[1] / "lessons"
ENTRIES = [e for e in catalog(LESSONS)[0] if e.ok]


@pytest.mark.parametrize("entry", ENTRIES, ids=lambda e: e.path.stem)
def test_every_widget_of_every_lesson_has_a_plain_distinct_name(entry):
    widgets = ctl.scene_controls(entry.scene)
    names = {c.path: spoken_label(c) for c in widgets}
    for path, name in names.items():
        assert name and "$" not in name and "\\" not in name and "{" not in name, (path, name)
    sliders = [names[c.path] for c in widgets if c.kind == "slider"]
    assert len(set(sliders)) == len(sliders), sorted(sliders)  # a screen reader tells them apart


@pytest.mark.parametrize("rule, words", [
    (schema.RGB_RULE, "a number of 0 or more, or three of them (red, green, blue) separated by commas"),
    (schema.NUMBER_RULE, "a number of 0 or more"),
    (schema.VECTOR_RULE, "three numbers separated by commas (x, y, z)"),
    ("must be a finite number in [0, 1]", "a number from 0 to 1"),
    ("must be a whole number from 4 to 256", "a whole number from 4 to 256"),
    ('must be one of "sphere", "torus"', "sphere or torus"),
    ("must be a finite number > 0", "a number above 0"),
    ("must be a value with x >= 2 and y <= 3", "a value with x at least 2 and y at most 3"),
    # the upper limits (phonglab.core.model), as a value past them is refused
    ("must be a finite number in [0, 1000] or a list of 3 of them (RGB)",
     "a number from 0 to 1000, or three of them (red, green, blue) separated by commas"),
    ("must be a finite number in [0, 1e6]", "a number from 0 to 1,000,000"),
    ("must be a finite number in (0, 1000]", "a number above 0 and at most 1000"),
    ("must be (a, b, c) with every coefficient within ±1e6", "three numbers a, b, c, each at most 1,000,000 in size"),
])
def test_a_rule_reads_as_what_the_field_takes(rule, words):
    text = plain_rule(rule)
    assert text == words, (rule, text)
    assert not any(code in text for code in (">", "<", "must", '"', "'")), (rule, text)


def test_only_a_slider_with_a_key_step_takes_the_arrow_keys():
    widgets = {c.path: c for c in ctl.scene_controls(ENTRIES[0].scene)}
    shininess = widgets["material.shininess.log"]
    assert shininess.key_step == ctl.SHININESS_KEY_STEP > 2 * shininess.step, shininess
    attributes = slider_attributes(shininess)
    assert attributes["name"] == "shininess α" and "keydown_capture" in attributes, attributes
    handler = key_step_handler(shininess)
    assert '"' not in handler and f"* {ctl.SHININESS_KEY_STEP!r}" in handler, handler
    bias = widgets["shadow_bias"]
    assert "keydown_capture" in slider_attributes(bias) and f"* {ctl.SHADOW_BIAS_KEY_STEP!r}" in key_step_handler(bias)
    stepped = [c for c in widgets.values() if c.path.endswith(".intensity")]
    assert stepped and all(f"* {ctl.INTENSITY_KEY_STEP!r}" in key_step_handler(c) for c in stepped), stepped
    others = [c for c in widgets.values() if c.kind == "slider" and c not in (shininess, bias, *stepped)]
    assert others and all(set(slider_attributes(c)) == {"name"} for c in others), others


def test_the_shadow_offset_reaches_leaking_in_tens_of_key_presses_and_a_drag_still_finds_0_001():
    """Lesson 14's offset slider moved 0.001 per arrow key: 0.5, where light leaks, was 500 presses away."""
    widgets = {c.path: c for c in ctl.scene_controls(ENTRIES[0].scene)}
    bias = widgets["shadow_bias"]
    presses = (0.5 - bias.low) / (bias.key_step or bias.step)
    assert presses <= 60, (bias.low, bias.high, bias.step, bias.key_step, presses)
    assert bias.step == 0.001, bias  # the lesson's 0.001, which removes the acne, is a step of a drag


def test_a_lights_intensity_goes_from_off_to_full_in_twenty_key_presses():
    """It moved 0.01 per arrow key: 100 presses from off to 1, 500 to the slider's end."""
    widgets = {c.path: c for c in ctl.scene_controls(ENTRIES[0].scene)}
    intensities = [c for c in widgets.values() if c.path.endswith(".intensity")]
    assert intensities, sorted(widgets)
    for c in intensities:
        assert (1.0 - c.low) / (c.key_step or c.step) <= 20, (c.path, c.low, c.high, c.step, c.key_step)


#: characters that act instead of showing: NUL, escape, a right-to-left override, a zero-width joiner, a line separator
HIDDEN = ["\x00", "\x1b", "\u202e", "\u200d", "\u2028"]


@pytest.mark.parametrize("sentence", [
    lambda bad: wording.unknown_setting(f"ks{bad}", f"0.5{bad}"),
    lambda bad: wording.no_lesson(f"01{bad}", ["01-light"]),
    lambda bad: wording.long_key(f"k{bad}" * 30),
], ids=["unknown setting", "no lesson", "long key"])
def test_an_address_notice_shows_hidden_characters_escaped(sentence):
    for bad in HIDDEN:
        text = sentence(bad)
        assert bad not in text, (bad, text)
    # shown as Python writes them; a line separator is white space, read as a space
    assert "\\x00" in sentence("\x00") and "\\u202e" in sentence("\u202e"), (sentence("\x00"), sentence("\u202e"))


@pytest.mark.parametrize("text, shown", [
    ("k_a ∘ I_a = (0.0225, 0.045, 0.1125), the same at every point",
     "<i>k</i><sub>a</sub> ∘ <i>I</i><sub>a</sub> = (0.0225, 0.045, 0.1125), the same at every point"),
    ("k_d > 0 and a light reaches the surface", "<i>k</i><sub>d</sub> &gt; 0 and a light reaches the surface"),
    ("its material's k_a, k_d, k_s and α are used",
     "its material's <i>k</i><sub>a</sub>, <i>k</i><sub>d</sub>, <i>k</i><sub>s</sub> and α are used"),
    ("<img src=x onerror=alert(1)> f_l", "&lt;img src=x onerror=alert(1)&gt; <i>f</i><sub>l</sub>"),
    ("max_x, snake_case, k_ab and x_1 stay as they are", "max_x, snake_case, k_ab and x_1 stay as they are"),
])
def test_symbols_in_plain_sentences_get_their_subscripts_and_nothing_else_is_markup(text, shown):
    from phonglab.app.wording import symbols_html

    assert symbols_html(text) == shown, text
