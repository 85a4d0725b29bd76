"""Per-edge and per-publisher statistics of a buffer: rates, gaps, delays (tf_monitor's numbers)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.core.buffer import Buffer
from tftools.core.history import EdgeHistory
from tftools.core.time import NS_PER_S

Int64Array = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class EdgeStats:
    """One parent -> child edge over a time window.

    Rates and gaps come from the stamps (sorted, as tf2 stores them); delays are record
    (receive) time minus stamp, NaN where record times are unknown and for static edges.
    """

    parent: str
    child: str
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

    @property
    def key(self) -> tuple[str, str]:
        return (self.parent, self.child)


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
    buffer: Buffer, start: int | None = None, end: int | None = None, *, by_record_time: bool = False
) -> list[EdgeStats]:
    """Statistics of every edge with samples in ``[start, end]`` (static edges always).

    The window selects samples by stamp, or with ``by_record_time`` by when they were
    received (the stamp where that is unknown): what a live monitor saw in its last seconds.
    """
    result = []
    for child, hist in buffer.histories():
        window = _window(hist, start, end, by_record_time)
        for parent_id in _parents_in_order(hist):
            rows = window & (hist.parents == parent_id)
            if rows.any():
                result.append(_edge(buffer, child, buffer.frame_name(int(parent_id)), hist, rows))
    return result


def authority_stats(
    buffer: Buffer, start: int | None = None, end: int | None = None, *, by_record_time: bool = False
) -> list[AuthorityStats]:
    """Each publisher's message rate over the window (as ``edge_stats`` selects it) and its edges."""
    record_times: dict[int, list[Int64Array]] = {}
    delays: dict[int, list[Int64Array]] = {}
    edges: dict[int, list[tuple[str, str]]] = {}
    for child, hist in buffer.histories():
        window = _window(hist, start, end, by_record_time)
        for authority in np.unique(hist.authorities[window]):
            mine = window & (hist.authorities == authority)
            record_times.setdefault(int(authority), []).append(hist.record_times[mine])
            delays.setdefault(int(authority), []).append(_delays(hist, mine))
            for parent_id in np.unique(hist.parents[mine]):
                edges.setdefault(int(authority), []).append((buffer.frame_name(int(parent_id)), child))
    return [
        _authority(buffer.authorities[a], np.unique(np.concatenate(times)), tuple(edges[a]), np.concatenate(delays[a]))
        for a, times in sorted(record_times.items(), key=lambda item: buffer.authorities[item[0]])
    ]


def _authority(name: str, times: Int64Array, edges: tuple[tuple[str, str], ...], delays: Int64Array) -> AuthorityStats:
    times = times[times > 0]
    span = int(times[-1] - times[0]) if len(times) else 0
    rate = (len(times) - 1) * NS_PER_S / span if span > 0 else 0.0
    mean, largest = _mean_max(delays)
    return AuthorityStats(name, len(times), rate, edges, mean, largest)


def _parents_in_order(hist: EdgeHistory) -> list[int]:
    arrival = hist.parents[np.argsort(hist.sequence, kind="stable")]
    ids, first = np.unique(arrival, return_index=True)
    return [int(i) for i in ids[np.argsort(first)]]


def _window(hist: EdgeHistory, start: int | None, end: int | None, by_record_time: bool) -> BoolArray:
    if hist.static:
        return np.ones(len(hist), bool)
    times = hist.stamps
    if by_record_time:
        records = hist.record_times
        times = np.where(records > 0, records, times)
    mask = np.ones(len(times), bool)
    if start is not None:
        mask &= times >= start
    if end is not None:
        mask &= times <= end
    return mask


def _delays(hist: EdgeHistory, rows: BoolArray) -> Int64Array:
    """Record time minus stamp (ns) of the rows where the record time is known; none if static."""
    if hist.static:
        return np.zeros(0, np.int64)
    records = hist.record_times[rows]
    known = records > 0
    return records[known] - hist.stamps[rows][known]


def _mean_max(delays_ns: Int64Array) -> tuple[float, float]:
    if not len(delays_ns):
        return math.nan, math.nan
    return float(delays_ns.mean()) / NS_PER_S, float(delays_ns.max()) / NS_PER_S


def _edge(buffer: Buffer, child: str, parent: str, hist: EdgeHistory, rows: BoolArray) -> EdgeStats:
    stamps = hist.stamps[rows]  # a dynamic history is sorted by stamp already
    dynamic = not hist.static
    intervals = np.diff(stamps) if dynamic else np.zeros(0, np.int64)
    gap_index = int(np.argmax(intervals)) if len(intervals) else 0
    span = int(stamps[-1] - stamps[0])
    delay_mean, delay_max = _mean_max(_delays(hist, rows))
    return EdgeStats(
        parent=parent,
        child=child,
        static=hist.static,
        count=len(stamps),
        authorities=tuple(buffer.authorities[int(a)] for a in np.unique(hist.authorities[rows])),
        first_stamp=int(stamps.min()),
        last_stamp=int(stamps.max()),
        rate_hz=(len(stamps) - 1) * NS_PER_S / span if dynamic and span > 0 else 0.0,
        jitter_s=float(np.std(intervals)) / NS_PER_S if len(intervals) else 0.0,
        gap_max_s=float(intervals[gap_index]) / NS_PER_S if len(intervals) else 0.0,
        gap_start=int(stamps[gap_index]),
        delay_mean_s=delay_mean,
        delay_max_s=delay_max,
        last_record=int(hist.record_times[rows].max()),
    )
