"""``tfx wtf --urdf``'s checks on designed recordings of a small robot, in every bag format: healthy (nothing
false), a joint never published, robot_state_publisher not running, its statics not recorded, a sensor moved
or flipped, joint states the URDF lacks, a recorded /robot_description used without --urdf."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tests.analysis.robot_scenes import (
    DELAY,
    FLIPPED,
    MOVED,
    ROBOT,
    URDF,
    Recorded,
    Setup,
    recorded,
    robot_bag,
    write_robot_bag,
)
from tests.analysis.wtf_scenes import START, recording
from tests.bags import BagFormat, TfMessage
from tftools.analysis.description import Robot, check_joints, description_shape, robot_of
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import frame_tree
from tftools.analysis.wtf import CHECKS, Scene, findings_of
from tftools.core.rotation import Vec3
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.bag import messages as bag_messages
from tftools.sources.bag.reader import BagReader
from tftools.sources.bag.robot import ROBOT_TOPICS
from tftools.sources.recording import read_recording
from tftools.sources.urdf import parse_urdf

FORMATS = list(BagFormat)


def _findings(tmp_path: Path, setup: Setup, fmt: BagFormat = BagFormat.ros1, urdf: bool = True) -> list[Finding]:
    bag = robot_bag(tmp_path, "rover", setup, fmt)
    recording = read_recording([bag])
    robot, said = robot_of([bag], recording, ROBOT if urdf else None)
    found = findings_of(Scene(recording, robot=robot))
    return [f for f in found + ([said] if said else []) if f.code.startswith("urdf")]


def _codes(findings: list[Finding]) -> list[tuple[str, str]]:
    return [(f.code, f.severity.value) for f in findings]


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_joint_states_and_the_description_are_read_in_every_format(tmp_path: Path, fmt: BagFormat) -> None:
    bag = robot_bag(tmp_path, "rover", Setup(description=True), fmt)
    read = read_recording([bag], whole=ROBOT_TOPICS).robot
    assert read.description == URDF
    assert len(read.joint_states) == 100 and read.problems == []
    first, last = read.joint_states[0], read.joint_states[-1]
    assert set(first.positions) == {"wheel_left_joint", "wheel_right_joint"}
    assert last.positions["wheel_left_joint"] == pytest.approx(2.0 * 4.95)
    assert list(read.record_time) == sorted(read.record_time)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_healthy_robot_says_only_that_odom_is_not_its_own(tmp_path: Path, fmt: BagFormat) -> None:
    findings = _findings(tmp_path, Setup(), fmt)
    assert _codes(findings) == [("urdf_extra", "info")]
    assert findings[0].frames == ("odom",) and "odometry and localization" in findings[0].hint
    bag = tmp_path / ("rover.bag" if fmt is BagFormat.ros1 else f"rover_{fmt.value}")
    recording = read_recording([bag])
    robot, _ = robot_of([bag], recording, ROBOT)
    assert robot is not None
    checks = {c.joint: c for c in check_joints(robot, recording.buffer, frame_tree(recording))}
    assert {c.verdict.value for c in checks.values()} == {"fine"}
    assert checks["wheel_left_joint"].compared == 100 and checks["wheel_left_joint"].rotation_deg < 1e-6


def test_a_frame_moving_under_odom_is_said_odometry_s_base_and_a_driver_s_frame_a_driver_s(tmp_path: Path) -> None:
    """The real create3 (ros2_db3_create3_real_two_urdfs): its odometry moves base_footprint and base_link under
    odom, and urdf_extra said of base_footprint "a camera or lidar driver's own frames". A moving child of odom is
    odometry's base (REP 105); a static frame under a link is still a driver's, or a link the URDF lacks."""
    messages = recorded(Setup())
    for m in [m for m in messages if m.topic == "/tf" and m.publisher == "/odometry"]:
        (odom,) = m.value
        messages.append(Recorded("/tf", m.record_time + 1, [replace(odom, child_frame_id="base_odom")], "/odometry"))
    cam = Transform((0.0, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0), START, "camera_link", "camera_optical")
    messages.append(Recorded("/tf_static", START + 1, [cam], "/camera_driver"))
    bag = write_robot_bag(tmp_path / "rover.bag", sorted(messages, key=lambda m: m.record_time))
    recording = read_recording([bag])
    robot, _ = robot_of([bag], recording, ROBOT)
    extras = {f.frames[-1]: f.hint for f in findings_of(Scene(recording, robot=robot)) if f.code == "urdf_extra"}
    assert "the robot's base as its odometry publishes it (REP 105" in extras["base_odom"], extras
    assert "camera or lidar" not in extras["base_odom"]
    assert "a camera or lidar driver's own frames" in extras["camera_optical"], extras


def test_an_odom_frame_heading_a_tree_apart_from_the_links_is_said_rep_105_s(tmp_path: Path) -> None:
    """The e-Yantra Hologlyph bags (ros2_db3_eyrc_hologlyph_hb_bot_gazebo_two_trees_two_clocks_2023): Gazebo's
    odometry sends odom -> base_footprint beside a URDF rooted at footprint_link, and urdf_extra said of odom (a root
    apart from the links) and of base_footprint "a camera or lidar driver's own frames". odom is REP 105's frame,
    the moving frame under it odometry's base, whichever tree they head."""
    messages = recorded(Setup())
    for m in messages:
        if m.topic == "/tf" and m.publisher == "/odometry":
            m.value[:] = [replace(t, child_frame_id="base_apart") for t in m.value]
    bag = write_robot_bag(tmp_path / "apart.bag", messages)
    recording = read_recording([bag])
    robot, _ = robot_of([bag], recording, ROBOT)
    findings = findings_of(Scene(recording, robot=robot))
    assert "disconnected" in {f.code for f in findings}
    extras = {f.frames[-1]: f.hint for f in findings if f.code == "urdf_extra"}
    assert "REP 105's odom frame is published by odometry or localization" in extras["odom"], extras
    assert "the robot's base as its odometry publishes it (REP 105" in extras["base_apart"], extras
    assert not any("camera or lidar" in hint for hint in extras.values()), extras


