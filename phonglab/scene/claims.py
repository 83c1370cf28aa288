"""A lesson's executable claims: the ``[[claims]]`` tables of its front matter.

A claim pairs a sentence of the lesson (``says``) with a check the test suite
and ``phonglab check`` run on the lesson's own scene (``check``), optionally
after an experiment's settings (``experiment = N``, counted from 1) and
further settings (``set = {...}``, applied with :meth:`Scene.replace_many`
as the page applies an experiment). Every claim says what it speaks of
(``about``): the model's numbers (``"model"``) or the picture the student
sees (``"picture"``, measured with the ``shown_*`` functions), and how its
sentence would be made false (``false_when``: other settings, or a number or
comparison of the check replaced), under which the check must fail::

    [[claims]]
    says = "0.9^10 ≈ 0.35"
    about = "model"
    check = "abs(pow(0.9, 10) - 0.35) < 0.005"
    false_when = { replace = ["0.35", "0.45"] }

    [[claims]]
    says = "At exposure 3 a quarter of the sphere is clipped to white."
    about = "picture"
    experiment = 3
    check = "0.2 < shown_fraction('color', 255, 255) < 0.3"
    false_when = { set = { "exposure" = 1 } }

The check is a small, safe expression language, read with :mod:`ast` and
never passed to ``eval``: numbers, ``+ - * / **``, comparisons (chains
allowed), ``and``/``or``/``not``, and calls of the functions of
:data:`~phonglab.scene.schema.CLAIM_FUNCTIONS` with words (quoted) from
their fixed lists. No names, attributes, subscripts or other calls; at most
:data:`~phonglab.scene.schema.CLAIM_MAX_CHARS` characters. This module only
checks the form; :mod:`phonglab.accuracy.claims` measures and decides.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass

from phonglab.scene.errors import SceneError, did_you_mean
from phonglab.scene.schema import CLAIM_FUNCTIONS, CLAIM_MAX_CHARS, CLAIM_MAX_NODES, PICTURE_FUNCTIONS

__all__ = ["Claim", "FalseWhen", "parse_check", "calls", "about_problem", "seeing_word", "replaced_check"]

_BINARY = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)
_UNARY = (ast.USub, ast.UAdd, ast.Not)
_COMPARE = (ast.Lt, ast.LtE, ast.Gt, ast.GtE, ast.Eq, ast.NotEq)


@dataclass(frozen=True)
class FalseWhen:
    """How to make a claim's sentence false: the check must then fail.

    Parameters
    ----------
    settings : tuple of (str, object)
        Field paths and values applied after the claim's own (a scene of
        which the sentence is false).
    replace : (str, str) or None
        Text of the check and what replaces it (every occurrence): the
        sentence's number or direction changed.
    """

    settings: tuple = ()
    replace: tuple[str, str] | None = None


@dataclass(frozen=True)
class Claim:
    """One executable claim of a lesson.

    Parameters
    ----------
    says : str
        The sentence, as the lesson states it.
    check : str
        The expression that must be true (see the module docstring).
    about : str
        ``"model"`` (the model's numbers) or ``"picture"`` (what the page shows).
    false_when : FalseWhen
        A change that makes the sentence false, under which the check must fail.
    experiment : int or None
        Apply this experiment's settings first (1 is the first experiment).
    settings : tuple of (str, object)
        Further field paths and values, applied after the experiment's.
    index : int
        Position in the lesson's ``[[claims]]`` list, from 0.
    """

    says: str
    check: str
    about: str = "model"
    false_when: FalseWhen = FalseWhen()
    experiment: int | None = None
    settings: tuple = ()
    index: int = 0


def _fail(problem: str, value=None, hint: str | None = None) -> SceneError:
    return SceneError(problem, value=value,
                      hint=hint or "allowed: numbers, + - * / **, comparisons, and/or/not, and calls of "
                      + ", ".join(CLAIM_FUNCTIONS))


def _check_call(node: ast.Call) -> None:
    if not isinstance(node.func, ast.Name) or node.func.id not in CLAIM_FUNCTIONS:
        shown = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
        raise _fail("calls an unknown function", shown, did_you_mean(shown, CLAIM_FUNCTIONS))
    if node.keywords:
        raise _fail(f"{node.func.id}() takes no keyword arguments", ast.unparse(node))
    kinds = CLAIM_FUNCTIONS[node.func.id][0]
    required = [k for k in kinds if not (k == "number?" or (isinstance(k, tuple) and "?" in k))]
    if not len(required) <= len(node.args) <= len(kinds):
        raise _fail(f"{node.func.id}() takes {len(required)}"
                    + (f" to {len(kinds)}" if len(kinds) != len(required) else "") + " arguments",
                    ast.unparse(node))
    for arg, kind in zip(node.args, kinds):
        if isinstance(kind, tuple):  # a word from a fixed list
            words = tuple(k for k in kind if k != "?")
            if not (isinstance(arg, ast.Constant) and arg.value in words):
                raise _fail(f"{node.func.id}(): must be one of " + ", ".join(repr(w) for w in words),
                            ast.unparse(arg))
        else:
            _check_number(arg)


def _check_number(node) -> None:
    """A node that gives a number (or a truth value): everything but words."""
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise _fail("may hold only numbers outside a function's word argument", repr(node.value))
    elif isinstance(node, ast.BinOp) and isinstance(node.op, _BINARY):
        _check_number(node.left)
        _check_number(node.right)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, _UNARY):
        _check_number(node.operand)
    elif isinstance(node, ast.BoolOp):
        for value in node.values:
            _check_number(value)
    elif isinstance(node, ast.Compare) and all(isinstance(op, _COMPARE) for op in node.ops):
        for value in [node.left, *node.comparators]:
            _check_number(value)
    elif isinstance(node, ast.Call):
        _check_call(node)
    elif isinstance(node, ast.Name):
        raise _fail("names a value that is not a function call", node.id)
    else:
        raise _fail("uses a construct the check language does not allow", ast.unparse(node))


def parse_check(text) -> ast.Expression:
    """Parse and check a claim's ``check`` expression.

    Returns
    -------
    ast.Expression
        The checked syntax tree (evaluated by :mod:`phonglab.accuracy.claims`).

    Raises
    ------
    SceneError
        Naming the construct that is not allowed.
    """
    if not isinstance(text, str) or not text.strip():
        raise SceneError("must be a non-empty expression, e.g. \"abs(pow(0.9, 10) - 0.35) < 0.005\"", value=text)
    if len(text) > CLAIM_MAX_CHARS:
        raise SceneError(f"must be at most {CLAIM_MAX_CHARS} characters", value=f"{len(text)} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise SceneError(f"is not a valid expression ({exc.msg})", value=text) from None
    if sum(1 for _ in ast.walk(tree)) > CLAIM_MAX_NODES:
        raise SceneError(f"must have at most {CLAIM_MAX_NODES} parts; split it into several claims", value=text)
    _check_number(tree.body)
    return tree


def calls(tree: ast.Expression) -> set[str]:
    """The names of the functions a checked expression calls."""
    return {node.func.id for node in ast.walk(tree) if isinstance(node, ast.Call)}


def about_problem(about: str, tree: ast.Expression) -> str | None:
    """What is wrong with a claim's ``about`` for the functions its check calls, or None.

    A picture claim measures the picture shown (a ``shown_*`` function; it
    may compare it with the model's numbers); a model claim measures none.
    """
    shown = sorted(calls(tree) & set(PICTURE_FUNCTIONS))
    if about == "picture" and not shown:
        return "a picture claim must measure the picture shown: call one of " + ", ".join(PICTURE_FUNCTIONS)
    if about == "model" and shown:
        return (f"a model claim speaks of the model's numbers, but the check measures the picture ({shown[0]}); "
                "say about = \"picture\"")
    return None


#: words that say how the picture looks; a sentence using one is a sentence about the picture.
#: (Words of viewpoint, "the side you see", say nothing about the picture; "white light" is a colour, a
#: "white metal" a material and the "white furnace" a test of the model.)
SEEING_WORDS = re.compile(
    r"\b(black|white(?! (?:lights?|metals?|furnace)\b)|dark|darker|darkest|bright|brighter|brightest|dim|dimmer|flattens|glows?|"
    r"gives back|catch(?:es)? up|clipped|washes out|fades?|pitch)\b",
    re.IGNORECASE)


def seeing_word(says: str) -> str | None:
    """The first word of ``says`` that speaks of what the student sees, or None."""
    match = SEEING_WORDS.search(says)
    return match.group(0) if match else None


def replaced_check(check: str, replace: tuple[str, str]) -> str:
    """``check`` with every occurrence of ``replace[0]`` replaced by ``replace[1]``."""
    return check.replace(replace[0], replace[1])
