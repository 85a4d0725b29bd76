"""``tick_every``: the live commands' ticking (``echo_stream``'s, live), on the wall clock or on /clock (sim time)."""

from __future__ import annotations

import itertools
import threading
import time

from tftools.core.time import NS_PER_S, SimClock
from tftools.sources.ticker import tick_every


def _play_clock(clock: SimClock, times_s: list[float], stop: threading.Event) -> threading.Thread:
    """A /clock publisher: each time in turn, every 10 ms of wall time."""

    def run() -> None:
        for t in times_s:
            if stop.is_set():
                return
            time.sleep(0.01)
            clock.set(round(t * NS_PER_S))

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread


def test_sim_ticks_wait_for_the_first_clock_then_follow_it() -> None:
    clock = SimClock()  # 0: no /clock heard yet
    ticks: list[int] = []
    stop = threading.Event()
    player = _play_clock(clock, [1000.0 + k * 0.05 for k in range(40)], stop)
    tick_every(0.25, lambda: ticks.append(clock.now()), count=3, clock=clock)
    stop.set()
    player.join()
    assert len(ticks) == 3
    assert ticks[0] >= 1000 * NS_PER_S  # never at time 0, as ros::Time::waitForValid
    steps = [(b - a) / NS_PER_S for a, b in itertools.pairwise(ticks)]
    assert all(0.25 <= step < 0.35 for step in steps)  # 4 Hz of sim time


def test_sim_ticks_stop_while_waiting_for_a_clock_that_never_comes() -> None:
    clock = SimClock()
    ticks: list[int] = []
    began = time.monotonic()
    tick_every(
        0.25, lambda: ticks.append(clock.now()), count=3, stop=lambda: time.monotonic() - began > 0.3, clock=clock
    )
    assert ticks == []


def test_wall_ticks_count_and_pace() -> None:
    ticks: list[float] = []
    tick_every(0.02, lambda: ticks.append(time.monotonic()), count=3)
    assert len(ticks) == 3
    assert 0.015 <= ticks[-1] - ticks[0] < 0.5  # two periods of 20 ms
