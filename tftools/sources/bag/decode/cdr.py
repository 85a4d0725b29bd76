"""Struct-based CDR parser of TFMessage and foxglove FrameTransform(s), learning their layout."""

from __future__ import annotations

import struct

from tftools.sources.bag.decode.template import DecodeError, Layout, Number, Parsed

_HEADER = 4  # encapsulation: 0x00, kind, 2 option bytes; CDR alignment counts from after it
_SMALLEST_TRANSFORM = 4 + 4 + 4 + 1 + 4 + 1 + 56  # stamp, two one-byte strings, values

_ORDERS = {0x00: ">", 0x01: "<"}  # plain CDR (XCDR1) big and little endian
_STAMP = {order: struct.Struct(f"{order}iI") for order in "<>"}
_UINT = {order: struct.Struct(f"{order}I") for order in "<>"}
_VALUES = {order: struct.Struct(f"{order}7d") for order in "<>"}


class _Cursor:
    """Reads ``data`` from just after the encapsulation header, noting the structural bytes."""

    def __init__(self, data: bytes, order: str) -> None:
        self.data = data
        self.order = order
        self.pos = _HEADER
        self.layout = Layout(order, exact=[(0, _HEADER)])

    def align(self, size: int) -> None:
        self.pos += -(self.pos - _HEADER) % size

    def need(self, size: int) -> int:
        start = self.pos
        if start + size > len(self.data):
            raise DecodeError(f"message ends at byte {len(self.data)}, field needs {start + size}")
        self.pos += size
        return start

    def count(self) -> int:
        self.align(4)
        start = self.need(4)
        self.layout.exact.append((start, self.pos))
        return int(_UINT[self.order].unpack_from(self.data, start)[0])

    def string(self) -> str:
        length = self.count()
        start = self.need(length)
        self.layout.exact[-1] = (self.layout.exact[-1][0], self.pos)
        return self.data[start : start + max(length - 1, 0)].decode("utf-8", "replace")


def parse_tf_message(data: bytes) -> Parsed:
    """A ``tf2_msgs/msg/TFMessage`` (or ``foxglove_msgs/msg/FrameTransforms``, same bytes)."""
    cursor = _Cursor(data, _order(data))
    count = cursor.count()
    if count * _SMALLEST_TRANSFORM > len(data):
        raise DecodeError(f"{count} transforms cannot fit in {len(data)} bytes")
    parsed = Parsed([], [], [], [], cursor.layout)
    for _ in range(count):
        _transform(cursor, parsed)
    return parsed


def parse_frame_transform(data: bytes) -> Parsed:
    """A single ``foxglove_msgs/msg/FrameTransform``."""
    cursor = _Cursor(data, _order(data))
    parsed = Parsed([], [], [], [], cursor.layout)
    _transform(cursor, parsed)
    return parsed


def _order(data: bytes) -> str:
    if len(data) < _HEADER or data[0] != 0 or data[1] not in _ORDERS:
        raise DecodeError(f"not a plain CDR payload (encapsulation {data[:2].hex() or 'missing'})")
    return _ORDERS[data[1]]


def _transform(cursor: _Cursor, parsed: Parsed) -> None:
    """stamp (int32 sec, uint32 nanosec), frame ids, translation and rotation (7 float64)."""
    cursor.align(4)
    at = cursor.need(8)
    sec, nsec = _STAMP[cursor.order].unpack_from(cursor.data, at)
    parsed.parents.append(cursor.string())
    parsed.children.append(cursor.string())
    cursor.align(8)
    values_at = cursor.need(56)
    parsed.stamps.append(sec * 1_000_000_000 + nsec)
    parsed.values.append(_VALUES[cursor.order].unpack_from(cursor.data, values_at))
    layout = cursor.layout
    layout.sec.append(Number(at, 4, "i"))
    layout.nsec.append(Number(at + 4, 4, "u"))
    layout.values.append([values_at + 8 * i for i in range(7)])
