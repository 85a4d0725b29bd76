"""A live source's errors in the words of the ROS it listens to (issue 39: both ROSes named to a user of one)."""

from __future__ import annotations

import pytest

from tftools.sources.live.base import LiveSource, OnBatch
from tftools.sources.live.errors import NoTransformsHeardError
from tftools.sources.live.sensor_headers import capture_live


class _Silent(LiveSource):
    """A live system of one ROS that sends no transform."""

    format = "test-live"

    def __init__(self, ros2: bool | None) -> None:
        self.ros2 = ros2
        super().__init__(None, False, None)

    def start(self, on_batch: OnBatch) -> None:
        pass

    def describe(self) -> str:
        return "a silent robot"

    def close(self) -> None:
        self._closed.set()


@pytest.mark.parametrize(
    ("ros2", "ask", "unsaid"),
    [
        (False, "(rostopic info /tf)", "ros2"),
        (True, "(ros2 topic info /tf --verbose)", "rostopic"),
        (None, "(rostopic info /tf on ROS 1, ros2 topic info /tf --verbose on ROS 2)", "nothing"),
    ],
)
def test_nothing_heard_asks_who_publishes_in_the_sources_ros_words(ros2: bool | None, ask: str, unsaid: str) -> None:
    with pytest.raises(NoTransformsHeardError, match=r"no transforms on /tf, /tf_static from a silent robot") as caught:
        capture_live(_Silent(ros2), 0.05)
    assert ask in caught.value.hint and unsaid not in caught.value.hint
