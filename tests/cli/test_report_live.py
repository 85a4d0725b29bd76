"""``tfx report``, ``tfx echo --plot`` and ``tfx monitor --plot`` on a live ROS1 system (roscore, rospy nodes)."""

from __future__ import annotations

from pathlib import Path

from tests.live import conftest as live
from tests.live.conftest import Ros, wait_until
from tests.render.report_scenes import page_data

# the real master and its processes, as the live tests have them
master, ros, ros1_available = live.master, live.ros, live.ros1_available


def _publishing(ros: Ros) -> None:
    ros.node("dynamic", "/report_odometry", "report_odom", "report_base", "0", "20")
    wait_until(lambda: ros.master.publishers("/tf"), 20, "the publisher")


def test_a_live_report_shows_what_was_heard(ros: Ros, tmp_path: Path) -> None:
    _publishing(ros)
    page = tmp_path / "live.html"
    result = ros.run_tfx("report", "--ros1", "--duration", "2", "-o", str(page))
    assert result.returncode == 0, result.stderr
    assert "listening to ROS1 master" in result.stderr and f"wrote {page}: no problems" in result.stderr
    (data,) = page_data(page)
    (edge,) = data["edges"]
    assert edge["name"] == "report_odom -> report_base" and 25 <= sum(edge["samples"]) <= 45  # 20 Hz for 2 s
    assert "ros1-live" in page.read_text()


def test_live_echo_and_monitor_plot_when_they_end(ros: Ros, tmp_path: Path) -> None:
    _publishing(ros)
    pose, rates = tmp_path / "pose.png", tmp_path / "rates.svg"
    echoed = ros.run_tfx(
        "echo", "report_odom", "report_base", "--ros1", "--count", "3", "--rate", "5", "--plot", str(pose)
    )
    assert echoed.returncode == 0, echoed.stderr
    assert echoed.stdout.count("- Translation:") == 3 and f"wrote {pose}: 3 lookups" in echoed.stderr
    watched = ros.run_tfx("monitor", "--ros1", "--duration", "3", "--plot", str(rates))
    assert watched.returncode == 0, watched.stderr
    assert "rate and delay of 1 edges" in watched.stderr and "report_odom -&gt; report_base" in rates.read_text()
