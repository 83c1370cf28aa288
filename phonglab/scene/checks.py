"""Value checks for the scene's own fields, each raising a located-ready SceneError.

Each check takes the field path and the value, returns the value in its
canonical form (floats, tuples) and raises :class:`SceneError` naming the
path, the value and what is allowed. "Three finite numbers" is the core's
validator (``phonglab.core.model._vec3``); here only the TOML shape around it
is checked. Material and light values are the core's to check:
:func:`check_shape` only refuses a value of the wrong TOML type (text where a
number belongs), which the core would otherwise convert.
"""

from __future__ import annotations

import math
import numbers
import re

from phonglab.core.model import InvalidValue, _vec3
from phonglab.scene.errors import SceneError, SceneErrors, did_you_mean
from phonglab.scene.schema import MAX_NESTING, SHAPE_RULES


def _is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def check_number(path, value, *, low=None, high=None, low_open=False, high_open=False) -> float:
    """A finite real number within optional bounds, as float; SceneError otherwise."""
    rule = "must be a finite number"
    if low is not None and high is not None:
        rule += f" in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
    elif low is not None:
        rule += f" {'>' if low_open else '>='} {low:g}"
    elif high is not None:
        rule += f" {'<' if high_open else '<='} {high:g}"
    if not _is_number(value) or not math.isfinite(value):
        raise SceneError(rule, field=path, value=value)
    x = float(value)
    if low is not None and (x < low or (low_open and x == low)):
        raise SceneError(rule, field=path, value=value)
    if high is not None and (x > high or (high_open and x == high)):
        raise SceneError(rule, field=path, value=value)
    return x


def check_int(path, value, *, low=None, high=None) -> int:
    """A whole number within optional closed bounds; SceneError otherwise."""
    rule = "must be a whole number"
    if low is not None and high is not None:
        rule += f" from {low} to {high}"
    elif low is not None:
        rule += f" >= {low}"
    ok = _is_number(value) and math.isfinite(value) and float(value).is_integer()
    if ok and low is not None and value < low:
        ok = False
    if ok and high is not None and value > high:
        ok = False
    if not ok:
        raise SceneError(rule, field=path, value=value)
    return int(value)


def check_vector(path, value, *, nonzero=False) -> tuple[float, float, float]:
    """A list of three finite numbers, as a tuple of floats; SceneError otherwise.

    The list's TOML shape (three numbers, not text or booleans) is checked
    here; finiteness and "not all zero" by the core's shared validator.
    """
    rule = "must be a list of 3 finite numbers" + (", not all zero" if nonzero else "")
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise SceneError(rule, field=path, value=value)
    if len(value) != 3:
        raise SceneError(rule, field=path, value=value, hint=f"{len(value)} given")
    if not all(_is_number(v) for v in value):
        raise SceneError(rule, field=path, value=value)
    try:
        return _vec3(path, value, nonzero=nonzero)
    except InvalidValue:
        raise SceneError(rule, field=path, value=value) from None


def check_choice(path, value, allowed) -> str:
    """One of the ``allowed`` strings; SceneError with a did-you-mean otherwise."""
    if not isinstance(value, str) or value not in allowed:
        rule = "must be one of " + ", ".join(f'"{a}"' for a in allowed)
        raise SceneError(rule, field=path, value=value, hint=did_you_mean(value, allowed))
    return value


def check_bool(path, value) -> bool:
    """``true`` or ``false``; SceneError otherwise (1 and "yes" are refused)."""
    if not isinstance(value, bool):
        raise SceneError("must be true or false", field=path, value=value)
    return value


def check_text(path, value) -> str:
    """A string; SceneError otherwise."""
    if not isinstance(value, str):
        raise SceneError("must be a text string", field=path, value=value)
    return value


def collect(checks) -> None:
    """Run each check (a thunk), raising every SceneError at once."""
    errors = []
    for check in checks:
        try:
            check()
        except SceneErrors as exc:
            errors.extend(exc.errors)
        except SceneError as exc:
            errors.append(exc)
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise SceneErrors(errors)


def setter(obj, name, check):
    """A thunk that checks ``obj.name`` and stores the canonical value back."""

    def run():
        object.__setattr__(obj, name, check(getattr(obj, name)))

    return run


def check_shape(path, value, shape: str, rule: str | None = None):
    """The TOML shape of a value the core checks: ``"number"``, ``"rgb"``, ``"vector"`` or ``"homogeneous"``.

    A number is a real number that is not a boolean; ``rgb`` a number or a
    list of three; ``vector`` a list of three numbers; ``homogeneous`` a list
    of four. Lists come back as tuples. Whether the numbers are allowed
    (finite, >= 0, in range) is left to the core.

    Raises
    ------
    SceneError
        With ``rule`` (or the shape's own wording) when the shape is wrong.
    """
    rule = rule or SHAPE_RULES[shape]
    if shape == "number" or (shape == "rgb" and not isinstance(value, (list, tuple))):
        if not _is_number(value):
            raise SceneError(rule, field=path, value=value)
        return value
    size = 4 if shape == "homogeneous" else 3
    if not isinstance(value, (list, tuple)):
        raise SceneError(rule, field=path, value=value)
    if len(value) != size:
        raise SceneError(rule, field=path, value=value, hint=f"{len(value)} given")
    if not all(_is_number(v) for v in value):
        raise SceneError(rule, field=path, value=value)
    return tuple(value)


def nesting_depth(text: str) -> int:
    """The deepest nesting of ``[ ]`` and ``{ }`` in ``text``, counted in one cheap pass.

    Brackets inside strings count too: an over-estimate only refuses text
    that is far past any teaching scene's nesting.
    """
    depth = deepest = 0
    for ch in text:
        if ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}" and depth:
            depth -= 1
    return deepest


def check_nesting(text: str, *, field=None, file=None) -> None:
    """Refuse text nested deeper than :data:`MAX_NESTING` before a recursive parser sees it.

    Raises
    ------
    SceneError
        Naming the depth found and the limit (and the file or field).
    """
    if "[" not in text and "{" not in text:
        return
    depth = nesting_depth(text)
    if depth > MAX_NESTING:
        raise SceneError(f"nests lists or tables {depth} deep, at most {MAX_NESTING} allowed",
                         field=field, file=file)


_MARKDOWN_LEVEL = re.compile(r"[ \t]*(?:[-*+>]|\d{1,9}[.)])(?:[ \t]+|$)")


def markdown_depth(text: str) -> tuple[int, int]:
    """The deepest nesting of list items and quotes on one Markdown line, and that line (1-based).

    Each ``-``, ``*``, ``+``, ``>`` or ``1.`` marker at the start of a line,
    one after the other, is a level (``- - - x`` is three deep).
    """
    deepest, where = 0, 0
    for number, line in enumerate(text.splitlines(), 1):
        depth, pos = 0, 0
        while True:
            match = _MARKDOWN_LEVEL.match(line, pos)
            if not match or match.end() == pos:
                break
            depth, pos = depth + 1, match.end()
        if depth > deepest:
            deepest, where = depth, number
    return deepest, where


__all__ = ["check_number", "check_int", "check_vector", "check_choice", "check_bool", "check_text", "check_shape",
           "collect", "setter", "nesting_depth", "check_nesting", "markdown_depth"]