def test_a_wheel_turning_more_than_half_a_turn_between_samples_is_no_false_alarm(tmp_path: Path) -> None:
    # tf at 5 Hz, 4 rad apart: a joint state between two samples would be interpolated the short way round
    setup = Setup(wheel_speed=20.0, tf_every=4)
    assert _codes(_findings(tmp_path, setup)) == [("urdf_extra", "info")]


def test_a_namespaced_robot_s_links_are_found_under_their_prefix(tmp_path: Path) -> None:
    findings = _findings(tmp_path, Setup(prefix="rover1/", joint_states=("wheel_left_joint",)))
    assert _codes(findings) == [("urdf_missing", "error"), ("urdf_extra", "info")]
    missing, extra = findings
    assert "wheel_right_joint (continuous, rover1/base_link -> rover1/wheel_right_link)" in missing.message
    assert extra.frames == ("rover1/odom",)


def test_a_joint_never_published_names_the_joint_its_link_and_the_publisher(tmp_path: Path) -> None:
    findings = _findings(tmp_path, Setup(joint_states=("wheel_left_joint",)))
    (missing,) = [f for f in findings if f.code == "urdf_missing"]
    assert missing.severity is Severity.error
    assert "wheel_right_joint" in missing.message and "wheel_right_link" in missing.message
    assert "no message on /joint_states names wheel_right_joint" in missing.hint
    assert "joint_state_publisher" in missing.hint
    assert missing.frames == ("base_link", "wheel_right_link")


@pytest.mark.parametrize(
    ("fmt", "launch"), [(BagFormat.ros1, "(roslaunch ..."), (BagFormat.rosbag2_sqlite3, "(ros2 launch ...")]
)
def test_robot_state_publisher_not_running(tmp_path: Path, fmt: BagFormat, launch: str) -> None:
    findings = _findings(tmp_path, Setup(state_publisher=False), fmt)
    (missing,) = [f for f in findings if f.code == "urdf_missing"]
    assert launch in missing.hint and "launch" not in missing.hint.replace(launch, "")  # its own ROS's only
    assert missing.message.startswith("none of the 5 joints of rover.urdf is on tf")
    for joint in ("base_joint", "laser_joint", "wheel_left_joint"):
        assert joint in missing.message
    assert "robot_state_publisher did not run" in missing.hint
    assert [f.code for f in findings] == ["urdf_missing", "urdf_extra"]  # odometry names the root: not unseen


