"""``tfx monitor``'s work: tf_monitor's numbers per edge, per publisher, and along a chain: ``monitor(recording,
query)`` over a recording, ``monitor_stream(feed, query, on_tick)`` refreshed over a replay or a live system."""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from tftools.analysis.edges import (
    WHOLE,
    AuthorityStats,
    EdgeStats,
    TimeWindow,
    authority_stats,
    chain_edges,
    chain_moving_edges,
    edge_stats,
    sorted_unique,
)
from tftools.analysis.expected import publishers_named
from tftools.analysis.listed import Listed, listed_publishers
from tftools.analysis.times import TimeSpec, played_range, resolve_range
from tftools.core.arrays import Int64Array
from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.buffer import DEFAULT_CACHE_TIME, Buffer
from tftools.core.errors import TimeRangeError, TransformError
from tftools.core.history import EdgeHistory, rows_as_sent
from tftools.core.semantics import Semantics
from tftools.core.stored import SENT_COLUMNS
from tftools.core.time import Clock
from tftools.sources.contents import OfferedQos, SentMessages, concat_sent
from tftools.sources.live.base import TickedClock
from tftools.sources.timeline import ON_RECORD_CLOCK, Timeline

if TYPE_CHECKING:
    from tftools.sources.recording import Recording
    from tftools.sources.replay import Feed
    from tftools.sources.stream import StreamedRecording


@dataclass(frozen=True)
class ChainStats:
    """The edges a lookup from ``source`` to ``target`` composes, and how stale their latest
    common time is: at each moment, now minus the oldest of the moving edges' newest stamps
    (tf_monitor's "Net delay"), averaged over time and at its worst (ns)."""

    target: str
    source: str
    frames: tuple[str, ...]  # from source to target, as the lookup walks
    edges: tuple[EdgeStats, ...]  # one per hop with data in the window
    delay_mean: float  # NaN if no moving edge, or their record times are unknown
    delay_max: float
    limiting: tuple[str, str] | None  # the edge that held the chain back the longest


@dataclass(frozen=True)
class MonitorReport:
    """Everything ``tfx monitor`` shows for one window of time."""

    start: int | None  # window (ns); None = open
    end: int | None
    edges: list[EdgeStats]
    authorities: list[AuthorityStats]
    chain: ChainStats | None
    delays_unavailable: str = ""  # why the delays are not shown (``Timeline.delays_unavailable``), "" if they are
    other_clock: tuple[str, ...] = ()  # the frames stamped on another clock than their arrival's (no delay)
    other_clock_why: str = ""  # why theirs are not shown (``Timeline.other_clock_delays``), "" if none is
    #: The recording names no publishers (a ROS 2 bag; a ROS 1 bag without callerids): each authority is the topic
    #: its transforms came on, not a node.
    unnamed: bool = False
    #: Where it names none (a ROS 2 bag): what its files list of each topic's publishers (``listed_publishers``).
    listed: tuple[tuple[str, Listed], ...] = ()
    #: The edges (parent, child) whose largest gap spans a part of the file that is damaged (``SourceInfo.damaged``):
    #: transforms lost there, not a pause of their publisher.
    damaged_gaps: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True, slots=True, kw_only=True)
class MonitorQuery:
    """What ``tfx monitor`` asks: every edge's and publisher's numbers, with ``target`` and ``source`` their
    chain's too; on a recording from ``start`` to ``end`` (default: all of it; on the clock of the chain asked
    about, ``Timeline.span_of``), on a stream over the last ``window`` (ns) of its clock."""

    target: str | None = None
    source: str | None = None
    start: TimeSpec | None = None
    end: TimeSpec | None = None
    window: int = DEFAULT_CACHE_TIME


def monitor(recording: Recording, query: MonitorQuery) -> MonitorReport:
    """``tfx monitor [TARGET SOURCE] -b BAG``: ``monitor_buffer`` over the recording, or over the window of
    ``query.start`` to ``query.end`` (``monitored_window``), windowed by when the transforms arrived.
    Raises tf2's errors when the frames are not connected, ``InvalidTimeError`` or ``TimeRangeError``."""
    first, last = monitored_window(recording, query)
    buffer, timeline = recording.buffer, recording.timeline
    window = TimeWindow(first, last, by_record_time=True, timeline=timeline, until=timeline.record_end)
    report = monitor_buffer(
        buffer, query.target, query.source, window, unstored=recording.refused, sent=recording.contents.sent
    )
    unnamed = not publishers_named(recording)
    return dataclasses.replace(
        report,
        unnamed=unnamed,
        listed=listed_of(recording.qos, report.authorities) if unnamed else (),
        damaged_gaps=_damaged_gaps(recording, report.edges),
    )


