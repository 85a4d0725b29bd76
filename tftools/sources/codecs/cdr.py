"""ROS 2's CDR, as bags hold it and DDS samples carry it: ``tf2_msgs/msg/TFMessage`` and foxglove's
``FrameTransforms`` (the same bytes) and ``FrameTransform`` decoded, ``rosgraph_msgs/msg/Clock`` too,
``std_msgs/msg/Header`` parsed.

A payload starts with the 4-byte encapsulation header (RTPS 10.5: 0x0000/0x0001 plain CDR big/little
endian, which rmw_cyclonedds and rosbag2 write; 0x0006/0x0007 XCDR2 for final types); alignment
counts from just after it, 8-byte values aligned to 8 in CDR and to 4 in XCDR2.
"""

from __future__ import annotations

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs.decoded import BytesLike, Clocks, Decoded, FrameNames
from tftools.sources.codecs.stepped import decode_transforms
from tftools.sources.codecs.wire import Header, Wire, decode_times, parse_header

WIRES = tuple(
    Wire(order, origin=4, align=align, seq=False, signed_sec=True, nul=True, exact=False, encapsulation=kind)
    for kind, order, align in ((0x01, "<", 8), (0x00, ">", 8), (0x07, "<", 4), (0x06, ">", 4))
)


def decode_tf(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    """TFMessages (or FrameTransforms), as ``wire.decode_transforms`` decodes them."""
    return decode_transforms(raw, starts, lengths, frames, WIRES)


def decode_frame_transform(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    """Single foxglove FrameTransforms: a transform each, without a count."""
    return decode_transforms(raw, starts, lengths, frames, WIRES, counted=False)


def decode_clocks(raw: UInt8Array, starts: Int64Array, lengths: Int64Array) -> Clocks:
    """Clocks, as ``wire.decode_times`` decodes them."""
    return decode_times(raw, starts, lengths, WIRES)


def header(raw: BytesLike) -> Header | None:
    """The header a CDR message starts with (after its encapsulation); None where it cannot be one."""
    return parse_header(raw, WIRES)
