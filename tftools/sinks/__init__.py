"""Where transforms go: static transform publishers on live systems, and copies of bags with static
transforms added. Sinks are apart from sources; they share the live systems' transports with them.

``tfx static``'s calls (``sinks.static``) load on first use (PEP 562)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from tftools import lazy
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


if TYPE_CHECKING:
    from tftools.sinks.static import add_static, checked, publish_static, repair_static, static_transform

__all__ = [
    "StaticBroadcaster",
    "add_static",
    "checked",
    "open_static_broadcaster",
    "publish_static",
    "repair_static",
    "static_transform",
]

#: Where each name that loads on first use is defined.
_HOME = {
    name: "tftools.sinks.static" for name in __all__ if name not in ("StaticBroadcaster", "open_static_broadcaster")
}

__getattr__, __dir__ = lazy.exports(__name__, _HOME, __all__)
