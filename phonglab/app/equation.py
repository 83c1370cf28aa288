"""The record's formulas as LaTeX: in symbols, and with the recorded numbers substituted.

A formula of :mod:`phonglab.core.record` is a value's name, a number, or
``(operator, *operands)``. :func:`symbols` writes it in the lesson's
symbols (``f\\, k_d I_d \\max(0, n\\cdot l)``), :func:`numbers` with each
name replaced by its value at the probe (``1.000 \\cdot 0.80 \\cdot 1.00
\\cdot \\max(0, 0.963)``). Nothing is computed here: the values are the
record's and each gate is resolved by the core (:func:`~phonglab.core.record.resolve`).

How numbers are written, so that a reader (and the tests) can tell the
precision of each: a coefficient or intensity (``k_a`` ... ``I_s``) with 2
decimals, any other value with 3, a value of 10⁴ or more as ``d.ddd × 10^k``;
an RGB triple whose channels read the same as one number; a whole number (an
integer exponent, the 0 of ``max(0, ·)``) is exact; α with 2 decimals unless
it is a whole number.

:func:`as_mathml` typesets a worked row: the row's shape (its LaTeX with
every number replaced by one digit) is converted to MathML once, and each
new set of numbers is put into that MathML's number elements.
"""

from __future__ import annotations

import functools
import math
import re

import numpy as np

from phonglab.app.text import mathml

#: how each recorded name is written in the lesson's symbols (others: as they are, or as text)
SYMBOLS = {
    "n·l": r"n\cdot l", "r·v": r"r\cdot v", "n·h": r"n\cdot h", "n·v": r"n\cdot v",
    "α": r"\alpha", "f_lamp": r"f_{\text{lamp}}", "diffuse weight": "w_d", "specular weight": "w_s",
    "ambient": r"k_a I_a", "emission": "k_e", "attenuation": r"f_{\text{att}}", "spot": r"f_{\text{spot}}",
    # Cook–Torrance
    "v·h": r"v\cdot h", "π": r"\pi", "α_GGX": r"\alpha", "F₀": "F_0", "k_D": "(1 - F)(1 - m)",
    # shadows: the light's visibility, lesson 14's S_l (1 lit, 0 in shadow)
    "lit": "S",
}
#: names written with 2 decimals (the coefficients and intensities of the lesson's tables)
TWO_DECIMALS = {"k_a", "k_d", "k_s", "k_e", "I_a", "I_d", "I_s"}
#: from this magnitude on, a number is written as d.ddd × 10^k
SCIENTIFIC = 1e4


def symbol(name: str) -> str:
    """A recorded name in the lesson's symbols: ``n·l`` -> ``n\\cdot l``; an unknown word as text."""
    if name in SYMBOLS:
        return SYMBOLS[name]
    if len(name) == 1 or (len(name) == 3 and name[1] == "_"):
        return name
    return rf"\text{{{name}}}"


def number(x: float, digits: int = 3) -> str:
    """One number as LaTeX with ``digits`` decimals (see the module's rules)."""
    x = float(x)
    if math.isnan(x):
        return r"\text{NaN}"
    if math.isinf(x):
        return r"\infty" if x > 0 else r"-\infty"
    if abs(x) >= SCIENTIFIC:
        mantissa, exponent = f"{x:.3e}".split("e")
        return rf"{mantissa} \times 10^{{{int(exponent)}}}"
    text = f"{x:.{digits}f}"
    return "0" + text[2:] if text.startswith("-0") and float(text) == 0 else text


def exponent(alpha: float) -> str:
    """An exponent: a whole number as it is (exact), else with 2 decimals."""
    alpha = float(alpha)
    return f"{alpha:.0f}" if alpha == round(alpha) and abs(alpha) < 1e15 else number(alpha, 2)


