"""Where transforms go: static transform publishers on live systems, and copies of bags with static
transforms added. Sinks are apart from sources; they share the live systems' transports with them."""

from __future__ import annotations

from tftools.sinks.broadcaster import StaticBroadcaster
from tftools.sources.live import choose_ros
from tftools.sources.live.notices import OnNotice


def open_static_broadcaster(
    ros: str | None = None, *, master_uri: str | None = None, on_notice: OnNotice | None = None
) -> StaticBroadcaster:
    """A static transform publisher on the system ``choose_ros`` picks (ROS1: a node registered
    with the master at ``master_uri`` or ``ROS_MASTER_URI``, latched ``/tf_static``; ROS2: a DDS
    writer on ``rt/tf_static``, transient local, keep last 1)."""
    chosen = "ros1" if master_uri else choose_ros(ros)
    if chosen == "ros2":
        from tftools.sources.live.ros2 import require_cyclonedds

        require_cyclonedds()
        from tftools.sinks.ros2_broadcaster import Ros2StaticBroadcaster

        return Ros2StaticBroadcaster(on_notice)
    from tftools.sinks.ros1_broadcaster import Ros1StaticBroadcaster

    return Ros1StaticBroadcaster(master_uri, on_notice)


__all__ = ["StaticBroadcaster", "open_static_broadcaster"]
