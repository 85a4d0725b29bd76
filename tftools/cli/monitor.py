"""``tfx monitor [TARGET SOURCE]``: tf_monitor's rates, gaps and delays, per edge and publisher."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import live, options
from tftools.cli.arguments import positive_seconds, rate_hz
from tftools.cli.common import TextOrJson, frame_arguments, slash_dropped, stdout, warn
from tftools.cli.errors import UsageError
from tftools.cli.plots import PLOT_FILE, check_plot, write_plot
from tftools.cli.reading import open_recording, open_stream
from tftools.core.frames import frame_name
from tftools.core.semantics import Semantics
from tftools.core.time import NS_PER_S, from_sec, span_from_to, to_sec

if TYPE_CHECKING:  # the figures and their renderers load when a command runs: --help needs none of them (nor numpy)
    from rich.console import RenderableType

    from tftools.analysis.monitor import LiveMonitor, MonitorQuery, MonitorReport
    from tftools.analysis.timelines import EdgeSeries, MonitorTrace
    from tftools.sources import Recording
    from tftools.sources.replay import Feed
    from tftools.sources.stream import StreamedRecording


def command(
    target: Annotated[
        str | None, typer.Argument(help="With SOURCE: the chain between them (tf_monitor's framea).")
    ] = None,
    source: Annotated[str | None, typer.Argument(help="The other end of the chain (tf_monitor's frameb).")] = None,
    bags: options.Bags = None,
    start: options.Start = None,
    end: options.End = None,
    play: Annotated[
        bool, typer.Option("--play", help="Replay the bag on a simulated clock and refresh the table live.")
    ] = False,
    rate: Annotated[
        float | None,
        typer.Option(
            "--rate",
            "-r",
            help="With --play: replay speed (default 1, real time); the table refreshes once a second of the "
            "recording (--rate 2: twice a second of wall time).",
        ),
    ] = None,
    window: Annotated[float, typer.Option(help="Live: the table covers the last WINDOW seconds.")] = 10.0,
    duration: Annotated[float | None, typer.Option(help="Live: stop after DURATION seconds of wall time.")] = None,
    fmt: Annotated[
        TextOrJson, typer.Option("--format", "-f", help="text (tf_monitor's, as tables) or json.")
    ] = TextOrJson.text,
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
    plot: Annotated[
        Path | None,
        typer.Option(
            help=f"Draw each edge's rate and delay over time into this picture ({PLOT_FILE}): on a bag instead of the "
            "table (with TARGET SOURCE, the chain's edges), live and with --play each refresh's, when it ends.",
        ),
    ] = None,
    force: options.Force = False,
) -> None:
    """Rates, jitter, gaps and delays of every edge and publisher, as tf_monitor shows them.

    The jitter is how irregular an edge's stamps are: the standard deviation of the intervals
    between them. The delay is how late a transform arrives behind its stamp (record time minus stamp);
    with TARGET and SOURCE, the chain between them and its net delay: how far behind the
    newest transform between them lags, the oldest edge deciding (what "extrapolation into
    the future" errors are about). On a bag: over the whole recording, or --start/--end
    (times of recording: with TARGET SOURCE, counted on their chain's clock, a device on the wall clock
    beside a simulation on its own stamps; without, on the tf span's clock, every edge windowed by when its
    transforms arrived on it). Without -b, on the live system, and with --play on a bag's replay:
    over the last --window seconds, refreshed once a second of wall time live, once a second of the
    recording with --play (--rate 2: every 0.5 s of wall time). Where no clock of the stamps was recorded
    (a simulation without /clock), --start/--end select, whole and with --play, by when the replay (the
    record clock, its start at the first stamp: +S is S s into the recording, as ros2 bag play
    --start-offset counts) plays the transforms, the clock publishers' rates are counted on: a simulation
    slower than real time has fewer stamps in such a window than its length.

    Examples: [cyan]tfx monitor -b robot.bag[/], [cyan]tfx monitor map base_link -b robot.bag --play --rate 2[/],
    [cyan]tfx monitor -b robot.bag --plot rates.svg[/]
    """
    from tftools.analysis.monitor import MonitorQuery, chain_span, monitor, monitored_window
    from tftools.analysis.timelines import MonitorTrace, edge_series
    from tftools.analysis.times import parse_time_spec
    from tftools.render import monitor as render
    from tftools.render.plots import monitor_figure
    from tftools.sources.live.capture import live_semantics

    check_plot(plot, bags, force)
    trace = MonitorTrace() if plot is not None else None
    if (target is None) != (source is None):
        raise UsageError("give two frames or none", "tfx monitor TARGET SOURCE, e.g. tfx monitor map base_link")
    if rate is not None and not play:  # said, not ignored: the table covers the whole bag whatever the speed
        raise UsageError("--rate is the replay speed of --play", "tfx monitor -b BAG --play --rate 2")
    rate = rate_hz(rate if rate is not None else 1.0, example="2")
    window = positive_seconds(window, "--window", "5")
    if duration is not None:
        duration = positive_seconds(duration, "--duration", "10")
    if not bags:
        live.no_bag_options(**{"--start": start, "--end": end, "--play": play})
        given = [f for f in (target, source) if f is not None]
        if target is not None and source is not None:
            target, source = frame_name(target), frame_name(source)
        query = MonitorQuery(target=target, source=source, window=from_sec(window))
        with live.open_source(ros1, use_sim_time, topics) as feed:
            semantics = tf2 or live_semantics(feed)
            slash_dropped(given, semantics)
            _watch(feed, query, duration, fmt, feed.describe(), semantics, trace)
        _write_trace(trace, plot, feed.describe())
        return
    first_spec = parse_time_spec(start, "start") if start is not None else None
    last_spec = parse_time_spec(end, "end") if end is not None else None
    if play:
        streamed = open_stream(bags, topics, tf2)
        if streamed.unplayable:  # a replay paced by no clock plays every message at once (rates of 1e11 Hz)
            why = f"--play replays by arrival, and {streamed.unplayable}"
            raise UsageError(why, "read it whole: tfx monitor -b BAG")
        target, source = _chain(streamed.frames, target, source, streamed.semantics)
        query = MonitorQuery(target=target, source=source, start=first_spec, end=last_spec, window=from_sec(window))
        _watch(streamed, query, duration, fmt, f"rate {rate:g}x", trace=trace, speed=rate)
        _write_trace(trace, plot, ", ".join(streamed.paths))
        return
    recording = open_recording(bags, topics, tf2)
    target, source = _chain(recording.buffer.frames, target, source, recording.buffer.semantics)
    query = MonitorQuery(target=target, source=source, start=first_spec, end=last_spec)
    report = monitor(recording, query)
    header = _header(recording, report, chain_span(recording, query), query.start is not None or query.end is not None)
    if plot is not None:
        keys = [e.key for e in report.chain.edges] if report.chain is not None else None
        first, last = monitored_window(recording, query)
        series = edge_series(recording.buffer, recording.timeline, first, last, keys)
        write_plot(monitor_figure(series, header), plot, _plotted(series))
    elif fmt is TextOrJson.json:
        render.write_json(report, stdout.file)
    else:
        stdout.print(render.renderable(report, header))


def _watch(
    feed: Feed | StreamedRecording,
    query: MonitorQuery,
    duration: float | None,
    fmt: TextOrJson,
    note: str = "",
    semantics: Semantics = "ros1",
    trace: MonitorTrace | None = None,
    speed: float = 1.0,
) -> None:
    """The live table: ``feed`` into a monitor (``monitor_stream``), its report over the last ``query.window`` (ns)
    once a second, until ``duration`` wall seconds pass or the feed ends; each report kept in ``trace``
    if given. Works with any feed: a recording replayed (at ``speed``) or a live source."""
    from rich.live import Live

    from tftools.analysis.monitor import monitor_stream
    from tftools.render import monitor as render

    target, source, window = query.target, query.source, query.window

    def report(live_monitor: LiveMonitor) -> MonitorReport:
        current = live_monitor.report(target, source)
        if trace is not None:
            trace.add(live_monitor.clock.now(), current)
        return current

    def table(live_monitor: LiveMonitor) -> RenderableType:
        header = render.live_header(live_monitor.clock.now(), live_monitor.origin, window, note)
        current = report(live_monitor)
        own = render.own_clock_stamps(current)  # a chain on a clock of its own: its stamps, not the replay's clock
        return render.renderable(current, header + (f"\n{own}" if own else ""), target, source)

    def run(on_tick: Callable[[LiveMonitor], None]) -> None:
        monitor_stream(feed, query, on_tick, semantics=semantics, duration=duration, speed=speed)

    try:
        if fmt is TextOrJson.json:
            run(lambda live_monitor: render.write_json_line(report(live_monitor), stdout.file))
        elif stdout.is_terminal:
            with Live(console=stdout, auto_refresh=False) as screen:
                run(lambda live_monitor: screen.update(table(live_monitor), refresh=True))
        else:  # piped: one table per refresh, as tf_monitor prints its results
            run(lambda live_monitor: stdout.print(table(live_monitor), "\n"))
    except KeyboardInterrupt:  # Ctrl-C is how a live monitor ends: the last table stays
        pass


def _chain(
    frames: Sequence[str], target: str | None, source: str | None, semantics: Semantics
) -> tuple[str | None, str | None]:
    """TARGET and SOURCE, if given, as frames of the recording (whose tf2 is ``semantics``)."""
    if target is None or source is None:
        return target, source
    named = frame_arguments(frames, (target, source), semantics)
    return named[0], named[1]


def _write_trace(trace: MonitorTrace | None, plot: Path | None, what: str) -> None:
    """The picture of a refreshing monitor's reports, once it ended (nothing if none came)."""
    from tftools.render.plots import monitor_figure

    if trace is None or plot is None:
        return
    series = trace.series()
    if not series:
        warn(f"no moving transform was seen: {plot} not drawn")
        return
    write_plot(monitor_figure(series, f"tfx monitor: {what}"), plot, _plotted(series))


def _plotted(series: Sequence[EdgeSeries]) -> str:
    return f"rate and delay of {len(series)} edges over {len(series[0].times) if series else 0} points"


def _header(
    recording: Recording, report: MonitorReport, own: tuple[int, int] | None = None, windowed: bool = False
) -> str:
    """The recording and the time it covers: the tf span's (within the window asked for, ``windowed``), or ``own``,
    the span of the chain asked about on its own clock (``chain_span``). A chain's report ends at the recording's
    clock (its delays are counted to then): without a window asked for, the header is still the stamps' span, as
    without a chain (the real create3's "50.902 s from 1663967370.849 to 1663967421.751", a stamp to a record time,
    beside "tf stamped over 50.850 s" for all frames)."""
    from tftools.core.history import FROM_STATIC_TOPIC

    timeline = recording.timeline
    if own is not None and report.chain is not None:
        chain = f"{report.chain.target} to {report.chain.source}"
        # the span of its clock's tf (``Timeline.span_of``), which a frame seen late on it (a detection) starts after
        return f"{', '.join(recording.paths)}: {chain} on a clock of its own, its tf stamped over {span_from_to(*own)}"
    first = report.start if windowed and report.start is not None else timeline.tf_start
    last = report.end if windowed and report.end is not None else timeline.tf_end
    span = span_from_to(first, last)
    paths = ", ".join(recording.paths)
    # Sent on /tf, not static to tf2: a frame tf2 made static (its first transform on /tf_static) is still
    # a recording of moving transforms (the real neato_urdf_beside_driver: 2177 on /tf, all "static").
    if windowed:
        return f"{paths}: {span}"
    if any(((hist.flags & FROM_STATIC_TOPIC) == 0).any() for _, hist in recording.buffer.histories()):
        return f"{paths}: tf stamped over {span}"  # the stamps' span, not the record span wtf gives ("s recorded")
    # Static transforms only: the span of their stamps says nothing of the recording's (a 54 s drive whose
    # /tf_static was stamped in 0.449 s, 37 s before recording began).
    one = last - first < NS_PER_S // 1000  # what ``span_from_to`` shows as "0.000 s from t to t"
    statics = f"static transforms only, stamped {f'at {to_sec(first):.3f}' if one else span}"
    start, end = recording.start, recording.end
    if start <= 0 or end < start:  # no record times: the stamps are all there is
        return f"{paths}: {statics}"
    latest = "" if one else " the latest"
    before = f",{latest} {(start - last) / NS_PER_S:.1f} s before recording began" if last < start else ""
    return f"{paths}: recorded {span_from_to(start, end)}; {statics}{before}"
