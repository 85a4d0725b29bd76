"""What corpus32's recordings showed, fixed on the recordings that showed it; the designed reproductions are beside
the code's own tests (tests/analysis/test_description.py, tests/analysis/test_wtf_clocks_and_words.py)."""

from __future__ import annotations

import json

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

THRICE = "ros2-eyrc-hologlyph-holonomic-bot-gazebo-planar-move-three-times-odometry-thrice-metadata-renamed-2023-db3"

HOLOGLYPH = {
    "ros2-eyrc-hologlyph-holonomic-bot-gazebo-plugin-default-base-footprint-two-trees-wheels-on-wall-clock-2023-db3": (
        "rear_wheel"
    ),
    "ros2-eyrc-hologlyph-holonomic-bot-gazebo-started-after-recording-wall-clock-wheels-before-clock-2023-db3": (
        "front_wheel"
    ),
    THRICE: "rear_wheel",
}


@pytest.mark.parametrize("name", sorted(HOLOGLYPH))
def test_the_descriptions_own_frames_are_named_as_such(name: str, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """e-Yantra's Hologlyph bot in Gazebo: its URDF (recorded on /robot_description) is rooted at footprint_link
    with three continuous wheels, which robot_state_publisher, without use_sim_time, sends on the wall clock
    (joint_state_publisher's zeros); Gazebo's planar move, its ROS 1 tags unread, sends its default
    odom -> base_footprint on /clock's time. wtf said 'static_on_dynamic: ... publish it once on /tf_static (... or
    a fixed joint ...)' of each wheel, 'a device on the wall clock beside the simulation' of the wheels, and
    'publish the transform that attaches odom to the footprint_link tree ... or check the frame names for typos'."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[name]), "--format", "json").stdout)["bags"]
    codes = {f["code"] for f in bag["findings"]}
    assert "static_on_dynamic" not in codes
    (clock,) = [f for f in bag["findings"] if f["code"] == "clock" and f["severity"] == "error"]
    assert set(clock["frames"]) == {"base_link", "left_wheel", "right_wheel", HOLOGLYPH[name]}
    assert "joints of the recorded /robot_description, robot_state_publisher's" in clock["message"]
    assert "device" not in clock["message"] + clock["hint"]
    assert "robot_state_publisher (and the joint states it follows) runs without use_sim_time" in clock["hint"]
    (apart,) = [f for f in bag["findings"] if f["code"] == "disconnected"]
    assert "odom -> base_footprint names a base that the recorded /robot_description lacks" in apart["hint"]
    assert "make the odometry publish odom -> footprint_link" in apart["hint"]
    extras = {f["frames"][-1]: f["hint"] for f in bag["findings"] if f["code"] == "urdf_extra"}
    assert "REP 105's odom frame is published by odometry or localization" in extras["odom"], extras
    assert "the robot's base as its odometry publishes it" in extras["base_footprint"], extras
    assert not any("camera or lidar" in hint for hint in extras.values()), extras  # the lead's mend, on corpus32's note


def test_odometry_sent_three_times_a_stamp_is_said_three_times(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Team 1809's URDF holds Gazebo's planar move three times: odom -> base_footprint arrives 3 times a stamp
    (308 stamps, 924 samples). wtf said 'arrives twice: 308 of its 308 stamps arrived again (3 times each)'."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[THRICE]), "--format", "json").stdout)["bags"]
    (twins,) = [f for f in bag["findings"] if f["code"] == "multiple_authorities"]
    assert (
        "odom -> base_footprint on /tf arrives 3 times: 308 of its 308 stamps arrived again (3 times each)"
        in (twins["message"])
    )
    assert "twice" not in twins["message"] + twins["hint"]