def test_a_joint_state_published_but_no_state_publisher_for_it(tmp_path: Path) -> None:
    # joint states for both wheels, robot_state_publisher only placing the left one: it runs another URDF
    setup = Setup(joint_states=("wheel_left_joint",), extra_states=("wheel_right_joint",))
    (missing,) = [f for f in _findings(tmp_path, setup) if f.code == "urdf_missing"]
    assert "/joint_states names wheel_right_joint, yet tf lacks it" in missing.hint


@pytest.mark.parametrize(
    ("fmt", "said", "unsaid"),
    [
        (BagFormat.ros1, "latched", "transient local"),  # ROS 1 gives a latched topic to a late recorder
        (BagFormat.rosbag2_sqlite3, "transient local", "latched"),
    ],
)
def test_statics_not_recorded(tmp_path: Path, fmt: BagFormat, said: str, unsaid: str) -> None:
    (missing,) = [f for f in _findings(tmp_path, Setup(fixed_published=False), fmt) if f.code == "urdf_missing"]
    assert "none of the 3 fixed joints of rover.urdf is on /tf_static" in missing.message
    assert said in missing.hint and unsaid not in missing.hint


@pytest.mark.parametrize(("origin", "mm", "deg"), [(MOVED, 20.0, 0.0), (FLIPPED, 0.0, 180.0)])
def test_a_moved_or_flipped_sensor(tmp_path: Path, origin: tuple[Vec3, Vec3], mm: float, deg: float) -> None:
    findings = _findings(tmp_path, Setup(real_origins={"laser_joint": origin}))
    assert _codes(findings) == [("urdf_moved", "error"), ("urdf_extra", "info")]
    moved = findings[0]
    assert moved.frames == ("base_link", "laser") and "joint laser_joint" in moved.message
    assert f"{mm:.1f} mm and {deg:.2f}°" in moved.message
    assert "edited" in moved.hint and "tfx echo base_link laser --format urdf" in moved.hint


def test_a_moved_sensor_s_static_stamped_hours_before_is_placed_when_it_arrived(tmp_path: Path) -> None:
    """robot_state_publisher stamps its statics when it starts, often hours before the recording (a real
    Create 3 recording: 4.1 h); the finding is at the /tf_static message's arrival, as urdf_parent's, not 4 h
    before the recording began (the report's timelines zoomed there)."""
    hours = 4 * 3600 * NS_PER_S
    findings = _findings(tmp_path, Setup(real_origins={"laser_joint": MOVED}, statics_stamped_before=hours))
    (moved,) = [f for f in findings if f.code == "urdf_moved"]
    laser = read_recording([tmp_path / "rover.bag"]).buffer.history("laser")
    assert laser is not None and laser.static and int(laser.stamps[0]) == START - hours
    assert moved.first_time == moved.last_time == START + DELAY


def test_joint_states_the_urdf_lacks(tmp_path: Path) -> None:
    findings = _findings(tmp_path, Setup(extra_states=("gripper_joint",)))
    (unknown,) = [f for f in findings if f.code == "urdf_joint_states"]
    assert unknown.severity is Severity.warning and "gripper_joint" in unknown.message


def test_a_moving_joint_not_where_its_state_puts_it(tmp_path: Path) -> None:
    other = URDF.replace(
        '<origin xyz="0 0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>',
        '<origin xyz="0 0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 -1"/>',
    )
    bag = robot_bag(tmp_path, "rover", Setup())
    recording = read_recording([bag])
    robot = Robot(parse_urdf(other, "other.urdf"), read_recording([bag], whole=ROBOT_TOPICS).robot)
    (off,) = [f for f in findings_of(Scene(recording, robot=robot)) if f.code == "urdf_joint_state"]
    assert "wheel_left_joint" in off.message and "median of 100 joint states" in off.message


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_recorded_description_is_used_without_urdf(tmp_path: Path, fmt: BagFormat) -> None:
    findings = _findings(tmp_path, Setup(description=True, joint_states=("wheel_left_joint",)), fmt, urdf=False)
    (missing,) = [f for f in findings if f.code == "urdf_missing"]
    assert "of the recorded /robot_description" in missing.message and "wheel_right_joint" in missing.message


