"""``tfx wtf --urdf`` on real recordings with joint states: the Franka Panda under MoveIt (its URDF:
franka_description's arm, the fixed joints as its /tf_static shows them: tests/analysis/urdf/panda.urdf),
a TurtleBot3 in Gazebo that recorded its own /robot_description, a Robotino, and a TurtleBot3 Waffle
recorded without /tf or /joint_states. Healthy ones say nothing false; each fault names its joint,
link and cause. The recordings are read from the shared corpus folder ($TFTOOLS_SHARED_DIR/corpus)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import shared_dir
from tftools.analysis.description import Verdict, check_joints, robot_of
from tftools.analysis.frames import frame_tree
from tftools.core.rotation import rpy_from_quat
from tftools.sources.recording import Recording, read_recording
from tftools.sources.urdf import read_urdf

PANDA_URDF = Path(__file__).parent.parent / "analysis" / "urdf" / "panda.urdf"


def _shared(name: str) -> Path:
    path = shared_dir() / "corpus" / name
    if not path.exists():
        pytest.skip(f"{name} is not in {path.parent} ($TFTOOLS_SHARED_DIR/corpus)")
    return path


def _joint(
    name: str, kind: str, parent: str, child: str, xyz: tuple[float, ...], rpy: tuple[float, ...], axis: str = "1 0 0"
) -> str:
    def f(v: tuple[float, ...]) -> str:
        return " ".join(repr(float(x)) for x in v)

    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{f(xyz)}" rpy="{f(rpy)}"/><axis xyz="{axis}"/></joint>'
    )


def urdf_from_tf(recording: Recording, root: str, moving: dict[str, str], extra: tuple[str, ...] = ()) -> str:
    """A URDF written from what the recording's tf shows under ``root``: each static edge a fixed joint at
    its value, each ``moving`` child (its joint's name) a continuous joint at its first value (its joint
    states are all 0 in these recordings); ``extra`` joints added as given."""
    tree = frame_tree(recording)
    links, joints, todo = [root], [], [root]
    while todo:
        for child in sorted(tree.children.get(todo.pop(), [])):
            links.append(child)
            todo.append(child)
            hist = recording.buffer.history(child)
            assert hist is not None
            xyz = tuple(float(v) for v in hist.translations[0])
            rpy = rpy_from_quat(tuple(float(v) for v in hist.rotations[0]))  # type: ignore[arg-type]  # a row of 4
            parent = tree.frames[child].parent
            if child in moving:
                joints.append(_joint(moving[child], "continuous", str(parent), child, xyz, rpy))
            else:
                joints.append(_joint(f"{child}_joint", "fixed", str(parent), child, xyz, rpy))
    names = set(links)
    extra_links = [link for j in extra for link in [j.split('child link="')[1].split('"')[0]] if link not in names]
    body = "".join(f'<link name="{link}"/>' for link in links + extra_links) + "".join(joints) + "".join(extra)
    return f'<?xml version="1.0"?><robot name="from_tf">{body}</robot>'


def _urdf_findings(tfx: Tfx, *args: str | Path) -> list[dict[str, Any]]:  # noqa: F811
    result = tfx("wtf", *args, "--format", "json")
    assert result.stdout, result.stderr
    (report,) = json.loads(result.stdout)["bags"]
    return [f for f in report["findings"] if f["code"].startswith("urdf")]


def test_the_panda_as_its_urdf_says(tfx: Tfx) -> None:  # noqa: F811
    bag = _shared("tfbag-franka-panda.bag")
    recording = read_recording([bag])
    robot, said = robot_of([bag], recording, read_urdf(PANDA_URDF))
    assert robot is not None and said is None and len(robot.messages.joint_states) == 110
    checks = check_joints(robot, recording.buffer, frame_tree(recording))
    assert {c.verdict for c in checks} == {Verdict.fine} and len(checks) == 21
    moving = [c for c in checks if c.compared]
    # every joint state of the 7 arm joints and both fingers (one mimics the other): where tf put the link
    assert len(moving) == 9 and all(c.compared == 110 for c in moving)
    assert max(c.translation_mm for c in moving) < 1e-3 and max(c.rotation_deg for c in moving) < 1e-3
    findings = _urdf_findings(tfx, bag, "--urdf", PANDA_URDF)
    assert [(f["code"], f["severity"]) for f in findings] == [("urdf_extra", "info")]
    assert findings[0]["frames"] == ["world"]  # MoveIt's virtual joint, above the robot: fine


@pytest.mark.parametrize("name", ["tfbag-franka-panda.bag", "tfbag-franka-panda-ros2"])
def test_diff_of_the_panda_and_its_urdf(tfx: Tfx, name: str) -> None:  # noqa: F811
    result = tfx("diff", PANDA_URDF, _shared(name))
    assert result.code == 0 and "no differences beyond the tolerances" in result.stdout, result.stdout


def test_the_panda_db3_conversion_has_no_joint_states_and_no_false_alarm(tfx: Tfx) -> None:  # noqa: F811
    bag = _shared("tfbag-franka-panda-ros2")
    findings = _urdf_findings(tfx, bag, "--urdf", PANDA_URDF)
    assert [(f["code"], f["severity"]) for f in findings] == [("urdf_extra", "info")]


def test_the_panda_with_a_moved_tool_frame(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    edited = tmp_path / "panda_edited.urdf"
    text = PANDA_URDF.read_text()
    line = next(row for row in text.splitlines() if 'name="panda_hand_tcp_joint"' in row)
    origin = line.split('<origin xyz="')[1].split('"')[0]
    x, y, z = (float(v) for v in origin.split())
    edited.write_text(
        text.replace(f'xyz="{origin}"', f'xyz="{x} {y} {z + 0.01}"', 1) if text.count(origin) == 1 else ""
    )
    assert edited.read_text(), "the tool frame's origin is not unique in panda.urdf"
    findings = _urdf_findings(tfx, _shared("tfbag-franka-panda.bag"), "--urdf", edited)
    moved = [f for f in findings if f["code"] == "urdf_moved"]
    assert len(moved) == 1 and moved[0]["severity"] == "error"
    assert "panda_hand_tcp_joint" in moved[0]["message"] and "10.0 mm and 0.00°" in moved[0]["message"]
    assert moved[0]["frames"] == ["panda_hand", "panda_hand_tcp"]


def test_the_panda_without_its_statics_names_robot_state_publisher(tfx: Tfx) -> None:  # noqa: F811
    # only /tf read: robot_state_publisher's /tf_static as if never recorded
    findings = _urdf_findings(tfx, _shared("tfbag-franka-panda.bag"), "--urdf", PANDA_URDF, "--topic", "/tf")
    (missing,) = [f for f in findings if f["code"] == "urdf_missing"]
    assert missing["message"].startswith("none of the 12 fixed joints of")
    assert "panda_hand_tcp_joint (panda_hand_tcp)" in missing["message"] or "panda_joint8" in missing["message"]
    assert "robot_state_publisher publishes them on /tf_static" in missing["hint"]


def test_the_panda_without_its_moving_transforms_says_robot_state_publisher(tfx: Tfx) -> None:  # noqa: F811
    # only /tf_static read: the joint states name every arm joint, yet tf lacks them
    findings = _urdf_findings(tfx, _shared("tfbag-franka-panda.bag"), "--urdf", PANDA_URDF, "--topic", "/tf_static")
    # one absent robot_state_publisher, said once (9 findings, one per joint, until rules48)
    (missing,) = [f for f in findings if f["code"] == "urdf_missing"]
    assert "none of the 9 moving joints" in missing["message"] and "names each" in missing["message"]
    assert "robot_state_publisher did not run with this URDF" in missing["hint"]
    assert "panda_joint1 (panda_link1)" in missing["message"]


def test_the_gazebo_turtlebot_against_its_own_recorded_description(tfx: Tfx) -> None:  # noqa: F811
    bag = _shared("ros2_db3_tb3_gazebo_walker")
    recording = read_recording([bag])
    robot, said = robot_of([bag], recording, None)
    assert robot is not None and said is None
    assert robot.description.name == "turtlebot3_waffle_pi" and robot.description.source.endswith("/robot_description")
    checks = {c.joint: c for c in check_joints(robot, recording.buffer, frame_tree(recording))}
    assert {c.verdict for c in checks.values()} == {Verdict.fine}
    # the joint states (200 of them, evenly spread) whose stamp tf has a sample at: robot_state_publisher's
    assert 100 < checks["wheel_left_joint"].compared <= 200 and checks["wheel_left_joint"].rotation_deg < 1e-3
    findings = _urdf_findings(tfx, bag)  # no --urdf: the recorded one
    assert [(f["code"], f["severity"]) for f in findings] == [("urdf_extra", "info")]
    assert findings[0]["frames"] == ["odom"]


def test_the_robotino_as_its_tf_shows_it(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    bag = _shared("uwb-slam-Record_2017-11-17-12-24-50.bag")
    recording = read_recording([bag])
    wheels = {f"wheel{i}_link": f"wheel{i}_joint" for i in range(3)}
    urdf = tmp_path / "robotino.urdf"
    urdf.write_text(urdf_from_tf(recording, "base_link", wheels))
    findings = _urdf_findings(tfx, bag, "--urdf", urdf)
    assert [(f["code"], f["severity"]) for f in findings] == [("urdf_extra", "info")]
    assert findings[0]["frames"] == ["odom"]


def test_a_turtlebot_recorded_without_joint_states_lacks_its_wheels(tfx: Tfx, tmp_path: Path) -> None:  # noqa: F811
    bag = _shared("ros1_tb3_waffle_static.bag")
    recording = read_recording([bag])
    # turtlebot3_description's waffle: its wheels, which only /tf (never recorded here) would carry
    wheels = (
        _joint(
            "wheel_left_joint",
            "continuous",
            "base_link",
            "wheel_left_link",
            (0, 0.144, 0.023),
            (-math.pi / 2, 0, 0),
            "0 0 1",
        ),
        _joint(
            "wheel_right_joint",
            "continuous",
            "base_link",
            "wheel_right_link",
            (0, -0.144, 0.023),
            (-math.pi / 2, 0, 0),
            "0 0 1",
        ),
    )
    urdf = tmp_path / "waffle.urdf"
    urdf.write_text(urdf_from_tf(recording, "base_footprint", {}, wheels))
    findings = _urdf_findings(tfx, bag, "--urdf", urdf)
    (missing,) = findings  # both wheels, one cause (two findings until rules48)
    assert missing["code"] == "urdf_missing" and "and /joint_states was not recorded" in missing["message"]
    assert "wheel_left_joint (wheel_left_link)" in missing["message"] and "wheel_right_joint" in missing["message"]
    assert "record /joint_states to tell whether joint_state_publisher" in missing["hint"]
