"""rosbags' deserializers, the yardstick of tftools' CDR and ROS1 decoders: each payload's transforms."""

from __future__ import annotations

from typing import Any

from tests.sources.ros2_helpers import TF_TYPE, ros1_typestore, typestore

FRAME_TRANSFORM = "foxglove_msgs/msg/FrameTransform"

#: A transform as tests compare them: parent, child, stamp (ns), translation and rotation by their bits.
Row = tuple[str, str, int, tuple[str, ...], tuple[str, ...]]


def reference_rows(payloads: list[bytes], key: tuple[str, str]) -> dict[int, list[Row]]:
    """The transforms of each payload (by its index) that rosbags deserializes as the codec ``key``
    (type name, encoding: cdr or ros1) says, those with any; the others are left out."""
    type_name, encoding = key
    out: dict[int, list[Row]] = {}
    for i, payload in enumerate(payloads):
        try:
            if encoding == "ros1":
                message = ros1_typestore().deserialize_ros1(payload, TF_TYPE)  # tf's tfMessage: the same bytes
            else:
                message = typestore().deserialize_cdr(payload, type_name)
        except Exception:  # rosbags raises many kinds on malformed bytes
            continue
        rows = [_row(t, encoding) for t in ([message] if type_name == FRAME_TRANSFORM else message.transforms)]
        if rows:
            out[i] = rows
    return out


def _row(t: Any, encoding: str) -> Row:
    if hasattr(t, "header"):
        parent, stamp, values = t.header.frame_id, t.header.stamp, t.transform
    else:  # a foxglove FrameTransform
        parent, stamp, values = t.parent_frame_id, t.timestamp, t
    sec = stamp.sec & 0xFFFFFFFF if encoding == "ros1" else stamp.sec  # rosbags reads ROS1's unsigned seconds as int32
    v, q = values.translation, values.rotation
    return (parent, t.child_frame_id, sec * 1_000_000_000 + stamp.nanosec,
            tuple(map(float.hex, (v.x, v.y, v.z))), tuple(map(float.hex, (q.x, q.y, q.z, q.w))))  # fmt: skip
