"""Which clock each frame's stamps are on: an ``EdgeClock`` per frame (how its arrivals relate to the
recording's clocks), frames grouped by clock (``clock_groups``), and the clocks outside the tf span beside its own
(``OtherClock``): a machine 5.8 h ahead of the recorder's, a replay's frames a week behind. What ``Timeline``
is built from; ``clocks_apart`` places times on those clocks against a timeline."""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from tftools.core import figures
from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.time import NS_PER_S, duration
from tftools.values import value


@value
class EdgeClock:
    """How one frame's dynamic transforms relate to the recording's clocks (medians of arrival - stamp, ns)."""

    child: str
    arrivals: int  # transforms with a known record time
    offset_record: int  # record time minus stamp
    offset_clock: int | None  # /clock at arrival minus stamp; None without /clock (or none arrived after it)
    median_stamp: int
    median_record: int
    first_stamp: int = 0
    last_stamp: int = 0
    reach_record: int = 0  # how far arrival strays from the stamp (95th percentile of |record time - stamp|)
    reach_clock: int = 0  # the same against /clock at arrival
    bases: int = 1  # time bases its samples are on (``figures.time_base_of``); all but the main one left out
    last_record: int = 0  # its last arrival (record time): how long it has been silent (``figures.silence``)
    # its samples on the other time bases: (first stamp, last stamp, record time minus stamp: the median)
    elsewhere: tuple[tuple[int, int, int], ...] = ()

    def offset(self, against_clock: bool) -> int | None:
        """Arrival minus stamp against /clock or the record clock (None: never arrived under /clock)."""
        return self.offset_clock if against_clock else self.offset_record

    def agrees(self, against_clock: bool, tolerance: int) -> bool:
        """Whether the stamps follow that clock: at most ``tolerance`` behind it, or ahead on its time base."""
        offset = self.offset(against_clock)
        if offset is None or offset > tolerance:
            return False
        reference = self.median_stamp + offset
        return offset >= -tolerance or figures.same_base(self.median_stamp, reference)


def edge_clock(child: str, stamps: Int64Array, records: Int64Array, ros: Int64Array, known: BoolArray) -> EdgeClock:
    """How ``child``'s transforms (``stamps`` recorded at ``records``, when /clock said ``ros`` where
    ``known``) relate to the recording's clocks: those on the time base most of them are on, where they are
    on several (``figures.time_base_of``: a replay's and a live publisher's, a week apart), so that no span
    or offset of one frame is measured across two clocks."""
    arrivals = len(stamps)  # all of them, on any base
    offsets, span = records - stamps, figures.record_span(records)
    bases = figures.time_bases(offsets, span)
    elsewhere: list[tuple[int, int, int]] = []
    if bases > 1:
        base = figures.time_base_of(offsets, span)
        main = int(np.argmax(np.bincount(base)))
        for other in sorted(set(base.tolist()) - {main}):
            theirs = base == other
            elsewhere.append((int(stamps[theirs].min()), int(stamps[theirs].max()), figures.median_ns(offsets[theirs])))
        mine = base == main
        stamps, records, ros, known, offsets = stamps[mine], records[mine], ros[mine], known[mine], offsets[mine]
    offset_clock: int | None = None
    reach_clock = 0
    if known.any():
        offset_clock, reach_clock = _median_and_reach(ros[known] - stamps[known])
    offset_record, reach_record = _median_and_reach(offsets)
    return EdgeClock(
        child,
        arrivals,
        offset_record,
        offset_clock,
        figures.median_ns(stamps),
        figures.median_ns(records),
        int(stamps.min()),
        int(stamps.max()),
        reach_record,
        reach_clock,
        bases,
        int(records.max()),
        tuple(elsewhere),
    )


def _median_and_reach(read: Int64Array) -> tuple[int, int]:
    """``figures.median_ns(read)`` and ``_reach(read)``: of offsets none of them negative (most edges' arrivals
    after their stamps), from one partition."""
    if not len(read) or read.min() < 0:
        return figures.median_ns(read), _reach(read)
    median, reach = figures.median_and_percentile(read, 95)
    return median, int(reach)


def _reach(read: Int64Array) -> int:
    """The 95th percentile of how far arrival strays from the stamp, either way (ns)."""
    return int(figures.percentile(np.abs(read), 95)) if len(read) else 0


