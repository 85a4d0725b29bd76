"""Sensor data in a tree apart from the frame it is checked in: the trees apart (``disconnected``) said once, with
each stream's ``sensor_frame`` beneath it, whose hint names the lookups that fail (those into the target) and not
the ones that work (within the stream's own tree); data in a frame no transform names stays its own finding.

As on the corpus' ros2_db3_ias0220_gazebo_diff_cont_2025: a simulated robot's odom tree beside a real IMU device's
imu_link -> ultrasound_distance_sensor, /imu and /distance in the device's frames."""

from __future__ import annotations

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.findings import Finding, Severity, causes, explained
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.contents import StampedMessages

START = 1_700_000_000 * NS_PER_S
PERIOD = NS_PER_S // 10
N = 100


def _tf(stamp: int, parent: str, child: str, yaw: float) -> Transform:
    return Transform.from_rpy((0.0, 0.0, yaw), (0.1, 0.0, 0.0), stamp, parent, child)


def _stream(topic: str, frame: str) -> StampedMessages:
    """Stamped with the transforms, recorded 1 ms after them."""
    stamps = START + np.arange(N, dtype=np.int64) * PERIOD
    return StampedMessages(topic, "sensor_msgs/Imu", stamps + 1_000_000, stamps, np.zeros(N, np.int32), [frame])


def _findings(*streams: StampedMessages) -> list[Finding]:
    stamps = [START + i * PERIOD for i in range(N)]
    tf = [
        TfMessage("/tf", t, [_tf(t, "odom", "base_link", 0.01 * i), _tf(t, "imu_link", "sonar", 0.02 * i)])
        for i, t in enumerate(stamps)
    ]
    rec = recording(tf, ros1=False)
    return findings_of(Scene(rec, streams=list(streams), target="odom"))


def test_data_in_the_other_tree_follows_the_trees_apart() -> None:
    findings = _findings(_stream("/imu", "imu_link"), _stream("/distance", "sonar"))
    (apart,) = causes(findings)
    assert apart.code == "disconnected" and apart.severity is Severity.error
    beneath = explained(findings, apart)
    assert [(f.code, f.message.split(":")[0]) for f in beneath] == [
        ("sensor_frame", "/imu"),
        ("sensor_frame", "/distance"),
    ]
    for f in beneath:
        assert "into odom fails (within its own tree they work)" in f.hint, f.hint
        assert "every tf lookup" not in f.hint


def test_data_in_a_frame_no_transform_names_is_its_own_finding() -> None:
    findings = _findings(_stream("/imu", "imu_link"), _stream("/camera", "camera_optical"))
    unknown = [f for f in findings if f.code == "sensor_frame" and "which no transform names" in f.message]
    assert [f.cause for f in unknown] == [""], findings
    assert unknown[0].hint.endswith("every tf lookup and MessageFilter on this data fails")
    (apart,) = [f for f in findings if f.code == "disconnected"]
    assert [f.message.split(":")[0] for f in explained(findings, apart)] == ["/imu"]


def _map_scene(*edges: tuple[str, str]) -> Scene:
    stamps = [START + i * PERIOD for i in range(N)]
    tf = [TfMessage("/tf_static", START, [_tf(START, "base_link", "imu_link", 0.0)])]
    tf += [TfMessage("/tf", t, [_tf(t, p, c, 0.01 * i) for p, c in edges]) for i, t in enumerate(stamps)]
    imu = _stream("/markers", "map")
    stream = StampedMessages("/markers", "mocap4r2_msgs/msg/Markers", imu.record_time, imu.stamp, imu.frame, ["map"])
    return Scene(recording(tf, ros1=False), streams=[stream], target=edges[0][0])


def test_data_in_map_is_said_the_same_by_filter_and_wtf() -> None:
    """CyberShip Voyager's motion capture (corpus ros2-cybership-voyager-mocap-basin-2025-mcap): /markers in 'map',
    the ship under 'world', no odom. wtf's sensor_frame says 'map' is not localization's here; tfx filter said
    "publish its frame's transform, or fix the frame_id". Both say wtf's words (``world_frame_unpublished``), as
    they do where 'map' is localization's (an odom frame, no map -> odom)."""
    for edges, words in (
        ((("world", "base_link"),), "with no odom frame 'map' is not localization's (REP 105) here"),
        ((("odom", "base_link"),), "'map' is localization's frame (REP 105)"),
    ):
        scene = _map_scene(*edges)
        (unknown,) = [f for f in findings_of(scene) if f.code == "sensor_frame"]
        (stream,) = scene.sensors.streams
        assert words in stream.unplaced and unknown.hint.startswith(stream.unplaced), (stream.unplaced, unknown.hint)
    assert (
        "ros2 run tf2_ros static_transform_publisher with world as parent and map as child"
        in _map_scene(("world", "base_link")).sensors.streams[0].unplaced
    )  # ROS 2's command for a ROS 2 type
