"""``tfx echo TARGET SOURCE``: the transform between two frames over time, like tf_echo."""

from __future__ import annotations

import dataclasses
import enum
import io
from typing import Annotated

import numpy as np
import typer

from tftools.analysis.echo import EchoSeries, chain_span, echo, sample_times, ticks
from tftools.cli import live
from tftools.cli.arguments import echo_line_count, parse_time, positive_seconds, rate_hz
from tftools.cli.common import (
    BagOption,
    EndOption,
    Exit,
    StartOption,
    Tf2Option,
    TopicOption,
    UsageError,
    exit_with,
    frame_argument,
    open_recording,
    stdout,
)
from tftools.core.arrays import Int64Array
from tftools.core.buffer import Buffer
from tftools.core.semantics import Semantics
from tftools.render import echo as render
from tftools.render.escape import printable
from tftools.sources import Recording
from tftools.sources.live.base import LiveSource
from tftools.sources.live.capture import listen
from tftools.sources.replay import follow_into, replay_of


class EchoFormat(str, enum.Enum):
    text = "text"
    json = "json"
    csv = "csv"


def command(
    target: Annotated[
        str, typer.Argument(help="The frame to express the transform in (tf_echo's first frame), e.g. map.")
    ],
    source: Annotated[str, typer.Argument(help="The frame whose pose is shown, e.g. base_link.")],
    bags: BagOption = None,
    rate: Annotated[
        float, typer.Option("--rate", "-r", help="Lines per second of bag time (a million lines at most).")
    ] = 1.0,
    at: Annotated[
        str | None,
        typer.Option(
            help="One lookup at TIME: absolute seconds, +S after the start, -S before the end, 0 = latest.",
            show_default=False,
        ),
    ] = None,
    every: Annotated[bool, typer.Option("--all", help="A line at every sample of the chain's moving edges.")] = False,
    start: StartOption = None,
    end: EndOption = None,
    precision: Annotated[int, typer.Option(min=1, max=12, help="Decimals in text output.")] = 3,
    matrix: Annotated[bool, typer.Option(help="Also print the 4x4 homogeneous matrix.")] = False,
    fmt: Annotated[
        EchoFormat, typer.Option("--format", "-f", help="text (tf_echo's), json (one object per line) or csv.")
    ] = EchoFormat.text,
    topics: TopicOption = None,
    tf2: Tf2Option = None,
    play: Annotated[
        bool, typer.Option("--play", help="Replay the bag in real time; the latest transform --rate times a second.")
    ] = False,
    count: Annotated[
        int | None, typer.Option("--count", "-n", min=1, help="Live: stop after N lines.", show_default=False)
    ] = None,
    wait: Annotated[
        float | None,
        typer.Option(help="Live: give up if the transform is not there within WAIT seconds.", show_default=False),
    ] = None,
    ros1: live.RosOption = None,
    use_sim_time: live.UseSimTimeOption = None,
    cache: live.CacheOption = 10.0,
) -> None:
    """Print the transform from SOURCE to TARGET, as tf_echo does: [bold]where SOURCE is in TARGET[/].

    On a bag, it steps through bag time at --rate Hz over the stretch where every moving
    edge between the frames has data (or --start/--end), interpolating as tf2 does; a lookup
    that fails prints tf2's reason and echo goes on. Exit code 1 if any lookup failed.

    Example: [cyan]tfx echo map base_link -b robot.bag --all --format csv > pose.csv[/]
    """
    rate = rate_hz(rate)
    if wait is not None:
        wait = positive_seconds(wait, "--wait", "10")
    cache = positive_seconds(cache, "--cache", "10")
    if at is not None and every:
        raise UsageError("--at and --all do not go together", "use one of them")
    if not bags:
        live.no_bag_options(**{"--at": at, "--all": every, "--start": start, "--end": end, "--play": play})
        feed = live.open_source(ros1, use_sim_time, topics)
        exit_with(_live(feed, target, source, rate, count, wait, cache, tf2, fmt, precision, matrix))
    recording = open_recording(bags, topics, tf2)
    target = frame_argument(recording.buffer, target)
    source = frame_argument(recording.buffer, source)
    if play:
        exit_with(_play(recording, target, source, rate, start, end, fmt, precision, matrix))
    times = _times(recording, target, source, rate, at, every, start, end)
    series = echo(recording.buffer, target, source, times)
    _write(series, fmt, precision, matrix)
    exit_with(Exit.OK if series.valid.all() else Exit.PROBLEMS)


