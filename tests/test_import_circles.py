"""No import circles among tftools' modules: every ``from tftools... import`` anywhere in a module (at its
top, under ``TYPE_CHECKING`` or inside a function) is an edge, and the graph has no cycle but those listed."""

from __future__ import annotations

import ast
from pathlib import Path

from tftools.analysis.wtf.loops import _tangles

PACKAGE = Path(__file__).resolve().parents[1] / "tftools"

#: Circles still to be undone, each as its modules.
KNOWN: list[set[str]] = []


def modules() -> dict[str, Path]:
    found = {}
    for path in PACKAGE.rglob("*.py"):
        name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        found[name.removesuffix(".__init__")] = path
    return found


def imports() -> dict[str, set[str]]:
    """Each module's tftools modules it imports (a name imported from a package counts as the module of
    that name when there is one, else as the package)."""
    known = modules()
    edges: dict[str, set[str]] = {name: set() for name in known}
    for name, path in known.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("tftools"):
                for alias in node.names:
                    full = f"{node.module}.{alias.name}"
                    edges[name].add(full if full in known else node.module)
            elif isinstance(node, ast.Import):
                edges[name].update(a.name for a in node.names if a.name in known)
    return edges


def circles(edges: dict[str, set[str]]) -> list[set[str]]:
    """The groups of modules that import each other (the strongly connected sets of ``find_loops``)."""
    return _tangles({name: sorted(imported) for name, imported in edges.items()})


def test_circles_are_found() -> None:
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [{"a", "b", "c"}]


def test_no_module_imports_itself_back() -> None:
    assert [c for c in circles(imports()) if c not in KNOWN] == []
