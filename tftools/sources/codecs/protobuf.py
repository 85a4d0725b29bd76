"""``foxglove.FrameTransform(s)`` on the protobuf wire: parsed one by one, learning their layout,
and decoded in bulk by the templates those layouts make."""

# FrameTransform { google.protobuf.Timestamp timestamp = 1 (int64 seconds = 1, int32 nanos = 2);
# string parent_frame_id = 2; string child_frame_id = 3; Vector3 translation = 4 (double x y z = 1..3);
# Quaternion rotation = 5 (double x y z w = 1..4) }; FrameTransforms { repeated FrameTransform
# transforms = 1 }. proto3 leaves zero values off the wire: a missing ``w`` is 0.0.

from __future__ import annotations

import struct
from collections.abc import Iterator

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames
from tftools.sources.codecs.parsed import Parsed
from tftools.sources.codecs.template import ABSENT, Layout, Varint, decode_templated

_VARINT, _FIXED64, _LEN, _FIXED32 = 0, 1, 2, 5
_DOUBLE = struct.Struct("<d")
_TRANSLATION, _ROTATION = 4, 5
#: (vector field, its field number) -> slot in x y z qx qy qz qw.
_VALUE_SLOT = {(_TRANSLATION, n): n - 1 for n in (1, 2, 3)} | {(_ROTATION, n): n + 2 for n in (1, 2, 3, 4)}


class _Wire:
    """Walks protobuf fields, noting tag and length bytes as structure in ``layout``."""

    def __init__(self, data: bytes) -> None:
        self.data = data
        self.layout = Layout()

    def varint(self, pos: int, end: int) -> tuple[int, int]:
        value = shift = 0
        while pos < end and shift < 70:
            byte = self.data[pos]
            value |= (byte & 0x7F) << shift
            pos += 1
            shift += 7
            if byte < 0x80:
                return value & 0xFFFFFFFFFFFFFFFF, pos
        raise DecodeError("truncated or overlong varint")

    def fields(self, pos: int, end: int) -> Iterator[tuple[int, int, int, int]]:
        """(field number, wire type, start, end) of each field's value in ``[pos, end)``."""
        while pos < end:
            tag_at = pos
            tag, pos = self.varint(pos, end)
            wire = tag & 7
            if wire == _VARINT:
                _, value_end = self.varint(pos, end)
            elif wire in (_FIXED64, _FIXED32):
                value_end = pos + (8 if wire == _FIXED64 else 4)
            elif wire == _LEN:
                length, pos = self.varint(pos, end)
                value_end = pos + length
            else:
                raise DecodeError(f"unsupported protobuf wire type {wire}")
            if value_end > end:
                raise DecodeError("protobuf field runs past its message")
            self.layout.exact.append((tag_at, pos))
            yield tag >> 3, wire, pos, value_end
            pos = value_end


class _Transform:
    """One FrameTransform being read: proto3 defaults until a field says otherwise."""

    def __init__(self) -> None:
        self.parent = self.child = ""
        self.sec = self.nsec = 0
        self.sec_at = self.nsec_at = ABSENT
        self.values = [0.0] * 7
        self.offsets = [-1] * 7


def decode_frame_transform(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    return decode_templated(raw, starts, lengths, frames, _learn_frame_transform)


def decode_frame_transforms(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    return decode_templated(raw, starts, lengths, frames, _learn_frame_transforms)


def _learn_frame_transform(data: bytes) -> tuple[Parsed, Layout]:
    wire = _Wire(data)
    parsed = Parsed()
    _add(parsed, wire.layout, _transform(wire, 0, len(data)))
    return parsed, wire.layout


def _learn_frame_transforms(data: bytes) -> tuple[Parsed, Layout]:
    wire = _Wire(data)
    parsed = Parsed()
    for number, kind, start, end in wire.fields(0, len(data)):
        if number == 1 and kind == _LEN:
            _add(parsed, wire.layout, _transform(wire, start, end))
        else:
            wire.layout.exact.append((start, end))
    return parsed, wire.layout


def _add(parsed: Parsed, layout: Layout, t: _Transform) -> None:
    parsed.parents.append(t.parent)
    parsed.children.append(t.child)
    parsed.stamps.append(t.sec * 1_000_000_000 + t.nsec)
    parsed.values.append(tuple(t.values))
    layout.sec.append(t.sec_at)
    layout.nsec.append(t.nsec_at)
    layout.values.append(t.offsets)


def _transform(wire: _Wire, pos: int, end: int) -> _Transform:
    t = _Transform()
    for number, kind, start, stop in wire.fields(pos, end):
        if number == 1 and kind == _LEN:
            _timestamp(wire, t, start, stop)
        elif number in (2, 3) and kind == _LEN:
            wire.layout.exact.append((start, stop))
            name = _text(wire.data[start:stop])
            t.parent, t.child = (name, t.child) if number == 2 else (t.parent, name)
        elif number in (_TRANSLATION, _ROTATION) and kind == _LEN:
            _vector(wire, t, number, start, stop)
        else:
            wire.layout.exact.append((start, stop))
    return t


def _timestamp(wire: _Wire, t: _Transform, pos: int, end: int) -> None:
    for number, kind, start, stop in wire.fields(pos, end):
        if number in (1, 2) and kind == _VARINT:
            wire.layout.varints.append((start, stop))
            value, _ = wire.varint(start, stop)
            if number == 1:
                t.sec, t.sec_at = _signed(value, 64), Varint(start, stop - start, 64)
            else:
                t.nsec, t.nsec_at = _signed(value, 32), Varint(start, stop - start, 32)
        else:
            wire.layout.exact.append((start, stop))


def _vector(wire: _Wire, t: _Transform, field: int, pos: int, end: int) -> None:
    for number, kind, start, stop in wire.fields(pos, end):
        slot = _VALUE_SLOT.get((field, number))
        if slot is not None and kind == _FIXED64:
            t.values[slot] = _DOUBLE.unpack_from(wire.data, start)[0]
            t.offsets[slot] = start
        else:
            wire.layout.exact.append((start, stop))


def _signed(value: int, bits: int) -> int:
    value &= (1 << bits) - 1
    return value - (1 << bits) if value >> (bits - 1) else value


def _text(data: bytes) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise DecodeError("a frame id is not UTF-8") from None
