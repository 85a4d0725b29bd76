"""Live ROS 2 over DDS, between processes on a private domain (random id, loopback only): tfx
processes, tftools in this process, and stand-in ROS 2 nodes (``ros2_nodes.py``: Cyclone DDS with
their own type definitions, as rmw_cyclonedds talks). No ROS 2 exists here to be the other side."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import pytest

from tests.live.ros2_processes import Ros2Domain, domain_fixture  # noqa: F401 - the fixture `domain`
from tftools.core.time import NS_PER_S
from tftools.sources.live import open_live
from tftools.sources.live.capture import capture, listen
from tftools.sources.recording import Recording

if TYPE_CHECKING:
    from tftools.sinks.ros2_broadcaster import Ros2StaticBroadcaster


def edges(recording: Recording) -> dict[tuple[str, str], dict[str, Any]]:
    """Per (parent, child): the authorities, stamps, x values and record times heard."""
    batch = recording.transforms
    names, authorities = list(batch.frame_names), list(batch.authorities)
    found: dict[tuple[str, str], dict[str, Any]] = {}
    for row in range(len(batch)):
        edge = found.setdefault((names[batch.parent[row]], names[batch.child[row]]), {"by": set(), "rows": []})
        edge["by"].add(authorities[batch.authority[row]])
        edge["rows"].append(row)
    for edge in found.values():
        rows = np.array(edge["rows"])
        edge.update(stamp=batch.stamp[rows], x=batch.translation[rows, 0], record=batch.record_time[rows])
    return found


def test_static_transforms_reach_late_joiners_in_one_transient_local_message(
    domain: Ros2Domain, tmp_path: Path
) -> None:
    extrinsics = tmp_path / "extrinsics.yaml"
    extrinsics.write_text("- {frame_id: base_link, child_frame_id: camera, x: 0.1, z: 0.3, roll: -1.5707963}\n")
    publisher = domain.tfx("static", "--ros2", "--from", str(extrinsics), "0.2", "0", "0.1", "1.0", "0", "0",
                           "base_link", "laser")  # fmt: skip
    node = publisher.wait_for("publishing base_link -> camera, base_link -> laser").split(" as node ")[1].split()[0]
    # Late joiners: a stand-in node with tf2_ros's StaticListenerQoS, and tfx.
    listener = domain.node("static_listener")
    echo = domain.tfx("echo", "--ros2", "base_link", "laser", "--count", "1", "--wait", "10")
    frames = domain.tfx("frames", "--ros2", "-d", "1")

    report = json.loads(listener.wait_for('"samples"'))
    assert len(report["samples"]) == 1  # one message holding both
    (sample,) = report["samples"]
    assert [(t["frame_id"], t["child_frame_id"]) for t in sample] == [("base_link", "camera"), ("base_link", "laser")]
    assert sample[0]["translation"] == [0.1, 0.0, 0.3] and sample[1]["translation"] == [0.2, 0.0, 0.1]
    assert sample[1]["rotation"] == pytest.approx([0, 0, math.sin(0.5), math.cos(0.5)], abs=1e-12)  # yaw 1
    assert sample[0]["stamp"] == sample[1]["stamp"] and sample[0]["stamp"][0] > 1_600_000_000
    # ... as static_transform_publisher's writer offers it (tf2_ros StaticBroadcasterQoS, rmw_cyclonedds).
    (writer,) = report["writers"].values()
    assert writer["type"] == "tf2_msgs::msg::dds_::TFMessage_"
    assert writer["reliability"].startswith("Policy.Reliability.Reliable(")
    assert writer["durability"] == "Policy.Durability.TransientLocal"
    assert writer["history"] == "Policy.History.KeepLast(depth=1)"
    assert "history=Policy.History.KeepLast(depth=1)" in writer["durability_service"]

    echoed = echo.finish()
    assert echoed.returncode == 0, echoed.stderr
    assert "- Translation: [0.200, 0.000, 0.100]" in echoed.stdout
    assert [line.endswith(", 1.000]") for line in echoed.stdout.splitlines() if "in RPY (radian)" in line] == [True]
    # tfx names the publisher by the node it announced on ros_discovery_info.
    listed = frames.finish()
    assert node.startswith("/tfx_static_") and f"camera  static  {node}" in listed.stdout, listed.stdout


def test_publishers_are_heard_and_named_by_their_nodes(domain: Ros2Domain) -> None:
    for node in (
        domain.node("dynamic", "jazzy_node", "odom", "base_link", "--gid", "16"),
        domain.node("dynamic", "humble_node", "map", "odom", "--gid", "24"),
        domain.node("dynamic", "plain_dds", "base_link", "camera", "--gid", "0"),
    ):
        node.wait_for("ready")
    echo = domain.tfx("echo", "--ros2", "map", "camera", "--count", "2", "--rate", "10", "--wait", "10")
    source = open_live("ros2")
    assert source.describe() == f"ROS2 DDS domain {domain.id}"
    recording = capture(source, duration=1.0)

    heard = edges(recording)
    assert set(heard) == {("map", "odom"), ("odom", "base_link"), ("base_link", "camera")}
    assert heard["map", "odom"]["by"] == {"/humble_node"}  # 24-byte Gids (Humble)
    assert heard["odom", "base_link"]["by"] == {"/jazzy_node"}  # 16-byte Gids (Iron on)
    (plain,) = heard["base_link", "camera"]["by"]  # no ros_discovery_info: the DDS participant
    assert plain.startswith("dds:") and len(plain) == len("dds:") + 26
    for edge in heard.values():
        assert len(edge["stamp"]) >= 10 and np.all(np.diff(edge["stamp"]) > 0)
        x = 100 - np.abs(edge["stamp"] % (200 * NS_PER_S) - 100 * NS_PER_S) / 1e9  # the nodes' x, as they compute it
        assert np.array_equal(edge["x"], x)
        assert np.all(edge["record"] >= edge["stamp"]) and np.all(edge["record"] - edge["stamp"] < 5 * NS_PER_S)
    assert source.message_count == len(recording.transforms)
    assert recording.contents.files[0].format == "ros2-live"

    echoed = echo.finish()
    assert echoed.returncode == 0, echoed.stderr
    assert echoed.stdout.count("At time ") == 2 and "- Translation: [" in echoed.stdout


def test_publishers_that_come_late_and_go_are_followed(domain: Ros2Domain) -> None:
    with open_live("ros2") as source:
        buffer = listen(source)
        first = domain.node("dynamic", "first", "odom", "base_link")
        buffer.wait_for_transform("odom", "base_link", 0, timeout_s=10)
        first.stop()
        domain.node("dynamic", "second", "odom", "camera", "--gid", "24")
        buffer.wait_for_transform("odom", "camera", 0, timeout_s=10)
        assert set(buffer.authorities) >= {"/first", "/second"}


def test_sim_time_follows_clock(domain: Ros2Domain) -> None:
    domain.node("dynamic", "player", "odom", "base_link", "--sim", "1000").wait_for("ready")
    echo = domain.tfx("echo", "--ros2", "--use-sim-time", "odom", "base_link", "--count", "2", "--wait", "10")
    source = open_live("ros2", use_sim_time=True)
    recording = capture(source, duration=1.0)
    heard = edges(recording)["odom", "base_link"]
    assert np.all((heard["stamp"] >= 1000 * NS_PER_S) & (heard["stamp"] < 1060 * NS_PER_S))
    # Record times are /clock's, not the wall's; 0 (unknown: ROS time is still 0) only before the first /clock.
    records = heard["record"]
    known = records > 0
    assert known.any() and not np.any(known[:-1] & ~known[1:])
    assert np.all((records[known] >= 1000 * NS_PER_S) & (records[known] < 1060 * NS_PER_S))
    assert 1000 * NS_PER_S < source.clock.now() < 1060 * NS_PER_S

    echoed = echo.finish()
    assert echoed.returncode == 0, echoed.stderr
    stamps = [float(line.split()[2]) for line in echoed.stdout.splitlines() if line.startswith("At time ")]
    assert len(stamps) == 2 and all(1000 < s < 1060 for s in stamps)


def test_sim_time_without_a_clock_is_said_in_ros2_words(domain: Ros2Domain) -> None:
    """--use-sim-time and nothing publishes /clock (a forgotten ``ros2 bag play --clock``): tfx says why after
    CLOCK_PATIENCE seconds, exits 2, in ROS 2's words only (no rosbag, no rosparam)."""
    domain.node("dynamic", "walltime", "odom", "base_link").wait_for("ready")
    result = domain.run_tfx("echo", "--ros2", "--use-sim-time", "odom", "base_link", "--count", "3", "--wait", "8")
    assert result.returncode == 2, result.stderr
    assert "no /clock came in 10 s" in result.stderr and "ros2 bag play --clock" in result.stderr
    assert "rosbag play" not in result.stderr and "rosparam" not in result.stderr and "ROS 1" not in result.stderr
    assert "Traceback" not in result.stderr


