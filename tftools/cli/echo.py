"""``tfx echo TARGET SOURCE``: the transform between two frames over time, like tf_echo."""

from __future__ import annotations

import enum
import io
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import IO, TYPE_CHECKING, Annotated

import typer

from tftools.cli import live, options
from tftools.cli.arguments import positive_seconds, rate_hz
from tftools.cli.common import Exit, exit_with, frame_arguments, say_hint, slash_dropped, stdout
from tftools.cli.errors import UsageError
from tftools.cli.plots import PLOT_FILE, check_plot, write_plot
from tftools.cli.reading import open_recording, open_stream
from tftools.core.frames import frame_name
from tftools.core.semantics import Semantics
from tftools.core.time import from_sec
from tftools.render.escape import printable_lines

if TYPE_CHECKING:  # the lookups and their renderers load when a command runs: --help needs none of them (nor numpy)
    from tftools.analysis.echo import EchoQuery, EchoSeries
    from tftools.core.buffer import Buffer
    from tftools.sources.live.base import LiveSource
    from tftools.sources.recording import Recording


class EchoFormat(str, enum.Enum):
    text = "text"
    json = "json"
    csv = "csv"
    static = "static"
    urdf = "urdf"
    yaml = "yaml"


#: Formats to paste elsewhere: one lookup, the latest, unless --at or --all says otherwise.
PASTE_FORMATS = frozenset({EchoFormat.static, EchoFormat.urdf, EchoFormat.yaml})


def _paste(fmt: EchoFormat, ros2: bool) -> Callable[[EchoSeries, IO[str]], None]:
    """The writer of a format of ``PASTE_FORMATS``; static's command lines are ROS 2's if ``ros2``, else ROS 1's."""
    from tftools.render import echo as render

    if fmt is EchoFormat.static:
        return lambda series, out: render.write_static(series, out, ros2)
    return render.write_urdf if fmt is EchoFormat.urdf else render.write_yaml


