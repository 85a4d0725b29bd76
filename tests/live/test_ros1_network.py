"""Where a tfx node says it lives, as rospy decides; and the choice of live system."""

from __future__ import annotations

import socket

import pytest

from tests.cli.conftest import Tfx
from tftools.sources.live import NoRosSelectedError, choose_ros
from tftools.sources.live.errors import LiveError
from tftools.sources.live.ros1 import network


def test_ros_hostname_then_ros_ip_then_the_host_name(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_HOSTNAME", "robot.local")
    monkeypatch.setenv("ROS_IP", "10.0.0.7")
    assert network.advertised_host() == "robot.local"
    monkeypatch.delenv("ROS_HOSTNAME")
    assert network.advertised_host() == "10.0.0.7"
    monkeypatch.delenv("ROS_IP")
    assert network.advertised_host() == socket.gethostname()


def test_binds_to_loopback_only_for_a_loopback_name() -> None:
    assert network.bind_address("127.0.0.1") == network.bind_address("localhost") == "127.0.0.1"
    assert network.bind_address("10.0.0.7") == "0.0.0.0"


def test_master_uri(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_MASTER_URI", "http://robot:11311")
    assert network.master_uri() == "http://robot:11311"
    assert network.master_uri("http://other:1234") == "http://other:1234"
    monkeypatch.delenv("ROS_MASTER_URI")
    assert network.master_uri() == "http://localhost:11311"
    with pytest.raises(LiveError, match="is not a ROS master URI"):
        network.master_uri("robot:11311")


def test_choosing_the_system(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("ROS_MASTER_URI", "ROS_VERSION", "ROS_DOMAIN_ID"):
        monkeypatch.delenv(name, raising=False)
    with pytest.raises(NoRosSelectedError):
        choose_ros()
    assert choose_ros("ros1") == "ros1"
    monkeypatch.setenv("ROS_MASTER_URI", "http://localhost:11311")
    assert choose_ros() == "ros1"


def test_bag_only_options_are_refused_live(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:9")
    result = tfx("echo", "a", "b", "--all")
    assert result.code == 2 and "--all only work on a bag" in result.stderr
