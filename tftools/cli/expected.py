"""The expected tree on the command line: its tolerance options, reading it, writing it (``wtf --init``, ``diff``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from tftools.cli import defaults
from tftools.cli.common import stdout, warn
from tftools.cli.errors import UsageError
from tftools.cli.reading import open_recording
from tftools.core.semantics import Semantics
from tftools.sources.user_files import MAX_ITEMS

if TYPE_CHECKING:
    from tftools.analysis.expected import Tolerances, TreeShape

_DEFAULTS = defaults.tolerances()
#: The frames of a tree file ``--init`` writes at most: each a line of 8 to 10 of the lines and items
#: that YAML is parsed within (``user_files.MAX_ITEMS``), so that ``--expect`` reads it back (writing
#: 100,000 frames took ruamel 169 s, for a file no reader would take).
MAX_INIT_FRAMES = MAX_ITEMS // 10


def _tolerance(option: str, beyond: str, default: float) -> Any:
    return typer.Option(option, help=f"{beyond} differs (default: the tree file's, else {default:g}).")


ToleranceMmOption = Annotated[
    float | None,
    _tolerance("--tolerance-mm", "A static edge that moved more than this many mm", _DEFAULTS["translation_mm"]),
]
ToleranceDegOption = Annotated[
    float | None,
    _tolerance("--tolerance-deg", "A static edge that turned more than this many degrees", _DEFAULTS["rotation_deg"]),
]
ToleranceRateOption = Annotated[
    float | None,
    _tolerance(
        "--tolerance-rate", "A rate more than this many percent below the other tree's", _DEFAULTS["rate_percent"]
    ),
]


def tolerances(base: Tolerances, mm: float | None, deg: float | None, rate: float | None) -> Tolerances:
    """``base`` with the tolerances given on the command line instead."""
    from tftools.analysis.diff import overridden

    try:
        return overridden(base, mm, deg, rate)
    except ValueError as error:
        raise UsageError(str(error), "e.g. --tolerance-mm 2 --tolerance-deg 0.5 --tolerance-rate 25") from None


def read_expected(path: Path, mm: float | None, deg: float | None, rate: float | None) -> TreeShape:
    """The tree file at ``path``, its tolerances overridden by those given."""
    from tftools.analysis.tree_file import read_tree

    tree = read_tree(path)
    return dataclasses.replace(tree, tolerances=tolerances(tree.tolerances, mm, deg, rate))


def write_init(bags: Sequence[str], topics: Sequence[str] | None, semantics: Semantics | None) -> None:
    """``tfx wtf --init``: the tree of the bags (one recording) as a tree file, on stdout."""
    if not bags:
        raise UsageError("--init needs a recording", "e.g. tfx wtf --init good_run.bag > tree.yaml")
    from tftools.analysis.diff import recorded_shape
    from tftools.analysis.tree_file import write_tree

    shape = recorded_shape(lambda: open_recording(bags, topics, semantics), " + ".join(bags))
    if shape.empty:  # a tree of no frame: what the recording holds, as tfx diff compares it
        warn(f"{shape.source}: {shape.empty}: the tree file has no frames")
    if len(shape.frames) > MAX_INIT_FRAMES:
        raise UsageError(
            f"--init: the recording has {len(shape.frames):,} frames, more than the {MAX_INIT_FRAMES:,} of a tree"
            " file that --expect reads back",
            "compare such recordings with each other: tfx diff good.bag new.bag",
        )
    write_tree(shape, stdout.file)