def test_a_recorded_xacro_is_said_not_checked(tmp_path: Path) -> None:
    xacro = URDF.replace(
        '<robot name="rover">',
        '<robot name="rover" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="r" value="1"/>',
    )
    findings = _findings(tmp_path, Setup(description=True, description_text=xacro), urdf=False)
    assert _codes(findings) == [("urdf_unread", "warning")]
    assert "is xacro" in findings[0].message and "xacro" in findings[0].hint


def test_a_recorded_description_naming_a_link_of_a_mebibyte_is_said_not_checked(tmp_path: Path) -> None:
    long = URDF.replace('"laser"', '"' + "l" * (1 << 20) + '"')
    findings = _findings(tmp_path, Setup(description=True, description_text=long), urdf=False)
    assert _codes(findings) == [("urdf_unread", "warning")]
    assert "a <link> name of 1,048,576 characters, longer than 4,096" in findings[0].message
    assert len(findings[0].message) < 300


def test_no_description_no_findings(tmp_path: Path) -> None:
    assert _findings(tmp_path, Setup(), urdf=False) == []


def test_the_description_as_a_tree_shape() -> None:
    shape = description_shape(ROBOT)
    assert shape.frames["base_footprint"].parent is None
    laser = shape.frames["laser"]
    assert laser.static and laser.parent == "base_link" and laser.translation == (0.2, 0.0, 0.15)
    assert not shape.frames["wheel_left_link"].static


