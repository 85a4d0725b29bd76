"""A live source's clock jumping back, seen as tf2_ros's listeners see it.

tf2_ros clears its buffer when time goes backwards (a bag replay that loops, a clock set back), or
the new pass's transforms would be refused as too old while lookups keep answering the old pass's.
ROS 1's ``TransformListener`` compares ``ros::Time::now()`` at each message with its value at the one
before; ROS 2's ``Buffer`` clears on its clock's jump callback. ``BufferCore::clear`` keeps statics.
Here, for both, ``watch_jumps`` reads the source's clock at each batch delivered.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tftools.core.arrays import BoolArray
from tftools.core.batch import TransformBatch, take_rows
from tftools.core.time import Clock, SimClock, to_sec
from tftools.sources.live.base import LiveSource, OnBatch


@dataclass(frozen=True)
class TimeJump:
    """The source's clock read earlier than at the batch before: from ``before`` to ``after`` (ns)."""

    before: int
    after: int
    sim_time: bool  # ROS time from /clock, else the wall clock

    def notice(self) -> str:
        """The line that says it, e.g. ``ROS time jumped back from 1012.300 s to 1000.000 s (a looped
        replay?): cleared the tf buffer, static transforms kept``."""
        clock, guess = ("ROS time", "a looped replay?") if self.sim_time else ("wall time", "the clock set back?")
        span = f"from {to_sec(self.before):.3f} s to {to_sec(self.after):.3f} s"
        return f"{clock} jumped back {span} ({guess}): cleared the tf buffer, static transforms kept"

    def stale(self, batch: TransformBatch) -> BoolArray:
        """The dynamic rows of ``batch`` stamped about the time before the jump, nearer it than the time
        after (within half the jump either side): the pass before's last transforms, sent before the clock
        went back but delivered after. A stamp further ahead is of neither pass (tf2_ros's time_reset_test
        sends one after the jump): it is kept, as tf2_ros keeps it."""
        half = (self.before - self.after) // 2
        return ~batch.static & (batch.stamp > self.after + half) & (batch.stamp <= self.before + half)


#: Called with each jump back, before the batch that revealed it is delivered.
OnJump = Callable[[TimeJump], None]


class JumpDetector:
    """Reads ``clock`` at each ``check`` (from one thread) and tells when it went back since the last."""

    def __init__(self, clock: Clock) -> None:
        self._clock = clock
        self._last = clock.now()

    def check(self) -> TimeJump | None:
        now = self._clock.now()
        before, self._last = self._last, now
        if now >= before:
            return None
        return TimeJump(before, now, isinstance(self._clock, SimClock))


def watch_jumps(
    source: LiveSource,
    on_batch: Callable[[TransformBatch], object],
    on_jump: OnJump,
    now: Callable[[], float] | None = None,
) -> OnBatch:
    """``on_batch`` as ``source.start`` takes it, with jumps back of the source's clock seen first:
    ``on_jump`` is called (to clear what was heard) and said through ``source.notice``, then the batch
    that revealed the jump is passed on, as tf2_ros stores the message whose callback cleared its buffer.
    A clock that keeps jumping is said at most once every ``QUIET_SECONDS`` (of ``now``, by default
    ``time.monotonic``), with a count.

    ``/clock`` and ``/tf`` come on separate connections, so around a replay's loop either pass's
    transforms may come after the clock went back: the pass before's (``stale``) are dropped, and if
    none of the new pass's are left, the clearing waits for the next batch, so that lookups never
    find the cleared buffer empty."""
    detector = JumpDetector(source.clock)
    waiting: TimeJump | None = None  # a jump whose batch held only the pass before's transforms
    said = _SaidEvery(QUIET_SECONDS, now or time.monotonic)

    def watch(batch: TransformBatch) -> None:
        nonlocal waiting
        jump = detector.check() or waiting
        if jump is not None:
            stale = jump.stale(batch)
            if stale.any():
                batch = take_rows(batch, np.flatnonzero(~stale))
                if waiting is None and not np.any(~batch.static):
                    waiting = jump  # nothing of the new pass yet: clear with the next batch
                    jump = None
            if jump is not None:
                waiting = None
                on_jump(jump)
                said(source.notice, jump.notice())
        if len(batch):
            on_batch(batch)

    return watch


#: A clock going back and forth jumps at every pass: after a jump is said, those of the next second are
#: counted, and said with the next one said (a replay looping every few seconds is said at every loop).
QUIET_SECONDS = 1.0


class _SaidEvery:
    """Says a line at most once every ``seconds`` (of ``now``), with how many went unsaid since."""

    def __init__(self, seconds: float, now: Callable[[], float]) -> None:
        self._seconds, self._now = seconds, now
        self._last: float | None = None
        self._unsaid = 0

    def __call__(self, say: Callable[[str], object], line: str) -> None:
        at = self._now()
        if self._last is not None and at - self._last < self._seconds:
            self._unsaid += 1
            return
        plural = "" if self._unsaid == 1 else "s"
        more = f" ({self._unsaid} more jump{plural} back since the last said)" if self._unsaid else ""
        say(line + more)
        self._last, self._unsaid = at, 0
