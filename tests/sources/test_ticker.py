"""``tick_every``, the one ticker of the live and replayed commands, on a fake wall clock."""

from __future__ import annotations

import pytest

from tftools.sources.ticker import tick_every


class Wall:
    """A wall clock that moves only when slept on (or when a tick takes time)."""

    def __init__(self) -> None:
        self.now = 100.0

    def monotonic(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds


def test_ticks_come_every_period_the_first_at_once_or_after_one_period() -> None:
    wall, ticks = Wall(), []
    tick_every(0.5, lambda: ticks.append(wall.now), count=3, sleep=wall.sleep, monotonic=wall.monotonic)
    assert ticks == pytest.approx([100.0, 100.5, 101.0])
    later: list[float] = []
    tick_every(1.0, lambda: later.append(wall.now), duration=2.5, first_now=False, sleep=wall.sleep,
               monotonic=wall.monotonic)  # fmt: skip
    assert later == pytest.approx([102.0, 103.0])


def test_a_slow_tick_is_not_made_up_for_with_a_burst() -> None:
    wall, ticks = Wall(), []

    def slow() -> None:
        ticks.append(wall.now)
        if len(ticks) == 1:
            wall.now += 2.2  # the first tick took more than two periods

    tick_every(1.0, slow, count=3, sleep=wall.sleep, monotonic=wall.monotonic)
    assert ticks == pytest.approx([100.0, 102.2, 103.2])


def test_stop_ends_the_ticks() -> None:
    wall, ticks = Wall(), []
    tick_every(0.1, lambda: ticks.append(wall.now), stop=lambda: len(ticks) == 2, sleep=wall.sleep,
               monotonic=wall.monotonic)  # fmt: skip
    assert len(ticks) == 2
