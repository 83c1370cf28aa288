"""No lighting physics above the core and the teaching layer: the layers above read the record.

DESIGN.md: every piece of physics exists once, in ``phonglab.core`` (the
teaching layer's mistakes are the core's kernel with one step swapped).
The scene, render, accuracy, app, bench and cli layers format what the core
computed (its record of the sum, :mod:`phonglab.core.record`); they never
clamp a cosine (``max(0, n·l)``) or take a dot product of the model's
vectors (``n·l``, ``r·v``, ``n·h``) themselves. This test parses every module
of those layers and finds both:

- a clamp: ``max``/``maximum``/``fmax``/``clip`` with a literal 0 and an
  operand that names a cosine (``nl``, ``rv``, ``nh``, ``cos``, ...) or holds
  a dot product;
- a dot product of two of the model's vectors: ``a @ b``, ``dot(a, b)``
  (``np.dot``, ``np.vdot``, ``np.inner``, ``dot_c``) or ``sum(a * b)`` where
  both ``a`` and ``b`` name one of ``n, l, r, v, h`` (or ``normal``,
  ``to_light``, ``to_eye``), as a variable or an attribute (``vec.l``).

A few modules are exempt, by design (:data:`EXEMPT`): the independent
50-digit mpmath evaluation the core is measured against and the two
textbook baselines the benchmarks time the core and the page against.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "phonglab"
ABOVE = ("scene", "render", "accuracy", "app", "bench", "cli")
#: module -> why it may compute the model itself
EXEMPT = {
    "accuracy/precision.py": "the independent mpmath reference the core is measured against",
    "bench/core.py": "naive_phong, the textbook NumPy Phong the fast kernel's speed is compared with",
    "bench/ui_baseline.py": "the plain trame app (its own textbook Phong) the page's speed is compared with",
}
#: names of the model's vectors
VECTORS = {"n", "l", "r", "v", "h", "normal", "to_light", "to_eye"}
#: words that name one of the model's cosines, alone or as part of a name (``specular_cos``)
COSINES = {"nl", "rv", "nh", "nv", "cos", "cosine", "cosines"}
CLAMPS = {"max", "maximum", "fmax", "clip"}
DOTS = {"dot", "vdot", "inner", "dot_c"}
SUMS = {"sum", "einsum"}


def _name(node) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def _is_vector(node) -> bool:
    return _name(node) in VECTORS


def _is_dot(node) -> bool:
    """A dot product of two of the model's vectors."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.MatMult):
        return _is_vector(node.left) and _is_vector(node.right)
    if isinstance(node, ast.Call):
        name = _name(node.func)
        if name in DOTS and len(node.args) >= 2:
            return _is_vector(node.args[0]) and _is_vector(node.args[1])
        if name == "einsum":
            operands = node.args[1:]
            return len(operands) >= 2 and _is_vector(operands[0]) and _is_vector(operands[1])
        if name == "sum":
            # np.sum(a * b, ...) or (a * b).sum(...)
            on = node.func.value if isinstance(node.func, ast.Attribute) else None
            target = on if isinstance(on, ast.BinOp) else (node.args[0] if node.args else None)
            return (isinstance(target, ast.BinOp) and isinstance(target.op, ast.Mult)
                    and _is_vector(target.left) and _is_vector(target.right))
    return False


def _is_cosine(node) -> bool:
    name = _name(node)
    return name is not None and any(part in COSINES for part in name.lower().split("_"))


def _mentions_cosine(node) -> bool:
    return any(_is_cosine(x) or _is_dot(x) for x in ast.walk(node))


def _is_zero(node) -> bool:
    return isinstance(node, ast.Constant) and not isinstance(node.value, bool) and node.value == 0


def _is_clamp(node) -> bool:
    if not (isinstance(node, ast.Call) and _name(node.func) in CLAMPS):
        return False
    args = list(node.args) + [k.value for k in node.keywords]
    return any(_is_zero(a) for a in args) and any(_mentions_cosine(a) for a in args if not _is_zero(a))


def physics(source: str, filename: str = "<module>") -> list[str]:
    """``line: code`` for every clamp of a cosine and every dot product of the model's vectors."""
    found = []
    for node in ast.walk(ast.parse(source, filename=filename)):
        if _is_clamp(node) or _is_dot(node):
            found.append(f"{filename}:{node.lineno}: {ast.unparse(node)}")
    return found


def modules():
    for layer in ABOVE:
        for path in sorted((PACKAGE / layer).rglob("*.py")):
            yield str(path.relative_to(PACKAGE))


@pytest.mark.parametrize("module", list(modules()))
def test_no_lighting_physics_above_core_and_teaching(module):
    if module in EXEMPT:
        pytest.skip(EXEMPT[module])
    found = physics((PACKAGE / module).read_text(encoding="utf-8"), module)
    assert not found, ("lighting physics outside the core (read it from the core's record, "
                       "phonglab.scene.trace, instead):\n" + "\n".join(found))


@pytest.mark.parametrize("code", [
    "w = max(0.0, vectors.nl)",
    "w = np.maximum(0, cos)",
    "w = np.clip(n @ l, 0, 1)",
    "c = l @ n",
    "c = np.dot(vec.r, vec.v)",
    "c = np.sum(n * h, axis=-1)",
    "c = (r * v).sum(-1)",
    "t = max(0.0, specular_cos) ** alpha",
    "c = np.einsum('ij,ij->i', n, l)",
])
def test_the_check_finds_the_physics_it_forbids(code):
    assert physics(code), code


@pytest.mark.parametrize("code", [
    "depth = max(0, depth - 1)",
    "c = u @ x_axis",
    "towards = up - (up @ v) * v",
    "angle = math.acos(max(-1.0, min(1.0, vec.nl)))",
    "w = record.light(1)['diffuse weight']",
    "ms = max(0.0, cost_ms - 1)",
])
def test_the_check_lets_other_arithmetic_be(code):
    assert not physics(code), code
