"""``tfx view-frames`` without a bag: it listens to a real ROS1 system (roscore and tf2_ros publishers)."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
import xmlrpc.client
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, cast

import pytest

from tests.cli.conftest import Tfx
from tests.cli.test_view_frames import need, pdf_lines
from tests.patience import patient

DYNAMIC_PUBLISHER = """
import math, rospy, tf2_ros
from geometry_msgs.msg import TransformStamped
rospy.init_node("odometry")
broadcaster = tf2_ros.TransformBroadcaster()
rate = rospy.Rate(20)
while not rospy.is_shutdown():
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id, t.child_frame_id = "odom", "base_link"
    # moving (or it belongs on /tf_static), smoothly (a wrap would be an odom jump: an error under REP 105)
    t.transform.translation.x = math.sin(rospy.get_time())
    t.transform.rotation.w = 1.0
    broadcaster.sendTransform(t)
    rate.sleep()
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def start(args: list[str], env: dict[str, str]) -> subprocess.Popen[bytes]:
    return subprocess.Popen(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)


def stop(process: subprocess.Popen[bytes]) -> None:
    try:
        os.killpg(process.pid, signal.SIGINT)
        process.wait(timeout=5)
    except (ProcessLookupError, subprocess.TimeoutExpired):
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()


def wait_for(condition: Callable[[], bool], timeout: float = 15.0) -> None:
    deadline = time.monotonic() + patient(timeout)
    while time.monotonic() < deadline:
        try:
            if condition():
                return
        except OSError:
            pass
        time.sleep(0.1)
    pytest.fail("the ROS system did not come up in time")


@pytest.fixture
def ros_system(monkeypatch: pytest.MonkeyPatch) -> Iterator[str]:
    """A roscore on a free port, a latched static publisher and a 20 Hz odom -> base_link publisher."""
    if shutil.which("roscore") is None or not Path("/usr/lib/tf2_ros/static_transform_publisher").exists():
        if os.environ.get("CI") == "true":
            pytest.fail("CI must have roscore and tf2_ros")
        pytest.skip("roscore / tf2_ros are not installed (see REFERENCE.md)")
    uri = f"http://127.0.0.1:{free_port()}"
    env = {**os.environ, "ROS_MASTER_URI": uri, "ROS_HOSTNAME": "127.0.0.1"}
    for name in ("ROS_MASTER_URI", "ROS_HOSTNAME"):
        monkeypatch.setenv(name, env[name])
    processes = [start(["roscore", "-p", uri.rsplit(":", 1)[1]], env)]
    try:
        master: Any = xmlrpc.client.ServerProxy(uri)
        wait_for(lambda: master.getSystemState("/test")[0] == 1)
        static = ["/usr/lib/tf2_ros/static_transform_publisher", "0", "0", "0.3", "0", "0", "0", "base_link", "laser"]
        processes.append(start(static, env))
        processes.append(start(["/usr/bin/python3", "-c", DYNAMIC_PUBLISHER], env))

        def publishing() -> bool:
            publishers = dict(cast(Any, master.getSystemState("/test"))[2][0])
            return "/tf" in publishers and "/tf_static" in publishers

        wait_for(publishing)
        yield uri
    finally:
        for process in reversed(processes):
            stop(process)


def test_listens_and_draws_what_it_heard(tfx: Tfx, ros_system: str, tmp_path: Path) -> None:
    need("dot")
    output = tmp_path / "live.pdf"
    result = tfx("view-frames", "--duration", "2", "-o", output)
    assert result.code == 0, result.stderr
    lines = pdf_lines(output)
    assert {"odom", "base_link", "laser"} <= set(lines)
    assert f"Listened to: ROS1 master {ros_system}" in lines
    assert any(line.startswith("Broadcaster: /static_transform_publisher") for line in lines)
    assert "Broadcaster: /odometry" in lines
    rate = next(line for line in lines if line.startswith("Average rate:"))
    assert 15 < float(rate.split()[2]) < 25  # 20 Hz, whatever the machine's load
    assert "No problems found" in lines