def command(
    target: Annotated[
        str, typer.Argument(help="The frame to express the transform in (tf_echo's first frame), e.g. map.")
    ],
    source: Annotated[str, typer.Argument(help="The frame whose pose is shown, e.g. base_link.")],
    echo_rate: Annotated[
        float | None,
        typer.Argument(
            metavar="RATE", help="Lines a second, as tf_echo's echo_rate after the frames: the same as --rate."
        ),
    ] = None,
    bags: options.Bags = None,
    rate: Annotated[
        float | None,
        typer.Option("--rate", "-r", help="Lines a second of bag time (at most a million lines; default 1)."),
    ] = None,
    at: Annotated[
        str | None,
        typer.Option(
            help="One lookup at TIME: absolute seconds, +S after the start, -S before the end, 0 = latest.",
        ),
    ] = None,
    every: Annotated[
        bool,
        typer.Option("--all", help="A line at every sample of the chain's moving edges (one if only static edges)."),
    ] = False,
    start: options.Start = None,
    end: options.End = None,
    precision: Annotated[int, typer.Option(min=1, max=12, help="Decimals in text output.")] = 3,
    matrix: Annotated[bool, typer.Option(help="Also print the 4x4 homogeneous matrix.")] = False,
    fmt: Annotated[
        EchoFormat,
        typer.Option(
            "--format",
            "-f",
            help="text (tf_echo's), json (one object per line), csv; to paste elsewhere (the latest transform "
            "unless --at): static (static_transform_publisher's command line, in the data's ROS), urdf (a fixed "
            "joint's <origin xyz rpy>), yaml (an entry of tfx static --from).",
        ),
    ] = EchoFormat.text,
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    play: Annotated[
        bool,
        typer.Option(
            "--play",
            help="Replay the bag in real time; the latest transform --rate times a second of the recording (so of wall "
            "time too).",
        ),
    ] = False,
    count: Annotated[int | None, typer.Option("--count", "-n", min=1, help="Live: stop after N lines.")] = None,
    wait: Annotated[
        float | None,
        typer.Option(help="Live: give up if the transform is not there within WAIT seconds."),
    ] = None,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
    cache: Annotated[float, typer.Option(help="Live: seconds of history kept per edge, as tf2's buffer.")] = 10.0,
    plot: Annotated[
        Path | None,
        typer.Option(
            help=f"Draw translation and roll/pitch/yaw over time into this picture ({PLOT_FILE}): on a bag instead of "
            "the lines (every sample, unless --rate), live and with --play when they end.",
        ),
    ] = None,
    force: options.Force = False,
) -> None:
    """Print the transform from SOURCE to TARGET, as tf_echo does: [bold]where SOURCE is in TARGET[/].

    On a bag, it steps through bag time at --rate Hz over the stretch where every moving
    edge between the frames has data (or --start/--end), interpolating as tf2 does; a lookup
    that fails prints tf2's reason and echo goes on. Exit code 1 if any lookup failed. A frame
    given as /map is looked up as map, as ROS 1's tf_echo does (ROS 2's tf2 refuses the slash: a
    hint says so on ROS 2 data).

    Examples: [cyan]tfx echo map base_link -b robot.bag --all --format csv > pose.csv[/],
    [cyan]tfx echo map base_link -b robot.bag --plot pose.png[/],
    [cyan]tfx echo base_link camera -b robot.bag --at +5 --format static[/]
    """
    from tftools.analysis.echo import EchoQuery, echo, echo_stream
    from tftools.analysis.times import Stamp, parse_time_spec

    check_plot(plot, bags, force)
    rate = _one_rate(echo_rate, rate)
    every = every or (plot is not None and rate is None and at is None)
    rate_given, rate = rate, rate_hz(1.0 if rate is None else rate)
    if wait is not None:
        wait = positive_seconds(wait, "--wait", "10")
    cache = positive_seconds(cache, "--cache", "10")
    if at is not None and every:
        raise UsageError("--at and --all do not go together", "use one of them")
    latest = fmt in PASTE_FORMATS and at is None and not every and rate_given is None and start is None and end is None
    lines = Lines(fmt, precision, matrix, plot)
    if not bags:
        live.no_bag_options(**{"--at": at, "--all": every, "--start": start, "--end": end, "--play": play})
        feed = live.open_source(ros1, use_sim_time, topics)
        query = EchoQuery(target=target, source=source, rate=rate, cache_time=from_sec(cache))
        ros2 = (tf2 or ("ros2" if feed.format.startswith("ros2") else "ros1")) == "ros2"
        slash_dropped((target, source), "ros2" if ros2 else "ros1")
        exit_with(_live(feed, query, count, wait, tf2, replace(lines, ros2=ros2, live=True)))
    query = EchoQuery(
        target=target,
        source=source,
        at=Stamp(0) if latest else parse_time_spec(at, "at") if at is not None else None,
        start=parse_time_spec(start, "start") if start is not None else None,
        end=parse_time_spec(end, "end") if end is not None else None,
        rate=rate,
        every=every,
    )
    if play:  # as tf_echo sees a live system: the bag streamed on a sim clock into a tf2-sized buffer
        streamed = open_stream(bags, topics, tf2)
        lines = replace(lines, ros2=streamed.semantics == "ros2")
        named = frame_arguments(streamed.frames, (target, source), streamed.semantics)
        query = replace(query, target=named[0], source=named[1])
        echo_stream(streamed, query, lines.show)
        exit_with(lines.done())
    recording = open_recording(bags, topics, tf2)
    lines = replace(lines, ros2=recording.buffer.semantics == "ros2")
    named = frame_arguments(recording.buffer.frames, (target, source), recording.buffer.semantics)
    query = replace(query, target=named[0], source=named[1])
    series = echo(recording, query)
    lines.show(series, recording.buffer, print_lines=plot is None)  # on a bag, the picture instead of the lines
    lines.say_span(recording, query, series)
    lines.say_gap(recording.buffer, series)
    exit_with(lines.done())


def _one_rate(echo_rate: float | None, rate: float | None) -> float | None:
    """The rate given after the frames (tf_echo's and tf2_echo's ``source target [echo_rate]``) or as --rate."""
    if echo_rate is not None and rate is not None and echo_rate != rate:
        raise UsageError(f"two rates: {echo_rate:g} after the frames and --rate {rate:g}", "give one of them")
    return rate if echo_rate is None else echo_rate


