"""Two sources of joint states told from the shapes of robot_state_publisher's messages (e-Yantra's eBot with its UR5
in Gazebo, 2021-22: 12 joints at 40 Hz, and 16 with the wheels at 10 Hz), and what wtf says of them: the kinds of
message after what each finding observed, and one cause for the joints' findings."""

from __future__ import annotations

import math

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import causes
from tftools.analysis.wtf import Scene
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.joint_sources import joint_sources
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

MS = 1_000_000
ARM = [(f"link{i}", f"link{i + 1}") for i in range(12)]
WHEELS = [("base", f"wheel{i}") for i in range(4)]


def _joints(edges: list[tuple[str, str]], stamp: int) -> list[Transform]:
    angle = math.sin((stamp - scenes.START) / NS_PER_S)
    return [Transform.from_rpy((0.0, 0.0, 0.1), (0.0, 0.0, angle), stamp, p, c) for p, c in edges]


def _state_publisher(first: list[tuple[str, str]], second: list[tuple[str, str]]) -> list[TfMessage]:
    """/state_publisher sending ``first`` at 40 Hz and ``second`` at 10 Hz, each stamped as its source's joint
    states, the 10 Hz source's clock 20 ms behind (out of order on the joints both send)."""
    fast = scenes.periodic("/state_publisher", 40, lambda t: _joints(first, t))
    slow = scenes.periodic(
        "/state_publisher", 10, lambda t: _joints(second, t), phase=0.0121, stamp=lambda t: t - 20 * MS
    )
    return fast + slow


def _scene(messages: list[TfMessage]) -> Scene:
    return Scene(scenes.recording(scenes.healthy(rsp=messages)))


def test_joints_in_messages_of_two_kinds_are_two_sources() -> None:
    found = joint_sources(_scene(_state_publisher(ARM, ARM + WHEELS)))
    assert set(found) == set(ARM), found
    (sources,) = set(found.values())
    assert [(k.joints, k.messages) for k in sources.kinds] == [(12, 400), (16, 100)], sources
    assert [round(k.rate_hz) for k in sources.kinds] == [40, 10] and sources.shared == 12, sources


def test_an_arm_and_wheels_in_messages_of_their_own_are_one_source_each() -> None:
    assert joint_sources(_scene(_state_publisher(ARM, WHEELS))) == {}


def test_a_message_recorded_twice_is_no_second_kind() -> None:
    """The same message twice at one record time and stamp (a Gazebo plugin's repeated stamps) is one kind."""
    once = scenes.periodic("/state_publisher", 40, lambda t: _joints(ARM[:2], t))
    twice = [TfMessage(m.topic, m.record_time, [*m.transforms, *m.transforms], m.publisher) for m in once[::3]]
    assert joint_sources(_scene(once[1::3] + once[2::3] + twice)) == {}


def test_the_joints_findings_say_the_two_kinds_and_are_one_cause() -> None:
    findings = check(scenes.recording(scenes.healthy(rsp=_state_publisher(ARM, ARM + WHEELS)))).findings
    told = [f for f in findings if f.frames[:2] in set(ARM)]
    assert {f.code for f in told} == {"time_backwards"}, told
    assert all("messages of 2 kinds: 400 of 12 joints at 40.0 Hz and 100 of 16 at 10.0 Hz" in f.message for f in told)
    assert "two sources of joint states" in told[0].hint, told[0].hint
    (cause,) = [f for f in causes(findings) if f in told]
    assert all(f.cause == cause.key for f in told if f is not cause) and len(told) == 12, told
