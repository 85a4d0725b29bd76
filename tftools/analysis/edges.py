"""Per-edge and per-publisher statistics of a buffer: rates, gaps, delays (tf_monitor's numbers)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from tftools.core.arrays import BoolArray, Int32Array, Int64Array, IntpArray
from tftools.core.buffer import Buffer
from tftools.core.history import EdgeHistory
from tftools.core.time import NS_PER_S
from tftools.sources.timeline import ON_RECORD_CLOCK, Timeline

#: An edge counts as stale, or a pause as a gap, only when it lasts this many of its periods too.
PERIODS = 10


@dataclass(frozen=True)
class Gaps:
    """The pauses in an edge's stamps longer than ``PERIODS`` periods and a floor (ns)."""

    period: int  # the median interval between consecutive stamps
    count: int
    longest: int
    longest_start: int  # the stamp the longest one begins at
    first: int  # where the first one begins, and the last one ends
    last: int


def rate_hz(samples: int, span: int) -> float:
    """The one definition of a rate: ``samples`` over a span of ``span`` ns, (samples - 1) / span; 0
    for fewer than two samples or an empty span."""
    return (samples - 1) * NS_PER_S / span if samples > 1 and span > 0 else 0.0


def silence_limit(rate: float, floor: int = 0) -> float:
    """How long (ns) an edge publishing at ``rate`` Hz (its ``rate_hz``) may be silent and still be publishing:
    ``PERIODS`` of its periods, and at least ``floor``. The one definition ``stale`` and the filter's replay share."""
    return max(float(floor), PERIODS * NS_PER_S / rate if rate > 0 else 0.0)


def edge_gaps(stamps: Int64Array, floor: int) -> Gaps | None:
    """The gaps of an edge's sorted ``stamps``: intervals longer than ``floor`` and ``PERIODS`` times
    the usual one; None if there is none. The one definition of a gap, as ``EdgeStats.gap_max_s``
    is of the longest interval."""
    if len(stamps) < 3:
        return None
    period, intervals, gaps = gap_rows(stamps, floor)
    if not len(gaps):
        return None
    longest = int(gaps[np.argmax(intervals[gaps])])
    return Gaps(
        period,
        len(gaps),
        int(intervals[longest]),
        int(stamps[longest]),
        int(stamps[gaps[0]]),
        int(stamps[gaps[-1] + 1]),
    )


def gap_rows(stamps: Int64Array, floor: int) -> tuple[int, Int64Array, IntpArray]:
    """The median interval of sorted ``stamps``, the intervals, and the rows ``i`` where the interval
    from ``stamps[i]`` to ``stamps[i + 1]`` is a gap (see ``edge_gaps``)."""
    intervals = np.diff(stamps)
    period = int(np.median(intervals)) if len(intervals) else 0
    return period, intervals, np.flatnonzero(intervals > max(floor, PERIODS * period))


@dataclass(frozen=True)
class Edge:
    """A parent -> child edge, by its frames' names."""

    parent: str
    child: str

    @property
    def key(self) -> tuple[str, str]:
        return (self.parent, self.child)


@dataclass(frozen=True)
class EdgeStats(Edge):
    """One parent -> child edge over a time window.

    Rates and gaps come from the stamps (sorted, as tf2 stores them); delays are ROS time at
    arrival minus stamp (``Timeline.delays``), NaN where that is unknown and for static edges.
    """

    static: bool
    count: int
    authorities: tuple[str, ...]
    first_stamp: int
    last_stamp: int
    rate_hz: float  # (count - 1) / stamp span; 0 for static or single samples
    jitter_s: float  # standard deviation of the intervals between stamps
    gap_max_s: float  # the longest interval between two consecutive stamps
    gap_start: int  # stamp where that interval begins
    delay_mean_s: float
    delay_max_s: float
    last_record: int  # latest record time (0 where unknown)


@dataclass(frozen=True)
class AuthorityStats:
    """One publisher: its message rate (distinct record times per second), its edges, and
    the mean and largest delay of its dynamic transforms (tf_monitor's "Node:" line)."""

    authority: str
    messages: int
    rate_hz: float
    edges: tuple[tuple[str, str], ...]
    delay_mean_s: float = math.nan
    delay_max_s: float = math.nan


