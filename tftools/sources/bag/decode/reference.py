"""Reference decoding with rosbags' deserializers (CDR and ROS1), the yardstick of the fast decoders."""

from __future__ import annotations

from functools import cache
from typing import Any

from tftools.sources.bag.decode.template import DecodeError, Parsed

TF_MESSAGE = "tf2_msgs/msg/TFMessage"
ROS1_TF_MESSAGES = ("tf2_msgs/TFMessage", "tf/tfMessage")  # as MCAP files of ROS1 name them
FRAME_TRANSFORM = "foxglove_msgs/msg/FrameTransform"
FRAME_TRANSFORMS = "foxglove_msgs/msg/FrameTransforms"

_FRAME_TRANSFORM_MSG = """\
builtin_interfaces/Time timestamp
string parent_frame_id
string child_frame_id
geometry_msgs/Vector3 translation
geometry_msgs/Quaternion rotation
"""
_FRAME_TRANSFORMS_MSG = "foxglove_msgs/FrameTransform[] transforms\n"


@cache
def _typestore() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    store.register(get_types_from_msg(_FRAME_TRANSFORM_MSG, FRAME_TRANSFORM))
    store.register(get_types_from_msg(_FRAME_TRANSFORMS_MSG, FRAME_TRANSFORMS))
    return store


@cache
def _ros1_typestore() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)  # without tf2_msgs
    store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_MESSAGE))
    return store


def _deserialize(data: bytes, type_name: str, *, ros1: bool = False) -> Any:
    try:
        if ros1:
            return _ros1_typestore().deserialize_ros1(data, type_name)
        return _typestore().deserialize_cdr(data, type_name)
    except Exception as e:  # rosbags raises many kinds on malformed bytes
        raise DecodeError(f"rosbags cannot deserialize it ({type(e).__name__}: {e})") from None


def reference_tf_message(data: bytes) -> Parsed:
    parsed = Parsed([], [], [], [])
    for t in _deserialize(data, TF_MESSAGE).transforms:
        stamp, v = t.header.stamp, t.transform
        _add(parsed, t.header.frame_id, t.child_frame_id, stamp.sec, stamp.nanosec, v.translation, v.rotation)
    return parsed


def reference_ros1_tf_message(data: bytes) -> Parsed:
    """A ROS1 ``tf2_msgs/TFMessage`` or ``tf/tfMessage`` (the same bytes)."""
    parsed = Parsed([], [], [], [])
    for t in _deserialize(data, TF_MESSAGE, ros1=True).transforms:
        stamp, v = t.header.stamp, t.transform
        sec = stamp.sec & 0xFFFFFFFF  # rosbags reads ROS1's unsigned seconds as int32
        _add(parsed, t.header.frame_id, t.child_frame_id, sec, stamp.nanosec, v.translation, v.rotation)
    return parsed


def reference_frame_transforms(data: bytes) -> Parsed:
    parsed = Parsed([], [], [], [])
    for t in _deserialize(data, FRAME_TRANSFORMS).transforms:
        _add_foxglove(parsed, t)
    return parsed


def reference_frame_transform(data: bytes) -> Parsed:
    parsed = Parsed([], [], [], [])
    _add_foxglove(parsed, _deserialize(data, FRAME_TRANSFORM))
    return parsed


def _add_foxglove(parsed: Parsed, t: Any) -> None:
    stamp = t.timestamp
    _add(parsed, t.parent_frame_id, t.child_frame_id, stamp.sec, stamp.nanosec, t.translation, t.rotation)


def _add(parsed: Parsed, parent: str, child: str, sec: int, nsec: int, tr: Any, rot: Any) -> None:
    parsed.parents.append(parent)
    parsed.children.append(child)
    parsed.stamps.append(int(sec) * 1_000_000_000 + int(nsec))
    parsed.values.append((tr.x, tr.y, tr.z, rot.x, rot.y, rot.z, rot.w))
