"""Clocks apart: frames stamped on a clock other than the tf span's (``Timeline``; the clocks themselves:
``edge_clocks.OtherClock``), on the same time base or not: a machine 5.8 h ahead of the recorder's, a replay's
frames a week behind, a device on the wall clock beside a simulation. Where a time on one falls on the span's
clock (``placed``), and how far a frame's stamps run ahead of the clock that timed their arrival (``apart``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from tftools.core import figures
from tftools.core.arrays import Int64Array, UInt8Array
from tftools.core.history import FROM_STATIC_TOPIC
from tftools.core.time import NS_PER_S

if TYPE_CHECKING:
    from tftools.sources.timeline import Timeline


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
