"""``tfx diff`` says once what several edges did together: edges sent in the same messages that changed rate
alike, edges that stopped early at one point, and mimic joints held apart with the joint they follow (by a recorded
/robot_description only). The real pairs that showed each are in tests/corpus/test_diff43.py and test_diff46.py."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

from tests.analysis.robot_scenes import START as ROBOT_START
from tests.analysis.robot_scenes import Recorded, write_robot_bag
from tests.analysis.wtf_scenes import DELAY, _t, ekf, healthy, periodic, recording, wheels
from tests.bags import TfMessage
from tftools.analysis.diff import diff_trees
from tftools.analysis.differences import Change, Part, compare, describe
from tftools.analysis.expected import Tolerances, shape_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

#: The Kinect's three edges: (parent, child, x).
KINECT = (("base_link", "kinect", 0.1), ("kinect", "kinect_depth", 0.02), ("kinect", "kinect_rgb", 0.04))


def _kinect(stamp: int) -> list[Transform]:
    return [_t(parent, child, stamp, x) for parent, child, x in KINECT]


def _kinect_apart(hz: tuple[float, float, float]) -> list[TfMessage]:
    """Each of the Kinect's edges from its own static_transform_publisher, at ``hz``."""
    found: list[TfMessage] = []
    for k, ((parent, child, x), rate) in enumerate(zip(KINECT, hz, strict=True)):
        found += periodic(f"/kinect_{child}", rate, _one_edge(parent, child, x), phase=0.013 + k / 1000)
    return found


def _one_edge(parent: str, child: str, x: float) -> Callable[[int], list[Transform]]:
    return lambda stamp: [_t(parent, child, stamp, x)]


def test_edges_sent_in_one_message_that_changed_rate_alike_are_one_difference() -> None:
    """JSK's real PR2 (October and January 2012): the Kinect's five edges came in robot_state_publisher's messages
    at 50 Hz in one recording, from five static_transform_publishers at 10 Hz in the other: five rate lines. Edges
    that came in the same messages (in either recording) and changed rate alike are one difference, said with the
    first of them; an edge of those messages whose rate changed otherwise stays a difference of its own. (January's
    bag names no publisher, so no publishers are compared: ROS 2 bags here.)"""
    together = shape_of(recording(healthy(wheels=[*wheels(), *periodic("/rsp", 50, _kinect, phase=0.003)]), ros1=False))
    apart = shape_of(recording(healthy(wheels=[*wheels(), *_kinect_apart((10.0, 10.0, 10.0))]), ros1=False))
    (d,) = compare(together, apart, Tolerances())
    assert (d.change, d.frame, d.said_with, d.sent_in, d.beneath_all) == (
        Change.rate,
        "kinect",
        ("kinect_depth", "kinect_rgb"),
        "a",
        True,
    )
    assert describe(d) == (
        "base_link -> kinect at 10.0 Hz in B, 50.0 Hz in A (B 80% slower); the edges of the 2 frames beneath it, "
        "sent in the same messages in A, changed rate with it: kinect_depth, kinect_rgb"
    ), describe(d)
    (back,) = compare(apart, together, Tolerances())
    assert (back.frame, back.said_with, back.sent_in) == ("kinect", ("kinect_depth", "kinect_rgb"), "b")
    unlike = shape_of(recording(healthy(wheels=[*wheels(), *_kinect_apart((10.0, 10.0, 30.0))]), ros1=False))
    said = compare(together, unlike, Tolerances())
    assert [(x.frame, x.said_with) for x in said] == [("kinect", ("kinect_depth",)), ("kinect_rgb", ())]


def test_edges_that_stopped_early_at_one_point_are_one_difference() -> None:
    """Two real Neato wall-follower runs: in the 2023 one the driver's odom -> base_footprint and its two wheels last
    arrive 59.7 s into 71.1 s, each 'stopped early in B', three lines for one stop (tests/corpus/test_diff43.py).
    Edges that stopped early in the same recording at one point (no further apart than their rates explain) are one
    difference; at points apart, two."""
    whole = shape_of(recording(healthy()))
    paused = shape_of(recording(healthy(ekf=ekf(end=4.0), wheels=wheels(end=4.02))))
    (d,) = compare(whole, paused, Tolerances())
    assert (d.change, d.frame, d.said_with) == (Change.stopped, "base_link", ("wheel",))
    assert describe(d).endswith(
        "in A it was sent to the end (10.0 s of 10.0 s); the edge of one more frame stopped in B at the same point, "
        "each sent to the end in A: wheel"
    ), describe(d)
    apart = shape_of(recording(healthy(ekf=ekf(end=4.0), wheels=wheels(end=8.0))))
    assert [(x.frame, x.said_with) for x in compare(whole, apart, Tolerances())] == [("base_link", ()), ("wheel", ())]


GRIPPER = """<?xml version="1.0"?>
<robot name="gripper">
  <link name="base_link"/><link name="wheel"/><link name="finger_l"/><link name="finger_r"/>
  <joint name="wheel_joint" type="continuous">
    <parent link="base_link"/><child link="wheel"/><origin xyz="0 0.2 0"/><axis xyz="0 1 0"/>
  </joint>
  <joint name="gripper_joint" type="revolute">
    <parent link="base_link"/><child link="finger_l"/><origin xyz="0.3 0.01 0.5"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="gripper_r_joint" type="revolute">
    <parent link="base_link"/><child link="finger_r"/><origin xyz="0.3 -0.01 0.5"/><axis xyz="0 0 1"/>
    <mimic joint="gripper_joint" multiplier="-1"/>
  </joint>
</robot>
"""


