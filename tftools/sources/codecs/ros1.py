"""ROS1's serialization, little endian and packed: ``tf2_msgs/TFMessage`` (and ``tf/tfMessage``,
the same bytes) decoded and encoded, ``rosgraph_msgs/Clock`` too, ``std_msgs/Header`` parsed."""

from __future__ import annotations

from functools import partial

from tftools.sources.codecs.decoded import BulkDecoder, ClockDecoder, HeaderDecoder, TransformEncoder
from tftools.sources.codecs.stepped import SteppedDecoder
from tftools.sources.codecs.wire import Wire, decode_times, encode_transforms, read_headers

WIRES = (Wire("<", origin=0, align=1, seq=True, signed_sec=False, nul=False, exact=True),)

decode_tf: BulkDecoder = SteppedDecoder(WIRES)
decode_clocks: ClockDecoder = partial(decode_times, wires=WIRES)
decode_headers: HeaderDecoder = partial(read_headers, wires=WIRES)
#: Odometry's headers, each with the child_frame_id after it.
decode_odometry_headers: HeaderDecoder = partial(read_headers, wires=WIRES, children=True)
#: ``tf2_msgs/TFMessage`` serialized, every seq 0.
encode_tf_message: TransformEncoder = partial(encode_transforms, wire=WIRES[0])
