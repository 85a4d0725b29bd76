"""``tfx wtf`` without a bag: it listens to a real ROS1 system (roscore, tf2_ros publishers) and checks it."""

from __future__ import annotations

import json
from typing import Any

from tests.live import conftest as live
from tests.live.conftest import Ros, wait_until

# the real master and its processes, as the live tests have them
master, ros, ros1_available = live.master, live.ros, live.ros1_available

STATIC_PUBLISHER = "/usr/lib/tf2_ros/static_transform_publisher"


def wtf(ros: Ros, *arguments: str) -> tuple[int, dict[str, Any], str]:
    result = ros.run_tfx("wtf", "--ros1", "--duration", "2", "--format", "json", *arguments)
    return result.returncode, json.loads(result.stdout), result.stderr


def test_a_healthy_live_system_passes(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0.2", "0", "0.1", "0", "0", "0", "live_base", "live_laser")
    ros.node("dynamic", "/live_odometry", "live_odom", "live_base", "0", "20")
    wait_until(lambda: ros.master.publishers("/tf") and ros.master.publishers("/tf_static"), 20, "the publishers")
    code, report, stderr = wtf(ros)
    (bag,) = report["bags"]
    assert code == 0, bag
    assert bag["findings"] == [] and bag["formats"] == ["ros1-live"]
    assert bag["paths"][0].startswith("ROS1 master http://127.0.0.1:") and "listening to ROS1 master" in stderr


def test_two_nodes_fighting_over_a_frame_are_named(ros: Ros) -> None:
    ros.node("dynamic", "/fight_odometry", "fight_odom", "fight_base", "0", "20")
    ros.node("dynamic", "/fight_localizer", "fight_map", "fight_base", "1", "20")
    wait_until(lambda: len(ros.master.publishers("/tf")) >= 2, 20, "both publishers")
    code, report, _ = wtf(ros)
    findings = report["bags"][0]["findings"]
    assert code == 1
    reparented = next(f for f in findings if f["code"] == "multiple_parents")
    assert reparented["severity"] == "error" and reparented["frames"][0] == "fight_base"
    assert set(reparented["frames"][1:]) == {"fight_odom", "fight_map"}
    assert set(reparented["authorities"]) == {"/fight_odometry", "/fight_localizer"}
    assert "/fight_localizer" in reparented["message"] and "fight over it" in reparented["hint"]


def test_nothing_published_is_the_no_tf_error(ros: Ros) -> None:
    code, report, _ = wtf(ros, "--topic", "/nobody_tf")
    (finding,) = report["bags"][0]["findings"]
    assert code == 1 and finding["code"] == "no_tf" and "from ROS1 master" in finding["message"]
