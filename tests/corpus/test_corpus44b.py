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


def test_the_turtlebot4_simulator_s_wheels_from_two_publishers_are_said_once(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Each wheel comes in two message layouts taking turns at 10 Hz: 127 messages of the two wheels with the joints'
    angles, 117 of four transforms (base_link -> wheel_drop_left/right too) with the wheels always the identity; 10
    stamps of each sent in both, up to 167.82° apart (sim 23.802: the left wheel at 192.18° and at 0°). One cause,
    one error naming both wheels, said from the message layouts (rules46; it was an error per wheel told from the
    values alternating, '108.49°' apart); the 244 messages without a transform and the wall-clock record times a
    note each; nothing else."""
    code, findings = _findings(tfx, corpus(BY_ID[TB4]))
    (authorities,) = [f for f in findings if f["code"] == "multiple_authorities"]
    assert authorities["severity"] == "error"
    assert authorities["frames"] == ["wheel_drop_left", "left_wheel", "wheel_drop_right", "right_wheel"]
    message = authorities["message"]
    assert (
        "come in two kinds of message taking turns (233 turns in 244 samples, each): 127 messages of 2 transforms "
        "(nothing else), every 99.0 ms, and 117 messages of 4 transforms (with base_link -> wheel_drop_left and "
        "base_link -> wheel_drop_right), every 99.0 ms, in which wheel_drop_left -> left_wheel and wheel_drop_right "
        "-> right_wheel never change, each always at 0.0 mm and 0.00° from its parent (the identity); 10 stamps of "
        "each came in both, with other values up to 167.82° apart ("
    ) in message, message
    assert message.index("kinds of message") < message.index("two publishers, it seems")  # observed, then concluded
    (silent,) = [f for f in findings if f["code"] == "silent_tf"]
    assert "244 of 1,214 messages on /tf carry no transform" in silent["message"], silent["message"]
    assert sorted(f["code"] for f in findings) == ["clock", "multiple_authorities", "silent_tf"]
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
    assert code == 1


def test_the_paused_simulator_s_left_wheel_is_two_publishers_not_a_jump(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The same two message layouts: 109 messages of the two wheels (the joints' angles, a median 22° a sample),
    94 of four with the wheels always at 0°, 15 stamps of each sent in both. tfx said two publishers of the right
    wheel alone, and of the left only its symptoms, jump (79.1° in 0 s) and time_backwards (15 stamps resent with
    other values): the turn-taking check could not follow a wheel turning ~23° a sample. Now one error names both,
    from the layouts, and the symptoms are not said apart."""
    code, findings = _findings(tfx, corpus(BY_ID[PAUSED]))
    (authorities,) = [f for f in findings if f["code"] == "multiple_authorities"]
    assert authorities["frames"] == ["wheel_drop_left", "left_wheel", "wheel_drop_right", "right_wheel"]
    assert authorities["severity"] == "error"
    assert (
        "(186 turns in 203 samples, each): 109 messages of 2 transforms (nothing else), every 99.0 ms, and 94 "
        "messages of 4 transforms (with base_link -> wheel_drop_left and base_link -> wheel_drop_right)"
    ) in authorities["message"], authorities["message"]
    assert "15 stamps of each came in both, with other values up to 178.14° apart (" in authorities["message"]
    assert sorted(f["code"] for f in findings) == ["clock", "multiple_authorities", "silent_tf"]
    assert code == 1
