"""Live on simulated time, against the real roscore, rospy and rosbag: a jump back of /clock as tf2_ros's
time_reset_test makes it, and the figures of a ``rosbag play --clock`` replay (spans from what was heard,
delays unavailable on /clock's 10 ms steps, no false alarm on a healthy bag)."""

from __future__ import annotations

import json
import re
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.live.conftest import Ros, read_line, wait_until
from tftools.core.time import NS_PER_S
from tftools.sources.live import open_live
from tftools.sources.live.capture import listen

S = NS_PER_S
SAMPLE = Path(__file__).resolve().parents[2] / "sample_bags" / "robot.bag"


class Publisher:
    """``ros1_nodes.py clock_and_tf``: /clock and /tf sent when told."""

    def __init__(self, ros: Ros) -> None:
        self.process = ros.node("clock_and_tf", "/time_reset_publisher", stdin=True)
        read_line(self.process, "ready", timeout=30)

    def say(self, line: str) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()
        read_line(self.process, "ok", timeout=10)

    def until(self, line: str, heard: Callable[[], bool], what: str) -> None:
        """Say ``line`` again until ``heard()``: a message sent before tfx's connection to the node is up
        is lost (tf2_ros's own test spins a second for that); once up, said once more changes nothing."""
        deadline = time.monotonic() + 20
        while True:
            self.say(line)
            try:
                wait_until(heard, 0.5, what)
                return
            except pytest.fail.Exception:
                if time.monotonic() > deadline:
                    raise


@pytest.fixture
def publisher(ros: Ros) -> Publisher:
    return Publisher(ros)


def test_a_jump_back_clears_the_buffer_and_keeps_what_comes_after(ros: Ros, publisher: Publisher) -> None:
    """tf2_ros's time_reset_test, on ROS 1: /clock 100 s; foo -> bar at 100 and 102 s; /clock 90 s; then
    foo2 -> bar2 at 110 s. tf2_ros clears its buffer at the jump and stores foo2 -> bar2: tftools too."""
    notices: list[str] = []
    source = open_live("ros1", use_sim_time=True, master_uri=ros.master.uri, on_notice=notices.append)
    buffer = listen(source)
    try:
        publisher.until("clock 100", lambda: source.clock.now() == 100 * S, "ROS time 100 s")
        publisher.until("tf foo bar 100", lambda: buffer.has_frame("bar"), "foo -> bar")
        publisher.say("tf foo bar 102")
        wait_until(lambda: buffer.can_transform("foo", "bar", 101 * S), 10, "foo -> bar at 101 s")
        publisher.say("clock 90")
        wait_until(lambda: source.clock.now() == 90 * S, 10, "ROS time back at 90 s")
        publisher.say("tf foo2 bar2 110")
        wait_until(lambda: buffer.has_frame("bar2"), 10, "foo2 -> bar2 after the jump")
        assert buffer.lookup("foo2", "bar2").stamp == 110 * S
        assert not buffer.can_transform("foo", "bar", 101 * S)
        assert any("ROS time jumped back from 100.000 s to 90.000 s" in n for n in notices), notices
    finally:
        source.close()


def _play(ros: Ros) -> None:
    ros.spawn("rosbag", "play", "--clock", "-q", str(SAMPLE))
    wait_until(lambda: ros.master.publishers("/clock") and ros.master.publishers("/tf"), 20, "rosbag play")


def test_a_replay_on_sim_time_is_checked_with_plausible_figures(ros: Ros) -> None:
    """``tfx wtf --use-sim-time -d 6`` beside ``rosbag play --clock`` of the healthy sample bag: its span is
    what was heard (not '1700000012.2 s', from ROS time 0), no warning, and the JSON says why delays are not
    measured (/clock every 10 ms)."""
    _play(ros)
    result = ros.run_tfx("wtf", "--ros1", "--use-sim-time", "-d", "6", "--strict", timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    said = re.search(r"ros1-live, ([\d.]+) s recorded,", result.stdout)
    assert said is not None, result.stdout
    seconds = float(said.group(1))
    assert 1 <= seconds <= 20, result.stdout


def test_a_live_monitor_on_sim_time_counts_from_what_it_heard(ros: Ros) -> None:
    """The live table's header: '(+1700000010.5 s)' counted from ROS time 0; now from the first arrival."""
    _play(ros)
    result = ros.run_tfx("monitor", "--ros1", "--use-sim-time", "--duration", "4", timeout=60)
    assert result.returncode == 0, result.stderr
    since = [float(s) for s in re.findall(r"^time [\d.]+ \(([+-][\d.]+) s\)", result.stdout, re.MULTILINE)]
    assert since and all(0 <= s <= 15 for s in since), result.stdout[:2000]
    assert (
        "delays unavailable: arrivals were timed by /clock (ROS time under use_sim_time), which ticks every 0.01"
        in (result.stdout)
    )
    json_result = ros.run_tfx("monitor", "--ros1", "--use-sim-time", "--duration", "3", "-f", "json", timeout=60)
    reports = [json.loads(line) for line in json_result.stdout.splitlines() if line.strip()]
    assert reports and all(e["delay_mean_s"] is None for r in reports if r["delays_unavailable"] for e in r["edges"]), (
        json_result.stdout[:2000]
    )
