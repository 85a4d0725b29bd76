"""Simulated time asked for and never given (issue 32, H3), without a ROS master."""

from __future__ import annotations

import pytest

from tftools.core.time import SimClock
from tftools.sources import ticker
from tftools.sources.live.errors import NoClockError
from tftools.sources.live.ros1.source import param_is_true


@pytest.mark.parametrize(
    ("value", "true"),
    [
        (True, True),
        (False, False),
        (None, False),
        ("false", False),
        ("False", False),
        ("true", True),
        (" TRUE", True),
        (1, True),
        (0, False),
        ("", False),
        ([1], False),
    ],
)
def test_use_sim_time_is_read_as_a_user_means_it(value: object, true: bool) -> None:
    assert param_is_true(value) is true


def test_ticks_on_a_clock_that_never_starts_end_with_the_reason(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(ticker, "CLOCK_PATIENCE", 0.3)
    ticks: list[None] = []
    with pytest.raises(NoClockError, match=r"no /clock came in 0.3 s") as caught:
        ticker.tick_every(0.1, lambda: ticks.append(None), count=3, clock=SimClock())
    assert not ticks and "--clock" in caught.value.hint
    # the clock does not know its ROS: each ROS's way, neither said as the only one (issue 39)
    assert "ROS 1: rosbag play --clock" in caught.value.hint and "ROS 2: ros2 bag play --clock" in caught.value.hint


def test_ticks_on_a_clock_that_runs_are_counted_on_it() -> None:
    clock = SimClock()
    clock.set(5_000_000_000)
    ticks: list[int] = []

    def tick() -> None:
        ticks.append(clock.now())
        clock.set(clock.now() + 100_000_000)

    ticker.tick_every(0.1, tick, count=3, clock=clock)
    assert ticks == [5_000_000_000, 5_100_000_000, 5_200_000_000]
