"""Parser of ROS1-serialized TFMessages (as MCAP files recorded from ROS1 hold them), learning their layout."""

from __future__ import annotations

import struct

from tftools.sources.bag.decode.template import DecodeError, Layout, Number, Parsed

_SMALLEST_TRANSFORM = 12 + 4 + 4 + 56  # seq and stamp, two empty strings, values
_U32 = struct.Struct("<I")
_STAMP = struct.Struct("<II")  # ROS1 time: unsigned seconds and nanoseconds
_VALUES = struct.Struct("<7d")


def parse_tf_message(data: bytes) -> Parsed:
    """uint32 count, then per transform: header (uint32 seq, time stamp, string frame_id),
    string child_frame_id, translation and rotation (7 float64); little endian, unaligned."""
    layout = Layout("<")
    parsed = Parsed([], [], [], [], layout)
    pos = _count(data, 0, layout)
    count = _U32.unpack_from(data)[0]
    if count * _SMALLEST_TRANSFORM > len(data):
        raise DecodeError(f"{count} transforms cannot fit in {len(data)} bytes")
    for _ in range(count):
        _need(data, pos, 12)
        sec, nsec = _STAMP.unpack_from(data, pos + 4)  # after the seq, which may differ in look-alikes
        layout.sec.append(Number(pos + 4, 4, "u"))
        layout.nsec.append(Number(pos + 8, 4, "u"))
        parent, pos = _string(data, pos + 12, layout)
        child, pos = _string(data, pos, layout)
        _need(data, pos, 56)
        parsed.parents.append(parent)
        parsed.children.append(child)
        parsed.stamps.append(sec * 1_000_000_000 + nsec)
        parsed.values.append(_VALUES.unpack_from(data, pos))
        layout.values.append([pos + 8 * i for i in range(7)])
        pos += 56
    return parsed


def _need(data: bytes, pos: int, size: int) -> None:
    if pos + size > len(data):
        raise DecodeError(f"message ends at byte {len(data)}, field needs {pos + size}")


def _count(data: bytes, pos: int, layout: Layout) -> int:
    _need(data, pos, 4)
    layout.exact.append((pos, pos + 4))
    return pos + 4


def _string(data: bytes, pos: int, layout: Layout) -> tuple[str, int]:
    _need(data, pos, 4)
    length = _U32.unpack_from(data, pos)[0]
    _need(data, pos + 4, length)
    layout.exact.append((pos, pos + 4 + length))
    return data[pos + 4 : pos + 4 + length].decode("utf-8", "replace"), pos + 4 + length