def listed_of(qos: Mapping[str, OfferedQos], authorities: Sequence[AuthorityStats]) -> tuple[tuple[str, Listed], ...]:
    """The publishers the recording lists of each topic the transforms came on (its authorities, where it names no
    publisher), in their order; those no file lists left out, as those it lists none of (a writer that kept no
    QoS profile, not a recorder that found no publisher: their messages are there)."""
    found = ((a.authority, listed_publishers(qos, a.authority)) for a in authorities)
    return tuple((topic, n) for topic, n in found if n is not None and n.publishers)


def _damaged_gaps(recording: Recording, edges: Sequence[EdgeStats]) -> tuple[tuple[str, str], ...]:
    """The edges whose largest gap overlaps a damaged part of a file: the record times of the samples that begin and
    end it against the parts' (``SourceInfo.damaged``), on the record clock both are on."""
    spans = [span for source in recording.contents.files for span in source.damaged]
    out = []
    for e in edges if spans else ():
        hist = recording.buffer.history(e.child)
        if e.static or not e.longest_interval or hist is None or not len(hist.stamps):
            continue
        at = min(int(np.searchsorted(hist.stamps, e.longest_interval_start)), len(hist.stamps) - 1)
        first, last = int(hist.record_times[at]), int(hist.record_times[min(at + 1, len(hist.stamps) - 1)])
        if any(first <= b and a <= last for a, b in spans):
            out.append(e.key)
    return tuple(out)


def monitored_window(recording: Recording, query: MonitorQuery) -> tuple[int | None, int | None]:
    """``query.start`` and ``query.end`` on the arrival axis (ROS time when transforms arrived; None: open),
    counted on the clock of the chain asked about: a chain stamped on its own clock (simulated time among
    frames on wall time) is windowed from the arrival of its first transform stamped at or after ``start``
    to that of its last stamped at or before ``end``. A ``TimeRangeError`` when they miss its tf."""
    buffer, timeline = recording.buffer, recording.timeline
    frames = list(chain_moving_edges(buffer, query.target, query.source)) if query.target and query.source else []
    first, last = resolve_range(timeline, query.start, query.end, (None, None), frames)
    reach = timeline.arrival_span(frames)
    if (first is not None and first > reach[1]) or (last is not None and last < reach[0]):
        raise TimeRangeError(reach)
    span = timeline.span_of(frames)
    if span == (timeline.tf_start, timeline.tf_end) or (first is None and last is None):
        return first, last
    hists = [hist for child in frames if (hist := buffer.history(child)) is not None]
    stamps = np.concatenate([hist.stamps for hist in hists])
    arrived = np.concatenate([timeline.arrival(hist.stamps, hist.record_times) for hist in hists])
    after, before = (
        arrived[stamps >= first] if first is not None else arrived,
        arrived[stamps <= last] if last is not None else arrived,
    )
    # none of the chain's stamps in the range (its clock's other frames are): an empty window after or before them
    return (
        None if first is None else int(after.min()) if len(after) else int(arrived.max()) + 1,
        None if last is None else int(before.max()) if len(before) else int(arrived.min()) - 1,
    )


def chain_span(recording: Recording, query: MonitorQuery) -> tuple[int, int] | None:
    """The stamps ``monitor`` covers of the chain asked about, where it is stamped on another clock than the tf
    span's (``Timeline.span_of``: a Gazebo robot stamped from zero beside a device on the wall clock): its own
    span, within ``query.start`` and ``query.end``; None where the chain keeps the tf span's clock."""
    if not (query.target and query.source):
        return None
    timeline = recording.timeline
    frames = list(chain_moving_edges(recording.buffer, query.target, query.source))
    span = timeline.span_of(frames)
    if span == (timeline.tf_start, timeline.tf_end):
        return None
    first, last = resolve_range(timeline, query.start, query.end, span, frames)
    return max(first, span[0]), min(last, span[1])