def stamps_behind(edges: Sequence[EdgeClock]) -> int:
    """How far (ns) the frames' stamps are behind the record clock, negative where ahead: the median of
    their record times minus the median of their stamps."""
    stamp, record = stamp_medians(edges)
    return record - stamp


def stamp_medians(edges: Sequence[EdgeClock]) -> tuple[int, int]:
    """The median of the frames' median stamps, and of their median record times (exact: ``median_ns``)."""
    stamps = np.array([e.median_stamp for e in edges], np.int64)
    records = np.array([e.median_record for e in edges], np.int64)
    return figures.median_ns(stamps), figures.median_ns(records)


class OtherClock(NamedTuple):
    """A clock of stamps outside the tf span, beside the span's own (``other_clocks``)."""

    frames: tuple[str, ...]  # the frames on it ("part of imu_link": an edge's second publisher's samples)
    first: int  # its first and last stamp
    last: int
    ahead: int  # how far (ns) it runs ahead of the span's clock, both against the record clock (negative: behind)


def clock_groups(edges: Sequence[EdgeClock], same_clock: int) -> list[list[EdgeClock]]:
    """The frames (some) grouped by clock: their offsets from the record clock in order, a new group
    where the next is more than ``same_clock`` further."""
    ordered = sorted(edges, key=lambda e: e.offset_record)
    groups: list[list[EdgeClock]] = [[ordered[0]]]
    for e in ordered[1:]:
        if e.offset_record - groups[-1][-1].offset_record > same_clock:
            groups.append([])
        groups[-1].append(e)
    return groups


def stamp_groups(edges: Sequence[EdgeClock], same_clock: int) -> list[list[EdgeClock]]:
    """The frames (some) grouped by their stamps alone, where record times time nothing
    (``Timeline.record_clock_void``: their offsets from it are the stamps themselves, so ``clock_groups`` would
    part two detections on one clock seen 20 s apart): in order of first stamp, a new group where the next
    begins more than ``same_clock`` after every stamp before it."""
    ordered = sorted(edges, key=lambda e: e.first_stamp)
    groups: list[list[EdgeClock]] = [[ordered[0]]]
    last = ordered[0].last_stamp
    for e in ordered[1:]:
        if e.first_stamp - last > same_clock:
            groups.append([])
        groups[-1].append(e)
        last = max(last, e.last_stamp)
    return groups


def other_clocks(groups: Sequence[Sequence[EdgeClock]], tf_start: int, tf_end: int) -> tuple[OtherClock, ...]:
    """The clocks of stamps outside the tf span (``tf_start`` to ``tf_end``), beside the span's own: the frames'
    ``groups`` (``Timeline.clocks``) and an edge's second publisher's samples (``EdgeClock.elsewhere``)."""
    edges = [e for g in groups for e in g]
    main = next((g for g in groups if any(tf_start <= e.median_stamp <= tf_end for e in g)), None)
    if main is None:
        return ()
    own = main[0].offset_record
    return (
        *(
            OtherClock(
                tuple(e.child for e in g),
                min(e.first_stamp for e in g),
                max(e.last_stamp for e in g),
                own - g[0].offset_record,
            )
            for g in groups
            if g is not main
        ),
        *(
            OtherClock((f"part of {e.child}",), first, last, own - offset)
            for e in edges
            for first, last, offset in e.elsewhere
        ),
    )


def ahead_said(others: Sequence[OtherClock], origin: int, same_clock: int) -> str:
    """The frames stamped on a clock running ahead of the tf span's (its first stamp: ``origin``) on its time
    base (off it by more than ``same_clock``: ``others``), said beside it: '; imu_link and base_link (a second
    publisher) on a clock 5.8 h ahead'."""
    ahead = sorted(
        (other.ahead, other.frames)
        for other in others
        if other.ahead > same_clock and figures.same_base(other.first, origin)
    )
    clocks: list[tuple[int, list[str]]] = []  # one clock: within ``same_clock`` of the one before
    for by, frames in ahead:
        if not clocks or by - clocks[-1][0] > same_clock:
            clocks.append((by, []))
        clocks[-1][1].extend(frames)
    said = [f"{', '.join(frames)} on a clock {duration(by / NS_PER_S)} ahead" for by, frames in clocks]
    return f"; but {'; '.join(said)} (not in the tf stamps' span)" if said else ""