def edge_stats(
    buffer: Buffer,
    start: int | None = None,
    end: int | None = None,
    *,
    by_record_time: bool = False,
    timeline: Timeline | None = None,
) -> list[EdgeStats]:
    """Statistics of every edge with samples in ``[start, end]`` (static edges always).

    ``timeline`` turns record times into ROS time (a recording's); without it, record times are
    ROS time (a live buffer's). The window selects samples by stamp, or with ``by_record_time``
    by when they arrived (the stamp where that is unknown): what a live monitor saw in its last seconds.
    The largest gap counts every interval that overlaps the window: the one from the last
    sample before it, and with ``by_record_time`` and an ``end``, the silence since the last
    arrival (so an edge that stopped shows it at once, not when it leaves the window).
    """
    timeline = timeline or ON_RECORD_CLOCK
    result = []
    for parent, child, hist, mine in edge_rows(buffer):
        rows = _window(hist, start, end, by_record_time, timeline) & mine
        if rows.any():
            before = _previous_stamp(hist, mine, rows) if start is not None else None
            silence_end = end if by_record_time else None
            result.append(_edge(buffer, child, parent, hist, rows, timeline, before, silence_end))
    return result


def authority_stats(
    buffer: Buffer,
    start: int | None = None,
    end: int | None = None,
    *,
    by_record_time: bool = False,
    timeline: Timeline | None = None,
) -> list[AuthorityStats]:
    """Each publisher's messages over the window (as ``edge_stats`` selects it) and its edges.

    Its rate counts the messages of its moving edges only: a latched static message sent
    once is not part of a rhythm (tf_monitor lists static publishers apart).
    """
    moving: dict[int, list[Int64Array]] = {}
    static: dict[int, list[Int64Array]] = {}
    delays: dict[int, list[Int64Array]] = {}
    edges: dict[int, list[tuple[str, str]]] = {}
    timeline = timeline or ON_RECORD_CLOCK
    for child, hist in buffer.histories():
        window = _window(hist, start, end, by_record_time, timeline)
        for authority in _ids(hist.authorities[window]):
            a = int(authority)
            mine = window & (hist.authorities == authority)
            (static if hist.static else moving).setdefault(a, []).append(hist.record_times[mine])
            delays.setdefault(a, []).append(_delays(child, hist, mine, timeline))
            edges.setdefault(a, []).extend((buffer.frame_name(int(p)), child) for p in _ids(hist.parents[mine]))
    return [
        _authority(buffer.authorities[a], _arrivals(moving.get(a)), _arrivals(static.get(a)), edges[a], delays[a])
        for a in sorted(edges, key=lambda a: buffer.authorities[a])
    ]


def _arrivals(record_times: list[Int64Array] | None) -> Int64Array:
    """The distinct known record times: one per message."""
    if not record_times:
        return np.zeros(0, np.int64)
    times = sorted_unique(np.concatenate(record_times))
    return times[times > 0]


def sorted_unique(values: Int64Array) -> Int64Array:
    """``np.unique`` for arrays made of a few sorted runs: timsort merges runs in linear time."""
    ordered = np.sort(values, kind="stable")
    if len(ordered) < 2:
        return ordered
    keep = np.empty(len(ordered), bool)
    keep[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=keep[1:])
    return ordered[keep]


def _authority(
    name: str, moving: Int64Array, static: Int64Array, edges: list[tuple[str, str]], delays: list[Int64Array]
) -> AuthorityStats:
    rate = rate_hz(len(moving), int(moving[-1] - moving[0])) if len(moving) else 0.0
    messages = len(np.union1d(moving, static)) if len(static) else len(moving)
    mean, largest = _mean_max(np.concatenate(delays))
    return AuthorityStats(name, messages, rate, tuple(edges), mean, largest)


def _ids(values: Int32Array) -> IntpArray:
    """The distinct small non-negative ids in ``values``, ascending (faster than ``np.unique``)."""
    return np.flatnonzero(np.bincount(values)) if len(values) else np.zeros(0, np.intp)


def publishers(buffer: Buffer, authorities: Int32Array) -> tuple[str, ...]:
    """The names of the distinct ``authorities`` (ids of ``buffer``'s), by id."""
    return tuple(buffer.authorities[int(a)] for a in _ids(authorities))


def parents_in_order(hist: EdgeHistory) -> list[int]:
    """The ids of every parent ``hist`` had, first seen first: the one order a frame's history splits into edges."""
    parents = hist.parents
    if len(parents) and parents.min() == parents.max():  # the usual case: one parent ever
        return [int(parents[0])]
    arrival = hist.parents[np.argsort(hist.sequence, kind="stable")]
    ids, first = np.unique(arrival, return_index=True)
    return [int(i) for i in ids[np.argsort(first)]]


