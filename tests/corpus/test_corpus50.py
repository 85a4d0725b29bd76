"""What round 50's scouts found on recordings nobody here had seen (a mapping robot of 2018, CompRobo's Neatos in
Gazebo, e-Yantra's Krishi Bot), fixed on the recording that showed it; the designed reproductions are beside the
code's own tests (tests/analysis/test_wtf_clocks_and_words.py, test_filter_faults.py, test_detections.py,
test_wtf.py; tests/cli/test_monitor.py)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

NAMED_OTHERWISE = "ros1-robo-lape-mounts-named-otherwise-no-tf-2018-bag"
ODOMETRY_LATE = "ros2-neato-gazebo-odometry-starts-late-2025-db3"
TRIANGLE = "ros2-neato-gazebo-drawing-triangle-2025-db3"
FRUITS = "ros1-eyrc-krishibot-gazebo-four-trees-fruit-detections-2022-bag"
TWO_SOURCES = "ros1-eyrc-krishibot-gazebo-two-joint-state-sources-2022-bag"
NAN_AT_THE_END = "ros1-eyrc-krishibot-gazebo-fruit-nan-at-the-end-2022-bag"
STANDING = "ros2-turtlebot4-real-standing-two-static-publishers-2022-db3"
LINEAR_PATH = "ros2-turtlebot3-gazebo-clock-linear-path-2022-db3"


def _findings(tfx: Tfx, path: Path, code: str) -> list[dict[str, Any]]:  # noqa: F811
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    return [f for f in bag["findings"] if f["code"] == code]


def test_a_sensors_frame_named_otherwise_than_its_mount_is_told_the_two_names(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/scan in 'laser' and /imu/data in '/imu' beside mounts base_laser and base_imu, no /tf: told to record /tf,
    where the robot's next recording shows both sides renamed. wtf and filter name the tree's frame."""
    bag = corpus(BY_ID[NAMED_OTHERWISE])
    hints = {tuple(f["frames"]): f["hint"] for f in _findings(tfx, bag, "sensor_frame")}
    assert hints[("laser",)].startswith("the tree has 'base_laser' (base_link -> base_laser) for 'laser'"), hints
    assert hints[("/imu",)].startswith("the tree has 'base_imu' (base_link -> base_imu) for '/imu'"), hints
    assert "rosbag record" in hints[("odom_fake",)]  # odometry's own frame: its tf was not recorded
    report = json.loads(tfx("filter", "-b", bag, "--format", "json").stdout)
    scan = {t["topic"]: t for t in report["topics"]}["/scan"]
    assert scan["namesakes"] == [{"frame_id": "laser", "tree_frame": "base_laser", "parent": "base_link"}]


