"""``tfx filter``'s advice: what keeps the messages a MessageFilter loses, said for every reason they are lost."""

from __future__ import annotations

import dataclasses

import pytest
from rich.console import Console

from tftools.analysis.filter.fates import LOST, Fate, FilterReport, StreamReport
from tftools.analysis.targets import odometry_tf_unpublished, world_pose_unpublished
from tftools.core.time import NS_PER_S
from tftools.render.filter import renderable


def _lost(reason: str, messages: int = 229, never: int = 5) -> StreamReport:
    """A stream of which ``never`` messages were lost for ``reason``, and no timeout keeps them."""
    waits = dict.fromkeys(("p50", "p95", "p99", "max"), 0.0)
    return StreamReport(
        "/wall", "visualization_msgs/msg/Marker", ("base_link",), messages, messages - never, 0, never, waits,
        {reason: never}, None, 0.0, None, 0, None, lost_edge=("base_footprint", "base_link"),
    )  # fmt: skip


def _said(stream: StreamReport, width: int = 400) -> str:
    console = Console(width=width, record=True)
    report = FilterReport("odom", "REP 105's odom frame", 10 * NS_PER_S, [stream], [], {})
    console.print(renderable(report))
    return " ".join(console.export_text().split())


@pytest.mark.parametrize("fate", LOST, ids=[f.reason for f in LOST])
def test_no_timeout_can_is_never_said_alone(fate: Fate) -> None:
    """A real Neato's /wall markers (ros2_db3_neato_real_fsm_odom_jump_2023), stamped 0, 5 of them arriving
    before odom's tf: tf2 drops them as older than its cache, and `tfx filter` said "to keep 99.9%: no timeout
    can", and stopped there. Each reason a message is lost for good comes with what keeps it instead."""
    said = _said(_lost(fate.reason))
    assert "no timeout can" in said
    assert "no timeout can (" in said, said


def test_a_stamp_too_old_for_the_cache_is_told_to_be_stamped_when_measured() -> None:
    for width in (400, 80):  # the table and, where it does not fit, the paragraphs
        said = _said(_lost("older_than_cache"), width)
        assert "no timeout can (stamp each message when it was measured, on the clock tf is stamped on)" in said


def test_messages_all_stamped_0_are_told_once_what_keeps_them() -> None:
    """The same Neato's /wall markers as tfx counts them (all 5 lost stamped 0, before their chain): one advice,
    to set header.stamp, not a second one to stamp each message when it was measured."""
    said = _said(dataclasses.replace(_lost("older_than_cache"), stamped_zero=5))
    assert "no timeout can, 5 stamped 0 arrived before their tf: no cache keeps them; set header.stamp" in said
    assert "when it was measured" not in said


@pytest.mark.parametrize("msgtype", ["nav_msgs/Odometry", "nav_msgs/msg/Odometry"])
def test_odometry_in_a_frame_no_transform_names_is_told_its_own_tf_is_not_published(msgtype: str) -> None:
    """frand08/ramon_slam's cartographer bag: /odom_enc (nav_msgs/Odometry) in odom_enc, which nothing on tf
    names. `tfx filter` said "publish its frame's transform, or fix the frame_id" where `tfx wtf` says the
    odometry's own tf is not published: both say it in the same words."""
    odometry = dataclasses.replace(_lost("unknown_frame", 427, 427), topic="/odom_enc", type=msgtype)
    odometry = dataclasses.replace(odometry, frame_ids=("odom_enc",))
    for width in (400, 80):
        said = _said(odometry, width)
        assert f"no timeout can ({' '.join(odometry_tf_unpublished(repr('odom_enc')).split())})" in said, said
        assert "'odom_enc' is the frame of odometry" in said and "enable_odom_tf" in said
        assert "fix the frame_id" not in said
    sensor = dataclasses.replace(odometry, type="sensor_msgs/msg/LaserScan")
    assert "no timeout can (publish its frame's transform, or fix the frame_id)" in _said(sensor)


def test_an_empty_frame_id_is_said_empty_not_left_blank() -> None:
    """foxglove-wizard's drone.mcap: /pose_stamped's 17 default-made messages have an empty frame_id, the rest
    world. The table and the paragraphs said ', world' and 'in  world'."""
    stream = dataclasses.replace(_lost("empty_frame"), frame_ids=("", "world"))
    for width in (400, 80):
        said = _said(stream, width)
        assert "(empty)" in said and " , world" not in said and "in , world" not in said, said


def test_a_ground_truth_pose_in_map_is_told_as_tfx_wtf_tells_it() -> None:
    """corpus33's Guardian in Gazebo: /base_pose_ground_truth (nav_msgs/Odometry) in 'map': `tfx filter` says
    what `tfx wtf` says of a pose in the world (``world_pose_unpublished``), not the odometry's own tf."""
    truth = dataclasses.replace(_lost("unknown_frame", 427, 427), topic="/base_pose_ground_truth", frame_ids=("map",))
    truth = dataclasses.replace(truth, type="nav_msgs/msg/Odometry", unplaced=world_pose_unpublished("'map'", True))
    said = _said(truth)
    assert f"no timeout can ({' '.join(world_pose_unpublished(repr('map'), True).split())})" in said, said
    assert "enable_odom_tf" not in said