@dataclass(frozen=True)
class Lines:
    """How echo shows its lookups: lines on stdout, and the picture it draws of those ``shown`` when it ends."""

    fmt: EchoFormat
    precision: int
    matrix: bool
    plot: Path | None
    ros2: bool = False  # the data's ROS: whose static_transform_publisher line ``static`` prints
    live: bool = False  # a live system's lookups: its tree is the one heard so far
    shown: list[EchoSeries] = field(default_factory=list)
    looked_in: list[Buffer] = field(default_factory=list)  # the buffer of the latest lookups shown
    hinted: list[str] = field(default_factory=list)  # the hint said (one at most)

    def print(self, series: EchoSeries) -> None:
        """Print the lookups (CSV's header only before the first)."""
        from tftools.render import echo as render

        if self.fmt is EchoFormat.json:
            render.write_json(series, stdout.file)
        elif self.fmt in PASTE_FORMATS:
            _paste(self.fmt, self.ros2)(series, stdout.file)
        elif self.fmt is EchoFormat.csv:
            text = io.StringIO()
            render.write_csv(series, text)
            stdout.file.write(text.getvalue().split("\n", 1)[1] if self.shown else text.getvalue())
        else:
            render.write_text(series, stdout.file, self.precision, self.matrix)
        stdout.file.flush()

    def show(self, series: EchoSeries, buffer: Buffer, *, print_lines: bool = True) -> EchoSeries:
        """Print lookups (a whole read's, or one of the latest transform, ``analysis.echo.latest``) and show
        them in the picture; ``buffer``: the one they were looked up in, whose tree ``done`` looks at."""
        if print_lines:
            self.print(series)
        self.shown.append(series)
        self.looked_in[:] = [buffer]
        return series

    def hint(self, series: EchoSeries, buffer: Buffer) -> None:
        """On stderr, once: that the frames of ``series``, whose lookups failed, are in trees that no transform
        in ``buffer`` joins (``analysis.echo.apart_hint``): what tf2's reason leaves unsaid. Said when echo ends,
        of the tree then (a recording read whole or replayed, a live system), and while a live echo waits."""
        from tftools.analysis.echo import apart_hint

        if self.hinted or series.valid.all():
            return
        said = apart_hint(buffer, series.target, series.source, series.errors.values(), heard_so_far=self.live)
        if said is not None:
            self.hinted.append(said)
            say_hint(said)

    def say_span(self, recording: Recording, query: EchoQuery, series: EchoSeries) -> None:
        """On stderr, once: where ``--at`` fell outside the recording's tf of the chain, its span and the times
        that reach it (``analysis.echo.span_hint``): tf2's extrapolation text, kept as tf2's, says neither."""
        from tftools.analysis.echo import span_hint

        said = None if self.hinted else span_hint(recording, query, series)
        if said is not None:
            self.hinted.append(said)
            say_hint(said)

    def say_gap(self, buffer: Buffer, series: EchoSeries) -> None:
        """On stderr, once: where lookups answered inside a pause of an edge of their chain, that tf2 interpolated
        across it (``analysis.echo.gap_hint``): tf_echo's lines look the same as any other."""
        from tftools.analysis.echo import gap_hint

        said = gap_hint(buffer, series)
        if said is not None and said not in self.hinted:
            self.hinted.append(said)
            say_hint(said)

    def done(self) -> Exit:
        """The hint under failures (``hint``); the picture, if asked for and anything was shown; PROBLEMS if a
        lookup failed."""
        from tftools.analysis.echo import joined
        from tftools.render.plots import echo_figure

        failed = [s for s in self.shown if not s.valid.all()]
        if failed and self.looked_in:
            self.hint(joined(failed), self.looked_in[0])
        if self.plot is not None and self.shown:
            series = joined(self.shown)
            write_plot(echo_figure(series), self.plot, f"{len(series)} lookups of {series.target} <- {series.source}")
        return Exit.PROBLEMS if failed else Exit.OK


def _live(
    feed: LiveSource, query: EchoQuery, count: int | None, wait: float | None, semantics: Semantics | None, lines: Lines
) -> Exit:
    """Without -b, as tf_echo (``echo_stream`` of the live source): wait for the transform, then the latest
    one ``query.rate`` times a second (``count`` times, or until Ctrl-C); a failure prints tf2's reason and
    the frames known."""
    from tftools.analysis.echo import echo_stream
    from tftools.sources.live.errors import TransformNotHeardError

    def show(series: EchoSeries, buffer: Buffer) -> None:
        lines.show(series, buffer)
        if not series.valid.all() and lines.fmt is EchoFormat.text:  # tf_echo lists the frames after a failure
            stdout.file.write(f"The current list of frames is:\n{printable_lines(buffer.all_frames_as_string())}")
            stdout.file.flush()

    what = feed.describe()
    live.say(f"listening to {what}; waiting for the transform {frame_name(query.target)} <- {frame_name(query.source)}")
    try:
        echo_stream(
            feed,
            query,
            show,
            count=count,
            wait=wait,
            semantics=semantics,
            on_reminder=live.remind,
            on_waiting=lines.hint,
        )
    except TransformNotHeardError as error:
        raise UsageError(
            f"no transform {error.target} <- {error.source} from {what} after {error.waited:.1f} s: {error.reason}",
            "check the frame names with `tfx frames`, or wait longer with --wait",
        ) from None
    return lines.done()
