"""``tfx filter`` without a bag: it listens to tf and to the sensor topics of a live system, ROS 1
(a real roscore, rospy publishers of sensor_msgs/LaserScan, tf2_ros's static publisher) and ROS 2
(stand-in nodes on a private DDS domain), and reports as on a bag."""

from __future__ import annotations

import json
from typing import Any

from tests.live import conftest as live
from tests.live.conftest import STATIC_PUBLISHER, Ros, wait_until
from tests.live.ros2_processes import Ros2Domain, domain_fixture

# the real master and its processes, as the live tests have them; a private DDS domain
master, ros, ros1_available, domain = live.master, live.ros, live.ros1_available, domain_fixture


def _topics(report: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {t["topic"]: t for t in report["topics"]}


def _assert_scans_go_through_and_the_misspelt_never(report: dict[str, Any]) -> None:
    topics = _topics(report)
    assert report["target"] == "odom" and "/tf" not in topics and "/tf_static" not in topics
    scan, misspelt = topics["/scan"], topics["/scan_misspelt"]
    assert scan["type"] == "sensor_msgs/msg/LaserScan" and scan["frame_ids"] == ["laser"]
    assert scan["messages"] >= 10 and scan["never"] == 0, scan
    # undecided: the first scans may come before any tf, the last wait for tf after the listening ended;
    # never's reasons add up to never (none here)
    undecided = sum(scan["undecided"].values())
    assert set(scan["undecided"]) <= {"before_recorded_tf", "after_recorded_tf"} and undecided <= 4, scan
    assert not scan["reasons"] and scan["on_arrival"] + scan["later"] + undecided == scan["messages"], scan
    assert misspelt["frame_ids"] == ["lasr"] and misspelt["messages"] >= 10
    assert misspelt["never"] == misspelt["messages"] and misspelt["reasons"] == {"unknown_frame": misspelt["never"]}


def test_ros1_live_filter_passes_the_scans_and_loses_a_misspelt_frame(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0.2", "0", "0.1", "0", "0", "0", "base_link", "laser")
    ros.node("dynamic", "/odometry", "odom", "base_link", "0", "20")
    ros.node("scan", "/laser_driver", "/scan", "laser", "10")
    ros.node("scan", "/misspelt_driver", "/scan_misspelt", "lasr", "10")
    topics = ("/tf", "/tf_static", "/scan", "/scan_misspelt")
    wait_until(lambda: all(ros.master.publishers(t) for t in topics), 20, "the publishers")
    # registered is not yet publishing: without the chain's tf flowing, the first scans are stamped before any of
    # it (undecided), as many as tfx starts listening early (0.4 s less of imports made it 5 or 6, not <= 4)
    assert ros.run_tfx("echo", "odom", "laser", "--ros1", "-n", "1", "--wait", "20").returncode == 0
    result = ros.run_tfx("filter", "--ros1", "-d", "3", "--target", "odom", "-f", "json")
    assert result.returncode == 1, result.stderr  # the misspelt frame's scans are lost
    _assert_scans_go_through_and_the_misspelt_never(json.loads(result.stdout))
    assert "listening to ROS1 master" in result.stderr


def test_ros1_live_filter_of_named_topics_says_what_it_could_not_hear(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0.2", "0", "0.1", "0", "0", "0", "base_link", "laser")
    ros.node("dynamic", "/odometry", "odom", "base_link", "0", "20")
    ros.node("scan", "/laser_driver", "/scan", "laser", "10")
    ros.node("wrong_type", "/chatter_node", "/chatter")
    wait_until(lambda: ros.master.publishers("/scan") and ros.master.publishers("/chatter"), 20, "the publishers")
    result = ros.run_tfx("filter", "/scan", "/chatter", "/nobody", "--ros1", "-d", "2", "-f", "json")
    assert result.returncode == 0, result.stderr
    (scan,) = json.loads(result.stdout)["topics"]
    assert scan["topic"] == "/scan" and scan["never"] == 0 and scan["messages"] >= 5
    assert "/chatter: std_msgs/msg/String messages have no header" in result.stderr
    assert "/nobody: no message heard" in result.stderr
    text = ros.run_tfx("filter", "/scan", "--ros1", "-d", "2", "--target", "odom")
    assert text.returncode == 0 and "/scan" in text.stdout and "ROS1 master" in text.stdout


def test_ros1_live_filter_with_no_sensor_data_is_a_one_line_error(ros: Ros) -> None:
    ros.node("dynamic", "/odometry", "odom", "base_link", "0", "20")
    wait_until(lambda: ros.master.publishers("/tf"), 20, "the tf publisher")
    result = ros.run_tfx("filter", "/nothing_here", "--ros1", "-d", "1")
    assert result.returncode == 2 and "no topic with a Header to check" in result.stderr
    assert "or none: tfx filter checks every such topic advertised; or listen longer" in result.stderr
    assert "Traceback" not in result.stderr


def test_ros2_live_filter_passes_the_scans_and_loses_a_misspelt_frame(domain: Ros2Domain) -> None:
    domain.tfx("static", "--ros2", "0.2", "0", "0.1", "0", "0", "0", "base_link", "laser").wait_for("publishing")
    domain.node("dynamic", "odometry", "odom", "base_link", "--hz", "20").wait_for("ready")
    domain.node("scan", "/scan", "laser").wait_for("ready")
    domain.node("scan", "/scan_misspelt", "lasr").wait_for("ready")
    result = domain.run_tfx("filter", "--ros2", "-d", "3", "--target", "odom", "-f", "json")
    assert result.returncode == 1, result.stderr
    _assert_scans_go_through_and_the_misspelt_never(json.loads(result.stdout))
    assert "listening to ROS2 DDS domain" in result.stderr


def test_ros1_live_wtf_checks_the_sensor_topics_it_is_given(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "0.2", "0", "0.1", "0", "0", "0", "base_link", "laser")
    ros.node("dynamic", "/odometry", "odom", "base_link", "0", "20")
    ros.node("scan", "/misspelt_driver", "/scan_misspelt", "lasr", "10")
    wait_until(lambda: ros.master.publishers("/tf") and ros.master.publishers("/scan_misspelt"), 20, "the publishers")
    plain = json.loads(ros.run_tfx("wtf", "--ros1", "-d", "2", "-f", "json").stdout)["bags"][0]
    assert plain["sensor_data"] is None  # live, no sensor data unless named: it could load the network
    result = ros.run_tfx("wtf", "--ros1", "-d", "3", "--sensor", "/scan_misspelt", "-f", "json")
    assert result.returncode == 1, result.stderr
    (report,) = json.loads(result.stdout)["bags"]
    assert report["sensor_data"]["topics"] == ["/scan_misspelt"] and report["sensor_data"]["target"] == "odom"
    (finding,) = [f for f in report["findings"] if f["code"] == "sensor_frame"]
    assert "'lasr' (did you mean 'laser'?)" in finding["message"]
