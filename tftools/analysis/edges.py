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
    """One publisher: its message rate (distinct record times per second) and its edges."""

    authority: str
    messages: int
    rate_hz: float
    edges: tuple[tuple[str, str], ...]


def edge_stats(buffer: Buffer, start: int | None = None, end: int | None = None) -> list[EdgeStats]:
    """Statistics of every edge whose samples have stamps in ``[start, end]`` (static edges always)."""
    result = []
    for child, hist in buffer.histories():
        for parent_id in _parents_in_order(hist):
            rows = hist.parents == parent_id
            if not hist.static:
                rows &= _in_window(hist.stamps, start, end)
            if rows.any():
                result.append(_edge(buffer, child, buffer.frame_name(int(parent_id)), hist, rows))
    return result


def authority_stats(buffer: Buffer, start: int | None = None, end: int | None = None) -> list[AuthorityStats]:
    """Each publisher's message rate over the window and the edges it published (static ones too)."""
    record_times: dict[int, list[Int64Array]] = {}
    edges: dict[int, list[tuple[str, str]]] = {}
    for child, hist in buffer.histories():
        window = np.ones(len(hist), bool) if hist.static else _in_window(hist.stamps, start, end)
        for authority in np.unique(hist.authorities[window]):
            mine = window & (hist.authorities == authority)
            record_times.setdefault(int(authority), []).append(hist.record_times[mine])
            for parent_id in np.unique(hist.parents[mine]):
                edges.setdefault(int(authority), []).append((buffer.frame_name(int(parent_id)), child))
    return [
        _authority(buffer.authorities[a], np.unique(np.concatenate(times)), tuple(edges[a]))
        for a, times in sorted(record_times.items(), key=lambda item: buffer.authorities[item[0]])
    ]


def _authority(name: str, times: Int64Array, edges: tuple[tuple[str, str], ...]) -> AuthorityStats:
    span = int(times[-1] - times[0]) if len(times) else 0
    rate = (len(times) - 1) * NS_PER_S / span if span > 0 else 0.0
    return AuthorityStats(name, len(times), rate, edges)


def _parents_in_order(hist: EdgeHistory) -> list[int]:
    arrival = hist.parents[np.argsort(hist.sequence, kind="stable")]
    ids, first = np.unique(arrival, return_index=True)
    return [int(i) for i in ids[np.argsort(first)]]


def _in_window(stamps: Int64Array, start: int | None, end: int | None) -> npt.NDArray[np.bool_]:
    mask = np.ones(len(stamps), bool)
    if start is not None:
        mask &= stamps >= start
    if end is not None:
        mask &= stamps <= end
    return mask


def _edge(buffer: Buffer, child: str, parent: str, hist: EdgeHistory, rows: npt.NDArray[np.bool_]) -> EdgeStats:
    stamps = hist.stamps[rows]
    records = hist.record_times[rows]
    order = np.argsort(stamps, kind="stable")
    stamps, records = stamps[order], records[order]
    intervals = np.diff(stamps)
    gap_index = int(np.argmax(intervals)) if len(intervals) else 0
    span = int(stamps[-1] - stamps[0])
    dynamic = not hist.static
    known = records > 0
    delays = (records[known] - stamps[known]) / NS_PER_S if dynamic else np.zeros(0)
    return EdgeStats(
        parent=parent,
        child=child,
        static=hist.static,
        count=len(stamps),
        authorities=tuple(buffer.authorities[int(a)] for a in np.unique(hist.authorities[rows])),
        first_stamp=int(stamps[0]),
        last_stamp=int(stamps[-1]),
        rate_hz=(len(stamps) - 1) * NS_PER_S / span if dynamic and span > 0 else 0.0,
        jitter_s=float(np.std(intervals)) / NS_PER_S if dynamic and len(intervals) else 0.0,
        gap_max_s=float(intervals[gap_index]) / NS_PER_S if dynamic and len(intervals) else 0.0,
        gap_start=int(stamps[gap_index]),
        delay_mean_s=float(delays.mean()) if len(delays) else math.nan,
        delay_max_s=float(delays.max()) if len(delays) else math.nan,
        last_record=int(records.max()),
    )
