"""The one ticker of the live and replayed commands: a call every period, of the wall or of a simulated
clock (``/clock``, as ``ros::Rate`` under sim time). Light: ``tfx`` loads it with a live command."""

from __future__ import annotations

import time
from collections.abc import Callable

from tftools.core.time import Clock, SimClock, from_sec

__all__ = ["CLOCK_PATIENCE", "tick_every"]

#: Seconds of wall time to wait for the first /clock under simulated time.
CLOCK_PATIENCE = 10.0
#: The longest wall sleep between two looks at ``stop`` (and at a simulated clock).
_POLL_S = 0.05


def tick_every(
    period: float,
    on_tick: Callable[[], object],
    *,
    count: int | None = None,
    stop: Callable[[], bool] = lambda: False,
    duration: float | None = None,
    first_now: bool = True,
    clock: Clock | None = None,
    since: int | None = None,
    sleep: Callable[[float], None] = time.sleep,
    monotonic: Callable[[], float] = time.monotonic,
) -> None:
    """Call ``on_tick`` every ``period`` seconds (the first at once, or after one period), ``count`` times
    (None: until ``stop()`` or until ``duration`` wall seconds have passed, a tick due by then included).

    Seconds of ``clock`` when it is a ``SimClock``: its first time is waited for, as
    ``ros::Time::waitForValid`` (``NoClockError`` after ``CLOCK_PATIENCE`` wall seconds without one), the
    periods counted from ``since`` (default: its first time), and a jump back (a replay restarted) starts
    again from there; a tick the clock reached is made even if ``stop()`` came meanwhile. Else of the wall:
    a tick that runs late is not made up for with a burst of ticks, as ``ros::Rate``."""
    if isinstance(clock, SimClock):
        _on_sim_clock(from_sec(period), on_tick, count, stop, first_now, clock, since)
        return
    started = monotonic()
    due = started if first_now else started + period
    end = None if duration is None else started + duration
    done = 0
    while count is None or done < count:
        now = monotonic()
        if now >= due and (end is None or due <= end):  # a tick due as the duration ends, or stop comes, is made
            on_tick()
            done += 1
            due += period
            if due <= now:  # fell behind (a slow tick): skip, do not burst
                due = now + period
            continue
        if stop() or (end is not None and now >= end):
            break
        until = due if end is None else min(due, end)
        sleep(max(0.0, min(until - now, _POLL_S)))


def _on_sim_clock(
    period: int,
    on_tick: Callable[[], object],
    count: int | None,
    stop: Callable[[], bool],
    first_now: bool,
    clock: SimClock,
    since: int | None,
) -> None:
    given_up = time.monotonic() + CLOCK_PATIENCE
    while clock.now() == 0 and not stop():  # no /clock yet: wait for a valid time, as ros::Time::waitForValid
        if time.monotonic() > given_up:  # ... which waits for ever: a forgotten --clock
            from tftools.sources.live.base import TickedClock
            from tftools.sources.live.errors import NoClockError

            raise NoClockError(CLOCK_PATIENCE, clock.ros2 if isinstance(clock, TickedClock) else None)
        clock.wait_until(1, timeout_s=0.1)
    if clock.now() == 0:  # stopped before the clock came: no tick is due on a clock that never began
        return
    due = (clock.now() if since is None else since) + (0 if first_now else period)
    done = 0
    while count is None or done < count:
        if clock.now() < due - period:  # the clock jumped back (a replay restarted): start again from there
            due = clock.now()
        if clock.wait_until(due, timeout_s=0.1):
            on_tick()
            done += 1
            due += period
        elif stop():
            break
