"""Live echo on simulated time: ``rosbag play --clock`` of a bag written by the real rosbag."""

from __future__ import annotations

import itertools
import json
import subprocess
from pathlib import Path

import pytest

from tests.live.conftest import NODES, ROS_PYTHON, Ros, wait_until


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
