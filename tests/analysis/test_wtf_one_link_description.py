"""A robot description of one link, no fixed joint (a student's disc-robot simulator, corpus
PlaidTrack/CSCE-452-Project-4 project4c test1): robot_state_publisher's one /tf_static message is empty, and the
scans name a frame the description lacks. Said as that, not as publishers that did not run."""

from __future__ import annotations

from pathlib import Path

from tests.analysis.robot_scenes import DELAY, START, Recorded, write_robot_bag
from tests.analysis.wtf_scenes import ekf, recording, sensor
from tests.bags import BagFormat, TfMessage
from tftools.analysis.description import Robot, robot_of
from tftools.analysis.findings import Severity
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.recording import read_recording
from tftools.sources.urdf import parse_urdf

ONE_LINK = '<?xml version="1.0"?><robot name="disc"><link name="base_link"/></robot>'
WITH_LASER = (
    '<?xml version="1.0"?><robot name="disc"><link name="base_link"/><link name="laser"/>'
    '<joint name="base_to_laser" type="fixed"><parent link="base_link"/><child link="laser"/>'
    '<origin xyz="0.1 0 0"/></joint></robot>'
)


def _sensor_frame_hint(urdf: str) -> str:
    messages = [*ekf(), TfMessage("/tf_static", START + NS_PER_S, [], "/tf_static")]
    rec = recording(sorted(messages, key=lambda m: m.record_time), ros1=False)
    robot = Robot(parse_urdf(urdf, "the recorded /robot_description"))
    scene = Scene(rec, streams=[sensor("/scan", "laser", 10, 5_000_000)], robot=robot)
    (found,) = [f for f in findings_of(scene) if f.code == "sensor_frame"]
    return found.hint


def test_a_scan_frame_the_one_link_description_lacks_is_said_as_the_description_s() -> None:
    hint = _sensor_frame_hint(ONE_LINK)
    assert hint.startswith(
        "/tf_static was recorded but holds no transform, and the recorded /robot_description has no link 'laser' "
        "(its links: base_link): robot_state_publisher had no mount of it to send"
    ), hint
    assert "check that they ran" not in hint
    # the link described, its mount not on /tf_static: its publisher did not run, as before
    assert "check that they ran" in _sensor_frame_hint(WITH_LASER)


def test_robot_state_publisher_s_empty_static_message_without_a_fixed_joint_is_a_note(tmp_path: Path) -> None:
    stamps = [START + i * NS_PER_S // 10 for i in range(20)]
    odom = [
        Recorded("/tf", t + DELAY, [Transform((0.01 * i, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), t, "world", "base_link")])
        for i, t in enumerate(stamps)
    ]
    for urdf, severity in ((ONE_LINK, Severity.info), (WITH_LASER, Severity.warning)):
        messages = [
            Recorded("/robot_description", START, urdf, "/robot_state_publisher"),
            Recorded("/tf_static", START + DELAY, [], "/robot_state_publisher"),
            *odom,
        ]
        bag = write_robot_bag(tmp_path / f"disc_{severity.name}", messages, BagFormat.rosbag2_sqlite3)
        rec = read_recording([bag])
        robot, _ = robot_of([bag], rec, None)
        (silent,) = [f for f in findings_of(Scene(rec, robot=robot)) if f.code == "silent_tf"]
        assert silent.message.endswith(": its only message on /tf_static carries no transform"), silent.message
        assert silent.severity is severity, silent
        if severity is Severity.info:
            assert "the recorded /robot_description has none (its links: base_link)" in silent.hint, silent.hint