def test_scans_before_an_odometry_that_started_late_are_not_told_to_record_tf_earlier(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """odom -> base_footprint's first transform came 0.99 s after the wheels' and /stable_scan's, all recorded:
    5 scans before it were told 'record tf from before the sensor'."""
    bag = corpus(BY_ID[ODOMETRY_LATE])
    text = " ".join(tfx("filter", "-b", bag).stdout.split())
    assert "record tf from before the sensor" not in text, text
    assert "odom -> base_footprint's first transform arrived 0.989 s after the first of them" in text, text
    report = json.loads(tfx("filter", "-b", bag, "--format", "json").stdout)
    late = {t["topic"]: t for t in report["topics"]}["/stable_scan"]["began_late"]
    assert (late["parent"], late["child"], round(late["after_s"], 3)) == ("odom", "base_footprint", 0.989), late


def test_a_ros2_bags_listed_publishers_are_said_by_monitor(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A ROS 2 bag names no publisher, but its metadata.yaml lists 2 of /tf (the diff-drive plugin and
    robot_state_publisher) and 1 of /tf_static: monitor said only that none was named."""
    bag = corpus(BY_ID[TRIANGLE])
    listed = json.loads(tfx("monitor", "-b", bag, "-f", "json").stdout)["publishers_listed"]
    assert listed == {
        "/tf": {"publishers": 2, "in": "metadata.yaml"},
        "/tf_static": {"publishers": 1, "in": "metadata.yaml"},
    }
    text = " ".join(tfx("monitor", "-b", bag).stdout.split())
    assert "metadata.yaml lists 2 publishers of /tf and 1 publisher of /tf_static" in text, text


def test_its_trees_apart_are_told_tfx_static_and_its_fruit_hops_no_markers_flip(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    bag = corpus(BY_ID[FRUITS])
    (apart,) = _findings(tfx, bag, "disconnected")
    assert f"tfx static X Y Z YAW PITCH ROLL PARENT CHILD -b {bag} -o COPY adds one to a copy" in apart["hint"]
    (jump,) = _findings(tfx, bag, "jump")
    assert "0.238 m and 0.0°" in jump["message"], jump["message"]
    assert jump["hint"].startswith("a detector's position estimate steps") and "marker" not in jump["hint"]


def test_joints_fed_by_two_joint_state_sources_and_repeats_timed_when_they_came(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The arm's joints arrive irregularly because two sources feed robot_state_publisher /joint_states: told to
    'publish on a timer'. odom -> ebot_base's repeated stamps said 'first at 389.769' beside a JSON time of the
    stamp they repeat (389.647)."""
    bag = corpus(BY_ID[TWO_SOURCES])
    joints = [f for f in _findings(tfx, bag, "rate") if not f["frames"][-1].startswith("fruit_")]
    assert len(joints) == 12, [f["frames"] for f in joints]
    for found in joints:
        assert "of the intervals between its arrivals" in found["message"], found["message"]
        assert found["hint"].startswith("robot_state_publisher sends a joint's transform for each /joint_states")
        assert "rostopic info /joint_states" in found["hint"]
    (repeated,) = _findings(tfx, bag, "time_backwards")
    assert "first at 389.769 (+11.6 s)" in repeated["message"] and repeated["first_time"] == 389.769, repeated


def test_mounts_renamed_between_the_robots_two_bags_are_said_renamed(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Five days apart the robot's mounts went from base_imu and base_laser to imu_frame and laser_frame, the same
    values, and its EKF hung base_link under odom: diff said two frames lost and two added."""
    before, after = corpus(BY_ID[NAMED_OTHERWISE]), corpus(BY_ID["ros1-robo-lape-ekf-repeated-stamps-2018-bag"])
    said = tfx("diff", before, after).stdout
    assert "base_imu in A is imu_frame in B, renamed" in said and "base_laser in A is laser_frame in B, renamed" in said
    assert "lost" not in said, said


def test_echo_inside_a_detections_long_gap_says_it_interpolates_across_it(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """fruit_red_1 unseen for 13.99 s: echo printed a value inside it like any other."""
    bag = corpus(BY_ID[FRUITS])
    result = tfx("echo", "camera_depth_frame2", "fruit_red_1", "-b", bag, "--at", "23.529")
    assert result.code == 0, result.stderr
    assert "the lookup falls where camera_depth_frame2 -> fruit_red_1 had no sample for 13.987 s" in result.stderr


def test_a_detection_ending_in_nan_is_stale_beneath_the_refusal_and_its_joints_told_joint_states(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """fruit_red's last 33 transforms NaN, their stamps going on: said 'stopped advancing at 50.489, re-sent to the
    end' with a stalled localizer's hint. The arm's joints arriving in pairs were told a USB driver's batches, then
    (round 50) /joint_states' rhythm; their stamps are one source's, every 20 ms, one in five 14 ms early: no rate
    warning at all (round 51, tests/analysis/test_wtf.py's jittered stamps)."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[NAN_AT_THE_END]), "--format", "json").stdout)["bags"]
    (stale,) = [f for f in bag["findings"] if f["code"] == "stale" and f["frames"][-1] == "fruit_red"]
    assert "holds nothing newer than 50.489 (+50.4 s): the 33 transforms sent after it" in stale["message"], stale
    assert "re-sent" not in stale["message"] and "stalled localizer" not in stale["hint"]
    (refused,) = [f for f in bag["findings"] if f["code"] == "invalid_values" and f["frames"][-1] == "fruit_red"]
    assert stale["cause"] == refused["key"] and refused["key"], (stale["cause"], refused["key"])
    joints = [f for f in bag["findings"] if f["code"] == "rate" and not f["frames"][-1].startswith("fruit_")]
    assert not joints, [f["message"] for f in joints]


def test_a_few_scans_waiting_are_all_within_and_the_conflict_names_the_values_kept(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real TurtleBot 4's 116 scans were '99.9% within 0.115 s' (99.9% of 116 is all of them); its static
    conflict ended 'tf2 keeps the last received for every time: publisher 2's', read as cut off."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[STANDING]), "--format", "json").stdout)["bags"]
    (waiting,) = [f for f in bag["findings"] if f["code"] == "sensor_wait"]
    assert "(all within 0.115 s)" in waiting["message"] and "99.9%" not in waiting["message"], waiting["message"]
    (conflict,) = [f for f in bag["findings"] if f["code"] == "static_conflict"]
    assert conflict["message"].endswith("tf2 keeps the values last received for every time: publisher 2's")


def test_imu_messages_before_tf_are_said_left_out_of_the_wait(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The simulated TurtleBot3's first 5 IMU messages, stamped before its odometry's first, vanished from wtf's
    counts ('5168 of 5280 waited' beside 107 on arrival)."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[LINEAR_PATH]), "--format", "json").stdout)["bags"]
    (imu,) = [f for f in bag["findings"] if f["code"] == "sensor_wait" and f["message"].startswith("/imu:")]
    assert imu["message"].endswith("(5 stamped before the recording's tf of their chain began: undecided, left out)")