def test_a_looped_replay_clears_the_buffer_and_keeps_the_statics(domain: Ros2Domain) -> None:
    """/clock back to 1000 s every 1.5 s: tfx echo (a 1 s cache) answers each pass's transforms,
    not the pass before's last one, keeps a static transform published once, says each jump."""
    domain.tfx("static", "--ros2", "0", "0", "0.25", "0", "0", "0", "base_link", "laser").wait_for("publishing")
    domain.node("dynamic", "player", "odom", "base_link", "--sim", "1000", "--loop", "1.5").wait_for("ready")
    echo = ("echo", "--ros2", "--use-sim-time", "odom", "laser", "--cache", "1", "--count", "8", "--rate", "2")
    echoed = domain.run_tfx(*echo, "--format", "json", "--wait", "10")
    assert echoed.returncode == 0, echoed.stderr + echoed.stdout
    records = [json.loads(line) for line in echoed.stdout.splitlines()]
    assert len(records) == 8
    for r in records:
        stamp = r["stamp_ns"] / NS_PER_S
        assert r["translation"] == pytest.approx([stamp - 1000, 0.5, 0.25], abs=1e-6)
        if r["time"] >= 1000.1:  # a tick at the jump itself may come before the new pass's first transform
            assert 0 <= r["time"] - stamp < 0.2, records
    jumps = [line for line in echoed.stderr.splitlines() if "jumped back" in line]
    assert len(jumps) >= 2, echoed.stderr  # 4 s of ticks over passes of 1.5 s
    assert all(
        re.search(r"ROS time jumped back from 1001\.\d{3} s to 1000\.\d{3} s \(a looped replay\?\): ", line)
        and line.endswith(": cleared the tf buffer, static transforms kept")
        for line in jumps
    ), jumps