def _on_tf(*transforms: tuple[str, str, str, Vec3, Vec3]) -> list[Finding]:
    """The robot's URDF against a recording (without files) of ``(topic, parent, child, xyz, rpy)`` at 10 Hz."""
    messages = [
        TfMessage(topic, START + i * NS_PER_S // 10, [Transform.from_rpy(xyz, rpy, START + i * NS_PER_S // 10, p, c)])
        for i in range(20)
        for topic, p, c, xyz, rpy in transforms
        if topic == "/tf" or i == 0
    ]
    found = findings_of(Scene(recording(sorted(messages, key=lambda m: m.record_time)), robot=Robot(ROBOT)))
    return [f for f in found if f.code.startswith("urdf")]


def test_every_description_check_has_a_scene() -> None:
    tested = {
        "urdf_missing", "urdf_parent", "urdf_moved", "urdf_joint_state", "urdf_kind", "urdf_unseen", "urdf_extra",
        "urdf_joint_states", "urdf_unread",
    }  # fmt: skip
    assert {c for c in CHECKS if c.startswith("urdf_")} == tested


def test_a_link_under_another_parent() -> None:
    base = ("/tf_static", "base_footprint", "base_link", (0, 0, 0.1), (0, 0, 0))
    laser = ("/tf_static", "camera_link", "laser", (0.2, 0, 0.15), (0, 0, 0))
    (parent,) = [f for f in _on_tf(base, laser) if f.code == "urdf_parent"]
    assert "link laser is a child of camera_link on tf, of base_link in rover.urdf" in parent.message


def test_a_fixed_joint_on_tf_and_a_moving_one_on_tf_static() -> None:
    base = ("/tf", "base_footprint", "base_link", (0, 0, 0.1), (0, 0, 0))
    wheel = ("/tf_static", "base_link", "wheel_left_link", (0, 0.15, 0), (-math.pi / 2, 0, 0))
    kinds = [f for f in _on_tf(base, wheel) if f.code == "urdf_kind"]
    assert [f.frames for f in kinds] == [("base_footprint", "base_link"), ("base_link", "wheel_left_link")]
    assert "comes on /tf, not /tf_static" in kinds[0].message and "only on /tf_static" in kinds[1].message


def test_a_link_joined_to_nothing_is_unseen() -> None:
    lonely = parse_urdf(URDF.replace("</robot>", '<link name="antenna"/></robot>'), "rover.urdf")
    base = ("/tf_static", "base_footprint", "base_link", (0, 0, 0.1), (0, 0, 0))
    found = findings_of(
        Scene(
            recording([TfMessage(m[0], START, [Transform.from_rpy(m[3], m[4], START, m[1], m[2])]) for m in [base]]),
            robot=Robot(lonely),
        )
    )
    (unseen,) = [f for f in found if f.code == "urdf_unseen"]
    assert unseen.message == "link antenna of rover.urdf is never named on tf" and "joined to nothing" in unseen.hint


@pytest.mark.parametrize(("ros1", "echo"), [(True, "rostopic echo /joint_states"), (False, "ros2 topic echo")])
def test_live_the_joint_states_are_not_heard_and_the_hint_says_what_to_look_at(ros1: bool, echo: str) -> None:
    base = ("/tf_static", "base_footprint", "base_link", (0, 0, 0.1), (0, 0, 0))
    messages = [TfMessage(base[0], START, [Transform.from_rpy(base[3], base[4], START, base[1], base[2])])]
    found = findings_of(Scene(recording(messages, ros1=ros1), robot=Robot(ROBOT, live=True)))
    wheels = [f for f in found if f.code == "urdf_missing" and "wheel" in f.message]
    assert len(wheels) == 2 and all("does a node publish" in f.hint and echo in f.hint for f in wheels)
    assert not any(("ros2 " if ros1 else "rostopic") in f.hint for f in wheels)


@pytest.mark.parametrize("multiplier", ["1e308", "-1e308"])
def test_a_mimic_multiplier_past_any_position_is_no_crash_and_no_figure(tmp_path: Path, multiplier: str) -> None:
    """A mimic joint whose leader's position times its multiplier overflows: that state has no position to
    compare (and numpy says nothing on stderr), where "math domain error" was raised."""
    mimic = URDF.replace(
        '<origin xyz="0 -0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>',
        '<origin xyz="0 -0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>'
        f'<mimic joint="wheel_left_joint" multiplier="{multiplier}"/>',
    )
    bag = robot_bag(tmp_path, "rover", Setup())
    recording = read_recording([bag])
    robot = Robot(parse_urdf(mimic, "mimic.urdf"), read_recording([bag], whole=ROBOT_TOPICS).robot)
    with np.errstate(all="raise"):  # a warning numpy would print is an error here
        joints = check_joints(robot, recording.buffer, frame_tree(recording))
    right = next(j for j in joints if j.joint == "wheel_right_joint")
    assert 0 < right.compared < 100  # the states whose product overflowed are not compared
    assert all(math.isfinite(v) for v in (right.translation_mm, right.rotation_deg))
    findings_of(Scene(recording, robot=robot))  # and the whole check runs


@pytest.mark.parametrize("fmt", FORMATS)
def test_of_many_recorded_descriptions_the_latest_is_read_and_few_are_held(
    tmp_path: Path, fmt: BagFormat, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A recording that holds the description many times (re-latched at every start): the latest one is used,
    and the reader holds the latest ones only up to its budget, not every one (hundreds of 4 MiB took GBs)."""
    monkeypatch.setattr(bag_messages, "MAX_WHOLE_TEXT", 3 * len(URDF))
    messages = recorded(Setup())
    texts = [URDF.replace('name="rover"', f'name="rover{n}"') for n in range(12)]
    messages += [Recorded("/robot_description", START + n * NS_PER_S // 10, t, "/rsp") for n, t in enumerate(texts)]
    path = tmp_path / ("many.bag" if fmt is BagFormat.ros1 else "many")
    bag = write_robot_bag(path, sorted(messages, key=lambda m: m.record_time), fmt)
    assert read_recording([bag], whole=ROBOT_TOPICS).robot.description == texts[-1]
    with BagReader([bag], ("/robot_description",), whole=("/robot_description",)) as reader:
        (held,) = [w for w in reader.read().whole if w.topic == "/robot_description"]
    assert held.values[-1] == texts[-1] and 1 <= len(held.values) <= 3


@pytest.mark.parametrize("described", [True, False], ids=["with-urdf", "without"])
def test_a_movable_joint_constant_on_tf_is_a_joint_at_rest_not_a_fixed_transform(described: bool) -> None:
    """ros2_db3_eyrc_hologlyph_hb_bot_gazebo_two_trees_two_clocks_2023: robot_state_publisher sends the three
    continuous wheels (joint_state_publisher's zeros) on /tf, constant at 10 Hz. ROS 2 names no publisher, so
    wtf said static_on_dynamic, 'publish it once on /tf_static ... or a fixed joint', though the recorded
    /robot_description calls them continuous. Without a description the warning stands."""
    wheel = Transform.from_rpy((0, 0.15, 0), (-math.pi / 2, 0, 0), START, "base_link", "wheel_left_link")
    messages = [
        TfMessage("/tf", START + i * NS_PER_S // 10, [replace(wheel, stamp=START + i * NS_PER_S // 10)])
        for i in range(30)
    ]
    scene = Scene(recording(messages, ros1=False), robot=Robot(ROBOT) if described else None)
    said = [f.frames for f in findings_of(scene) if f.code == "static_on_dynamic"]
    assert said == ([] if described else [("base_link", "wheel_left_link")])


def test_odometry_publishing_a_base_the_description_lacks_names_both_frames() -> None:
    """ros2_db3_eyrc_hologlyph_hb_bot_gazebo_two_trees_two_clocks_2023: Gazebo's planar move, its ROS 1 tags
    unread, publishes its default odom -> base_footprint, while the recorded URDF's root is footprint_link:
    two trees, and the hint said 'publish the transform that attaches odom to the footprint_link tree ... or
    check the frame names for typos'. The description names the two frames to make one."""
    renamed = parse_urdf(URDF.replace("base_footprint", "footprint_link"), "rover.urdf")
    body = Transform.from_rpy((0, 0, 0.1), (0, 0, 0), START, "footprint_link", "base_link")
    messages = [TfMessage("/tf_static", START, [body])] + [
        TfMessage("/tf", t, [Transform.from_rpy((0.01 * i, 0, 0), (0, 0, 0), t, "odom", "base_footprint")])
        for i, t in enumerate(START + k * NS_PER_S // 20 for k in range(40))
    ]
    for robot, said in ((Robot(renamed), True), (None, False)):
        (apart,) = [
            f for f in findings_of(Scene(recording(messages, ros1=False), robot=robot)) if f.code == "disconnected"
        ]
        assert ("odom -> base_footprint names a base that rover.urdf lacks" in apart.hint) is said
        assert ("make the odometry publish odom -> footprint_link" in apart.hint) is said


@pytest.mark.parametrize("ros1", [True, False])
def test_a_recording_whose_moving_joints_are_all_missing_says_one_absent_state_publisher(ros1: bool) -> None:
    """Only the base's fixed joint on tf, from another broadcaster (Franka teleop's recorder sends its base alone):
    the URDF's 2 moving joints and its 2 other fixed ones missing are one absent robot_state_publisher, one
    finding naming them all and what tf carries, not one per joint."""
    base = ("/tf_static", "base_footprint", "base_link", (0, 0, 0.1), (0, 0, 0))
    messages = [TfMessage(base[0], START, [Transform.from_rpy(base[3], base[4], START, base[1], base[2])])]
    found = findings_of(Scene(recording(messages, ros1=ros1), robot=Robot(ROBOT)))
    (missing,) = [f for f in found if f.code == "urdf_missing"]
    assert missing.message.startswith("none of the 2 moving joints of rover.urdf is on tf, and /joint_states was not")
    assert "of its 5 joints tf carries only base_joint, 4 are missing: laser_joint (laser)" in missing.message
    assert "record /joint_states to tell whether joint_state_publisher" in missing.hint
    assert ("roslaunch" if ros1 else "ros2 launch") in missing.hint
