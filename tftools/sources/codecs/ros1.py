"""ROS1's serialization, little endian and packed: ``tf2_msgs/TFMessage`` (and ``tf/tfMessage``,
the same bytes) decoded and encoded, ``rosgraph_msgs/Clock`` too, ``std_msgs/Header`` parsed."""

from __future__ import annotations

import struct
from collections.abc import Sequence
from functools import partial

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.codecs.decoded import BulkDecoder, ClockDecoder, HeaderDecoder
from tftools.sources.codecs.stepped import decode_transforms
from tftools.sources.codecs.wire import Wire, decode_times, read_headers

WIRES = (Wire("<", origin=0, align=1, seq=True, signed_sec=False, nul=False, exact=True),)

_COUNT = struct.Struct("<I")
_HEADER = struct.Struct("<III")  # seq, stamp sec, stamp nsec
_VALUES = struct.Struct("<7d")

decode_tf: BulkDecoder = partial(decode_transforms, wires=WIRES)
decode_clocks: ClockDecoder = partial(decode_times, wires=WIRES)
decode_headers: HeaderDecoder = partial(read_headers, wires=WIRES)


def encode_tf_message(transforms: Sequence[Transform]) -> bytes:
    """``transforms`` as one serialized ``tf2_msgs/TFMessage`` (every seq 0)."""
    parts = [_COUNT.pack(len(transforms))]
    for t in transforms:
        parts.append(_HEADER.pack(0, *divmod(t.stamp, NS_PER_S)))
        for name in (t.frame_id, t.child_frame_id):
            encoded = name.encode()
            parts.append(_COUNT.pack(len(encoded)) + encoded)
        parts.append(_VALUES.pack(*t.translation, *t.rotation))
    return b"".join(parts)
