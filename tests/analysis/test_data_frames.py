"""``data_frames``: what the headers of a recording without tf say of the tree its data needs (designed streams)."""

from __future__ import annotations

import numpy as np

from tftools.analysis.data_frames import data_frames
from tftools.sources.contents import StampedMessages


def _stream(topic: str, type_name: str, frame_ids: list[str]) -> StampedMessages:
    n = len(frame_ids)
    times = np.arange(n, dtype=np.int64)
    return StampedMessages(topic, type_name, times, times, np.arange(n, dtype=np.int32), frame_ids)


def test_frames_are_grouped_poses_told_apart_and_an_empty_frame_id_said() -> None:
    streams = [
        _stream("/left/image", "sensor_msgs/Image", ["camera"]),
        _stream("/right/image", "sensor_msgs/Image", ["camera"]),
        _stream("/odom", "nav_msgs/Odometry", ["odom"]),
        _stream("/sonar", "sensor_msgs/Range", [""]),
        _stream("/never", "sensor_msgs/Imu", []),  # recorded without a message: nothing to tell
    ]
    topics = {"/dvl": "dvl_msgs/msg/DVL", "/count": "std_msgs/msg/Int32"}
    said = data_frames(streams, topics)
    assert said.frames == ("camera", "odom")
    assert said.figures == {"/left/image": "camera", "/right/image": "camera", "/odom": "odom", "/sonar": ""}
    assert said.said == (
        "; its data is stamped in camera (/left/image, /right/image), odom (poses on /odom), an empty frame_id "
        "(/sonar), which a tree cannot hold; the frames of /dvl are not told (dvl_msgs/msg/DVL: types tfx has no "
        "definition of)"
    )
    assert "a tree for its data must hold camera: what places it" in said.hint
    assert "the poses on /odom as nav_msgs/Odometry become tf only through a node that broadcasts them" in said.hint


def test_nothing_stamped_and_every_type_known_adds_nothing() -> None:
    said = data_frames([_stream("/never", "sensor_msgs/Imu", [])], {"/joy": "sensor_msgs/msg/Joy"})
    assert (said.frames, said.figures, said.said, said.hint) == ((), {}, "", "")
