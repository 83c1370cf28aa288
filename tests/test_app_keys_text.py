"""State keys for field paths, and lesson Markdown with MathML."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from phonglab.app.keys import field_path, state_key
from phonglab.app.text import inline, mathml, render_markdown

# ---------------------------------------------------------------------------
# keys

names = st.from_regex(r"[a-z][a-z]{0,6}(_[a-z]{1,6}){0,2}", fullmatch=True)
segments = st.tuples(names, st.lists(st.integers(0, 99), max_size=2)).map(
    lambda t: t[0] + "".join(f"[{i}]" for i in t[1])
)
paths = st.lists(segments, min_size=1, max_size=4).map(".".join)


@pytest.mark.parametrize(
    "path, key",
    [
        ("model", "model"),
        ("material.ks", "material__ks"),
        ("lights[1].position", "lights_1__position"),
        ("lights[1].position[2]", "lights_1__position_2"),
        ("camera.infinite_viewer", "camera__infinite_viewer"),
        ("two_sided", "two_sided"),
    ],
)
def test_documented_key_spellings(path, key):
    assert state_key(path) == key, path
    assert field_path(key) == path, key


@given(paths)
def test_keys_round_trip_and_hold_no_dot_or_bracket(path):
    key = state_key(path)
    assert "." not in key and "[" not in key and "]" not in key, (path, key)
    assert field_path(key) == path, (path, key)


@pytest.mark.parametrize("bad", ["", "a..b", "lights[x]", "1abc", "a__b", "light_1.x", "a b"])
def test_malformed_paths_are_refused(bad):
    with pytest.raises(ValueError, match="not a field path"):
        state_key(bad)


# ---------------------------------------------------------------------------
# text


def test_inline_and_display_maths_become_mathml_without_dollars():
    html = render_markdown("The term $k_d \\max(0, n\\cdot l)$ is diffuse.\n\n$$I = k_a I_a$$\n\nDone.")
    assert html.count("<math") == 2, html
    assert 'display="block"' in html and 'display="inline"' in html, html
    assert '<div class="math-block"><math' in html, html
    assert "$" not in html, html


def test_underscores_and_stars_inside_maths_are_not_markdown():
    html = render_markdown("See $a_i * b_i * c_i$ and _this_.")
    maths = re.search(r"<math.*?</math>", html).group(0)
    assert "<em>" not in maths, html
    assert "<em>this</em>" in html, html


def test_escaped_dollar_stays_a_dollar_and_lone_dollars_are_text():
    html = render_markdown("It costs \\$5, or 5 $ and 6 $.")
    assert "<math" not in html, html
    assert "$5" in html, html


def test_a_formula_that_cannot_be_typeset_shows_its_source_marked():
    out = mathml("\\frac{1}{")
    assert out.startswith('<code class="math-error"'), out
    assert "\\frac{1}{" in out, out


def test_inline_drops_the_paragraph():
    assert inline("a $x$ b").startswith("a <math"), inline("a $x$ b")
    assert not inline("plain").startswith("<p>")


def test_a_formula_and_the_punctuation_touching_it_are_one_unbreakable_span():
    html = render_markdown("Light ($k_d$), then $n\\cdot l$. A $x$ alone and $y$-ish.")
    spans = re.findall(r'<span class="phonglab-nobreak">(.*?)</span>', html)
    assert len(spans) == 2, html
    assert spans[0].startswith("(<math") and spans[0].endswith("</math>),"), html
    assert spans[1].startswith("<math") and spans[1].endswith("</math>."), html
    # a formula with a space on both sides (or a hyphen after it) may break there as any word does
    assert "A <math" in html and "and <math" in html, html
