"""Packages whose names load on first use (PEP 562): ``import tftools.core`` costs nothing until a name of it is
asked for, so that a light module of a package (``tftools.core.time``) does not bring numpy along."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any


def exports(
    package: str, homes: Mapping[str, str], names: Sequence[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package``, whose ``names`` each come from the module ``homes`` says
    (imported then, once)."""
    namespace = sys.modules[package].__dict__

    def attribute(name: str) -> Any:
        if name not in homes:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(homes[name]), name)
        namespace[name] = value  # looked up once
        return value

    def listing() -> list[str]:
        return sorted([*namespace, *names])

    return attribute, listing
