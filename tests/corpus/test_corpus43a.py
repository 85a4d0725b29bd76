"""What corpus43a's recordings showed (a real PR2 of JSK, pr1012, in jsk_pr2eus's test data: October and January
2012), fixed on the recording that showed it; the designed reproductions are beside the code's own tests
(tests/analysis/test_wtf_clocks_and_words.py, tests/sources/codecs/test_odometry.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

OCTOBER = "ros1-pr2-real-jsk-pr1012-tf1-eleven-publishers-building-map-odometry-fused-by-robot-pose-ekf-2012-bag"
JANUARY = "ros1-pr2-real-jsk-pr1012-tf1-no-callerids-same-robot-nine-months-earlier-2012-bag"


def test_odometry_robot_pose_ekf_fuses_is_a_note_naming_the_ekf_not_an_error(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/base_odometry/odom's 1,229 messages are in 'odom' (child_frame_id empty), which no transform names, while
    robot_pose_ekf sends odom_combined -> base_footprint: wtf said sensor_frame (error, exit 1), and wtf and filter
    told to turn the odometry's tf on, which would give base_footprint a second parent."""
    path = corpus(BY_ID[OCTOBER])
    code, findings = _findings(tfx, path)
    (frame,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert frame["severity"] == "info" and frame["frames"] == ["odom"], frame
    assert (
        frame["message"] == "/base_odometry/odom: 1229 of 1229 messages are in frame 'odom', which no transform names"
    )
    assert "odom_combined -> base_footprint from /robot_pose_ekf" in frame["hint"] and "second parent" in frame["hint"]
    assert "enable_odom_tf" not in frame["hint"]
    assert code == 0
    said = " ".join(tfx("filter", "-b", path).stdout.split())
    assert "odom_combined -> base_footprint from /robot_pose_ekf" in said and "enable_odom_tf" not in said, said


def test_empty_tf_messages_name_the_node_the_bag_says_sent_them(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """13 of the 3,734 /tf messages hold no transform, all from /dynamic_tf_publisher (the connection's callerid):
    the hint said 'rostopic info /tf names them'. The January bag names no publisher: that hint stays."""
    _, findings = _findings(tfx, corpus(BY_ID[OCTOBER]))
    (silent,) = [f for f in findings if f["code"] == "silent_tf"]
    assert silent["severity"] == "info" and "13 of 3,734 messages on /tf carry no transform" in silent["message"]
    assert silent["hint"].startswith("/dynamic_tf_publisher sent 13:"), silent["hint"]
    _, earlier = _findings(tfx, corpus(BY_ID[JANUARY]))
    (unnamed,) = [f for f in earlier if f["code"] == "silent_tf"]
    assert "rostopic info /tf names them" in unnamed["hint"]


def test_the_same_robot_without_callerids_is_told_the_same_of_its_odometry(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """January's bag names no publisher: the EKF's edge is said without one."""
    code, findings = _findings(tfx, corpus(BY_ID[JANUARY]))
    (frame,) = [f for f in findings if f["code"] == "sensor_frame"]
    assert (
        frame["severity"] == "info"
        and "the robot's odometry on tf is odom_combined -> base_footprint," in frame["hint"]
    )
    assert code == 0
