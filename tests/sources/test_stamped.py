"""Sensor data's headers per topic: the streams of a split recording's files merged into one."""

from __future__ import annotations

import numpy as np

from tftools.sources.contents import StampedMessages
from tftools.sources.headers import merged


def _stream(topic: str, times: list[int], frames: list[int], names: list[str]) -> StampedMessages:
    record_time = np.array(times, np.int64)
    return StampedMessages(
        topic, "sensor_msgs/msg/Imu", record_time, record_time - 5, np.array(frames, np.int32), names
    )


def test_a_topic_of_two_files_is_one_stream_in_record_order_naming_only_its_frames() -> None:
    first = _stream("/imu", [10, 30], [2, 2], ["map", "odom", "imu_left"])
    second = _stream("/imu", [20, 40], [0, 1], ["imu_right", "imu_left"])
    other = _stream("/scan", [15], [0], ["laser"])
    scan, imu = merged([first, other, second])[::-1]
    assert imu.record_time.tolist() == [10, 20, 30, 40] and imu.stamp.tolist() == [5, 15, 25, 35]
    assert list(imu.frame_ids) == ["imu_left", "imu_right"]
    assert [imu.frame_ids[f] for f in imu.frame.tolist()] == ["imu_left", "imu_right", "imu_left", "imu_left"]
    assert (scan.topic, list(scan.frame_ids), scan.frame.tolist()) == ("/scan", ["laser"], [0])
