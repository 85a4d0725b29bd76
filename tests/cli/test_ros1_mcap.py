"""An MCAP file of the ros1 profile (what ``mcap convert`` makes of a ROS 1 bag: one channel per
connection, its callerid in the channel's metadata) is ROS 1 data: its publishers are the callerids and
ROS 1's tf2 judges it, as the bag it came from. Seen on the corpus' ROS 1 bags converted so: read as
ROS 2 data without publishers, the Robotino's wheels (robot_state_publisher's joints at rest) were
warned of as statics on /tf, the Kobuki's re-stamped odometry was ROS 2's warning instead of ROS 1's
TF_REPEATED_DATA error, and the Neato's laser mount lost its publisher's name."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from mcap.writer import Writer

from tests.cli.conftest import Tfx
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import NS, ROS1_TF2, ROS1_TF_DEFINITION, T0, Tf, tf_ros1
from tftools.sources.recording import semantics_of


@dataclass(frozen=True)
class Sent:
    """One /tf message as a ROS 1 node published it."""

    callerid: str
    record_time: int
    transforms: tuple[Tf, ...]


def write_ros1_mcap(path: Path, sent: Sequence[Sent], profile: str = "ros1") -> Path:
    """``sent`` as ``mcap convert`` writes a bag: a channel per callerid, the callerid in its metadata
    (left out, with the profile, when ``profile`` is "")."""
    with path.open("wb") as f:
        writer = Writer(f)
        writer.start(profile=profile, library="tftools-tests")
        schema = writer.register_schema(ROS1_TF2, "ros1msg", ROS1_TF_DEFINITION.encode())
        channels: dict[str, int] = {}
        for message in sorted(sent, key=lambda m: m.record_time):
            if message.callerid not in channels:
                metadata = {"callerid": message.callerid} if profile else {}
                channels[message.callerid] = writer.register_channel("/tf", "ros1", schema, metadata)
            data = tf_ros1(message.transforms)
            writer.add_message(channels[message.callerid], message.record_time, data, message.record_time)
        writer.finish()
    return path


def stamp(t: int) -> tuple[int, int]:
    return t // NS, t % NS


def robot(seconds: int = 6) -> list[Sent]:
    """odom -> base_link moving at 20 Hz from /odom_node; a wheel joint at rest at 15 Hz from
    /robot_state_publisher, in messages of its own (as the Robotino's three wheels)."""
    sent = []
    for i in range(seconds * 20):
        t = T0 + i * NS // 20
        sent.append(Sent("/odom_node", t + NS // 1000, (Tf("odom", "base_link", *stamp(t), (0.01 * i, 0.0, 0.0)),)))
    for i in range(seconds * 15):
        t = T0 + i * NS // 15
        sent.append(
            Sent("/robot_state_publisher", t + NS // 1000, (Tf("base_link", "wheel", *stamp(t), (0.0, 0.2, 0.0)),))
        )
    return sent


def wtf(tfx: Tfx, path: Path) -> list[dict[str, Any]]:
    """The findings of ``tfx wtf`` on the file."""
    [recording] = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    found: list[dict[str, Any]] = recording["findings"]
    return found


def codes(findings: list[dict[str, Any]], severity: str) -> list[str]:
    return [f["code"] for f in findings if f["severity"] == severity]


def test_callerids_are_the_publishers_and_ros1_tf2_reads_them(tmp_path: Path) -> None:
    path = write_ros1_mcap(tmp_path / "converted.mcap", robot())
    contents = read_contents([path])
    batch = contents.transforms
    assert {batch.authorities[a] for a in batch.authority} == {"/odom_node", "/robot_state_publisher"}
    assert contents.files[0].format == "ros1-mcap" and contents.files[0].names_publishers
    assert semantics_of(contents) == "ros1"


def test_without_the_ros1_profile_an_mcap_is_read_as_before(tmp_path: Path) -> None:
    """The same messages in an MCAP that does not say it is ROS 1: ROS 2's tf2, the topic as authority."""
    contents = read_contents([write_ros1_mcap(tmp_path / "plain.mcap", robot(), profile="")])
    batch = contents.transforms
    assert {batch.authorities[a] for a in batch.authority} == {"/tf"}
    assert contents.files[0].format == "mcap" and semantics_of(contents) == "ros2"


@pytest.mark.parametrize(("profile", "warned"), [("ros1", []), ("", ["static_on_dynamic"])])
def test_robot_state_publishers_joint_at_rest(tfx: Tfx, tmp_path: Path, profile: str, warned: list[str]) -> None:
    """The wheel that did not turn is robot_state_publisher's movable joint, where the file names it."""
    findings = wtf(tfx, write_ros1_mcap(tmp_path / "robot.mcap", robot(), profile))
    assert codes(findings, "error") == [] and codes(findings, "warning") == warned


def test_a_restamped_sample_is_ros1s_repeated_data(tfx: Tfx, tmp_path: Path) -> None:
    """A stamp sent again with other values (as Gazebo's Kobuki did): ROS 1's tf2 ignores it
    (TF_REPEATED_DATA, an error naming the publisher), where ROS 2's would keep it."""
    sent = robot()
    t = T0 + 2 * NS
    sent.append(Sent("/odom_node", t + NS // 100, (Tf("odom", "base_link", *stamp(t), (9.0, 0.0, 0.0)),)))
    [finding] = [
        f for f in wtf(tfx, write_ros1_mcap(tmp_path / "restamped.mcap", sent)) if f["code"] == "time_backwards"
    ]
    assert finding["severity"] == "error" and "/odom_node" in finding["message"]
    assert "TF_REPEATED_DATA" in finding["message"]