def played_window(stream: StreamedRecording, query: MonitorQuery) -> tuple[int | None, int | None]:
    """``query.start`` and ``query.end`` of a replay of ``stream`` on its clock (None: open), counted on the
    clock of the chain asked about as ``monitored_window`` counts them (``played_range``); a
    ``TimeRangeError`` when they miss its tf."""
    return played_range(stream, query.start, query.end, query.target, query.source)


def monitor_buffer(
    buffer: Buffer,
    target: str | None = None,
    source: str | None = None,
    window: TimeWindow = WHOLE,
    *,
    unstored: TransformBatch | None = None,
    sent: SentMessages | None = None,
) -> MonitorReport:
    """tf_monitor's statistics over the ``window`` (``edge_stats``); with two frames, their chain too, its delay
    over the same window on the arrival axis (an open end: the buffer's clock). ``unstored``: the rows tf2 did
    not store, ``sent``: the messages that arrived (``authority_stats``). Raises tf2's errors when the frames are
    not connected."""
    edges = edge_stats(buffer, window)
    authorities = authority_stats(buffer, window, unstored=unstored, sent=sent)
    chain = None
    if target is not None and source is not None:
        # the chain's delay is counted to the buffer's clock where the window is open; the report's window stays
        # as asked (open: null in JSON, as the text's header says the stamps' span)
        end = window.end if window.end is not None else buffer.now()
        chain = chain_stats(buffer, edges, target, source, window.start, end, window.timeline)
    timeline = window.clock
    moving = [e.child for e in (chain.edges if chain is not None else edges) if not e.static]  # those shown
    return MonitorReport(
        window.start,
        window.end,
        edges,
        authorities,
        chain,
        timeline.delays_unavailable,
        timeline.on_other_clock(moving),
        timeline.other_clock_delays(moving),
    )


def chain_stats(
    buffer: Buffer,
    edges: list[EdgeStats],
    target: str,
    source: str,
    start: int | None,
    end: int,
    timeline: Timeline | None,
) -> ChainStats:
    """The chain between the frames, its edges' numbers (from ``edges``) and its delay."""
    frames = tuple(buffer.chain(target, source))
    by_key = {e.key: e for e in edges}
    hops = chain_edges(buffer, frames)
    moving = [hop for hop in hops if (hist := buffer.history(hop[1])) is not None and not hist.static]
    mean, largest, limiting = _chain_delay(buffer, moving, start, end, timeline)
    return ChainStats(target, source, frames, tuple(by_key[h] for h in hops if h in by_key), mean, largest, limiting)


def _newest_stamps(
    buffer: Buffer, edge: tuple[str, str], end: int, timeline: Timeline | None
) -> tuple[Int64Array, Int64Array]:
    """When each sample of ``edge`` arrived in ROS time (sorted) and the newest stamp known from then on;
    only the samples with a delay (``Timeline.measurable``)."""
    hist = buffer.history(edge[1])
    assert hist is not None
    parent_ids = [i for i in np.flatnonzero(np.bincount(hist.parents)) if buffer.frame_name(int(i)) == edge[0]]
    timeline = timeline or ON_RECORD_CLOCK
    arrived, known = timeline.measurable(edge[1], hist.record_times, hist.flags, hist.stamps)
    rows = np.isin(hist.parents, parent_ids) & known & (arrived <= end)
    records, stamps = arrived[rows], hist.stamps[rows]
    order = np.argsort(records, kind="stable")
    return records[order], np.maximum.accumulate(stamps[order]) if len(stamps) else stamps