def value(x, digits: int = 3) -> str:
    """A scalar, or an RGB triple (one number when its channels read the same)."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim == 0:
        return number(x, digits)
    texts = [number(c, digits) for c in x]
    if len(set(texts)) == 1:
        return texts[0]
    return r"\left(" + ", ".join(texts) + r"\right)"


def _leaf_number(name: str, x) -> str:
    if name == "lit":  # the record's yes or no: exactly 1 or 0
        return "1" if bool(np.all(np.asarray(x))) else "0"
    if name == "α":
        return exponent(x)
    return value(x, 2 if name in TWO_DECIMALS else 3)


def _negative(text: str) -> bool:
    return text.startswith("-")


def _sum(operand) -> bool:
    """A sum or difference: bracketed where it is a factor."""
    return isinstance(operand, tuple) and operand[0] in ("add", "sub")


def _sqrt(formula) -> bool:
    return isinstance(formula, tuple) and formula[0] == "pow" and not isinstance(formula[2], (str, tuple)) \
        and float(formula[2]) == 0.5


def _root(inside: str, operand) -> str:
    """``√inside``; a sum inside brackets too, so that where a font draws no bar over it (no maths
    font), where the root ends is still plain: √((n·v)²(1 − α²) + α²), not √(n·v)²(1 − α²) + α²."""
    return rf"\sqrt{{\left({inside}\right)}}" if _sum(operand) else rf"\sqrt{{{inside}}}"


def shadow_factor(formula):
    """``formula`` with each shadow gate, ``("if", ("lit",), term)``, written as the factor ``S`` times the term.

    The kernel keeps a blocked light's term out of the sum (the gate); the
    lesson writes the same as a product, ``S_l f_l [...]`` with ``S`` 1 or 0.
    Written so, a worked row shows ``S`` and its recorded value (``0 · … =
    0.000``) instead of jumping from the formula to 0. Other gates are kept.
    """
    if not isinstance(formula, tuple):
        return formula
    operator, *operands = formula
    if operator == "if":
        conditions, inner = operands
        inner = shadow_factor(inner)
        if tuple(conditions) == ("lit",):
            return ("mul", "lit", *inner[1:]) if isinstance(inner, tuple) and inner[0] == "mul" else ("mul", "lit", inner)
        return ("if", conditions, inner)
    return (operator, *(shadow_factor(x) for x in operands))


def symbols(formula) -> str:
    """``formula`` in the lesson's symbols (a gate is written as what it guards).

    A formula is written the same way every time: remembered (a slider's
    step changes the numbers of a worked row, not its symbols).
    """
    try:
        return _remembered_symbols(formula)
    except TypeError:  # something unhashable in it
        return _symbols(formula)


@functools.lru_cache(maxsize=4096)
def _remembered_symbols(formula) -> str:
    return _symbols(formula)


def _symbols(formula) -> str:
    if isinstance(formula, str):
        return symbol(formula)
    if not isinstance(formula, tuple):
        return exponent(formula)
    operator, *operands = formula
    if operator == "if":
        return symbols(operands[1])
    if operator == "mul":
        names = [rf"\left({symbols(x)}\right)" if _sum(x) else symbols(x) for x in operands]
        # S\, f\, k_d I_d ...: a thin space after the light's factors (its visibility, then f)
        lead = 1 if operands[0] == "lit" and len(names) > 1 else 0
        if lead:
            names[0] = r"S\,"
        if operands[lead] == "f" and len(names) > lead + 1:
            names[lead] = r"f\,"
        return " ".join(names)
    if operator == "add":
        return " + ".join(symbols(x) for x in operands)
    if operator == "sub":
        right = rf"\left({symbols(operands[1])}\right)" if _sum(operands[1]) else symbols(operands[1])
        return f"{symbols(operands[0])} - {right}"
    if _sqrt(formula):
        return _root(symbols(operands[0]), operands[0])
    if operator == "div":
        return rf"\frac{{{symbols(operands[0])}}}{{{symbols(operands[1])}}}"
    if operator == "max0":
        return rf"\max(0, {symbols(operands[0])})"
    base, power = operands
    single = isinstance(base, str) and (len(symbol(base)) == 1 or symbol(base) in (r"\alpha", r"\pi"))
    return _power(symbols(base), symbols(power), plain=single,
                  grouped=isinstance(base, tuple) and base[0] == "max0")


def _power(base: str, power: str, *, plain: bool, grouped: bool) -> str:
    """``base^power``: a plain number or letter as it is, ``max(...)`` in braces, anything else in brackets."""
    if not plain and not grouped:
        base = rf"\left({base}\right)"
    return rf"{{{base}}}^{{{power}}}"


def numbers(formula, lookup) -> str:
    """``formula`` with every name replaced by its value, ``lookup(name)`` (gates already resolved)."""
    if isinstance(formula, str):
        return _leaf_number(formula, lookup(formula))
    if not isinstance(formula, tuple):
        return exponent(formula)
    operator, *operands = formula
    if operator == "if":  # a gate left in: written as what it guards
        return numbers(operands[1], lookup)
    if _sqrt(formula):
        return _root(numbers(operands[0], lookup), operands[0])
    parts = [numbers(x, lookup) for x in operands]
    if operator in ("mul", "add", "sub"):
        # a negative factor or addend in brackets: "1.000 · (−0.300)"; a sum inside a product or after a minus
        parts = [rf"\left({p}\right)" if (_negative(p) and i) or (operator != "add" and _sum(x) and
                                                                     (operator == "mul" or i)) else p
                 for i, (p, x) in enumerate(zip(parts, operands))]
        return {"mul": r" \cdot ", "add": " + ", "sub": " - "}[operator].join(parts)
    if operator == "div":
        return rf"\frac{{{parts[0]}}}{{{parts[1]}}}"
    if operator == "max0":
        return rf"\max(0, {parts[0]})"
    base, power = parts
    leaf = isinstance(operands[0], str) and not _negative(base) and r"\left(" not in base and "\\" not in base
    return _power(base, power, plain=leaf, grouped=isinstance(operands[0], tuple) and operands[0][0] == "max0")


#: a number of a row's LaTeX (its digits; a sign is an operator) or a piece of text, whose digits are words
_NUMBER_OR_TEXT = re.compile(r"\\text\{[^{}]*\}|\d+(?:\.\d+)?")
#: what stands for every number in a row's shape
_SLOT = "7"
_SLOT_MATHML = f"<mn>{_SLOT}</mn>"


@functools.lru_cache(maxsize=1024)
def _shape_pieces(shape: str) -> tuple[str, ...]:
    """The MathML of a row's shape cut at its number elements."""
    return tuple(mathml(shape).split(_SLOT_MATHML))


def as_mathml(tex: str) -> str:
    """A worked row's LaTeX as MathML: the same markup as :func:`phonglab.app.text.mathml` gives.

    A slider's every step gives a row new numbers in the same formula; the
    formula's MathML is made once (for its shape, every number a ``7``) and
    the numbers are put into its ``<mn>`` elements, each a number's own
    element. A shape whose MathML does not hold one such element per number
    is converted whole instead.
    """
    found = []

    def slot(match: re.Match) -> str:
        if match.group(0).startswith("\\"):
            return match.group(0)  # \text{light 1}: words, not a number
        found.append(match.group(0))
        return _SLOT

    pieces = _shape_pieces(_NUMBER_OR_TEXT.sub(slot, tex))
    if len(pieces) != len(found) + 1:
        return mathml(tex)
    out = [pieces[0]]
    for number_text, piece in zip(found, pieces[1:]):
        out.append(f"<mn>{number_text}</mn>")
        out.append(piece)
    return "".join(out)
