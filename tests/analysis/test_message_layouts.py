"""Two publishers of one edge told apart by the shape of their messages, where a ROS 2 bag names no publishers
(issue 39; the TurtleBot 4 simulator's wheels, tests/corpus/test_corpus44b.py): one sends the two wheels' angles in
messages of 2 transforms, the other 4 transforms with the wheels always at 0, each at 10 Hz, taking turns. A wheel
turning ~23 degrees a sample could not be followed as two tracks of values: the left wheel was said as a ``jump``
and ``time_backwards``. One sender whose messages vary (a tracker sending what is in view) is not two."""

from __future__ import annotations

import dataclasses
import math

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import check
from tftools.core.transform import Transform

MS = scenes.MS
START = scenes.START
SAMPLES = 100  # of each publisher, 100 ms apart


def _wheels(stamp: int, left: float, right: float) -> list[Transform]:
    return [
        scenes._t("drop_left", "left_wheel", stamp, yaw=left),
        scenes._t("drop_right", "right_wheel", stamp, yaw=right),
    ]


def _two_publishers(both_every: int = 10) -> list[TfMessage]:
    """Every 100 ms the joint publisher's 2 transforms, the wheels turning 0.4 rad a sample; 50 ms later the other's 4,
    the drops and the wheels at 0; every ``both_every``-th of its messages at the joint publisher's stamp."""
    messages = []
    for i in range(SAMPLES):
        stamp = START + i * 100 * MS
        angle = math.remainder(0.4 * i, 2 * math.pi)
        messages.append(TfMessage("/tf", stamp + 2 * MS, _wheels(stamp, angle, -angle)))
        other = stamp if i % both_every == 0 else stamp + 50 * MS
        drops = [scenes._t("base_link", "drop_left", other), scenes._t("base_link", "drop_right", other)]
        messages.append(TfMessage("/tf", stamp + 52 * MS, drops + _wheels(other, 0.0, 0.0)))
    odometry = [TfMessage("/tf", START + i * 20 * MS + MS, scenes.odom_base(START + i * 20 * MS)) for i in range(500)]
    return sorted(messages + odometry, key=lambda m: m.record_time)


def _tracker() -> list[TfMessage]:
    """One tracker at 20 Hz: a person walking 0.05 m a sample, sent alone or with a second one in view, by turns."""
    messages = []
    for i in range(2 * SAMPLES):
        stamp = START + i * 50 * MS
        person = [scenes._t("camera", "person_1", stamp, x=0.05 * i, yaw=0.01 * i)]
        second = [scenes._t("camera", "person_2", stamp, x=3.0)] if i % 2 else []
        messages.append(TfMessage("/tf", stamp + 3 * MS, person + second))
    return messages


def _authorities(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.code == "multiple_authorities"]


def test_two_message_layouts_taking_turns_are_two_publishers_said_once_for_both_edges() -> None:
    findings = check(scenes.recording(_two_publishers(), ros1=False))
    (two,) = _authorities(findings)
    assert two.frames == ("drop_left", "left_wheel", "drop_right", "right_wheel")
    assert two.severity.value == "error"
    assert (
        f"come in two kinds of message taking turns ({2 * SAMPLES - 1} turns in {2 * SAMPLES} samples, each): "
        f"{SAMPLES} messages of 2 transforms (nothing else), every 100.0 ms, and {SAMPLES} messages of 4 transforms "
        "(with base_link -> drop_left and base_link -> drop_right)"
    ) in two.message, two.message
    # of the 10 stamps each sent by both, the first holds the same value in both (the wheels start at 0)
    assert (
        "in which drop_left -> left_wheel and drop_right -> right_wheel never change, each always at 100.0 mm and "
        "0.00° from its parent; 9 stamps of each came in both, with other values"
    ) in two.message, two.message
    assert "ROS 2's tf2 keeps both: at that stamp it answers with the one received last" in two.message
    assert two.message.index("kinds of message") < two.message.index("two publishers, it seems")
    assert two.figures["stamps_in_both_with_other_values"] == 18 and two.figures["layouts"] == 2
    assert not {"jump", "time_backwards"} & {f.code for f in findings}  # its symptoms, not said apart


def test_one_publisher_whose_messages_vary_is_not_two() -> None:
    findings = check(scenes.recording(_tracker(), ros1=False))
    assert not _authorities(findings), [f.message for f in _authorities(findings)]


def test_ros1s_tf2_is_said_to_refuse_the_stamps_both_kinds_sent() -> None:
    """The same two layouts in a ROS 1 bag without callerids: ROS 1's tf2 keeps a stamp's first value and refuses
    the other (TF_REPEATED_DATA), where ROS 2's keeps both."""
    unnamed = [dataclasses.replace(m, publisher=m.topic) for m in _two_publishers()]  # each authority its topic
    findings = check(scenes.recording(unnamed, ros1=True))
    (two,) = _authorities(findings)
    assert "ROS 1's tf2 keeps the first and refuses the other (TF_REPEATED_DATA)" in two.message, two.message
    assert "ROS 2's" not in two.message
