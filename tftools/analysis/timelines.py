"""Edges and sensor streams over time, on one time axis cut into equal bins: what ``tfx report`` draws.

Each figure is the local form of ``analysis.edges``' and of ``analysis.filter``'s fates. The axis is the
tf stamps' clock; a frame stamped on another clock is placed at its arrival, so that every row shares it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tftools.analysis.edges import Edge, edge_delays, edge_rows
from tftools.analysis.filter.fates import LOST, UNDECIDED, Fate, FilterReport, StreamReport
from tftools.analysis.monitor import MonitorReport
from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.buffer import Buffer
from tftools.core.figures import pause_rows, record_span
from tftools.core.history import EdgeHistory
from tftools.core.time import NS_PER_S
from tftools.sources.contents import StampedMessages
from tftools.sources.timeline import Timeline

#: The axis is cut into at most this many bins, each at least ``FINEST_BIN`` long.
MAX_BINS = 500
#: The bins of all timelines together, at most (but ``MIN_BINS`` each): a recording of 20,000 moving edges
#: gets 10 bins an edge, not 500 (950 MB and a page of 150 MB).
MAX_CELLS = 200_000
MIN_BINS = 10
FINEST_BIN = NS_PER_S // 1000
#: At most this many re-parentings of one frame are kept (two publishers disagreeing at 50 Hz make thousands).
MAX_REPARENTINGS = 200
#: What became of sensor messages, in the order they are stacked.
FATE_GROUPS = {
    "on_arrival": (Fate.ON_ARRIVAL,),
    "later": (Fate.LATER,),
    "lost": LOST,
    "undecided": UNDECIDED,
}


@dataclass(frozen=True)
class Bins:
    """``count`` equal stretches of ``width`` ns from ``start``."""

    start: int
    width: int
    count: int

    def edges(self) -> Int64Array:
        """The ``count + 1`` times between bins."""
        return self.start + self.width * np.arange(self.count + 1, dtype=np.int64)

    def index(self, times: Int64Array) -> IntpArray:
        """The bin of each time; times outside the axis fall into its first or last bin."""
        return np.clip((times - self.start) // self.width, 0, self.count - 1).astype(np.intp)


def bins_over(start: int, end: int, rows: int = 1) -> Bins:
    """At most ``MAX_BINS`` bins covering ``[start, end]``, each 1, 2 or 5 times a power of ten ns long
    and none shorter than ``FINEST_BIN``; for ``rows`` timelines, fewer (down to ``MIN_BINS``) so that they
    hold at most ``MAX_CELLS`` bins in all."""
    span = max(end - start, 1)
    most = max(MIN_BINS, min(MAX_BINS, MAX_CELLS // max(rows, 1)))
    width = _round_up(max(-(-span // most), FINEST_BIN))
    return Bins(start, width, max(1, -(-span // width)))


def _round_up(ns: int) -> int:
    """The least 1, 2 or 5 times a power of ten at or above ``ns``."""
    power: int = 10 ** (len(str(ns)) - 1)
    return next(step * power for step in (1, 2, 5, 10) if step * power >= ns)  # 10: ns was above 5 * power


@dataclass(frozen=True)
class Reparenting:
    """A frame's parent changed at ``time`` (axis time of the first sample under the new one)."""

    time: int
    child: str
    before: str
    after: str


@dataclass(frozen=True)
class EdgeTimeline(Edge):
    """One parent -> child edge over the axis: per bin its samples, rate, mean and largest delay (ns; NaN
    where there is none, outside its span, or where delays cannot be measured); its pauses as (start, end)
    axis times (``figures.pauses``); its frame's re-parentings."""

    static: bool
    at_arrival: bool  # placed at arrival: its stamps are on another clock than the reference
    samples: Int64Array
    rate_hz: FloatArray
    delay_mean: FloatArray
    delay_max: FloatArray
    pauses: tuple[tuple[int, int], ...]
    reparentings: tuple[Reparenting, ...]
    unplaced: bool = False  # on a clock beside the axis's that no arrival places (``_unplaced``): no samples drawn


@dataclass(frozen=True)
class StreamTimeline:
    """One sensor topic through a MessageFilter: its report, and per bin of arrival how many of its
    messages went through on arrival, later, never (lost), or cannot be judged (``FATE_GROUPS``), and the
    longest wait (ns) of those that waited (NaN where none)."""

    report: StreamReport
    fates: dict[str, Int64Array]
    wait_max: FloatArray


def edge_axis(buffer: Buffer, timeline: Timeline) -> tuple[int, int]:
    """The span of the dynamic edges on the axis (the tf stamps' without any)."""
    spans = [
        (int(axis[0]), int(axis[-1]))
        for child, hist in buffer.histories()
        if not hist.static and len(hist) and not _unplaced(timeline, child)
        for axis in [_axis(timeline, child, hist.stamps, hist.record_times)]
    ]
    return _hull(spans) or (timeline.tf_start, timeline.tf_end)


def _hull(spans: Sequence[tuple[int, int]]) -> tuple[int, int] | None:
    return (min(s for s, _ in spans), max(e for _, e in spans)) if spans else None


