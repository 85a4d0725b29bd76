"""Defects seen on the ROS 1 bags and MCAP files added by corpus17, each on the recording that showed it.

Each test skips while its recording awaits placement in the shared corpus, as the rest of the corpus tests do."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

MIR = "ros1-mir-gazebo-landmark-mcl-input-no-map-2021-bag"


def test_topics_in_the_unrecorded_map_frame_are_one_finding(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ruvu/mcl's MiR bag is the input of a localization under test: /initialpose and /landmark_list are in map, and
    nothing recorded publishes map -> odom. One cause, one finding naming both topics, pointing at localization (it
    was two errors, each telling of odometry's odom -> base_link)."""
    result = tfx("wtf", corpus(BY_ID[MIR]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (missing,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert missing["frames"] == ["map"]
    assert "/initialpose (1 of 1 messages), /landmark_list (1 of 1 messages)" in missing["message"]
    assert "'map' is localization's frame" in missing["hint"] and "odom -> base_link" not in missing["hint"]
    assert bag["summary"]["errors"] == 1 and result.code == 1


AGV = "ros1-agv-two-lasers-mounts-on-tf-and-tf-static-replayed-2018-bag"


def test_two_descriptions_of_the_lasers_and_the_odometry_frame_are_told_so(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """frand08/ramon_slam's cartographer bag (a real robot, re-recorded through rosbag play): each laser is under
    laser_link on /tf_static and under base_link on /tf (not 'an object picked up'); base_footprint -> base_link is
    on both too (mixed_static, not also static_on_dynamic: it already is on /tf_static); /odom_enc's frame is the
    odometry's, whose transform is not published (not a mount, not a driver's frame_id)."""
    result = tfx("wtf", corpus(BY_ID[AGV]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    findings = bag["findings"]
    parents = [f for f in findings if f["code"] == "multiple_parents"]
    assert sorted(f["frames"][0] for f in parents) == ["back_laser_link", "front_laser_link"]
    for finding in parents:
        assert "under laser_link on /tf_static and under base_link on /tf" in finding["hint"]
        assert "ROS 1's tf2 keeps it a static frame" in finding["hint"] and "picked up" not in finding["hint"]
    constant = {tuple(f["frames"]) for f in findings if f["code"] == "static_on_dynamic"}
    assert ("base_footprint", "base_link") not in constant and len(constant) == 3
    (odometry,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert "'odom_enc' is the frame of odometry" in odometry["hint"] and "frame_id parameter" not in odometry["hint"]


def test_filter_says_the_odometry_s_own_tf_is_not_published(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The same bag's /odom_enc through `tfx filter`: its advice says what wtf's hint says (one place,
    ``targets.odometry_tf_unpublished``), not "publish its frame's transform, or fix the frame_id"."""
    result = tfx("filter", "/odom_enc", "-b", corpus(BY_ID[AGV]))
    text = " ".join(result.stdout.split())
    assert "'odom_enc' is the frame of odometry (nav_msgs/Odometry)" in text
    assert "fix the frame_id" not in text and result.code == 1
