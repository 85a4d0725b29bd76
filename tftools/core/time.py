"""Time: integer nanoseconds everywhere, with ROS's conversions and clocks."""

from __future__ import annotations

import math
import threading
import time as _time
from typing import Protocol

NS_PER_S = 1_000_000_000

#: Time 0 asks a lookup for the latest time common to every edge of the chain, as in tf2.
LATEST = 0

#: Stamps below this (2001-09-09) count from boot or a simulation's start, not from the epoch.
EPOCH_FLOOR = 1_000_000_000 * NS_PER_S

#: The last time a time holds (int64 ns: 2262-04-11). A format's unsigned time past it is damage, held as this
#: one: it sorts after every other time, and is said as past 2262.
TIME_MAX = 2**63 - 1


def to_sec(stamp_ns: int) -> float:
    """Seconds as ``ros::Time::toSec`` computes them (``sec + 1e-9 * nsec``, floor-normalised)."""
    sec, nsec = divmod(int(stamp_ns), NS_PER_S)
    return float(sec) + 1e-9 * float(nsec)


def from_sec(seconds: float) -> int:
    """Nanoseconds nearest to ``seconds``."""
    if not math.isfinite(seconds):
        raise ValueError(f"time must be a finite number of seconds, got {seconds}")
    sec = math.floor(seconds)
    return int(sec) * NS_PER_S + round((seconds - sec) * NS_PER_S)


def format_sec(stamp_ns: int, precision: int = 9) -> str:
    """``stamp_ns`` in seconds with ``precision`` decimals, exactly: from the integer, not a double.

    Nine decimals print every nanosecond (1700000007.990000001 and ...123 stay apart, where a
    double would print both as 1700000007.990000010); fewer round half to even, as ``printf``
    rounds a value it holds exactly. tf2's own messages print through a double instead
    (``semantics.Dialect.seconds``), and tftools' copies of them do too.
    """
    if precision < 0:
        raise ValueError(f"precision must be >= 0, got {precision}")
    sign = "-" if stamp_ns < 0 else ""
    units = abs(int(stamp_ns))
    if precision < 9:
        step = 10 ** (9 - precision)
        units, rest = divmod(units, step)
        if 2 * rest > step or (2 * rest == step and units % 2):
            units += 1
    else:
        units *= 10 ** (precision - 9)
    if precision == 0:
        return f"{sign}{units}"
    whole, fraction = divmod(units, 10**precision)
    return f"{sign}{whole}.{fraction:0{precision}d}"


def signed_seconds(seconds: float, digits: int = 1) -> str:
    """The one way a signed seconds figure (an offset, "+S") is shown: its sign, ``digits`` decimals; a moment
    a hair before the origin is "+0.0", never "-0.0"."""
    return f"{round(seconds, digits) + 0.0:+.{digits}f}"


def duration(seconds: float) -> str:
    """``seconds`` in the unit a person would use: "0.044 s", "6.0 days" (a replay's stamps 515,220 s behind
    its record clock), for the checks and the sources' reasons alike."""
    s = abs(seconds)
    if s < 1:
        return f"{seconds:.3f} s"
    if s < 120:
        return f"{seconds:.1f} s"
    if s < 2 * 3600:
        return f"{seconds / 60:.1f} min"
    if s < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} days"


def span_from_to(first: int, last: int) -> str:
    """A span of time as the commands' headers give it: "27.667 s from 46.230 to 73.897" (ns in)."""
    return f"{(last - first) / NS_PER_S:.3f} s from {to_sec(first):.3f} to {to_sec(last):.3f}"


def duration_to_sec(ns: int) -> float:
    """Seconds as ROS 2's tf2 computes them (``tf2::durationToSec``, ``timeToSec``).

    Whole seconds and the rest, both truncated toward zero, the seconds cast to int32, summed
    as ``sec + 1e-9 * nsec``; equal to ``to_sec`` for non-negative times before 2038.
    """
    whole = abs(int(ns)) // NS_PER_S
    sec = whole if ns >= 0 else -whole
    nsec = int(ns) - sec * NS_PER_S
    sec = (sec + 2**31) % 2**32 - 2**31  # static_cast<int32_t>, as the compiler does it
    return float(sec) + 1e-9 * float(nsec)


class Clock(Protocol):
    """What answers "what time is it" for a buffer."""

    def now(self) -> int:
        """The current time in nanoseconds."""
        ...


class WallClock:
    """The system's real-time clock, for live sources without ``use_sim_time``."""

    def now(self) -> int:
        return _time.time_ns()


class SimClock:
    """A simulated clock set by its source (bag time, ``/clock``), like ROS's ``use_sim_time``.

    It stays at 0 until the source first sets it, as ``ros::Time::now()`` does before the
    first ``/clock`` message, and never runs backwards unless ``reset`` is called.
    """

    def __init__(self, start_ns: int = 0) -> None:
        self._now = start_ns
        self._changed = threading.Condition()

    def now(self) -> int:
        return self._now

    def set(self, now_ns: int) -> None:
        """Advance the clock to ``now_ns``; an earlier time is ignored."""
        with self._changed:
            if now_ns > self._now:
                self._now = now_ns
                self._changed.notify_all()

    def reset(self, now_ns: int = 0) -> None:
        """Jump to ``now_ns``, backwards included (a bag replay that loops)."""
        with self._changed:
            self._now = now_ns
            self._changed.notify_all()

    def wait_until(self, stamp_ns: int, timeout_s: float | None = None) -> bool:
        """Block until the clock reaches ``stamp_ns`` or ``timeout_s`` of wall time pass."""
        with self._changed:
            return self._changed.wait_for(lambda: self._now >= stamp_ns, timeout_s)
