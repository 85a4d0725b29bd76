"""Live ``tfx echo`` and ``tfx frames`` against a real roscore and real tf publishers."""

from __future__ import annotations

import json
import math
import signal
import socket

import pytest

from tests.live.conftest import STATIC_PUBLISHER, Ros, free_port, read_line, tf_echo_block, wait_until


def test_echo_prints_what_tf_echo_prints_for_a_static_publisher(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "1", "-2", "0.5", "0.3", "-0.2", "0.1", "echo_map", "echo_odom")
    result = ros.run_tfx("echo", "echo_map", "echo_odom", "-n", "2", "-r", "20", "--wait", "20")
    assert result.returncode == 0, result.stderr
    assert result.stdout == tf_echo_block(ros, "echo_map", "echo_odom") * 2
    assert "waiting for the transform echo_map <- echo_odom" in result.stderr


def test_echo_follows_a_rospy_broadcaster(ros: Ros) -> None:
    ros.node("dynamic", "/dyn_pub", "dyn_parent", "dyn_child", "1.5", "50")
    result = ros.run_tfx("echo", "dyn_parent", "dyn_child", "-n", "4", "-r", "10", "-f", "json", "--wait", "20")
    assert result.returncode == 0, result.stderr
    records = [json.loads(line) for line in result.stdout.splitlines()]
    assert len(records) == 4
    for r in records:
        assert r["translation"][0] == 1.5
        assert r["translation"][1] == pytest.approx(r["stamp_ns"] / 1e9 - 1.7e9, abs=1e-6)  # as sent for that stamp
        assert r["rotation"] == pytest.approx([0, 0, math.sin(0.15), math.cos(0.15)])
        assert r["time"] * 1e9 >= r["stamp_ns"] - 50_000_000  # "time" is now, on the wall clock
    assert len({r["stamp_ns"] for r in records}) == 4  # the latest, each time