def _chain_delay(
    buffer: Buffer, moving: list[tuple[str, str]], start: int | None, end: int, timeline: Timeline | None
) -> tuple[float, float, tuple[str, str] | None]:
    """Mean and max (ns) over ``[start, end]`` of (t - latest common stamp at t), and the limiting edge.

    The latest common stamp is a step function that changes only when a sample arrives,
    so the delay is a sawtooth: its integral and maximum are computed exactly per step.
    """
    timeline = timeline or ON_RECORD_CLOCK
    if not moving or not all(timeline.delays_measured_for(child) for _, child in moving):
        return math.nan, math.nan, None
    if all(child in timeline.record_clocked for _, child in moving):  # arrivals on their record times
        start, end = timeline.record_window(start, end)
    series = [_newest_stamps(buffer, edge, end, timeline) for edge in moving]
    if not series or any(len(records) == 0 for records, _ in series):
        return math.nan, math.nan, None
    first = max(int(records[0]) for records, _ in series)  # every edge has data from here on
    begin = max(first, start) if start is not None else first
    if begin >= end:
        return math.nan, math.nan, None
    arrivals = np.concatenate([records for records, _ in series])
    steps = sorted_unique(np.concatenate([[begin], arrivals[(arrivals > begin) & (arrivals < end)]]))
    common = np.full(len(steps), np.iinfo(np.int64).max, np.int64)
    limiting = np.zeros(len(steps), np.int64)
    for index, (records, newest) in enumerate(series):
        known = newest[np.searchsorted(records, steps, side="right") - 1]
        older = known < common
        common[older], limiting[older] = known[older], index
    bounds = np.append(steps, end)
    rise = (bounds[:-1] - common).astype(np.float64), (bounds[1:] - common).astype(np.float64)
    ticking = max(timeline.resolution_of(child) for _, child in moving)
    if ticking:  # read off a ticking clock: behind a stamp by less than a step
        rise = np.maximum(rise[0], 0.0), np.maximum(rise[1], 0.0)  # is no delay (``figures.delays``)
    integral = float(np.sum(rise[1] ** 2 - rise[0] ** 2)) / 2
    held = np.bincount(limiting, weights=np.diff(bounds).astype(float), minlength=len(series))
    return integral / (end - begin), float(rise[1].max()), moving[int(np.argmax(held))]