def edge_rows(buffer: Buffer) -> Iterator[tuple[str, str, EdgeHistory, BoolArray]]:
    """Each parent -> child edge of ``buffer``: its frames, its child's history, and which of the history's
    rows are the edge's (a frame that changed parent has an edge per parent, ``parents_in_order``)."""
    for child, hist in buffer.histories():
        for parent_id in parents_in_order(hist):
            yield buffer.frame_name(parent_id), child, hist, hist.parents == parent_id


def chain_edges(buffer: Buffer, frames: Sequence[str]) -> list[tuple[str, str]]:
    """The (parent, child) edges joining the neighbours of ``frames`` (a ``Buffer.chain``), in its order."""
    return [(b, a) if buffer.parent(a) == b else (a, b) for a, b in itertools.pairwise(frames)]


def _window(
    hist: EdgeHistory, start: int | None, end: int | None, by_record_time: bool, timeline: Timeline
) -> BoolArray:
    if hist.static:
        return np.ones(len(hist), bool)
    times = timeline.arrival(hist.stamps, hist.record_times) if by_record_time else hist.stamps
    mask = np.ones(len(times), bool)
    if start is not None:
        mask &= times >= start
    if end is not None:
        mask &= times <= end
    return mask


def _previous_stamp(hist: EdgeHistory, mine: BoolArray, rows: BoolArray) -> int | None:
    """The stamp of the edge's sample just before the first one in the window, if any."""
    if hist.static:
        return None
    earlier = np.flatnonzero(mine[: int(np.argmax(rows))])
    return int(hist.stamps[earlier[-1]]) if len(earlier) else None


def _delays(child: str, hist: EdgeHistory, rows: BoolArray, timeline: Timeline) -> Int64Array:
    return timeline.delays(child, hist.stamps[rows], hist.record_times[rows], hist.flags[rows])


def _mean_max(delays_ns: Int64Array) -> tuple[float, float]:
    if not len(delays_ns):
        return math.nan, math.nan
    return float(delays_ns.mean()) / NS_PER_S, float(delays_ns.max()) / NS_PER_S


def _edge(
    buffer: Buffer,
    child: str,
    parent: str,
    hist: EdgeHistory,
    rows: BoolArray,
    timeline: Timeline,
    before: int | None,
    silence_end: int | None,
) -> EdgeStats:
    stamps = hist.stamps[rows]  # a dynamic history is sorted by stamp already
    records = hist.record_times[rows]
    dynamic = not hist.static
    intervals = np.diff(stamps) if dynamic else np.zeros(0, np.int64)
    arrived = int(timeline.arrival(stamps, records).max())
    gap, gap_start = _largest_gap(stamps, intervals, before, silence_end - arrived if silence_end else 0)
    delay_mean, delay_max = _mean_max(_delays(child, hist, rows, timeline))
    return EdgeStats(
        parent=parent,
        child=child,
        static=hist.static,
        count=len(stamps),
        authorities=publishers(buffer, hist.authorities[rows]),
        first_stamp=int(stamps.min()),
        last_stamp=int(stamps.max()),
        rate_hz=rate_hz(len(stamps), int(stamps[-1] - stamps[0])) if dynamic else 0.0,
        jitter_s=float(np.std(intervals)) / NS_PER_S if len(intervals) else 0.0,
        gap_max_s=gap / NS_PER_S if dynamic else 0.0,
        gap_start=gap_start,
        delay_mean_s=delay_mean,
        delay_max_s=delay_max,
        last_record=int(records.max()),
    )


def _largest_gap(stamps: Int64Array, intervals: Int64Array, before: int | None, silence: int) -> tuple[int, int]:
    """The longest interval (ns) and the stamp it begins at: between samples, from the one
    before the window, or the silence since the last arrival."""
    candidates = [(0, int(stamps[0]))]
    if len(intervals):
        i = int(np.argmax(intervals))
        candidates.append((int(intervals[i]), int(stamps[i])))
    if before is not None:
        candidates.append((int(stamps[0]) - before, before))
    if silence > 0:
        candidates.append((silence, int(stamps[-1])))
    return max(candidates, key=lambda c: c[0])
