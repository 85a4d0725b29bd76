"""Issue 39 (brief diff46), on the real pairs that showed it: `tfx diff` says once what several edges did together,
reads mimic joints from a recorded description only, and measures a stop as wtf's stale does. The designed
reproductions are beside the code's own tests (tests/analysis/test_diff_groups.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus43a import JANUARY, OCTOBER
from tests.corpus.test_corpus44b import PAUSED, TB4
from tests.corpus.test_diff42 import _diff
from tests.corpus.test_diff43 import HUSKY_UR, HUSKY_UR_LONG
from tftools.analysis.diff.mimics import recorded_mimics
from tftools.sources.recording import read_recording

OPENNI = ["openni_depth_frame", "openni_depth_optical_frame", "openni_rgb_frame", "openni_rgb_optical_frame"]
FINGERS = ["l_gripper_l_finger_link", "l_gripper_l_finger_tip_link", "l_gripper_r_finger_link"]


def test_the_pr2s_kinect_at_another_rate_is_one_difference_and_its_fingers_stay_unjoined(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """JSK's real PR2 in October and January 2012. The Kinect's five edges (head_plate_frame -> openni_camera and the
    four below it) come in October's robot_state_publisher messages of 48 fixed transforms at 50 Hz, in January
    from static_transform_publishers at 10 Hz: diff said five rate lines, now one with the four beneath it (34
    differences, 38 before). The gripper's fingers are mimic joints of one joint in the PR2's URDF, but neither
    bag holds a description (by the bytes: topics /tf, /joint_states, /base_odometry/odom and two /pressure, no
    '<mimic' anywhere; ROS 1 bags hold no parameter): each finger stays its own line, nothing guessed."""
    code, found = _diff(tfx, corpus, OCTOBER, JANUARY)
    assert len(found) == 34 and code == 1
    rates = [d for d in found if d["change"] == "rate"]
    assert [(d["frame"], d["said_with"], d["sent_in"]) for d in rates] == [("openni_camera", OPENNI, "a")]
    assert rates[0]["message"] == (
        "head_plate_frame -> openni_camera at 10.0 Hz in B, 50.0 Hz in A (B 80% slower); the edges of the 4 frames "
        "beneath it, sent in the same messages in A, changed rate with it: " + ", ".join(OPENNI)
    )
    fingers = [d for d in found if d["frame"] in FINGERS]
    assert [(d["frame"], d["part"], d["mimics"]) for d in fingers] == [(f, "joint", []) for f in FINGERS]
    for bag in (OCTOBER, JANUARY):
        assert recorded_mimics(read_recording([str(corpus(BY_ID[bag]))])) == {}


def test_the_husky_ur_grippers_mimic_joints_are_read_from_its_recorded_description(corpus: Corpus) -> None:
    """The Husky with a UR arm and a Robotis RH-P12-RN gripper (two runs, 2025) records its /robot_description: by
    the bytes, joint rh_l1 holds <mimic joint="rh_p12_rn"/> and rh_l2 <mimic joint="rh_r2"/> (children
    rh_p12_rn_l1, rh_p12_rn_l2 of rh_p12_rn_r1's and rh_p12_rn_r2's joints). Its gripper moves in both runs, so
    diff finds no difference to say them with (tests/corpus/test_diff43.py)."""
    for run in (HUSKY_UR, HUSKY_UR_LONG):
        mimics = recorded_mimics(read_recording([str(corpus(BY_ID[run]))]))
        assert mimics == {"rh_p12_rn_l1": "rh_p12_rn_r1", "rh_p12_rn_l2": "rh_p12_rn_r2"}


def test_the_turtlebot4_simulation_paused_at_the_end_stopped_no_edge(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The TurtleBot 4 simulator's two runs of March 2025: in the later, /clock advances 12 ms over the recording's
    last 2.2 s (the simulation all but paused) and tf's last samples arrive then, 9 ms of simulated time before
    /clock's last value. diff said five edges 'stopped early in B ... silent for its last 2.2 s', measured on the
    record clock, where wtf (on the simulation's time, as a listener with use_sim_time sees it) says tf is fresh.
    A stop is now measured as wtf's stale is: no difference."""
    code, found = _diff(tfx, corpus, TB4, PAUSED)
    assert (code, found) == (0, [])