def test_publishers_tf2_would_not_hear_are_named(domain: Ros2Domain) -> None:
    for node in (domain.node("wrong_type", "/tf"), domain.node("volatile_static")):
        node.wait_for("ready")
    notices: list[str] = []
    recording = capture(open_live("ros2", on_notice=notices.append), duration=1.0)
    assert not len(recording.transforms)
    assert any("publishes /tf as std_msgs/msg/String, not tf2_msgs/msg/TFMessage: not heard" in n for n in notices)
    assert any("publishes /tf_static volatile: tf2 listeners (transient local) do not hear it" in n for n in notices)


def test_the_static_publisher_is_announced_in_the_systems_gid_size(
    domain: Ros2Domain, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tftools.sinks import open_static_broadcaster

    monkeypatch.delenv("ROS_DISTRO", raising=False)
    humble_graph = domain.node("discovery_listener", "24")
    humble_graph.wait_for("ready")
    with open_static_broadcaster("ros2") as opened:
        broadcaster = cast("Ros2StaticBroadcaster", opened)
        assert broadcaster.gid_size == 16  # Iron on, until the system shows otherwise
        domain.node("dynamic", "humble_node", "odom", "base_link", "--gid", "24")
        humble_graph.wait_for('"/humble_node"')
        announced = f'"/{broadcaster.node_name}"'  # announced again, in Humble's size (the listener hears no other)
        if not any(announced in line for line in humble_graph.seen):  # else heard before the Humble node's own
            humble_graph.wait_for(announced)
        assert broadcaster.gid_size == 24
