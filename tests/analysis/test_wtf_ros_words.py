"""Issue 39 item 5: each hint names the tools and concepts of the recording's own ROS (as ``no_tf`` and
``leading_slash`` do): latched in ROS 1, transient local durability (QoS) in ROS 2, and each ROS's commands."""

from __future__ import annotations

import pytest

from tests.analysis.wtf_scenes import PROBLEMS, recording
from tftools.analysis.findings import Finding
from tftools.analysis.wtf.fleet import check


def _only(code: str, ros1: bool) -> Finding:
    (found,) = [f for f in check(recording(PROBLEMS[code].make(), ros1=ros1)).findings if f.code == code]
    return found


@pytest.mark.parametrize(
    ("ros1", "said", "unsaid"),
    [
        (True, ("latched", "rosbag play without -s"), ("transient local", "ros2 bag")),
        (False, ("transient local", "ros2 bag play without --start-offset"), ("latched", "rosbag play")),
    ],
    ids=["ros1", "ros2"],
)
def test_statics_only_at_the_start_are_repaired_in_the_recordings_own_words(
    ros1: bool, said: tuple[str, ...], unsaid: tuple[str, ...]
) -> None:
    hint = _only("statics_early", ros1).hint
    assert all(words in hint for words in said), hint
    assert not any(words in hint for words in unsaid), hint
