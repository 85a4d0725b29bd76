"""What corpus44b's recordings showed (ROS 2 recordings of kinds the corpus lacked), checked on the recording that
showed it; the designed reproductions are beside the code's own tests (tests/analysis/test_filter_faults.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

TB4 = "ros2-turtlebot4-ignition-gazebo-wheels-from-two-publishers-five-static-senders-sim-clock-2025-db3"
PAUSED = (
    "ros2-turtlebot4-ignition-gazebo-simulation-paused-at-end-tf-fresh-on-sim-time-wheels-from-two-publishers-2025-db3"
)


def test_the_turtlebot4_simulator_s_wheels_from_two_publishers_are_said_once_each(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Each wheel comes in two message layouts taking turns at 10 Hz, one with the joint's angle, one always the
    identity: an error per wheel edge, with the 108.49° (left) and 58.52° (right) they are apart at the same stamps;
    the 244 messages without a transform and the wall-clock record times a note each; nothing else."""
    code, findings = _findings(tfx, corpus(BY_ID[TB4]))
    authorities = sorted((f for f in findings if f["code"] == "multiple_authorities"), key=lambda f: f["frames"])
    assert [(f["severity"], f["frames"]) for f in authorities] == [
        ("error", ["wheel_drop_left", "left_wheel"]),
        ("error", ["wheel_drop_right", "right_wheel"]),
    ]
    assert "up to 108.49° (at +0.1 s) apart" in authorities[0]["message"], authorities[0]["message"]
    assert "up to 58.52° (at +2.0 s) apart" in authorities[1]["message"], authorities[1]["message"]
    (silent,) = [f for f in findings if f["code"] == "silent_tf"]
    assert "244 of 1,214 messages on /tf carry no transform" in silent["message"], silent["message"]
    assert sorted(f["code"] for f in findings) == ["clock", "multiple_authorities", "multiple_authorities", "silent_tf"]
    assert code == 1


def test_the_turtlebot4_simulator_s_first_scans_are_said_to_wait_for_the_lidar_s_static(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """131 scans waited a few ms for odom -> base_link; the first 7 up to 0.543 s for rplidar_link ->
    turtlebot4/rplidar_link/rplidar, sent 0.68 s in. filter advised 'wait 0.543 s' naming odom -> base_link alone."""
    result = tfx("filter", "/scan", "-b", corpus(BY_ID[TB4]), "--target", "odom")
    text = " ".join(result.stdout.split())
    assert "waited for odom -> base_link: its newest stamp 0.006 s behind" in text, text
    assert (
        "; the longest for rplidar_link -> turtlebot4/rplidar_link/rplidar: 7 arrived before its first transform "
        "and waited for it; to keep 99.9%: wait 0.543 s, queue 7"
    ) in text, text
    assert result.code == 0


def test_tf_that_stopped_with_the_simulation_is_not_stale(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The same simulator three minutes earlier: tf's last samples arrive 2.2 s of wall time before the recording
    ends, while /clock advances 12 ms (the simulation all but paused): tfx said 3 stale errors ('stopped at 22.569
    (+9.4 s), 2.2 s before the recording ends'). On /clock's time tf is fresh to the end: no stale."""
    code, findings = _findings(tfx, corpus(BY_ID[PAUSED]))
    assert not [f for f in findings if f["code"] == "stale"], findings
    (authorities,) = [f for f in findings if f["code"] == "multiple_authorities"]
    assert authorities["frames"] == ["wheel_drop_right", "right_wheel"] and authorities["severity"] == "error"
    assert code == 1