def edge_timelines(
    buffer: Buffer, timeline: Timeline, bins: Bins, pause_floor: int, keys: Sequence[tuple[str, str]] | None = None
) -> list[EdgeTimeline]:
    """Every edge's timeline (static ones too, flat), in the order of ``keys`` when given (edges not
    among them left out); its pauses are those longer than ``pause_floor`` ns (``figures.pauses``)."""
    found = {}
    for parent, child, hist, mine in edge_rows(buffer):
        near = tuple(c for c in _reparentings(buffer, child, hist, timeline) if parent in (c.before, c.after))
        found[(parent, child)] = _timeline(parent, child, hist, mine, timeline, bins, pause_floor, near)
    return [found[key] for key in keys if key in found] if keys is not None else list(found.values())


def _axis(timeline: Timeline, child: str, stamps: Int64Array, records: Int64Array) -> Int64Array:
    """Where samples sit on the axis: their stamps, or their arrival where the frame is on another clock (made
    non-decreasing, as stamps are); where its stamps are on several, those off its main clock at their arrival,
    in order among the others. By stamps, a replay's map -> odom beside a live one's, a week apart, spread the
    raspimouse's 54 s over a 7-day axis of 2000 s bins (the edge at 1.7e-06 Hz in most), the SAIL boat's IMU on a
    clock 5.8 h ahead its 15.9 s over 5.8 h."""
    if child in timeline.on_several_bases:
        main = next(e.offset_record for e in timeline.edges if e.child == child)
        elsewhere = np.abs(records - stamps - main) > timeline.same_clock
        return np.sort(np.where(elsewhere, timeline.arrival_on_stamps(stamps, records), stamps))
    if not _at_arrival(timeline, child):
        return stamps
    return np.maximum.accumulate(timeline.arrival_on_stamps(stamps, records)) if len(stamps) else stamps


def _unplaced(timeline: Timeline, child: str) -> bool:
    """Whether a frame is stamped on a clock beside the tf span's where no time of arrival places it there (no
    reference: the logistic cobot's detections on the wall clock beside its simulated arm, record times all 0,
    stretched the axis over 55 years)."""
    return child in timeline.beside_span and not timeline.places_arrivals


def _at_arrival(timeline: Timeline, child: str) -> bool:
    """Whether a frame's samples sit on the axis at their arrival: stamped on another clock than the reference,
    or beside the tf span's."""
    return child in timeline.off_reference or child in timeline.beside_span


def _timeline(
    parent: str,
    child: str,
    hist: EdgeHistory,
    mine: BoolArray,
    timeline: Timeline,
    bins: Bins,
    pause_floor: int,
    reparentings: tuple[Reparenting, ...],
) -> EdgeTimeline:
    """The timeline of ``hist``'s samples ``mine`` (those under ``parent``)."""
    unplaced = _unplaced(timeline, child)
    if hist.static or unplaced:  # latched once, stamped at any time (often 0), or on no moment of the axis
        nothing = np.full(bins.count, np.nan)
        none = np.zeros(bins.count, np.int64)
        return EdgeTimeline(
            parent, child, hist.static, False, none, nothing, nothing, nothing, (), reparentings, unplaced
        )
    stamps, records = hist.stamps[mine], hist.record_times[mine]
    axis = _axis(timeline, child, stamps, records)
    where = bins.index(axis)
    samples = np.bincount(where, minlength=bins.count).astype(np.int64)
    mean, largest = _delays(timeline, child, hist, mine, where, bins.count)
    _, _, paused = pause_rows(stamps, pause_floor, record_span(records))
    spans = tuple((int(axis[i]), int(axis[i + 1])) for i in paused.tolist())
    at_arrival = _at_arrival(timeline, child) or child in timeline.on_several_bases
    rate = local_rate(axis, bins)
    return EdgeTimeline(parent, child, False, at_arrival, samples, rate, mean, largest, spans, reparentings)


def local_rate(times: Int64Array, bins: Bins) -> FloatArray:
    """Samples per second in each bin, of samples at sorted ``times``: the intervals between samples
    that fall in a bin, each counted for the share of it that does, over the part of the bin inside
    the samples' span (a bin the span only starts or ends in is not read as a slower rate); over the
    whole span this is ``EdgeStats.rate_hz``. NaN outside the span, and for fewer than two samples."""
    if len(times) < 2 or times[-1] == times[0]:
        return np.full(bins.count, np.nan)
    edges = bins.edges().astype(np.float64)
    first, last = float(times[0]), float(times[-1])
    count = np.interp(edges, times.astype(np.float64), np.arange(len(times), dtype=np.float64))
    covered = np.minimum(edges[1:], last) - np.maximum(edges[:-1], first)
    rate: FloatArray = np.full(bins.count, np.nan)
    inside = covered > 0
    rate[inside] = np.diff(count)[inside] * NS_PER_S / covered[inside]
    return rate


