"""ROS 2's CDR, as bags hold it and DDS samples carry it: ``tf2_msgs/msg/TFMessage`` and foxglove's
``FrameTransforms`` (the same bytes) and ``FrameTransform`` decoded, ``rosgraph_msgs/msg/Clock`` too,
``std_msgs/msg/Header`` parsed.

A payload starts with the 4-byte encapsulation header (RTPS 10.5: 0x0000/0x0001 plain CDR big/little
endian, which rmw_cyclonedds and rosbag2 write; 0x0006/0x0007 XCDR2 for final types); alignment
counts from just after it, 8-byte values aligned to 8 in CDR and to 4 in XCDR2.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from functools import partial

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.codecs.decoded import BulkDecoder, ClockDecoder, HeaderDecoder
from tftools.sources.codecs.stepped import decode_transforms
from tftools.sources.codecs.wire import Wire, decode_times, read_headers

WIRES = tuple(
    Wire(order, origin=4, align=align, seq=False, signed_sec=True, nul=True, exact=False, encapsulation=kind)
    for kind, order, align in ((0x01, "<", 8), (0x00, ">", 8), (0x07, "<", 4), (0x06, ">", 4))
)

_ENCAPSULATION = b"\x00\x01\x00\x00"  # plain CDR, little endian: what rosbag2 and rmw_cyclonedds write
_COUNT = struct.Struct("<I")
_TIME = struct.Struct("<iI")  # builtin_interfaces/Time: int32 sec, uint32 nanosec
_VALUES = struct.Struct("<7d")

decode_tf: BulkDecoder = partial(decode_transforms, wires=WIRES)  # FrameTransforms too: the same bytes
#: Foxglove FrameTransform messages: one transform each, without a count.
decode_frame_transform: BulkDecoder = partial(decode_transforms, wires=WIRES, counted=False)
decode_clocks: ClockDecoder = partial(decode_times, wires=WIRES)
decode_headers: HeaderDecoder = partial(read_headers, wires=WIRES)


def encode_tf_message(transforms: Sequence[Transform]) -> bytes:
    """``transforms`` as one serialized ``tf2_msgs/msg/TFMessage`` (plain CDR, little endian)."""
    body = bytearray(_COUNT.pack(len(transforms)))
    for t in transforms:
        body += _TIME.pack(*divmod(t.stamp, NS_PER_S))
        for name in (t.frame_id, t.child_frame_id):
            encoded = name.encode() + b"\0"
            body += b"\0" * (-len(body) % 4) + _COUNT.pack(len(encoded)) + encoded
        body += b"\0" * (-len(body) % 8) + _VALUES.pack(*t.translation, *t.rotation)
    return _ENCAPSULATION + bytes(body)
