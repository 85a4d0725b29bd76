"""Where a ROS1 node lives: the master's URI, this host's name for others, node names."""

from __future__ import annotations

import os
import socket
import time
from urllib.parse import urlsplit

from tftools.sources.live.errors import LiveError

DEFAULT_MASTER_URI = "http://localhost:11311"


def master_uri(uri: str | None = None) -> str:
    """The master to talk to: ``uri``, else ``ROS_MASTER_URI``, else ROS's default."""
    chosen = uri or os.environ.get("ROS_MASTER_URI") or DEFAULT_MASTER_URI
    parts = urlsplit(chosen)
    if parts.scheme != "http" or not parts.hostname:
        raise LiveError(f"{chosen!r} is not a ROS master URI", "it looks like http://HOST:11311")
    return chosen


def advertised_host() -> str:
    """How other nodes reach this one, as rospy decides: ``ROS_HOSTNAME``, ``ROS_IP``, the host name."""
    return os.environ.get("ROS_HOSTNAME") or os.environ.get("ROS_IP") or socket.gethostname()


def bind_address(host: str) -> str:
    """Listen on loopback only when the advertised host is loopback (as rospy does), else everywhere."""
    if host == "localhost" or host.startswith("127.") or host == "::1":
        return "127.0.0.1"
    return "0.0.0.0"  # other nodes must reach us, as any ROS node


def anonymous_name(base: str) -> str:
    """A node name no other node has, like rospy's ``anonymous=True``: ``/base_PID_MILLIS``."""
    return f"/{base}_{os.getpid()}_{int(time.time() * 1000)}"
