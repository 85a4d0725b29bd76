"""Reading a URDF within limits: its links and joints, each joint's transform at a position as
robot_state_publisher computes it, and what is refused (xacro, document types, too large, too deep, not XML)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tests.analysis.robot_scenes import URDF
from tftools.core.rotation import quat_from_rpy, quat_multiply_many, quat_rotate_many
from tftools.sources.urdf import UrdfError, parse_urdf, read_urdf
from tftools.sources.user_files import MAX_BYTES, MAX_DEPTH


def test_links_and_joints() -> None:
    robot = parse_urdf(URDF, "rover.urdf")
    assert robot.name == "rover" and robot.links[0] == "base_footprint" and len(robot.links) == 6
    camera = next(j for j in robot.joints if j.name == "camera_joint")
    assert (camera.type, camera.parent, camera.child, camera.xyz, camera.rpy) == (
        "fixed", "base_link", "camera_link", (0.1, 0.0, 0.3), (0.0, 0.2, 0.0)
    )  # fmt: skip
    wheel = next(j for j in robot.joints if j.name == "wheel_left_joint")
    assert wheel.moving and wheel.axis == (0.0, 0.0, 1.0)
    assert robot.joint_of("wheel_left_link") is wheel and robot.joint_of("base_footprint") is None


@pytest.mark.parametrize("kind", ["revolute", "continuous", "prismatic"])
def test_a_joint_at_a_position_is_its_origin_then_its_motion(kind: str) -> None:
    text = (
        '<robot name="r"><link name="a"/><link name="b"/>'
        f'<joint name="j" type="{kind}"><parent link="a"/><child link="b"/>'
        '<origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 1.1"/><axis xyz="0 2 0"/></joint></robot>'
    )
    (joint,) = parse_urdf(text, "r.urdf").joints
    q = 0.7
    xyz, quat = joint.transform_at(q)
    origin = np.array(quat_from_rpy(0.3, -0.2, 1.1))
    if kind == "prismatic":  # along the axis, made a unit vector (as KDL, robot_state_publisher's, does)
        moved = np.array([0.1, 0.2, 0.3]) + quat_rotate_many(origin[None], np.array([[0.0, q, 0.0]]))[0]
        assert xyz == pytest.approx(moved) and quat == pytest.approx(tuple(origin))
    else:  # about the axis, made a unit vector
        turn = np.array([0.0, math.sin(q / 2), 0.0, math.cos(q / 2)])
        assert xyz == (0.1, 0.2, 0.3)
        assert quat == pytest.approx(tuple(quat_multiply_many(origin[None], turn[None])[0]))


def test_mimic() -> None:
    robot = parse_urdf(
        URDF.replace('<origin xyz="0 -0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>',
                     '<origin xyz="0 -0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>'
                     '<mimic joint="wheel_left_joint" multiplier="-1" offset="0.5"/>'),
        "r.urdf",
    )  # fmt: skip
    assert next(j for j in robot.joints if j.name == "wheel_right_joint").mimic == ("wheel_left_joint", -1.0, 0.5)


@pytest.mark.parametrize(
    ("text", "said"),
    [
        (
            '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:include filename="x"/></robot>',
            "is xacro",
        ),
        ('<robot name="r"><link name="${name}"/></robot>', "is xacro"),
        ('<!DOCTYPE r [<!ENTITY a "aaaa">]><robot name="r"><link name="&a;"/></robot>', "document type declaration"),
        ("<robot name='r'><link name='a'>", "not well-formed XML"),
        ("<launch/>", "not <robot>"),
        ('<robot name="r"><link name="a"/><joint name="j" type="hinge"/></robot>', "type 'hinge'"),
        (
            '<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>'
            "</robot>",
            "child link 'b' is not a <link>",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/>'
            '<child link="b"/><origin xyz="1 2"/></joint></robot>',
            "is not three numbers",
        ),
        (
            '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/>'
            '<child link="b"/><origin xyz="1 2 nan"/></joint></robot>',
            "not a finite number",
        ),
        ("<robot>" + "<x>" * (MAX_DEPTH + 1) + "</x>" * (MAX_DEPTH + 1) + "</robot>", "nested deeper than"),
        ("<robot>" + " " * MAX_BYTES + "</robot>", "larger than 4 MiB"),
    ],
)
def test_what_is_refused(text: str, said: str) -> None:
    with pytest.raises(UrdfError, match=r"^r\.urdf: ") as raised:
        parse_urdf(text, "r.urdf")
    assert said in str(raised.value) and raised.value.hint


def test_a_file(tmp_path: Path) -> None:
    path = tmp_path / "rover.urdf"
    path.write_text(URDF)
    assert read_urdf(path).source == str(path)
    with pytest.raises(UrdfError, match="no such file"):
        read_urdf(tmp_path / "missing.urdf")
    xacro = tmp_path / "rover.urdf.xacro"
    xacro.write_text(URDF)
    with pytest.raises(UrdfError, match="is xacro") as raised:
        read_urdf(xacro)
    assert f"xacro {xacro} > robot.urdf" in raised.value.hint


ENTITY_URDF = (
    '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE r [<!ENTITY a "aaaa">]><robot name="r"><link name="&a;"/></robot>'
)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_a_declaration_is_refused_whatever_the_encoding(encoding: str) -> None:
    """utf-16 writes a byte order mark, the -le/-be forms none: the declaration is found after decoding."""
    with pytest.raises(UrdfError, match="document type declaration"):
        parse_urdf(ENTITY_URDF.encode(encoding), "r.urdf")


def test_an_entity_is_never_expanded_into_a_name() -> None:
    """Many references to a long entity (a 'billion laughs' of names) are refused before any is expanded."""
    text = (
        '<!DOCTYPE r [<!ENTITY a "' + "x" * 400 + '">]><robot name="r"><link name="' + "&a;" * 600_000 + '"/></robot>'
    )
    with pytest.raises(UrdfError, match="document type declaration"):
        parse_urdf(text.encode("utf-16"), "r.urdf")


def test_doctype_in_a_comment_is_only_a_comment() -> None:
    robot = parse_urdf('<!-- no <!DOCTYPE here --><robot name="r"><link name="a"/></robot>', "r.urdf")
    assert robot.links == ("a",)


def test_an_undeclared_entity_is_not_well_formed() -> None:
    with pytest.raises(UrdfError, match="not well-formed XML"):
        parse_urdf('<robot name="r"><link name="&a;"/></robot>'.encode("utf-16"), "r.urdf")


def test_a_utf16_urdf_reads() -> None:
    assert parse_urdf(URDF.encode("utf-16"), "rover.urdf") == parse_urdf(URDF, "rover.urdf")
