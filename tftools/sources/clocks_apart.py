"""Clocks apart: frames stamped on a clock other than the tf span's (``Timeline``), on the same time base or
not: a machine 5.8 h ahead of the recorder's, a replay's frames a week behind, a device on the wall clock beside
a simulation. Where they are (``OtherClock``), where a time on one falls on the span's clock (``placed``), and how
far a frame's stamps run ahead of the clock that timed their arrival (``apart``)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from tftools.core import figures
from tftools.core.arrays import Int64Array, UInt8Array
from tftools.core.history import FROM_STATIC_TOPIC
from tftools.core.time import NS_PER_S, duration

if TYPE_CHECKING:
    from tftools.sources.timeline import EdgeClock, Timeline


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


def other_clocks(timeline: Timeline) -> tuple[OtherClock, ...]:
    """The clocks of stamps outside ``timeline``'s tf span, beside the span's own (``clock_groups``, and an
    edge's second publisher's, ``EdgeClock.elsewhere``)."""
    groups = clock_groups(timeline.edges, timeline.same_clock) if timeline.edges else []
    main = next((g for g in groups if any(timeline.tf_start <= e.median_stamp <= timeline.tf_end for e in g)), None)
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
            for e in timeline.edges
            for first, last, offset in e.elsewhere
        ),
    )


def placed(timeline: Timeline, time: int, recorded: int = 0) -> tuple[float, int] | None:
    """A ``time`` that ``Timeline.since_origin`` cannot place, stamped on the clock of frames outside the tf span
    on the same time base (a machine hours ahead of the recorder's, a replay a week behind), moved onto the
    reference: by the arrival of the one sample stamped so where its record time ``recorded`` is known and
    placed (the EKF's first sample arrived at +0.1 s), else by how far their arrivals are from their stamps, the
    median: (seconds from the origin, how far (ns) that clock runs ahead of the origin's, negative where behind);
    None where no such frames' stamps hold it."""
    if not figures.same_base(timeline.origin, time):
        return None
    near = timeline.same_clock
    for other in timeline.other_clocks:
        if other.first - near <= time <= other.last + near:
            arrived = _arrived(timeline, recorded)
            return (time - other.ahead - timeline.origin) / NS_PER_S if arrived is None else arrived, other.ahead
    return None


def _arrived(timeline: Timeline, recorded: int) -> float | None:
    """Seconds from the origin to ROS time at the arrival of a message recorded at ``recorded`` (None: unknown,
    or no moment of the recording)."""
    if recorded <= 0:
        return None
    ros, known = timeline.ros_time(np.array([recorded], np.int64))
    return timeline.since_origin(int(ros[0])) if known[0] else None


def apart(timeline: Timeline, child: str, stamps: Int64Array, record_times: Int64Array, flags: UInt8Array) -> int:
    """How far (ns, the median) the stamps of ``child``'s transforms run ahead of the clock that timed their
    arrival, where none of them has a delay for that (``figures.clocks_apart``); 0 where some have one, or
    none is on a clock ahead."""
    times, measured = timeline.measurable(child, record_times, flags, stamps)
    if measured.any() or not timeline.delays_measured:
        return 0
    times, known = timeline.ros_time(record_times)
    arrived = known & ((flags & FROM_STATIC_TOPIC) == 0)
    read = times[arrived] - stamps[arrived]
    far = read[figures.clocks_apart(read, timeline.same_clock)]
    return -figures.median_ns(far) if len(far) else 0


def ahead_said(timeline: Timeline) -> str:
    """The frames stamped on a clock running ahead of the tf span's on its time base (off it by more than
    ``same_clock``), said beside it: '; imu_link and base_link (a second publisher) on a clock 5.8 h ahead'."""
    ahead = sorted(
        (other.ahead, other.frames)
        for other in timeline.other_clocks
        if other.ahead > timeline.same_clock and figures.same_base(other.first, timeline.origin)
    )
    clocks: list[tuple[int, list[str]]] = []  # one clock: within ``same_clock`` of the one before
    for by, frames in ahead:
        if not clocks or by - clocks[-1][0] > timeline.same_clock:
            clocks.append((by, []))
        clocks[-1][1].extend(frames)
    said = [f"{', '.join(frames)} on a clock {duration(by / NS_PER_S)} ahead" for by, frames in clocks]
    return f"; but {'; '.join(said)} (not in the tf stamps' span)" if said else ""
