"""``tfx filter`` against the real tf2 on a bag the real rosbag wrote, and on its ROS2 copies.

The oracle (tests/oracle/sensor_bag.py) reads the bag with rosbag and replays a MessageFilter on a
tf2 BufferCore; tftools reads the same recording with its own readers, message by message.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from tests.oracle import ROS_PYTHON
from tests.sources.bag.test_rosbag2 import convert
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.filter.fates import NEVER, Fate, message_fates
from tftools.core.time import NS_PER_S
from tftools.sources.recording import read_recording

HARNESS = Path(__file__).parents[1] / "oracle" / "sensor_bag.py"


def _harness(*arguments: str) -> str:
    done = subprocess.run([ROS_PYTHON, str(HARNESS), *arguments], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


@pytest.fixture(scope="module")
def recordings(tmp_path_factory: pytest.TempPathFactory, tf2_available: None) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("rosbag")
    bag = folder / "robot.bag"
    _harness("write", str(bag))
    return {
        "ros1": bag,
        "db3": convert(bag, folder / "robot_db3", "sqlite3"),
        "mcap": convert(bag, folder / "robot_mcap", "mcap"),
    }


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
@pytest.mark.parametrize(("target", "cache_s"), [("odom", 10.0), ("map", 10.0), ("odom", 0.5)])
def test_each_message_is_ready_when_the_real_tf2_says(
    recordings: dict[str, Path], fmt: str, target: str, cache_s: float
) -> None:
    expected = json.loads(_harness("replay", str(recordings["ros1"]), target, str(cache_s)))
    recording = read_recording([recordings[fmt]], headers=())
    buffer, streams = recording.buffer, recording.stamped.streams
    assert {s.topic for s in streams} == set(expected)
    for stream in streams:
        fates = message_fates(buffer, stream, target, round(cache_s * NS_PER_S))
        oracle = np.array([NEVER if r is None else r for r in expected[stream.topic]], np.int64)
        mismatched = np.flatnonzero(fates.ready != oracle)
        assert not len(mismatched), (stream.topic, [(int(fates.ready[i]), int(oracle[i])) for i in mismatched[:3]])


def test_each_stream_gets_the_reason_a_ros_user_would_see(recordings: dict[str, Path]) -> None:
    recording = read_recording([recordings["ros1"]], headers=())
    report = filter_streams(recording.buffer, recording.stamped.streams, FilterQuery())
    streams = {s.topic: s for s in report.streams}
    assert report.target == "odom"
    scan, imu, camera, points = (streams[t] for t in ("/scan", "/imu", "/camera/image_raw", "/points"))
    # A scan stamped 7 ms after a laser transform arrives 5 ms later; that transform comes 30 ms after its
    # stamp: each scan needs the next one, 50 ms on. The last scan's would have come after the recording.
    assert (scan.later, scan.never, scan.reasons) == (599, 0, {})
    assert scan.undecided == {Fate.AFTER_RECORDED_TF.reason: 1}
    assert scan.wait["p50"] == pytest.approx(0.068 * NS_PER_S) and scan.late_edge == ("base_link", "laser")
    assert (imu.on_arrival, imu.never) == (2998, 0)  # the last two: stamped past the last odometry recorded
    assert camera.reasons == {Fate.UNKNOWN_FRAME.reason: 150} and camera.never == 150
    assert points.reasons == {Fate.TOO_OLD_ON_ARRIVAL.reason: 30}  # dropped by add() itself
    assert points.undecided == {}
    assert points.cache_needed == 15 * NS_PER_S  # 12 s behind the newest transform
