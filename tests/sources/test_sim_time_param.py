"""Simulated time asked for and never given (issue 32, H3), without a ROS master."""

from __future__ import annotations

import pytest

from tftools.core.time import SimClock
from tftools.sources import ticker
from tftools.sources.live.base import LiveSource, TickedClock
from tftools.sources.live.errors import NoClockError
from tftools.sources.live.ros1.source import Ros1Source, param_is_true


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
    # a clock not told its ROS: each ROS's way, neither said as the only one
    assert "ROS 1: rosbag play --clock" in caught.value.hint and "ROS 2: ros2 bag play --clock" in caught.value.hint


@pytest.mark.parametrize(
    ("ros2", "said", "unsaid"),
    [
        (False, ["rosbag play --clock BAG", "rosparam set /use_sim_time false"],
         ["ros2 bag play", "ROS 2", "ROS 1"]),
        (True, ["ros2 bag play --clock BAG", "use_sim_time=False, a ROS 2 node's default"],
         ["rosbag play", "rosparam", "ROS 1", "/use_sim_time"]),
    ],
)  # fmt: skip
def test_a_clock_told_its_ros_says_the_missing_clock_in_that_ros_words_only(
    monkeypatch: pytest.MonkeyPatch, ros2: bool, said: list[str], unsaid: list[str]
) -> None:
    """The /clock a live ROS 1 (TCPROS) or ROS 2 (DDS) source follows knows its ROS: the error and hint are
    in that ROS's words only (issue 39: both ROSes were named to a user of one)."""
    monkeypatch.setattr(ticker, "CLOCK_PATIENCE", 0.2)
    with pytest.raises(NoClockError) as caught:
        ticker.tick_every(0.1, lambda: None, count=1, clock=TickedClock(ros2))
    words = f"{caught.value} {caught.value.hint}"
    assert caught.value.ros2 is ros2 and "no /clock came in 0.2 s" in words
    assert all(s in words for s in said), words
    assert not any(s in words for s in unsaid), words


@pytest.mark.parametrize("ros2", [False, True])
def test_each_live_source_tells_its_clock_its_ros(ros2: bool) -> None:
    """Without joining a system: the ROS 1 and ROS 2 sources' clocks under use_sim_time know their ROS."""
    kind: type[LiveSource] = Ros1Source
    if ros2:
        pytest.importorskip("cyclonedds")
        from tftools.sources.live.ros2.source import Ros2Source

        kind = Ros2Source
    source = kind.__new__(kind)
    LiveSource.__init__(source, None, True, None)
    assert isinstance(source.clock, TickedClock) and source.clock.ros2 is ros2


def test_ticks_on_a_clock_that_runs_are_counted_on_it() -> None:
    clock = SimClock()
    clock.set(5_000_000_000)
    ticks: list[int] = []

    def tick() -> None:
        ticks.append(clock.now())
        clock.set(clock.now() + 100_000_000)

    ticker.tick_every(0.1, tick, count=3, clock=clock)
    assert ticks == [5_000_000_000, 5_100_000_000, 5_200_000_000]
