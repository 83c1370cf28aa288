"""Every worked equation the readout shows holds with its own numbers, to the digits shown.

The walk: every common mistake of the catalogue (and the correct code), every
model of the core (a model or mistake added later is walked too), on the
example scenes and the lessons' scenes, at the probe and at mesh points on
every side of the lights. Each row of the page's equation (the MathML the
page shows) is read back as the page shows it: ``symbols = numbers = …
= value``. The numbers are parsed with the precision they are written with
(a number with k decimals stands for any value within half a unit of its
last digit; a whole number is exact; ``d.ddd × 10^k`` likewise) and every
numeric side is evaluated in interval arithmetic, channel by channel; the
row holds when each side's interval meets the last one's. So a row holds
exactly when some values that round to the shown digits satisfy it.

A failure prints the scene, the mistake, the model, the point and the row.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from phonglab import core
from phonglab.app.readout import probe_readout
from phonglab.render.mesh import build_mesh
from phonglab.render.probe import directed_light_index, locate_probe
from phonglab.scene import load_lesson, load_scene
from phonglab.teaching import MISTAKES

ROOT = Path(__file__).resolve().parent.parent
SCENES = sorted((ROOT / "assets" / "scenes").glob("*.toml"))
LESSONS = sorted((ROOT / "lessons").glob("[0-9]*.md"))
MATH = "{http://www.w3.org/1998/Math/MathML}"
#: relative slack for the float arithmetic of the check itself
SLACK = 1e-9

# ---------------------------------------------------------------------------
# reading MathML back: tokens, then an expression evaluated on intervals


class Symbolic(Exception):
    """The side holds a symbol, not only numbers: it is not checked."""


def tokens(element) -> list:
    """The element's content as a flat list: ('num', text), ('op', text), ('pow', base, exp), ('frac', a, b), ('sqrt', x)."""
    tag = element.tag.removeprefix(MATH)
    children = list(element)
    if tag == "mn":
        return [("num", element.text.strip())]
    if tag == "mo":
        return [("op", element.text.strip())]
    if tag in ("mi", "mtext", "msub", "munder", "munderover", "msubsup"):
        return [("sym", ET.tostring(element, encoding="unicode"))]
    if tag == "mspace":
        return []
    if tag == "msup":
        return [("pow", tokens(children[0]), tokens(children[1]))]
    if tag == "mfrac":
        return [("frac", tokens(children[0]), tokens(children[1]))]
    if tag == "msqrt":
        return [("sqrt", [t for child in children for t in tokens(child)])]
    out = []
    for child in children:
        out += tokens(child)
    return out


def interval(text: str):
    """A shown number as (lo, hi): half a unit of its last digit either side; a whole number is exact."""
    x = float(text)
    half = 0.5 * 10.0 ** -len(text.split(".")[1]) if "." in text else 0.0
    return np.array([x - half] * 3), np.array([x + half] * 3)


def _corners(fn, a, b):
    with np.errstate(all="ignore"):
        values = np.array([fn(x, y) for x in a for y in b])
    lo, hi = np.nanmin(values, axis=0), np.nanmax(values, axis=0)
    nan = np.all(np.isnan(values), axis=0)
    return np.where(nan, np.nan, lo), np.where(nan, np.nan, hi)


def power(base, exp):
    (b_lo, b_hi), (e_lo, e_hi) = base, exp
    exact_integer = np.all(e_lo == e_hi) and np.all(e_lo == np.round(e_lo))
    if np.all(b_lo >= 0) or exact_integer:
        lo, hi = _corners(np.power, (b_lo, b_hi), (e_lo, e_hi))
        if exact_integer:  # x^k over an interval holding 0 reaches 0 (even k) between the corners
            inside = (b_lo < 0) & (b_hi > 0)
            lo = np.where(inside & (e_lo > 0), np.minimum(lo, 0), lo)
        return lo, hi
    # a negative base to a fractional power: not a real number (NaN, as NumPy gives it)
    return np.full(3, np.nan), np.full(3, np.nan)


