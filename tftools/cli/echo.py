"""``tfx echo TARGET SOURCE``: the transform between two frames over time, like tf_echo."""

from __future__ import annotations

import enum
from typing import Annotated

import numpy as np
import numpy.typing as npt
import typer

from tftools.analysis.echo import chain_span, echo, sample_times, ticks
from tftools.cli.common import (
    BagOption,
    EndOption,
    Exit,
    StartOption,
    TopicOption,
    UsageError,
    exit_with,
    frame_argument,
    open_recording,
    parse_time,
    stdout,
)
from tftools.render import echo as render
from tftools.sources import Recording


class EchoFormat(str, enum.Enum):
    text = "text"
    json = "json"
    csv = "csv"


def command(
    target: Annotated[str, typer.Argument(help="The frame to express the transform in (tf_echo's first frame), e.g. map.")],
    source: Annotated[str, typer.Argument(help="The frame whose pose is shown, e.g. base_link.")],
    bags: BagOption = None,
    rate: Annotated[float, typer.Option("--rate", "-r", help="Lines per second of bag time.")] = 1.0,
    at: Annotated[
        str | None,
        typer.Option(help="One lookup at TIME: absolute seconds, +S after the start, -S before the end, 0 = latest.", show_default=False),
    ] = None,
    every: Annotated[bool, typer.Option("--all", help="A line at every sample of the chain's moving edges.")] = False,
    start: StartOption = None,
    end: EndOption = None,
    precision: Annotated[int, typer.Option(min=1, max=12, help="Decimals in text output.")] = 3,
    matrix: Annotated[bool, typer.Option(help="Also print the 4x4 homogeneous matrix.")] = False,
    fmt: Annotated[EchoFormat, typer.Option("--format", "-f", help="text (tf_echo's), json (one object per line) or csv.")] = EchoFormat.text,
    topics: TopicOption = None,
) -> None:
    """Print the transform from SOURCE to TARGET, as tf_echo does: [bold]where SOURCE is in TARGET[/].

    On a bag, it steps through bag time at --rate Hz over the stretch where every moving
    edge between the frames has data (or --start/--end), interpolating as tf2 does; a lookup
    that fails prints tf2's reason and echo goes on. Exit code 1 if any lookup failed.

    Example: [cyan]tfx echo map base_link -b robot.bag --all --format csv > pose.csv[/]
    """
    if rate <= 0:
        raise UsageError("--rate must be above 0", "e.g. --rate 10")
    if at is not None and every:
        raise UsageError("--at and --all do not go together", "use one of them")
    recording = open_recording(bags, topics)
    target = frame_argument(recording.buffer, target)
    source = frame_argument(recording.buffer, source)
    times = _times(recording, target, source, rate, at, every, start, end)
    series = echo(recording.buffer, target, source, times)
    if fmt is EchoFormat.json:
        render.write_json(series, stdout.file)
    elif fmt is EchoFormat.csv:
        render.write_csv(series, stdout.file)
    else:
        render.write_text(series, stdout.file, precision, matrix)
    exit_with(Exit.OK if series.valid.all() else Exit.PROBLEMS)


def _times(
    recording: Recording,
    target: str,
    source: str,
    rate: float,
    at: str | None,
    every: bool,
    start: str | None,
    end: str | None,
) -> npt.NDArray[np.int64]:
    if at is not None:
        return np.array([0 if at.strip() == "0" else parse_time(at, recording)], np.int64)
    span = chain_span(recording.buffer, target, source) or (recording.start, recording.end)
    first = parse_time(start, recording) if start is not None else span[0]
    last = parse_time(end, recording) if end is not None else span[1]
    if last < first:
        raise UsageError("the time range is empty", "--start must come before --end")
    if every:
        return sample_times(recording.buffer, target, source, first, last)
    return ticks(first, last, rate)