def _write(series: EchoSeries, fmt: EchoFormat, precision: int, matrix: bool, header: bool = True) -> None:
    if fmt is EchoFormat.json:
        render.write_json(series, stdout.file)
    elif fmt is EchoFormat.csv:
        text = io.StringIO()
        render.write_csv(series, text)
        stdout.file.write(text.getvalue() if header else text.getvalue().split("\n", 1)[1])
    else:
        render.write_text(series, stdout.file, precision, matrix)
    stdout.file.flush()


def _play(
    recording: Recording,
    target: str,
    source: str,
    rate: float,
    start: str | None,
    end: str | None,
    fmt: EchoFormat,
    precision: int,
    matrix: bool,
) -> Exit:
    """--play: the bag replayed on a sim clock into a tf2-sized buffer, as tf_echo sees a live
    system: the latest transform, ``rate`` times a second of wall (= bag) time."""
    first = parse_time(start, recording, "--start") if start is not None else None
    last = parse_time(end, recording, "--end") if end is not None else None
    if first is not None and last is not None and last < first:
        raise UsageError("the time range is empty", "--start must come before --end")
    replay = replay_of(recording, start=first, end=last)
    buffer = Buffer(clock=replay.clock, semantics=recording.buffer.semantics)
    failed: list[bool] = []

    def tick() -> None:
        series = echo(buffer, target, source, [0])
        failed.append(not series.valid.all())
        _write(series, fmt, precision, matrix, header=len(failed) == 1)

    follow_into(replay, buffer, tick, period=1.0 / rate)
    return Exit.PROBLEMS if any(failed) else Exit.OK


def _live(
    feed: LiveSource,
    target: str,
    source: str,
    rate: float,
    count: int | None,
    wait: float | None,
    cache: float,
    semantics: Semantics | None,
    fmt: EchoFormat,
    precision: int,
    matrix: bool,
) -> Exit:
    """Without -b, as tf_echo: wait for the transform, then the latest one ``rate`` times a second
    (``count`` times, or until Ctrl-C); a failure prints tf2's reason and the frames known."""
    target, source = target.removeprefix("/"), source.removeprefix("/")
    cache_ns = live.cache_time(cache)
    failed: list[bool] = []
    with feed:
        buffer = listen(feed, cache_ns, semantics)
        live.wait_for_transform(buffer, target, source, feed.describe(), wait)

        def tick() -> None:
            with buffer.lock:
                series = dataclasses.replace(echo(buffer, target, source, [0]), times=np.array([buffer.now()]))
                frames = buffer.all_frames_as_string()
            failed.append(not series.valid.all())
            _write(series, fmt, precision, matrix, header=len(failed) == 1)
            if failed[-1] and fmt is EchoFormat.text:  # tf_echo lists the frames after a failure
                listed = "".join(printable(line) + "\n" for line in frames.removesuffix("\n").split("\n"))
                stdout.file.write(f"The current list of frames is:\n{listed}")
                stdout.file.flush()

        live.every(rate, count, lambda: feed.finished, tick, feed.clock)
    return Exit.PROBLEMS if any(failed) else Exit.OK


def _times(
    recording: Recording,
    target: str,
    source: str,
    rate: float,
    at: str | None,
    every: bool,
    start: str | None,
    end: str | None,
) -> Int64Array:
    if at is not None:
        return np.array([0 if at.strip() == "0" else parse_time(at, recording, "--at")], np.int64)
    span = chain_span(recording.buffer, target, source) or (recording.timeline.tf_start, recording.timeline.tf_end)
    first = parse_time(start, recording, "--start") if start is not None else span[0]
    last = parse_time(end, recording, "--end") if end is not None else span[1]
    if last < first:
        raise UsageError("the time range is empty", "--start must come before --end")
    if every:
        return sample_times(recording.buffer, target, source, first, last)
    echo_line_count(first, last, rate)
    return ticks(first, last, rate)
