"""Live echo on simulated time: ``rosbag play --clock`` of a bag written by the real rosbag."""

from __future__ import annotations

import itertools
import json
import re
import subprocess
from pathlib import Path

import pytest

from tests.live.conftest import NODES, ROS_PYTHON, STATIC_PUBLISHER, Ros, wait_until


@pytest.fixture(scope="module")
def sim_bag(ros1_available: None, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """10 s of sim_parent -> sim_child at 20 Hz from t = 1000 s, x = t - 1000 (the real rosbag writes it)."""
    path = tmp_path_factory.mktemp("sim") / "sim.bag"
    subprocess.run([ROS_PYTHON, str(NODES), "write_bag", str(path), "sim_parent", "sim_child"], check=True)
    return path


def _play(ros: Ros, bag: Path) -> None:
    ros.spawn("rosbag", "play", "--clock", "-q", str(bag))
    wait_until(lambda: ros.master.publishers("/clock"), 20, "rosbag play's /clock")


@pytest.mark.parametrize("how", ["flag", "param"])
def test_echo_follows_the_bag_clock(ros: Ros, sim_bag: Path, how: str) -> None:
    if how == "param":
        ros.master.set_param("/use_sim_time", True)
    try:
        _play(ros, sim_bag)
        flag = ["--use-sim-time"] if how == "flag" else []
        result = ros.run_tfx("echo", "sim_parent", "sim_child", *flag, "-n3", "-r2", "-f", "json", "--wait", "20")
    finally:
        if how == "param":
            ros.master.delete_param("/use_sim_time")
    assert result.returncode == 0, result.stderr
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert len(records) == 3
    for r in records:
        assert 1000 <= r["time"] < 1011  # now is bag time, not wall time
        assert r["translation"][0] == pytest.approx(r["stamp_ns"] / 1e9 - 1000, abs=1e-6)
        # The latest transform, just published. rosbag play sends /clock at 100 Hz on its own connection,
        # so a transform can arrive up to one clock tick before the clock reaches its stamp.
        assert -0.011 <= r["time"] - r["stamp_ns"] / 1e9 < 0.2
    steps = [b["time"] - a["time"] for a, b in itertools.pairwise(records)]
    assert steps == pytest.approx([0.5, 0.5], abs=0.05)  # --rate 2 in sim seconds, as ros::Rate ticks


def test_wall_time_overrides_the_master(ros: Ros, sim_bag: Path) -> None:
    ros.master.set_param("/use_sim_time", True)
    try:
        _play(ros, sim_bag)
        result = ros.run_tfx("echo", "sim_parent", "sim_child", "--wall-time", "-n", "1", "-f", "json", "--wait", "20")
    finally:
        ros.master.delete_param("/use_sim_time")
    assert result.returncode == 0, result.stderr
    record = json.loads(result.stdout)
    assert record["time"] > 1.5e9 and 1000 <= record["stamp_ns"] / 1e9 < 1011


@pytest.fixture(scope="module")
def loop_bag(ros1_available: None, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """2 s of sim_parent -> sim_child at 20 Hz from t = 1000 s, x = t - 1000: a replay that loops quickly."""
    path = tmp_path_factory.mktemp("loop") / "loop.bag"
    subprocess.run([ROS_PYTHON, str(NODES), "write_bag", str(path), "sim_parent", "sim_child", "2"], check=True)
    return path


JUMP = re.compile(
    r"ROS time jumped back from 100[12]\.\d{3} s to 1000\.\d{3} s \(a looped replay\?\): "
    r"cleared the tf buffer, static transforms kept$"
)


def test_echo_follows_a_looped_replay_and_keeps_the_statics(ros: Ros, loop_bag: Path) -> None:
    """``rosbag play --clock --loop``: each pass's transforms are answered, not refused as older
    than the pass before's (a 1 s cache: they would be), and a static transform heard once stays."""
    ros.spawn(STATIC_PUBLISHER, "0", "0", "0.25", "0", "0", "0", "sim_child", "sim_laser")
    ros.spawn("rosbag", "play", "--clock", "--loop", "-q", str(loop_bag))
    wait_until(lambda: ros.master.publishers("/clock"), 20, "rosbag play's /clock")
    echo = ("echo", "sim_parent", "sim_laser", "--use-sim-time", "--cache", "1", "-n", "12", "-r", "2")
    result = ros.run_tfx(*echo, "-f", "json", "--wait", "20", timeout=60)
    assert result.returncode == 0, result.stderr + result.stdout
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert len(records) == 12
    for r in records:
        stamp = r["stamp_ns"] / 1e9
        assert r["translation"] == pytest.approx([stamp - 1000, 0, 0.25], abs=1e-6)
        if r["time"] >= 1000.1:  # a tick at the jump itself may come before the new pass's first transform
            assert -0.011 <= r["time"] - stamp < 0.2, records
    jumps = [line for line in result.stderr.splitlines() if "jumped back" in line]
    assert len(jumps) >= 2, result.stderr  # 6 s of ticks over passes of 2 s
    assert all(JUMP.search(line) for line in jumps), jumps


def test_sim_time_without_a_clock_is_said_not_waited_for_ever(ros: Ros) -> None:
    """A forgotten --clock (issue 32, H3): /use_sim_time true and nothing publishes /clock. ros::Rate
    would wait for ever; tfx says why after CLOCK_PATIENCE seconds and exits 2."""
    ros.master.set_param("/use_sim_time", True)
    try:
        ros.spawn(STATIC_PUBLISHER, "0", "0", "1", "0", "0", "0", "nc_parent", "nc_child")
        result = ros.run_tfx("echo", "nc_parent", "nc_child", "--count", "3", "--wait", "8")
    finally:
        ros.master.delete_param("/use_sim_time")
    assert result.returncode == 2, result.stderr
    assert "no /clock came in 10 s" in result.stderr and "rosbag play --clock" in result.stderr
    assert "ros2 bag play" not in result.stderr and "ROS 2" not in result.stderr  # ROS 1's words only
    assert "Traceback" not in result.stderr


def test_use_sim_time_as_the_text_false_is_false(ros: Ros) -> None:
    ros.master.set_param("/use_sim_time", "false")
    try:
        ros.spawn(STATIC_PUBLISHER, "0", "0", "1", "0", "0", "0", "tf_parent", "tf_child")
        result = ros.run_tfx("echo", "tf_parent", "tf_child", "--count", "1", "--wait", "10", "-f", "json")
    finally:
        ros.master.delete_param("/use_sim_time")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["time"] > 1.6e9  # wall time, not a /clock that never came