class LiveMonitor:
    """A buffer fed batch by batch (by a replay or a live source) and summed up on demand
    over the last ``window`` of its clock's time, as ``tfx monitor`` refreshes its table."""

    def __init__(
        self,
        clock: Clock,
        window: int = DEFAULT_CACHE_TIME,
        timeline: Timeline | None = None,
        semantics: Semantics = "ros1",
        unnamed: bool = False,
        qos: Mapping[str, OfferedQos] | None = None,
    ) -> None:
        """``timeline``: a replayed recording's (``Timeline.played``); none for a live system, whose
        receive times are read off ``clock`` (as coarse as its /clock under use_sim_time). ``unnamed``: a replayed
        recording names no publishers (``MonitorReport.unnamed``), and ``qos`` what its files list of them
        (``Recording.qos``)."""
        self.window = window
        self.clock = clock
        self.timeline = timeline
        #: Where +S counts from: a replay's recording's origin (its tf's first stamp, as --start's +S), else when
        #: the first transform arrived (since the last jump back).
        self.origin: int | None = timeline.origin if timeline is not None else None
        # Keep a little more than the window: samples that arrive late still fall inside it.
        self.buffer = Buffer(cache_time=window + DEFAULT_CACHE_TIME, clock=clock, semantics=semantics)
        self.unnamed = unnamed
        self.qos = qos or {}
        #: The rows tf2 refused or took again without storing them (ROS 2: an identical sample), as
        #: ``Recording.refused`` holds them: messages that arrived all the same.
        self.unstored: list[TransformBatch] = []
        #: The rows of caches ROS 2's tf2 replaced (a frame switching between /tf_static and /tf,
        #: ``_replaced_rows``): the moving ones for a window, the static ones kept as the buffer keeps its
        #: statics (the newest ``REPLACED_STATICS`` rows: a frame switching at every message stays bounded).
        self.replaced: list[TransformBatch] = []
        #: The tf messages that arrived (``add_sent``), as their source told them apart; None until one did
        #: (a feed that does not: the messages are guessed from the rows, ``authority_stats``).
        self.sent: SentMessages | None = None
        self._arrived: list[SentMessages] = []  # since the last report: joined once there, not at every batch
        self._arrived_count = 0  # messages in ``_arrived``
        self._lock = threading.Lock()

    def clear(self, _jump: object = None) -> None:
        """Forget the dynamic transforms (statics kept), as tf2_ros's listener at a jump back in time."""
        with self._lock:
            self.buffer.clear()
            self.unstored = []
            self.replaced = [_statics(b) for b in self.replaced]
            self._join_sent()
            if self.sent is not None:
                self.sent = self.sent.taken(np.flatnonzero(self.sent.static))
            self.origin = None

    def add_sent(self, sent: SentMessages) -> None:
        """The tf messages of the transforms ``add`` is given next (or was just given); safe from a source's thread."""
        with self._lock:
            self._arrived.append(sent)
            self._arrived_count += len(sent)
            if self._arrived_count > ARRIVED_HELD:  # a replay far ahead of its reports: keep what a window shows
                self._join_sent()
                # by the newest message, not the clock: a replay sets its clock once a catch-up is delivered
                newest = int(sent.record_time.max()) if len(sent) else self.buffer.now()
                self._drop_older(max(newest, self.buffer.now()) - 2 * self.window)

    def _join_sent(self) -> None:
        """The messages that arrived since the last report added to ``sent`` (the lock held)."""
        if self._arrived:
            self.sent = concat_sent([*([self.sent] if self.sent is not None else []), *self._arrived])
            self._arrived, self._arrived_count = [], 0

    def _drop_older(self, since: int) -> None:
        """Forget the messages, and the rows tf2 did not store, that arrived before ``since`` (the lock held)."""
        self.unstored = [b for b in self.unstored if int(b.record_time.max()) >= since]
        self.replaced = _kept_replaced(self.replaced, since)
        if self.sent is not None:
            self.sent = _kept_sent(self.sent, since)

    def add(self, batch: TransformBatch) -> None:
        """Insert a batch; safe to call from a source's thread."""
        with self._lock:
            if self.origin is None and len(batch) and (first := int(batch.record_time.min())) > 0:
                self.origin = first
            arrivals, refused = self.buffer.arrivals, self.buffer.rejections.total
            if len(replaced := _replaced_rows(self.buffer, batch)):
                self.replaced.append(replaced)
            self.buffer.insert(batch)
            again = self.buffer.duplicates  # arrival numbers, in arrival order: the newest last
            if self.buffer.rejections.total > refused or (len(again) and int(again[-1]) >= arrivals):
                sequence = np.concatenate([self.buffer.rejections.sequences(), again])
                self.unstored.append(take_rows(batch, np.unique(sequence[sequence >= arrivals]) - arrivals))

    def _timeline(self) -> Timeline:
        if self.timeline is not None:
            return self.timeline
        step = self.clock.step if isinstance(self.clock, TickedClock) else 0
        return dataclasses.replace(ON_RECORD_CLOCK, record_step=step) if step else ON_RECORD_CLOCK

    def report(self, target: str | None = None, source: str | None = None) -> MonitorReport:
        """The statistics of what arrived over the last window; the chain once it exists."""
        with self._lock:
            now = self.buffer.now()
            start = now - self.window
            if not all(frame is not None and self.buffer.has_frame(frame) for frame in (target, source)):
                target = source = None  # no chain asked for, or its frames not seen yet
            timeline = self._timeline()
            self._join_sent()
            self._drop_older(start - self.window)
            kept = self.unstored + self.replaced
            unstored = concat_batches(kept) if kept else None
            window = TimeWindow(start, now, by_record_time=True, timeline=timeline)
            try:
                report = monitor_buffer(self.buffer, target, source, window, unstored=unstored, sent=self.sent)
            except TransformError:  # the chain is not connected (yet): show the rest
                report = monitor_buffer(self.buffer, window=window, unstored=unstored, sent=self.sent)
            listed = listed_of(self.qos, report.authorities) if self.unnamed else ()
            return dataclasses.replace(report, unnamed=self.unnamed, listed=listed)


#: The most tf messages a ``LiveMonitor`` holds unjoined between two reports before it forgets those older than
#: its window shows (a replay played faster than its reports are made would hold the whole recording).
ARRIVED_HELD = 50_000

#: The most rows of replaced static caches a ``LiveMonitor`` keeps (the newest).
REPLACED_STATICS = 10_000


#: The most /tf_static messages a ``LiveMonitor`` keeps (the newest): a publisher re-sending its statics at
#: every message stays bounded.
SENT_STATICS = 10_000


def _kept_sent(sent: SentMessages, since: int) -> SentMessages:
    """``sent`` without its /tf messages recorded before ``since``, and its newest ``SENT_STATICS`` /tf_static ones."""
    statics = np.flatnonzero(sent.static)
    kept = ~sent.static & (sent.record_time >= since)
    kept[statics[-SENT_STATICS:]] = True
    return sent if kept.all() else sent.taken(np.flatnonzero(kept))


def _statics(batch: TransformBatch) -> TransformBatch:
    return take_rows(batch, np.flatnonzero(batch.static))


