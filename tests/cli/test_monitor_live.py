"""``tfx monitor`` without a bag: tf_monitor's numbers from a real ROS1 system (roscore, tf2_ros publishers)."""

from __future__ import annotations

import json

import pytest

from tests.cli.conftest import Tfx
from tests.cli.test_view_frames_live import ros_system  # noqa: F401 - the fixture


def test_live_refreshes_with_the_publishers_rates(tfx: Tfx, ros_system: str) -> None:  # noqa: F811
    result = tfx("monitor", "odom", "laser", "--duration", "3.5", "--window", "2", "-f", "json")
    assert result.code == 0, result.stderr
    reports = [json.loads(line) for line in result.stdout.splitlines()]
    assert len(reports) >= 3  # once a second, and at the end
    last = reports[-1]
    assert last["window"]["end"] - last["window"]["start"] == pytest.approx(2.0)
    edges = {e["child"]: e for e in last["edges"]}
    assert edges["laser"]["static"] and edges["laser"]["parent"] == "base_link"
    odom = edges["base_link"]
    assert odom["parent"] == "odom" and odom["authorities"] == ["/odometry"]
    assert 15 < odom["rate_hz"] < 25  # 20 Hz, whatever the machine's load
    assert 0 <= odom["delay_mean_s"] <= odom["delay_max_s"] < 0.5  # received on the same machine
    publishers = {a["authority"]: a for a in last["authorities"]}
    assert 15 < publishers["/odometry"]["rate_hz"] < 25
    assert any(name.startswith("/static_transform_publisher") for name in publishers)
    chain = last["chain"]
    assert chain["frames"] == ["laser", "base_link", "odom"] and chain["limiting"] == ["odom", "base_link"]
    assert 0 < chain["net_delay_mean_s"] < chain["net_delay_max_s"] < 0.5  # a 20 Hz edge: about 25 ms on average
    text = tfx("monitor", "--duration", "1.5")  # the same system, as a table
    assert text.code == 0, text.stderr
    assert f"ROS1 master {ros_system}" in text.stdout
    assert "RESULTS: for all Frames" in text.stdout and "/odometry" in text.stdout


def test_bag_only_options_are_refused_live(tfx: Tfx) -> None:
    result = tfx("monitor", "--play")
    assert result.code == 2 and "only work on a bag" in result.stderr