class Parser:
    """expr := term (('+' | '−') term)*; term := factor (('·' | '×') factor)*; factor := '−' factor | primary."""

    def __init__(self, items):
        self.items, self.i = items, 0

    def peek(self):
        return self.items[self.i] if self.i < len(self.items) else None

    def take(self):
        item = self.items[self.i]
        self.i += 1
        return item

    def expect(self, text):
        item = self.take()
        assert item == ("op", text), f"expected {text!r}, got {item!r}"

    def parse(self):
        value = self.expr()
        assert self.peek() is None, f"left over: {self.items[self.i:]}"
        return value

    def expr(self):
        value = self.term()
        while self.peek() in (("op", "+"), ("op", "−"), ("op", "-")):
            op = self.take()[1]
            right = self.term()
            value = (value[0] + right[0], value[1] + right[1]) if op == "+" else \
                (value[0] - right[1], value[1] - right[0])
        return value

    def term(self):
        value = self.factor()
        while self.peek() in (("op", "·"), ("op", "×")):
            self.take()
            value = _corners(np.multiply, value, self.factor())
        return value

    def factor(self):
        if self.peek() in (("op", "−"), ("op", "-")):
            self.take()
            lo, hi = self.factor()
            return -hi, -lo
        return self.primary()

    def primary(self):
        item = self.take()
        kind = item[0]
        if kind == "sym":
            raise Symbolic(item[1])
        if kind == "num":
            return interval(item[1])
        if kind == "pow":
            return power(Parser(item[1]).parse(), Parser(item[2]).parse())
        if kind == "frac":
            return _corners(np.divide, Parser(item[1]).parse(), Parser(item[2]).parse())
        if kind == "sqrt":  # increasing: the ends' roots (NaN below 0, as NumPy gives it)
            lo, hi = Parser(item[1]).parse()
            with np.errstate(invalid="ignore"):
                return np.sqrt(lo), np.sqrt(hi)
        text = item[1]
        if text == "∞":
            return np.full(3, np.inf), np.full(3, np.inf)
        if text == "max":
            self.expect("(")
            zero = self.expr()
            assert np.all(zero[0] == 0) and np.all(zero[1] == 0), "max(0, ·) with another first operand"
            self.expect(",")
            lo, hi = self.expr()
            self.expect(")")
            return np.fmax(lo, 0), np.fmax(hi, 0)  # NaN (a negative base to a fractional power) -> 0
        if text == "(":
            parts = [self.expr()]
            while self.peek() == ("op", ","):
                self.take()
                parts.append(self.expr())
            self.expect(")")
            if len(parts) == 1:
                return parts[0]
            assert len(parts) == 3, f"a triple of {len(parts)}"
            return np.array([p[0][0] for p in parts]), np.array([p[1][0] for p in parts])
        raise AssertionError(f"unexpected {item!r}")


def sides(math_text: str) -> list:
    """The sides of one row (split at its top-level '='): an interval pair, or None for a symbolic side."""
    root = ET.fromstring(math_text)
    items = tokens(root)
    groups, current = [], []
    for item in items:
        if item == ("op", "="):
            groups.append(current)
            current = []
        else:
            current.append(item)
    groups.append(current)
    out = []
    for group in groups:
        if _has_symbol(group):  # the formula in symbols (its products may be written side by side)
            out.append(None)
            continue
        try:
            out.append(Parser(group).parse())
        except Symbolic:
            out.append(None)
    return out


def _has_symbol(items) -> bool:
    for item in items:
        if item[0] == "sym":
            return True
        if item[0] in ("pow", "frac") and (_has_symbol(item[1]) or _has_symbol(item[2])):
            return True
        if item[0] == "sqrt" and _has_symbol(item[1]):
            return True
    return False


def meets(a, b) -> bool:
    (a_lo, a_hi), (b_lo, b_hi) = a, b
    scale = np.nanmax(np.abs([a_lo, a_hi, b_lo, b_hi]), axis=0)
    slack = SLACK * np.where(np.isfinite(scale), np.maximum(scale, 1.0), 1.0)
    with np.errstate(invalid="ignore"):
        ok = (np.maximum(a_lo, b_lo) <= np.minimum(a_hi, b_hi) + slack)
    both_nan = np.isnan(a_lo) & np.isnan(b_lo)
    return bool(np.all(ok | both_nan))