def _delays(
    timeline: Timeline, child: str, hist: EdgeHistory, mine: BoolArray, where: IntpArray, count: int
) -> tuple[FloatArray, FloatArray]:
    """Mean and largest delay (ns) of the samples ``mine`` in each bin: those that have one (``edges.edge_delays``)."""
    delays, measured = edge_delays(child, hist, mine, timeline)
    return _mean_max(where[measured], delays.astype(np.float64), count)


def _mean_max(where: IntpArray, values: FloatArray, count: int) -> tuple[FloatArray, FloatArray]:
    """Per bin, the mean and the largest of ``values`` (NaN where a bin has none)."""
    n = np.bincount(where, minlength=count)
    total = np.bincount(where, weights=values, minlength=count)
    largest = np.full(count, -np.inf)
    np.maximum.at(largest, where, values)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(n > 0, total / n, np.nan)
    return mean, np.where(n > 0, largest, np.nan)


def _reparentings(buffer: Buffer, child: str, hist: EdgeHistory, timeline: Timeline) -> tuple[Reparenting, ...]:
    """Where the frame's parent changes, in stamp order (the first ``MAX_REPARENTINGS``)."""
    parents = hist.parents
    if hist.static or not len(parents) or parents.min() == parents.max():
        return ()
    changes = np.flatnonzero(parents[1:] != parents[:-1])[:MAX_REPARENTINGS] + 1
    axis = _axis(timeline, child, hist.stamps, hist.record_times)
    return tuple(
        Reparenting(int(axis[i]), child, buffer.frame_name(int(parents[i - 1])), buffer.frame_name(int(parents[i])))
        for i in changes.tolist()
    )


def stream_axis(streams: Sequence[StampedMessages], timeline: Timeline) -> tuple[int, int] | None:
    """The span of the sensor messages' arrivals on the axis (None without any)."""
    arrivals = [timeline.arrival_on_stamps(s.stamp, s.record_time) for s in streams if len(s)]
    return _hull([(int(axis.min()), int(axis.max())) for axis in arrivals])


def stream_timelines(
    timeline: Timeline, bins: Bins, streams: Sequence[StampedMessages], sensors: FilterReport
) -> list[StreamTimeline]:
    """Each stream ``sensors`` reports on: its fates over the axis, binned at the messages' arrival in ROS time."""
    by_topic = {s.topic: s for s in streams}
    result = []
    for report in sensors.streams:
        stream, fates = by_topic[report.topic], sensors.fates[report.topic]
        where = bins.index(timeline.arrival_on_stamps(stream.stamp, stream.record_time))
        counts = {
            name: np.bincount(where[np.isin(fates.fate, group)], minlength=bins.count).astype(np.int64)
            for name, group in FATE_GROUPS.items()
        }
        later = fates.fate == Fate.LATER
        _, wait_max = _mean_max(where[later], fates.waits(stream).astype(np.float64), bins.count)
        result.append(StreamTimeline(report, counts, wait_max))
    return result


@dataclass(frozen=True)
class EdgeSeries(Edge):
    """One edge's rate and mean delay (ns) over time (NaN where unknown): what ``--plot`` draws."""

    times: Int64Array
    rate_hz: FloatArray
    delay: FloatArray


def edge_series(
    buffer: Buffer,
    timeline: Timeline,
    start: int | None = None,
    end: int | None = None,
    keys: Sequence[tuple[str, str]] | None = None,
) -> list[EdgeSeries]:
    """The moving edges' rates and delays over ``[start, end]`` (default: their span), in bins (their
    middles), those of ``keys`` only when given."""
    span = edge_axis(buffer, timeline)
    bins = bins_over(span[0] if start is None else start, span[1] if end is None else end)
    middles = bins.edges()[:-1] + bins.width // 2
    edges = edge_timelines(buffer, timeline, bins, pause_floor=0, keys=keys)
    return [EdgeSeries(e.parent, e.child, middles, e.rate_hz, e.delay_mean) for e in edges if not e.static]


class MonitorTrace:
    """The reports of a refreshing ``tfx monitor`` (live, or a replay), kept as each edge's rate and mean
    delay at each refresh."""

    def __init__(self) -> None:
        self._times: list[int] = []
        self._figures: dict[tuple[str, str], dict[int, tuple[float, float]]] = {}

    def add(self, time: int, report: MonitorReport) -> None:
        """The figures of ``report``, shown at ``time`` (ns)."""
        refresh = len(self._times)
        self._times.append(time)
        for e in report.edges:
            if not e.static:
                self._figures.setdefault(e.key, {})[refresh] = (e.rate_hz, e.delay_mean)

    def series(self) -> list[EdgeSeries]:
        """Each edge seen, over every refresh (NaN at those before it appeared or after it left the window)."""
        times = np.array(self._times, np.int64)
        result = []
        for (parent, child), figures in self._figures.items():
            rate, delay = np.full(len(times), np.nan), np.full(len(times), np.nan)
            for refresh, (hz, ns) in figures.items():
                rate[refresh], delay[refresh] = hz, ns
            result.append(EdgeSeries(parent, child, times, rate, delay))
        return result
