"""rosbags' type stores: the one place tftools makes them, and asks them for message definitions,
md5sums and field lists. (rosbags is imported on first use: it takes a while.)"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

from tftools.values import value

TF_MESSAGE = "tf2_msgs/msg/TFMessage"
#: tf1's /tf message (the same bytes as TFMessage), from before /tf_static existed (ROS Hydro brought tf2's).
TF1_MESSAGE = "tf/tfMessage"
CLOCK = "rosgraph_msgs/msg/Clock"
#: Odometry, whose header is followed by its child_frame_id (read with the header: ``decode_odometry_headers``).
ODOMETRY = "nav_msgs/msg/Odometry"
HEADER_TYPES = frozenset({"std_msgs/msg/Header", "std_msgs/Header"})
#: ROS 2's definitions tftools knows: the newest first, then Humble's (the long-term release most run).
ROS2_STORES = ("latest", "ros2_humble")


@functools.cache
def typestore(name: str) -> Any:
    """rosbags' type store ``name`` (a ``rosbags.typesys.Stores`` value: "ros1_noetic", "ros2_humble",
    ...); Noetic's with ``tf2_msgs/msg/TFMessage``, which it lacks."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores(name))
    if TF_MESSAGE not in store.fielddefs:
        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_MESSAGE))
    return store


@value
class MessageType:
    """What a TCPROS connection header says about a message type."""

    name: str  # ROS1 spelling: "tf2_msgs/TFMessage"
    md5sum: str
    definition: str


@functools.cache
def ros1_message_type(typename: str) -> MessageType:
    """``typename`` (rosbags' ``pkg/msg/Name``) with its ROS1 md5sum and full definition (Noetic's)."""
    definition, md5sum = typestore("ros1_noetic").generate_msgdef(typename, ros_version=1)
    return MessageType(typename.replace("/msg/", "/"), md5sum, definition)


def starts_with_header(msgtype: str, fielddefs: Mapping[str, Any]) -> bool:
    """Whether ``msgtype``'s first field is a std_msgs/Header, as a type store's ``fielddefs`` define it."""
    definition = fielddefs.get(msgtype)
    if not definition or not definition[1]:
        return False
    _name, (_kind, detail) = definition[1][0]
    return detail in HEADER_TYPES


def known_type(type_name: str) -> bool:
    """Whether a type store of tfx's (Noetic's or ROS 2's) defines ``type_name``: one it does not (a vendor's
    driver type) has its header read only where the recording gives its definition."""
    return any(rosidl_name(type_name) in typestore(name).fielddefs for name in ("ros1_noetic", *ROS2_STORES))


def definition_starts_with_header(msgtype: str, definition: str) -> bool:
    """Whether a ROS1 message definition (``message_definition`` of a connection header, nested
    types included) of ``msgtype`` has a ``Header`` as its first field."""
    from rosbags.typesys import get_types_from_msg

    try:
        fielddefs = get_types_from_msg(definition, msgtype)
    except Exception:  # rosbags raises several kinds on what it cannot parse: then it is no header
        return False
    return starts_with_header(msgtype, fielddefs)


def rosidl_name(type_name: str) -> str:
    """A type's name as ROS 2 and rosbags spell it: ROS1's ``pkg/Name`` as ``pkg/msg/Name``."""
    package, _, name = type_name.partition("/")
    return type_name if "/" in name or not name else f"{package}/msg/{name}"


@functools.cache
def has_header(type_name: str, encoding: str, definition: str = "") -> bool:
    """Whether messages of ``type_name`` start with a std_msgs/Header: as ``definition`` (a ROS1 or
    ROS 2 .msg text, nested types included) says, else as the type stores of ``encoding`` define it
    (Noetic's for ROS1, ROS 2's for CDR)."""
    if definition:
        return definition_starts_with_header(rosidl_name(type_name), definition)
    stores = ("ros1_noetic",) if encoding == "ros1" else ROS2_STORES
    return any(starts_with_header(rosidl_name(type_name), typestore(name).fielddefs) for name in stores)
