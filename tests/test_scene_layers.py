"""The scene package's modules import one way, in the order its docstring gives."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import phonglab.scene

SCENE_DIR = Path(phonglab.scene.__file__).parent
#: bottom first: a module may import only modules listed before it (toml_lines stands alone)
ORDER = ["errors", "schema", "toml_lines", "claims", "checks", "meshsize", "paths", "limits", "objects", "parts",
         "build", "check", "fieldpath", "editing", "model", "loader", "lessons", "shadowplan", "planner"]


def scene_imports(path: Path) -> set[str]:
    """The phonglab.scene modules a file imports anywhere (inside functions too); "" for the package itself."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module] + [f"{node.module}.{alias.name}" for alias in node.names]
            if node.module == "phonglab":
                names = [f"phonglab.{alias.name}" for alias in node.names]
        for name in names:
            if name == "phonglab.scene":
                found.add("")
            elif name.startswith("phonglab.scene.") and name.split(".")[2] in ORDER:
                found.add(name.split(".")[2])
    return found


def test_every_scene_module_has_a_place_in_the_order():
    modules = {p.stem for p in SCENE_DIR.glob("*.py")} - {"__init__"}
    assert modules == set(ORDER), f"add new modules to ORDER: {sorted(modules ^ set(ORDER))}"


@pytest.mark.parametrize("name", ORDER)
def test_scene_module_imports_only_modules_below_it(name):
    imported = scene_imports(SCENE_DIR / f"{name}.py")
    assert "" not in imported, f"{name} imports the package phonglab.scene: import the sibling module instead"
    above = sorted(m for m in imported if ORDER.index(m) >= ORDER.index(name))
    assert not above, f"phonglab.scene.{name} imports {above}, which are not below it in {ORDER}"
