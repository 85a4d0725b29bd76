"""What round 49's new-user trial found on recordings nobody here had seen (aerostack2's simulated Crazyflie, whose
cf0/base_link two sources send under two parents at each of the same stamps), fixed on the recording that showed
it; the designed reproductions are beside the code's own tests (tests/analysis/test_two_parents_at_once.py)."""

from __future__ import annotations

import json

import tftools
from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

CRAZYFLIE = "ros2-crazyflie-gazebo-aerostack2-base-link-two-parents-model-tree-apart-sim-stamps-no-clock-2023-db3"


def test_two_sources_of_base_link_at_once_are_one_cause_and_no_stamp_goes_back(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Gazebo's bridge (cf0 -> cf0/base_link) and the estimator (cf0/odom -> cf0/base_link) each send all 194 stamps
    once, rising. Before: time_backwards blamed cf0/odom -> cf0/base_link for '194 stamps it had already sent', and
    multiple_parents spoke of 'an object picked up'. Now the stamps under both parents are multiple_parents' own
    observation, and its hint ends the odometry at the model's root."""
    code, findings = _findings(tfx, corpus(BY_ID[CRAZYFLIE]))
    assert code == 1 and not [f for f in findings if f["code"] == "time_backwards"]
    (parents,) = [f for f in findings if f["code"] == "multiple_parents"]
    assert "it changed parent 357 times" in parents["message"] and "194 stamps came under both" in parents["message"]
    assert "the odometry should end at it (cf0/odom -> cf0)" in parents["hint"], parents["hint"]


def test_sensor_data_is_checked_in_the_robots_namespaced_odom(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The target was cf0, 'the root of the largest tree' (Gazebo's model): the estimator's pose (in earth) and twist
    were errors and the IMU, the one stream that cannot reach odom, a note. Now cf0/odom: the IMU's 582 messages are
    in a tree apart, and the twist's 7 messages whose stamp tf2 answers under cf0 are said as such."""
    result = tfx("wtf", corpus(BY_ID[CRAZYFLIE]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    assert bag["sensor_data"]["target"] == "cf0/odom"
    apart = {f["message"].split(":")[0]: f["message"] for f in bag["findings"] if f["code"] == "sensor_frame"}
    assert set(apart) == {"/cf0/sensor_measurements/imu", "/cf0/self_localization/twist"}
    assert "582 of 582 messages" in apart["/cf0/sensor_measurements/imu"]
    assert (
        "7 of 194 messages are in cf0/base_link at stamps where tf2 answers cf0/base_link under another parent"
        in (apart["/cf0/self_localization/twist"])
    )


def test_filter_holds_a_message_while_tf2_answers_its_stamp_under_the_other_parent(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Each twist is stamped at one of base_link's stamps. Before: 184 on arrival, 10 later, 0 never, while `tfx
    echo cf0/odom cf0/base_link --at 15.684` fails. From the arrival orders in the bytes (ROS 2's tf2 answers a stamp
    from its sample received last): 121 + 5 after the odom sample last, on arrival; 51 + 5 + 5 waiting for it; 7
    after the cf0 sample last, never."""
    result = tfx("filter", "-b", corpus(BY_ID[CRAZYFLIE]), "--format", "json")
    twist = next(t for t in json.loads(result.stdout)["topics"] if t["topic"] == "/cf0/self_localization/twist")
    assert (twist["on_arrival"], twist["later"], twist["never"]) == (126, 61, 7)
    assert twist["reasons"] == {"not_connected": 7} and round(twist["late_rate_hz"], 1) == 83.3
    echo = tfx("echo", "cf0/odom", "cf0/base_link", "-b", corpus(BY_ID[CRAZYFLIE]), "--at", "15.684")
    assert "not part of the same tree" in echo.stdout + echo.stderr


def test_the_two_parents_edges_figures_agree_across_commands(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """`tfx frames` showed cf0/base_link's parents as 'cf0 (194) → cf0/odom (194)' (one switch, where it switched
    357 times) beside the frame's 167.1 Hz, monitor named cf0/base_link twice in its /tf row, and report counted
    15 moving transforms where view-frames draws 16 moving edges. Each edge now at monitor's 83.3 Hz."""
    path = corpus(BY_ID[CRAZYFLIE])
    frames = tfx("frames", "-b", path)
    assert "parents in turn (samples): cf0 (194, 83.3 Hz) ⇄ cf0/odom (194, 83.3 Hz)" in frames.stdout, frames.stdout
    broadcasters = tfx("monitor", "-b", path).stdout.split("All Broadcasters:")[1]
    assert broadcasters.count("cf0/base_link") == 1, broadcasters
    facts = dict(tftools.report(tftools.read_recording([path])).facts)
    assert facts["Frames"] == "19 frames; 16 moving and 2 static transforms"


UR5 = "ros1-ur5-real-moveit-laser-tracker-tree-apart-tf1-static-publisher-2019-bag"
XSENS = "ros1-xsens-mti-imu-alone-stamps-in-batches-2022-bag"


def test_the_arms_data_is_checked_in_its_own_tree_and_the_trackers_said_apart(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real UR5's world tree beside its laser tracker's map -> tracker_frame (tf1's static_transform_publisher,
    one identity). Before: checked in 'map' (REP 105 names it), three errors on the arm's own /wrench, /tool_velocity
    and /joint_temperature, and /tracker_points, the one stream apart, unnamed; the hints spoke of base_link -> the
    sensor's frame and of localization's map -> odom, in a recording without odom."""
    result = tfx("wtf", corpus(BY_ID[UR5]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    assert bag["sensor_data"]["target"] == "world"
    (apart,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert apart["message"].startswith("/tracker_points: 200 of 200 messages are in tracker_frame, in a tree apart")
    assert "a static_transform_publisher world -> map where they are fixed to each other" in apart["hint"]
    (trees,) = [f for f in bag["findings"] if f["code"] == "disconnected"]
    assert "map -> odom" not in trees["hint"] and "base_link -> the sensor's frame" not in apart["hint"]


def test_an_imus_stamps_in_batches_are_said_as_batches(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real Xsens MTi: 81% of its intervals under 2 ms, the rest about 26 ms. Before: '81% of its intervals are
    more than 50% off the 0.026 s it keeps up most of the time', hinting at far-apart samples (the largest 0.029 s)."""
    _, findings = _findings(tfx, corpus(BY_ID[XSENS]))
    (rate,) = [f for f in findings if f["code"] == "rate"]
    assert rate["message"] == (
        "world -> imu_link by /xsens_mti_node comes in batches: 81% of its intervals are under 0.002 s (about 5.4 "
        "samples at a time), the batches 0.026 s apart (200.2 Hz on average)"
    )


def test_an_absolute_time_example_is_on_the_recordings_own_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The Crazyflie's tf is stamped on simulation time (15.3 to 17.6 s): asked at a wall-clock time, the hint's
    example of an absolute time was 1700000012.5, itself a wall-clock time, refused the same way."""
    result = tfx("echo", "cf0", "cf0/rotor_0", "-b", corpus(BY_ID[CRAZYFLIE]), "--at", "1683557378")
    assert result.code == 2 and "give absolute seconds (e.g. 16.4)" in result.stderr, result.stderr