def _kept_replaced(replaced: list[TransformBatch], since: int) -> list[TransformBatch]:
    """``replaced`` without its moving rows recorded before ``since``, and at most ``REPLACED_STATICS``
    static rows, the newest."""
    kept = [b if int(b.record_time.min()) >= since else _statics(b) for b in replaced]
    kept = [b for b in kept if len(b)]
    while sum(len(b) for b in kept) > REPLACED_STATICS and len(kept) > 1:
        kept.pop(0)
    return kept


def _replaced_rows(buffer: Buffer, batch: TransformBatch) -> TransformBatch:
    """The rows of the caches ROS 2's tf2 replaces when ``batch`` switches a frame between /tf_static and /tf
    (the frame's history, and its rows in ``batch`` before its last switch there): a live buffer keeps none
    of them (the whole read's keeps them, ``EdgeHistory.replaced``), yet they arrived."""
    if buffer.semantics != "ros2" or not len(batch):
        return TransformBatch.empty()
    names, authorities = ["", *buffer.frames], list(buffer.authorities)
    lost: list[TransformBatch] = []
    for child in np.flatnonzero(np.bincount(batch.child)):
        rows = np.flatnonzero(batch.child == child)
        static = batch.static[rows]
        name = batch.frame_names[int(child)].lstrip("/")
        hist = buffer.history(name)
        if hist is not None and len(hist) and bool(static[0]) != hist.static:
            lost.append(_history_rows(names, authorities, name, hist))
        if len(switches := np.flatnonzero(static[1:] != static[:-1])):
            lost.append(take_rows(batch, rows[: int(switches[-1]) + 1]))
    return concat_batches(lost) if lost else TransformBatch.empty()


def _history_rows(names: list[str], authorities: list[str], name: str, hist: EdgeHistory) -> TransformBatch:
    """``hist``'s rows (of frame ``name``) as they were sent."""
    columns = {of: getattr(hist, column) for of, column in SENT_COLUMNS.items()}
    return rows_as_sent(names, authorities, {**columns, "child": np.full(len(hist), names.index(name), np.int32)})


def monitor_stream(
    feed: Feed | StreamedRecording,
    query: MonitorQuery,
    on_tick: Callable[[LiveMonitor], None],
    *,
    timeline: Timeline | None = None,
    semantics: Semantics = "ros1",
    duration: float | None = None,
    speed: float = 1.0,
) -> None:
    """``tfx monitor`` live or ``--play``: ``feed`` into a ``LiveMonitor`` over the last ``query.window`` (ns),
    ``on_tick`` called with it once a second of the feed's clock, until ``duration`` wall seconds pass or the
    feed ends, and once more as it ends if its clock moved on (its report: ``LiveMonitor.report`` of the
    query's frames). Never twice at one time of that clock: a replay that ran ahead of its ticks (faster
    than its tables are drawn) has them made at once when they are due, at the time it reached; the first
    shows that window, the others would show it again and are not made.

    A recording streamed (``--play``): replayed at ``speed`` times real time from ``query.start`` to
    ``query.end`` (``played_window``: a ``TimeRangeError`` when they miss its tf) on its own timeline and
    semantics. A live source (or a replay made by hand, with its recording's ``timeline``,
    ``Timeline.played``): its jumps back in time clear the monitor, as tf2_ros's listener."""
    from tftools.sources.live.base import LiveSource
    from tftools.sources.live.time_jump import watch_jumps
    from tftools.sources.replay import Replay, follow
    from tftools.sources.stream import StreamedRecording

    unnamed, qos = False, None
    if isinstance(feed, StreamedRecording):
        unnamed, qos = not any(f.names_publishers for f in feed.contents.files), feed.contents.qos
        first, last = played_window(feed, query)
        timeline, semantics = feed.timeline, feed.semantics
        feed = feed.replay(rate=speed, start=first, end=last)

    live_monitor = LiveMonitor(feed.clock, query.window, timeline, semantics, unnamed, qos)
    if isinstance(feed, Replay | LiveSource):
        feed.on_sent = live_monitor.add_sent
    on_batch = (
        watch_jumps(feed, live_monitor.add, live_monitor.clear) if isinstance(feed, LiveSource) else live_monitor.add
    )
    follow(feed, on_batch, lambda: on_tick(live_monitor), duration=duration, summary=True)
