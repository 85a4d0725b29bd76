"""Every command with --ros2 (or ROS 2 chosen from the environment), and their one-line errors:
the ros2 extra missing, a DDS configuration Cyclone refuses, a bad ROS_DOMAIN_ID."""

from __future__ import annotations

import json
import sys

import pytest

from tests.cli.conftest import Tfx
from tests.live.ros2_processes import Ros2Domain, domain_fixture, require_cyclonedds  # noqa: F401 - fixture `domain`
from tftools.sources.live import NoRosSelectedError, choose_ros


def test_every_command_listens_to_ros2(domain: Ros2Domain) -> None:
    static = domain.tfx("static", "--ros2", "0", "0", "1", "0", "0", "0", "base_link", "laser")
    domain.node("dynamic", "odometry", "odom", "base_link", "--hz", "20").wait_for("ready")
    static.wait_for("publishing")
    monitor = domain.tfx("monitor", "--ros2", "--duration", "2")
    view = domain.tfx("view-frames", "--ros2", "-d", "1", "-f", "dot", "-o", "-")
    wtf = domain.tfx("wtf", "--ros2", "-d", "1", "-f", "json")
    monitored, viewed, checked = monitor.finish(), view.finish(), wtf.finish()
    assert monitored.returncode == 0, monitored.stderr
    assert "/odometry" in monitored.stdout and "laser" in monitored.stdout
    assert viewed.returncode == 0, viewed.stderr
    assert "odom -> base_link [" in viewed.stdout and "Broadcaster: /odometry" in viewed.stdout
    assert checked.returncode == 0, checked.stderr  # a healthy system: nothing to report
    (heard,) = json.loads(checked.stdout)["bags"]
    assert heard["paths"] == [f"ROS2 DDS domain {domain.id}"] and heard["findings"] == []


def test_the_environment_chooses_ros2(domain: Ros2Domain) -> None:
    domain.tfx("static", "--ros2", "1", "0", "0", "0", "0", "0", "a", "b").wait_for("publishing")
    listeners = [
        domain.tfx("frames", "-d", "1", env={**domain.env, **extra})
        for extra in ({"ROS_VERSION": "2", "ROS_MASTER_URI": "http://127.0.0.1:9"}, {})  # ROS_DOMAIN_ID alone
    ]
    for listener in listeners:
        listed = listener.finish()
        assert listed.returncode == 0, listed.stderr
        assert f"listening to ROS2 DDS domain {domain.id}" in listed.stderr and "└── b  static" in listed.stdout


def test_ros_version_decides_first(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("ROS_MASTER_URI", "ROS_VERSION", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("ROS_DOMAIN_ID", "3")
    assert choose_ros() == "ros2" and choose_ros("ros1") == "ros1"
    monkeypatch.setenv("ROS_MASTER_URI", "http://localhost:11311")
    assert choose_ros() == "ros1"
    monkeypatch.setenv("ROS_VERSION", "2")
    assert choose_ros() == "ros2"
    monkeypatch.setenv("ROS_VERSION", "1")
    monkeypatch.delenv("ROS_MASTER_URI")
    assert choose_ros() == "ros1" and choose_ros("ros2") == "ros2"
    for name in ("ROS_VERSION", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(name)
    with pytest.raises(NoRosSelectedError, match="ROS_MASTER_URI is not set"):
        choose_ros()


@pytest.mark.parametrize(
    "command",
    [
        ("echo", "--ros2", "a", "b"),
        ("frames", "--ros2"),
        ("static", "--ros2", "0", "0", "0", "0", "0", "0", "a", "b"),
        ("monitor", "--ros2", "--duration", "1"),
    ],
)
def test_without_the_ros2_extra_ros2_says_how_to_install_it(
    tfx: Tfx, monkeypatch: pytest.MonkeyPatch, command: tuple[str, ...]
) -> None:
    monkeypatch.setitem(sys.modules, "cyclonedds", None)  # as if not installed
    monkeypatch.setitem(sys.modules, "cyclonedds.domain", None)
    result = tfx(*command)
    assert result.code == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert result.stderr.startswith("tfx: error: live ROS 2 needs Eclipse Cyclone DDS's Python package (cyclonedds)")
    assert "pip install 'tftools[ros2]'" in result.stderr


def test_a_bad_domain_id_is_one_line(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    require_cyclonedds()
    monkeypatch.setenv("ROS_DOMAIN_ID", "300")
    result = tfx("frames", "--ros2")
    assert result.code == 2 and result.stderr.count("\n") == 1
    assert "ROS_DOMAIN_ID='300' is not a ROS 2 domain id (use a whole number from 0 to 232" in result.stderr


def test_a_dds_configuration_cyclone_refuses_is_one_line(domain: Ros2Domain) -> None:
    result = domain.run_tfx("frames", "--ros2", env={**domain.env, "CYCLONEDDS_URI": "<Broken"})
    assert result.returncode == 2
    (error,) = [line for line in result.stderr.splitlines() if line.startswith("tfx:")]
    assert f"Cyclone DDS could not join DDS domain {domain.id}" in error and "CYCLONEDDS_URI" in error
