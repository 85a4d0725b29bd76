"""The defaults of analysis' settings (``Thresholds``, ``Tolerances``), read from their source rather than
imported: the options that show them are declared when a command's module loads, and ``tfx COMMAND --help``
loads no numpy. (tests/cli/test_help.py checks that they are the classes' own.)"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parents[1]


@cache
def defaults(module: str, name: str) -> dict[str, float]:
    """The number each field of the dataclass ``name`` in ``module`` (a path below tftools, e.g.
    ``analysis/expected.py``) defaults to."""
    tree = ast.parse((_PACKAGE / module).read_text(encoding="utf-8"))
    found = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == name)
    return {
        field.target.id: float(ast.literal_eval(field.value))
        for field in found.body
        if isinstance(field, ast.AnnAssign) and isinstance(field.target, ast.Name) and field.value is not None
    }


def thresholds() -> dict[str, float]:
    """``tftools.analysis.wtf.Thresholds()``'s values."""
    return defaults("analysis/wtf/thresholds.py", "Thresholds")


def tolerances() -> dict[str, float]:
    """``tftools.analysis.expected.Tolerances()``'s values."""
    return defaults("analysis/expected.py", "Tolerances")
