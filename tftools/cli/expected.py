"""The expected tree on the command line: its tolerance options, reading it, writing it (``wtf --init``, ``diff``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated

import typer

from tftools.analysis.expected import Tolerances, TreeShape, shape_of
from tftools.analysis.tree_file import read_tree, write_tree
from tftools.cli.common import UsageError, open_recording, stdout
from tftools.core.semantics import Semantics

_DEFAULTS = Tolerances()

ToleranceMmOption = Annotated[
    float | None,
    typer.Option(
        "--tolerance-mm",
        help=f"A static edge that moved more than this many mm differs (default: the tree file's, else "
        f"{_DEFAULTS.translation_mm:g}).",
    ),
]
ToleranceDegOption = Annotated[
    float | None,
    typer.Option(
        "--tolerance-deg",
        help=f"A static edge that turned more than this many degrees differs (default: the tree file's, else "
        f"{_DEFAULTS.rotation_deg:g}).",
    ),
]
ToleranceRateOption = Annotated[
    float | None,
    typer.Option(
        "--tolerance-rate",
        help=f"A rate that changed more than this many percent differs (default: the tree file's, else "
        f"{_DEFAULTS.rate_percent:g}).",
    ),
]


def tolerances(base: Tolerances, mm: float | None, deg: float | None, rate: float | None) -> Tolerances:
    """``base`` with the tolerances given on the command line instead."""
    given = {"translation_mm": mm, "rotation_deg": deg, "rate_percent": rate}
    try:
        return dataclasses.replace(base, **{k: v for k, v in given.items() if v is not None})
    except ValueError as error:
        raise UsageError(str(error), "e.g. --tolerance-mm 2 --tolerance-deg 0.5 --tolerance-rate 25") from None


def read_expected(path: Path, mm: float | None, deg: float | None, rate: float | None) -> TreeShape:
    """The tree file at ``path``, its tolerances overridden by those given."""
    tree = read_tree(path)
    return dataclasses.replace(tree, tolerances=tolerances(tree.tolerances, mm, deg, rate))


def write_init(bags: Sequence[str], topics: Sequence[str] | None, semantics: Semantics | None) -> None:
    """``tfx wtf --init``: the tree of the bags (one recording) as a tree file, on stdout."""
    if not bags:
        raise UsageError("--init needs a recording", "e.g. tfx wtf --init good_run.bag > tree.yaml")
    write_tree(shape_of(open_recording(bags, topics, semantics)), stdout.file)
