"""Issue 39's `tfx diff` figures a user would believe (brief diff42), each on the real recordings that showed them;
the designed reproductions are beside the code's own tests (tests/analysis/test_expected.py,
tests/analysis/test_wtf_clocks_and_words.py)."""

from __future__ import annotations

import json
from typing import Any

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tftools.analysis.expected import shape_of
from tftools.sources.recording import read_recording

GUARDIAN = "ros1-robotnik-guardian-real-tilting-laser-pallet-robot-clock-7.6-s-ahead-no-callerid-2014-bag"
SHIP_SIM = "ros1-gazebo-guardian-ship-interior-record-times-from-zero-ground-truth-repeated-stamps-no-callerid-2014-bag"
OKOSLAM_AT_REST = "ros1-okoslam-real-scanner-cartographer-beside-odometry-bridge-at-rest-2019-bag"
OKOSLAM_MOVING = "ros1-okoslam-real-scanner-cartographer-beside-odometry-bridge-moving-2019-bag"
RASPIMOUSE = "ros1-raspimouse-gmapping-robot-clock-ahead-2018-bag"
RASPIMOUSE_REPLAY = "ros1-raspimouse-replayed-with-its-map-odom-beside-live-gmapping-2018-bag"
JETACKER_SIM = "ros2-jetacker-gazebo-slam-toolbox-static-map-2025-db3"
JETACKER_REAL = "ros2-jetacker-real-two-odometries-2026-db3"


def _diff(tfx: Tfx, corpus: Corpus, first: str, second: str) -> tuple[int, list[dict[str, Any]]]:  # noqa: F811
    result = tfx("diff", corpus(BY_ID[first]), corpus(BY_ID[second]), "--format", "json")
    return result.code, json.loads(result.stdout)["differences"]


def test_the_guardians_wheels_turning_in_both_runs_are_compared_by_their_origins(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The real Guardian's pallet run against its Gazebo model: each wheel turns about an origin that never
    changes, (+-0.3, -+0.265, 0) on the real robot, (+-0.3, +-0.306, 0) in Gazebo (left and right swapped between
    the two descriptions, by the bytes). diff compared no value of an edge that moves: the origins, fixed in
    both, now are (571 mm apart), the turning itself is not."""
    code, found = _diff(tfx, corpus, GUARDIAN, SHIP_SIM)
    moved = {d["frame"]: d for d in found if d["change"] == "moved"}
    assert sorted(moved) == ["back_left_wheel", "back_right_wheel", "front_left_wheel", "front_right_wheel"]
    assert {(round(d["translation_mm"], 1), d["rotation_deg"]) for d in moved.values()} == {(571.0, 0.0)}
    assert moved["back_left_wheel"]["message"] == (
        "base_link -> back_left_wheel (on /tf) moved by 571.0 mm (its translation, fixed in both): at xyz [-0.3000, "
        "-0.2650, 0.0000] m, turning by up to 179.96° in A, at xyz [-0.3000, 0.3060, 0.0000] m, turning by up to "
        "0.08° in B"
    )
    assert code == 1


def test_okoslams_two_publishers_of_odometry_each_kept_its_rate(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """okoslam's two cartographer bags: odom -> base_link from /odometry_bridge (20.0 Hz in both) and
    /cartographer_node (197.7 and 198.4 Hz), cartographer starting 3.7 s into the first. diff said "odom ->
    base_link at 218.6 Hz in B, 149.8 Hz in A (A 31% slower)", the two publishers' sum over spans that differ; each
    publisher is compared now, and neither changed. The wheels' 4 mm (held on /tf in both) stay."""
    code, found = _diff(tfx, corpus, OKOSLAM_AT_REST, OKOSLAM_MOVING)
    assert [(d["change"], d["frame"]) for d in found] == [("moved", "wheel_left_link"), ("moved", "wheel_right_link")]
    assert code == 1
    rates = [
        {r.source: round(r.rate_hz, 1) for r in shape_of(read_recording([corpus(BY_ID[i])])).frames["base_link"].rates}
        for i in (OKOSLAM_AT_REST, OKOSLAM_MOVING)
    ]
    assert rates == [
        {"/cartographer_node": 197.7, "/odometry_bridge": 20.0},
        {"/cartographer_node": 198.4, "/odometry_bridge": 20.0},
    ]


def test_the_raspimouse_replay_is_two_clocks_at_20_hz_not_a_rate_of_39(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The raspimouse replayed with its own map -> odom beside a live gmapping: 2,114 samples on two clocks a week
    apart, ~20 Hz each, against the robot's own run at 20.0 Hz. diff said "map -> odom at 39.1 Hz in B, 20.0 Hz in A
    (A 49% slower)" beside the clocks difference; the clocks difference alone now, with each clock's rate. And
    (diff43) the replay's odom -> base_link stopped 2.5 s before the recording ended (its last /tf record 51.55 s
    into 54.03 s, by rosbags' reader): that is said once, the live map -> odom went on."""
    code, found = _diff(tfx, corpus, RASPIMOUSE, RASPIMOUSE_REPLAY)
    clocks, stopped = found
    assert (stopped["change"], stopped["frame"]) == ("stopped", "base_link")
    assert "arrived 51.6 s into B's 54.0 s, silent for its last 2.5 s" in stopped["message"], stopped["message"]
    assert clocks["change"] == "clocks" and clocks["message"].startswith(
        "map -> odom is stamped on 2 clocks (clock 1 20.0 Hz, clock 2 20.0 Hz) in B, on one clock in A"
    ), clocks["message"]
    assert code == 1


def test_the_jetacker_simulations_rates_are_of_its_own_slow_clock(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The JetAcker in Gazebo (simulated time advancing 4.1 s in 62.4 s of recording) against the real one (wall
    clock): odom -> base_footprint 138 samples, 33.3 Hz of simulated time, 2.2 Hz of the recording's clock,
    against 3.9 Hz. diff said "B 88% slower"; the two clocks' seconds differ, and it says so."""
    code, found = _diff(tfx, corpus, JETACKER_SIM, JETACKER_REAL)
    assert not [d for d in found if d["change"] == "rate"]
    by_frame = {d["frame"]: d for d in found if d["change"] == "clocks"}
    assert sorted(by_frame) == ["base_footprint", "link1"]
    assert by_frame["base_footprint"]["message"] == (
        "odom -> base_footprint is stamped on a wall clock (from the epoch) in B, on a clock from a start (simulated "
        "time, or a boot's) advancing 0.066 s a second of its recording in A: 3.9 Hz in B and 33.3 Hz of A's clock "
        "(2.2 Hz of its recording's) in A count seconds of different lengths, not compared as rates"
    )
    assert code == 1


def test_the_guardian_simulations_ground_truth_in_map_is_told_as_a_pose_in_the_world(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The Guardian's Gazebo model: /base_pose_ground_truth, nav_msgs/Odometry from Gazebo's p3d plugin at 1 kHz,
    in 'map' with an empty child_frame_id; nothing on tf names map. The hint said "turn on the odometry node's tf";
    a ground truth has none: the error stays, its hint now says what the pose is and what a lookup into map needs."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[SHIP_SIM]), "--format", "json").stdout)["bags"]
    (truth,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert truth["message"].startswith("/base_pose_ground_truth: 20431 of 20431 messages are in frame 'map'")
    assert "'map' is a world frame (REP 105)" in truth["hint"] and "Gazebo's p3d plugin" in truth["hint"]
    assert "enable_odom_tf" not in truth["hint"] and "needs map -> odom" in truth["hint"]