def rows(equation_html: str) -> list[tuple[str, str]]:
    """(label, MathML) per row of the readout's equation."""
    import re

    return re.findall(r'<span class="eq-label">([^<]+)</span>(<math.*?</math>)', equation_html)


def broken_rows(readout: dict) -> list[str]:
    """The rows of the readout's worked equation that do not hold with their own numbers."""
    bad = []
    found = rows(readout["equation"])
    assert found, f"no rows in {readout['equation'][:300]}"
    for label, math_text in found:
        sides_ = sides(math_text)
        numeric = [s for s in sides_ if s is not None]
        if label == "model":
            assert not numeric, f"the model row has numbers: {math_text}"
            continue
        assert numeric, f"row {label!r} shows no numbers: {math_text}"
        result = numeric[-1]
        for side in numeric[:-1]:
            if not meets(side, result):
                bad.append(f"{label}: {side[0]}..{side[1]} does not meet {result[0]}..{result[1]} in {_text(math_text)}")
    return bad


def _text(math_text: str) -> str:
    return "".join(ET.fromstring(math_text).itertext())


# ---------------------------------------------------------------------------
# the walk


def _scenes():
    out = [(p.name, load_scene(p)) for p in SCENES]
    for p in LESSONS:
        lesson = load_lesson(p)
        out.append((p.name, lesson.scene))
    return out


@pytest.fixture(scope="module")
def places():
    """Per scene: (name, scene, [(point, normal)...]): the probe, then mesh points all round the mesh."""
    found = []
    for name, scene in _scenes():
        mesh = build_mesh(scene.geometry)
        point, normal = locate_probe(mesh, scene)
        points = np.asarray(mesh.points, float)
        normals = np.asarray(mesh.point_data["Normals"], float)
        picks = np.linspace(0, len(points) - 1, 7).astype(int)
        found.append((name, scene, [(point, normal)] + [(points[i], normals[i]) for i in picks]))
    return found


VARIANTS = [None, *MISTAKES]


@pytest.mark.parametrize("model", core.MODELS)
@pytest.mark.parametrize("mistake", VARIANTS, ids=[m or "correct" for m in VARIANTS])
def test_every_worked_equation_holds_with_its_own_numbers(places, model, mistake):
    failures = []
    for name, scene, points in places:
        scene = scene.replace("model", model)
        index = directed_light_index(scene.lights)
        for point, normal in points:
            out = probe_readout(scene, point, normal, index, mistake=mistake)
            failures += [f"{name} at {np.round(point, 3).tolist()}: {row}" for row in broken_rows(out)]
    assert not failures, f"{mistake or 'correct'}, {model}: {len(failures)} rows do not hold:\n" + \
        "\n".join(failures[:8])


# ---------------------------------------------------------------------------
# the checker itself


def test_the_checker_reads_the_digits_shown():
    from phonglab.app.text import mathml

    def holds(tex):
        return not [s for s in sides(mathml(tex))[1:-1] if s is not None and not meets(s, sides(mathml(tex))[-1])]

    assert holds(r"f = 1.000 \cdot 0.80 \cdot 1.00 \cdot 0.822 = 0.658")
    # the unnormalised light's row as it used to be: the correct n·l with the mistaken result
    assert not holds(r"f = 1.000 \cdot \left(0.80, 0.30, 0.20\right) \cdot 1.00 \cdot 0.822 "
                     r"= \left(2.320, 0.870, 0.580\right)")
    assert holds(r"x = {\max(0, 0.871)}^{40} = 0.004")
    assert not holds(r"x = {\max(0, 0.871)}^{40} = 0.006")  # 0.8715^40 = 0.0040: one digit off fails
    assert holds(r"x = 0.60 \cdot {\max(0, 2.815)}^{40} = 5.717 \times 10^{17}")
    assert holds(r"x = \max(0, \left(-0.500\right)^{40}) = 0.000")
    assert holds(r"x = 0.50 \cdot 0 = 0.000")
    assert holds(r"I = 0.020 + \left(0.771, 0.289, 0.193\right) = \left(0.791, 0.309, 0.213\right)")
    assert not holds(r"I = 0.020 + \left(0.771, 0.289, 0.193\right) = \left(0.795, 0.309, 0.213\right)")
    assert math.isclose(interval("0.80")[1][0] - interval("0.80")[0][0], 0.01)
