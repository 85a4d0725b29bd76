"""ROS 2's CDR, as bags hold it and DDS samples carry it: ``tf2_msgs/msg/TFMessage`` and foxglove's
``FrameTransforms`` (the same bytes) and ``FrameTransform`` decoded, ``rosgraph_msgs/msg/Clock`` too,
``std_msgs/msg/Header`` parsed.

A payload starts with the 4-byte encapsulation header (RTPS 10.5: 0x0000/0x0001 plain CDR big/little
endian, which rmw_cyclonedds and rosbag2 write; 0x0006/0x0007 XCDR2 for final types); alignment
counts from just after it, 8-byte values aligned to 8 in CDR and to 4 in XCDR2.
"""

from __future__ import annotations

from functools import partial

from tftools.sources.codecs.decoded import BulkDecoder, ClockDecoder, HeaderDecoder, TransformEncoder
from tftools.sources.codecs.stepped import SteppedDecoder
from tftools.sources.codecs.wire import Wire, decode_times, encode_transforms, read_headers

WIRES = tuple(
    Wire(order, origin=4, align=align, seq=False, signed_sec=True, nul=True, exact=False, encapsulation=kind)
    for kind, order, align in ((0x01, "<", 8), (0x00, ">", 8), (0x07, "<", 4), (0x06, ">", 4))
)

decode_tf: BulkDecoder = SteppedDecoder(WIRES)  # FrameTransforms too: the same bytes
#: Foxglove FrameTransform messages: one transform each, without a count.
decode_frame_transform: BulkDecoder = SteppedDecoder(WIRES, counted=False)
decode_clocks: ClockDecoder = partial(decode_times, wires=WIRES)
decode_headers: HeaderDecoder = partial(read_headers, wires=WIRES)
#: Odometry's headers, each with the child_frame_id after it.
decode_odometry_headers: HeaderDecoder = partial(read_headers, wires=WIRES, children=True)
#: ``tf2_msgs/msg/TFMessage`` serialized as rosbag2 and rmw_cyclonedds write it: plain CDR, little endian.
encode_tf_message: TransformEncoder = partial(encode_transforms, wire=WIRES[0])
