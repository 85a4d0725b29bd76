"""``--mcap FILE`` of ``tfx wtf`` and ``tfx report``: a recording's findings written beside it, for Foxglove."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import live
from tftools.cli.errors import UsageError
from tftools.cli.outputs import check_output, check_replaceable

if TYPE_CHECKING:
    from tftools.analysis.wtf.fleet import BagReport
    from tftools.analysis.wtf.query import CheckQuery

McapOption = Annotated[
    Path | None,
    typer.Option(
        help="Also write the findings to this MCAP file, to open beside the recording in Foxglove (as "
        "foxglove.Log, /diagnostics and foxglove.FrameTransforms; needs pip install 'tftools\\[foxglove]').",
    ),
]


def one_recording(groups: Sequence[Sequence[str]]) -> Sequence[str]:
    """The one recording ``--mcap`` writes the findings of (a ``UsageError`` for none or several)."""
    if len(groups) != 1:
        raise UsageError("--mcap writes the findings of one recording", "give one bag (or its parts with -b)")
    return groups[0]


def check_into_mcap(paths: Sequence[str], query: CheckQuery, mcap: Path, force: bool) -> BagReport:
    """Check the recording ``paths`` and write its findings to ``mcap``, said on stderr (refused before any
    reading if ``mcap`` may not be written)."""
    from tftools.sinks.findings_mcap import check_into_mcap as check

    report, written = check(paths, mcap, query, force=force)
    if report.usable:
        live.say(f"wrote {written} messages to {mcap}")
    return report


def refuse(mcap: Path, inputs: Sequence[str], force: bool) -> None:
    """Before any reading: a ``UsageError`` if ``mcap`` is an input, inside or above one, or exists (without
    ``force``, or not a regular file), as every output (``outputs``)."""
    from tftools.sinks.findings_mcap import refuse_output

    check_output(mcap, inputs, option="--mcap", file_name="findings.mcap")
    check_replaceable(mcap, force, "--mcap")
    refuse_output(mcap, inputs, force)