def _gripper(directory: Path, name: str, opening: float, description: bool) -> Path:
    """A robot whose state publisher sends its turning wheel and its two fingers (the right one mimicking the
    left, held still at ``opening`` rad) in one message at 25 Hz, with its /robot_description or without."""
    messages = [Recorded("/robot_description", ROBOT_START, GRIPPER, "/rsp")] if description else []
    for i in range(100):
        stamp = ROBOT_START + i * NS_PER_S // 25
        transforms = [
            Transform.from_rpy((0.0, 0.2, 0.0), (0.0, 0.1 * i, 0.0), stamp, "base_link", "wheel"),
            Transform.from_rpy((0.3, 0.01, 0.5), (0.0, 0.0, opening), stamp, "base_link", "finger_l"),
            Transform.from_rpy((0.3, -0.01, 0.5), (0.0, 0.0, -opening), stamp, "base_link", "finger_r"),
        ]
        messages.append(Recorded("/tf", stamp + 2_000_000, transforms, "/rsp"))
    return write_robot_bag(directory / f"{name}.bag", messages)


def test_a_mimic_joint_held_apart_is_said_with_the_joint_it_follows(tmp_path: Path) -> None:
    """JSK's real PR2: its gripper's fingers follow one joint (``<mimic>``), and diff said each finger held apart as
    a joint of its own. Where the recordings hold the robot's description, a mimic joint held apart is said with
    the joint it follows; where they do not (the PR2's bags hold none), nothing is guessed: each stays a line."""
    opened = _gripper(tmp_path, "opened", 0.5, description=True)
    closed = _gripper(tmp_path, "closed", 0.1, description=True)
    (d,) = diff_trees(str(opened), str(closed)).differences
    assert (d.change, d.frame, d.part, d.mimics) == (Change.moved, "finger_l", Part.joint, ("finger_r",))
    assert describe(d).endswith(
        "; its mimic joint's frame (the recorded /robot_description's <mimic>) followed it: finger_r"
    ), describe(d)
    closed_alone = str(_gripper(tmp_path, "closed_alone", 0.1, description=False))
    one_side = diff_trees(str(opened), closed_alone)
    assert [x.frame for x in one_side.differences] == ["finger_l"]  # the robot's description, from A
    unknown = diff_trees(str(_gripper(tmp_path, "opened_alone", 0.5, False)), closed_alone)
    assert [(x.frame, x.part, x.mimics) for x in unknown.differences] == [
        ("finger_l", Part.joint, ()),
        ("finger_r", Part.joint, ()),
    ]
    assert math.isclose(unknown.differences[1].rotation_deg, 22.918, abs_tol=0.01)


def _kinect_stamped(hz: float) -> list[TfMessage]:
    """Each of the Kinect's edges in messages of its own from one driver, the three stamped alike, each sample."""
    found: list[TfMessage] = []
    for k, (parent, child, x) in enumerate(KINECT):
        found += periodic("/driver", hz, _one_edge(parent, child, x), phase=0.013, delay=DELAY + k * 300_000)
    return found


def test_edges_each_in_its_own_message_stamped_alike_in_both_that_changed_rate_alike_are_one_difference() -> None:
    """The real Neato of 2023 and 2024: the driver sends odom -> base_footprint and each wheel in messages of their
    own, the three with one stamp each sample, at 6.1 Hz in 2023 and 4.7 Hz in 2024: three rate lines, now one.
    Stamped alike in one recording only (in the other, from publishers of their own): each its own line."""
    fast = shape_of(recording(healthy(wheels=[*wheels(), *_kinect_stamped(6.1)]), ros1=False))
    slow = shape_of(recording(healthy(wheels=[*wheels(), *_kinect_stamped(4.7)]), ros1=False))
    assert ("kinect", "kinect_depth", "kinect_rgb") in fast.stamped
    assert not any("kinect" in group for group in fast.together)
    (d,) = compare(fast, slow, Tolerances())
    assert (d.frame, d.said_with, d.sent_in) == ("kinect", ("kinect_depth", "kinect_rgb"), "stamped")
    assert describe(d).endswith(
        "; the edges of the 2 frames beneath it, each in messages of its own but stamped as it was, sample for "
        "sample, in A and in B (one source), changed rate with it: kinect_depth, kinect_rgb"
    ), describe(d)
    apart = shape_of(recording(healthy(wheels=[*wheels(), *_kinect_apart((4.7, 4.7, 4.7))]), ros1=False))
    said = compare(fast, apart, Tolerances())
    assert [(x.change, x.frame, x.said_with) for x in said] == [(Change.rate, f, ()) for _, f, _ in KINECT]


def test_edges_sent_together_whose_publisher_changed_are_one_difference() -> None:
    """The Kinect's three edges in one node's messages in A, in another's in B: one publishers line; the wheels'
    publisher, unchanged, is none."""
    a = shape_of(recording(healthy(wheels=[*wheels(), *periodic("/rsp", 50, _kinect, phase=0.003)])))
    b = shape_of(recording(healthy(wheels=[*wheels(), *periodic("/kinect_rsp", 50, _kinect, phase=0.003)])))
    (d,) = compare(a, b, Tolerances())
    assert (d.change, d.frame, d.said_with, d.sent_in) == (
        Change.publishers,
        "kinect",
        ("kinect_depth", "kinect_rgb"),
        "both",
    )
    assert describe(d) == (
        "base_link -> kinect published by /kinect_rsp in B, by /rsp in A; the edges of the 2 frames beneath it, "
        "sent in the same messages in A and in B, changed publishers with it: kinect_depth, kinect_rgb"
    ), describe(d)
