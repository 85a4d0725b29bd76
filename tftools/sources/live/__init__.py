"""Live systems: transforms as they arrive from a running ROS1 or ROS2 system."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Literal

from tftools.sources.live.base import LiveSource
from tftools.sources.live.errors import LiveError, NoRosSelectedError
from tftools.sources.live.notices import OnNotice

Ros = Literal["ros1", "ros2"]


def choose_ros(ros: str | None = None) -> Ros:
    """``ros`` if given, else what the environment says: ``ROS_VERSION`` (1 or 2, set by ROS's
    setup scripts), else ROS1 where ``ROS_MASTER_URI`` is set, else ROS2 where ``ROS_DOMAIN_ID`` is;
    raises ``NoRosSelectedError`` when nothing says which."""
    if ros in ("ros1", "ros2"):
        return ros  # type: ignore[return-value]
    if ros is not None:
        raise LiveError(f"unknown ROS version {ros!r}", "use ros1 or ros2")
    version = os.environ.get("ROS_VERSION", "").strip()
    if version in ("1", "2"):
        return "ros1" if version == "1" else "ros2"
    if os.environ.get("ROS_MASTER_URI"):
        return "ros1"
    if os.environ.get("ROS_DOMAIN_ID"):
        return "ros2"
    raise NoRosSelectedError()


def open_live(
    ros: str | None = None,
    use_sim_time: bool | None = None,
    topics: Sequence[str] | None = None,
    *,
    master_uri: str | None = None,
    on_notice: OnNotice | None = None,
    name: str = "tfx",
) -> LiveSource:
    """A live source, not yet started: ROS1 through its master (``master_uri`` or ``ROS_MASTER_URI``) or
    ROS2 over DDS (domain ``ROS_DOMAIN_ID``), as ``choose_ros`` says. ``use_sim_time``: follow ``/clock``;
    ``None`` does as the system says (ROS1: the master's ``/use_sim_time``; ROS2: wall time).
    ``on_notice`` hears one-line notices. Raises ``LiveError`` when the system cannot be reached."""
    chosen = "ros1" if master_uri else choose_ros(ros)
    if chosen == "ros2":
        from tftools.sources.live.ros2 import require_cyclonedds

        require_cyclonedds()
        from tftools.sources.live.ros2.source import Ros2Source

        return Ros2Source(topics, use_sim_time, on_notice)
    from tftools.sources.live.ros1.source import Ros1Source

    return Ros1Source(master_uri, topics, use_sim_time, on_notice, name)


__all__ = ["LiveError", "LiveSource", "NoRosSelectedError", "OnNotice", "Ros", "choose_ros", "open_live"]
