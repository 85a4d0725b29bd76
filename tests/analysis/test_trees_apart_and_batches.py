"""Round 49's ROS 1 trial (tests/corpus/test_corpus49.py): a real UR5 whose laser tracker's 'map' tree (tf1's
static_transform_publisher, one identity) stands apart from the arm's moving world tree, and a real Xsens IMU whose
driver stamps each USB packet's samples as it reads them. Designed twins: the frame sensor data is checked in, the
hints of two trees apart, and a rate said as batches."""

from __future__ import annotations

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.frames import tree_of
from tftools.analysis.targets import default_target
from tftools.analysis.wtf import check
from tftools.core.time import NS_PER_S

MS = 1_000_000
ARM = [("world", "base_link"), ("base_link", "shoulder"), ("shoulder", "elbow"), ("elbow", "wrist")]


def _arm(moving: bool) -> list[TfMessage]:
    statics = TfMessage("/tf_static", scenes.START, [scenes._t("world", "base_link", scenes.START)], "/rsp")
    joints = scenes.periodic(
        "/rsp",
        50,
        lambda t: [scenes._t(p, c, t, yaw=(t - scenes.START) / NS_PER_S if moving else 0.0) for p, c in ARM[1:]],
    )
    return [statics, *joints]


def _tracker() -> list[TfMessage]:  # tf1's static_transform_publisher: the same identity every 0.3 s on /tf
    return scenes.periodic("/static_transform_publisher", 1 / 0.3, lambda t: [scenes._t("map", "tracker_frame", t)])


def test_a_rep105_frame_alone_in_a_small_still_tree_is_not_where_data_is_checked() -> None:
    tree = tree_of(scenes.recording([*_arm(moving=True), *_tracker()]).buffer)
    assert tree.frames["tracker_frame"].held and not tree.frames["shoulder"].held
    assert default_target(tree) == ("world", "the root of the largest tree")


def test_a_robot_parked_in_the_largest_tree_keeps_its_odom() -> None:
    """Nothing of the robot moves (odom -> base_link held) while a small tree beside it moves: odom still."""
    parked = scenes.periodic("/odom", 20, lambda t: [scenes._t("odom", "base_link", t)])
    mounts = TfMessage("/tf_static", scenes.START, [scenes._t("base_link", f"m{i}", scenes.START) for i in range(4)])
    target = scenes.periodic(
        "/detector", 10, lambda t: [scenes._t("camera", "tag", t, x=(t - scenes.START) / NS_PER_S)]
    )
    tree = tree_of(scenes.recording([*parked, mounts, *target]).buffer)
    assert default_target(tree) == ("odom", "REP 105's odom frame")


def test_trees_apart_without_odom_are_joined_by_a_fixed_transform_not_localization() -> None:
    findings = check(scenes.recording([*_arm(moving=True), *_tracker()]))
    (apart,) = [f for f in findings if f.code == "disconnected"]
    assert "a static_transform_publisher for a fixed mount)" in apart.hint and "map -> odom" not in apart.hint


def test_samples_stamped_a_batch_at_a_time_are_said_as_batches() -> None:
    """5 samples stamped within 2 ms, then 26 ms on: a driver reading its device's packets (the Xsens at 200 Hz)."""
    messages = []
    for packet in range(300):
        for offset in (0, 200_000, 900_000, 1_100_000, 1_800_000):  # as read off the packet, 0.2 to 0.7 ms apart
            stamp = scenes.START + packet * 26 * MS + offset
            messages.append(
                TfMessage("/tf", stamp + MS, [scenes._t("world", "imu_link", stamp, yaw=packet * 0.01)], "/imu")
            )
    (rate,) = [f for f in check(scenes.recording(messages)) if f.code == "rate"]
    assert "comes in batches: 80% of its intervals are under" in rate.message, rate.message
    assert "about 5.0 samples at a time), the batches 0.024 s apart" in rate.message, rate.message
    assert "keeps up most of the time" not in rate.message and "stamps each as it is read" in rate.hint