def test_frames_names_each_publisher(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0", "0", "1", "0", "0", "0", "fr_base", "fr_laser")
    ros.node("dynamic", "/fr_odometry", "fr_odom", "fr_base", "0", "30")
    wait_until(lambda: ros.master.publishers("/tf") and ros.master.publishers("/tf_static"), 20, "the publishers")
    result = ros.run_tfx("frames", "-d", "1.5", "-f", "json")
    assert result.returncode == 0, result.stderr
    frames = {f["frame"]: f for f in json.loads(result.stdout)["frames"]}
    assert frames["fr_laser"]["parent"] == "fr_base" and frames["fr_laser"]["static"]
    assert frames["fr_laser"]["authorities"][0].startswith("/static_transform_publisher")
    assert frames["fr_base"]["authorities"] == ["/fr_odometry"] and not frames["fr_base"]["static"]
    assert 20 < frames["fr_base"]["rate_hz"] < 40
    assert "listening to ROS1 master" in result.stderr


def test_a_publisher_that_starts_late_is_heard(ros: Ros) -> None:
    echo = ros.tfx("echo", "late_a", "late_b", "-n", "1", "--wait", "30", "-f", "json")
    read_line(echo, "waiting for the transform late_a <- late_b", timeout=20, stream="stderr")
    ros.spawn(STATIC_PUBLISHER, "3", "0", "0", "0", "0", "0", "late_a", "late_b")
    (line,) = read_line(echo, "translation", timeout=20)
    assert json.loads(line)["translation"] == [3.0, 0.0, 0.0]
    assert echo.wait(10) == 0


def test_a_publisher_that_dies_is_replaced(ros: Ros) -> None:
    first = ros.node("dynamic", "/dying_pub", "die_parent", "die_child", "1.5", "50")
    read_line(first, "ready", timeout=20)
    echo = ros.tfx("echo", "die_parent", "die_child", "-r", "20", "-f", "json", "--wait", "30")
    read_line(echo, '"translation":[1.5,', timeout=20)
    first.kill()  # no unregistering: the master still lists it for a while
    read_line(echo, "lost the connection to /dying_pub", timeout=20, stream="stderr")
    ros.node("dynamic", "/second_pub", "die_parent", "die_child", "-2.5", "50")
    read_line(echo, '"translation":[-2.5,', timeout=20)
    echo.send_signal(signal.SIGINT)
    assert echo.wait(10) == 0


def test_a_publisher_of_another_type_is_named_and_ignored(ros: Ros) -> None:
    ros.node("wrong_type", "/stringy", "/tf")
    ros.spawn(STATIC_PUBLISHER, "0", "1", "0", "0", "0", "0", "wt_a", "wt_b")
    wait_until(lambda: "/stringy" in ros.master.publishers("/tf"), 20, "the String publisher")
    # Two lines a second apart: time for the String publisher's refusal, which races the static's answer.
    result = ros.run_tfx("echo", "wt_a", "wt_b", "-n", "2", "-r", "1", "--wait", "20", "-f", "json")
    assert result.returncode == 0, result.stderr
    assert [json.loads(line)["translation"] for line in result.stdout.splitlines()] == [[0.0, 1.0, 0.0]] * 2
    warnings = [line for line in result.stderr.splitlines() if "/stringy" in line]
    assert len(warnings) == 1 and "tfx: warning: /stringy refused to send /tf" in warnings[0]
    assert "[tf2_msgs/TFMessage] vs. [std_msgs/String]" in warnings[0]  # rospy's words, brackets and all


def test_a_frame_that_never_comes_is_a_one_line_error(ros: Ros) -> None:
    result = ros.run_tfx("echo", "nowhere_a", "nowhere_b", "--wait", "1")
    assert result.returncode == 2
    error = [line for line in result.stderr.splitlines() if "error" in line]
    assert len(error) == 1 and "no transform nowhere_a <- nowhere_b" in error[0] and "does not exist" in error[0]
    assert "Traceback" not in result.stderr


def test_echo_leaves_no_registration_behind(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0", "0", "0", "0", "0", "0", "reg_a", "reg_b")
    result = ros.run_tfx("echo", "reg_a", "reg_b", "-n", "1", "--wait", "20")
    assert result.returncode == 0, result.stderr
    assert not [node for node in ros.master.subscribers("/tf_static") if node.startswith("/tfx")]


STATIC_ARGS = ["static", "0", "0", "0", "0", "0", "0", "a", "b"]


@pytest.mark.parametrize("command", [["echo", "a", "b"], ["frames"], STATIC_ARGS])
def test_a_dead_master_is_a_one_line_error(ros: Ros, command: list[str]) -> None:
    env = {**ros.env, "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}"}
    result = ros.run_tfx(*command, env=env, timeout=20)
    assert result.returncode == 2
    assert (
        result.stderr.strip()
        .splitlines()[-1]
        .startswith("tfx: error: cannot reach the ROS master at http://127.0.0.1:")
    )
    assert "connection refused" in result.stderr and "Traceback" not in result.stderr


def test_a_master_that_never_answers_is_a_one_line_error(ros: Ros) -> None:
    with socket.create_server(("127.0.0.1", 0)) as silent:  # accepts connections, never answers
        env = {**ros.env, "ROS_MASTER_URI": f"http://127.0.0.1:{silent.getsockname()[1]}"}
        result = ros.run_tfx("echo", "a", "b", env=env, timeout=20)
    assert result.returncode == 2
    last = result.stderr.strip().splitlines()[-1]
    assert "tfx: error: the ROS master at http://127.0.0.1:" in last and "did not answer within 3 s" in last


def test_no_master_uri_says_what_to_do(ros: Ros) -> None:
    env = {k: v for k, v in ros.env.items() if not k.startswith("ROS_")}
    result = ros.run_tfx("frames", env=env)
    assert result.returncode == 2
    assert "ROS_MASTER_URI is not set" in result.stderr and "-b BAG" in result.stderr


@pytest.mark.live
def test_echo_between_separate_trees_says_which_while_it_waits(ros: Ros) -> None:
    """Issue 39: the hint a recording's echo gives under failures between two trees no transform joins, live
    too: once (with the first reminder, 5 s in, not again when echo gives up), naming both trees as heard so far."""
    ros.spawn(STATIC_PUBLISHER, "1", "0", "0", "0", "0", "0", "sep_map", "sep_odom")
    ros.spawn(STATIC_PUBLISHER, "0", "0", "1", "0", "0", "0", "sep_camera_root", "sep_marker")
    wait_until(lambda: len(ros.master.publishers("/tf_static")) >= 2, 20, "the two static publishers")
    result = ros.run_tfx("echo", "sep_odom", "sep_marker", "--wait", "6")
    assert result.returncode == 2
    assert "still waiting (5 s): Could not find a connection between 'sep_odom' and 'sep_marker'" in result.stderr
    hints = [line for line in result.stderr.splitlines() if line.startswith("hint: ")]
    assert hints == [
        "hint: sep_marker and sep_odom are in separate trees, sep_marker in sep_camera_root's (2 frames) and sep_odom "
        "in sep_map's (2 frames): no transform heard so far joins them, so no lookup between them succeeds yet; "
        "publish the transform that attaches sep_camera_root to the sep_map tree (a static_transform_publisher for a "
        "fixed mount), or check the frame names for typos"
    ]
    assert "no transform sep_odom <- sep_marker" in result.stderr
