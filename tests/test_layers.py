"""The import rule of DESIGN.md, checked on every module of the package.

The layers, foundation first: core → teaching → scene → render → accuracy →
app → bench → cli. A module may import its own layer or one before it in
that list, never a later one, and no two files may import each other, directly
or through others. Every import counts: top level, inside functions, inside
``if TYPE_CHECKING`` blocks. The package root ``phonglab/__init__.py`` is a
facade for users (``import phonglab as pl``); modules of the package import
the layer they need, never the root.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

LAYERS = ("core", "teaching", "scene", "render", "accuracy", "app", "bench", "cli")
PACKAGE_DIR = Path(__file__).resolve().parents[1] / "phonglab"


@dataclass(frozen=True)
class Import:
    source: str  # importing module, dotted
    target: str  # imported module, dotted (the nearest module that exists)
    file: str
    line: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}: {self.source} imports {self.target}"


def modules(package_dir: Path) -> dict[str, Path]:
    """Dotted module name -> file, for every ``.py`` file under ``package_dir``."""
    found = {}
    for path in sorted(package_dir.rglob("*.py")):
        parts = list(path.relative_to(package_dir.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def _nearest(name: str, known) -> str | None:
    while name not in known and "." in name:
        name = name.rsplit(".", 1)[0]
    return name if name in known else None


def imports(package_dir: Path) -> list[Import]:
    """Every import of a module of the package by another, wherever it is written."""
    known = modules(package_dir)
    root = package_dir.name
    found = []
    for name, path in known.items():
        is_package = path.name == "__init__.py"
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        shown = str(path.relative_to(package_dir.parent))
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = name.split(".") if is_package else name.split(".")[:-1]
                    base = base[: len(base) - (node.level - 1)]
                    prefix = ".".join(base + ([node.module] if node.module else []))
                else:
                    prefix = node.module or ""
                # `from pkg import module` imports the module, `from module import name` the module
                targets = [f"{prefix}.{alias.name}" if f"{prefix}.{alias.name}" in known else prefix
                           for alias in node.names]
            else:
                continue
            for target in targets:
                if target != root and not target.startswith(root + "."):
                    continue
                target = _nearest(target, known)
                if target is not None and target != name:
                    found.append(Import(name, target, shown, node.lineno))
    return found


def layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def upward(found: list[Import]) -> list[Import]:
    """Imports of a later layer, or of the package root, from inside the package."""
    bad = []
    for imp in found:
        source, target = layer(imp.source), layer(imp.target)
        if source is None:  # the root facade may import any layer
            continue
        if target is None or source not in LAYERS or target not in LAYERS:
            bad.append(imp)
        elif LAYERS.index(target) > LAYERS.index(source):
            bad.append(imp)
    return bad


def circles(found: list[Import]) -> list[list[str]]:
    """Groups of modules that import each other, directly or through others (Tarjan)."""
    graph: dict[str, set[str]] = {}
    for imp in found:
        graph.setdefault(imp.source, set()).add(imp.target)
        graph.setdefault(imp.target, set())
    index, low, on_stack, stack, groups = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return groups


def _edges_within(found, group):
    members = set(group)
    return [str(imp) for imp in found if imp.source in members and imp.target in members]


# ---------------------------------------------------------------------------
# the package


def test_every_layer_is_known():
    layers = {layer(m) for m in modules(PACKAGE_DIR)} - {None}
    assert layers <= set(LAYERS), f"modules outside the layers {LAYERS}: {sorted(layers - set(LAYERS))}"


def test_no_module_imports_a_later_layer():
    bad = upward(imports(PACKAGE_DIR))
    assert not bad, "imports against the layer order " + " → ".join(LAYERS) + ":\n" + "\n".join(map(str, bad))


def test_no_import_circles():
    found = imports(PACKAGE_DIR)
    groups = circles(found)
    report = "\n\n".join("circle: " + ", ".join(g) + "\n  " + "\n  ".join(_edges_within(found, g)) for g in groups)
    assert not groups, report


@pytest.mark.parametrize("path", sorted(PACKAGE_DIR.rglob("*.py")), ids=lambda p: str(p.relative_to(PACKAGE_DIR)))
def test_no_module_is_longer_than_700_lines(path):
    lines = len(path.read_text(encoding="utf-8").splitlines())
    assert lines <= 700, f"{path.relative_to(PACKAGE_DIR.parent)} has {lines} lines: split it by job"


# ---------------------------------------------------------------------------
# the checker finds what it must


def _write(root: Path, files: dict[str, str]) -> Path:
    package = root / "pkg"
    for name, text in files.items():
        path = package / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return package


def test_checker_finds_an_upward_import_inside_a_function(tmp_path):
    package = _write(tmp_path, {
        "__init__.py": "",
        "core/__init__.py": "",
        "core/a.py": "def f():\n    from pkg.render import b\n",
        "render/__init__.py": "",
        "render/b.py": "from pkg.core import a\n",
    })
    bad = upward(imports(package))
    assert [(i.source, i.target, i.line) for i in bad] == [("pkg.core.a", "pkg.render.b", 2)], bad


def test_checker_finds_a_circle_through_three_files_and_relative_imports(tmp_path):
    package = _write(tmp_path, {
        "__init__.py": "",
        "scene/__init__.py": "",
        "scene/a.py": "from .b import x\n",
        "scene/b.py": "from pkg.scene import c\n",
        "scene/c.py": "def g():\n    from . import a\n",
    })
    assert circles(imports(package)) == [["pkg.scene.a", "pkg.scene.b", "pkg.scene.c"]]


def test_checker_finds_a_circle_through_the_package_init(tmp_path):
    package = _write(tmp_path, {
        "__init__.py": "",
        "scene/__init__.py": "from pkg.scene.a import x\n",
        "scene/a.py": "from pkg.scene import y\n",
    })
    assert circles(imports(package)) == [["pkg.scene", "pkg.scene.a"]]


def test_checker_refuses_the_root_facade_from_inside(tmp_path):
    package = _write(tmp_path, {
        "__init__.py": "from pkg.core import a\n",
        "core/__init__.py": "",
        "core/a.py": "",
        "bench/__init__.py": "",
        "bench/b.py": "import pkg as pl\n",
    })
    assert [(i.source, i.target) for i in upward(imports(package))] == [("pkg.bench.b", "pkg")]
