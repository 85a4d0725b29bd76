"""ROS1 and CDR: fields of fixed kinds one after another, packed (ROS1) or aligned (CDR). How each
lays them out (``Wire``), a payload read field by field (``Cursor``), and the messages that start
with a header or a time, read so.

A header is, in ROS1, a uint32 seq, then in both a stamp (seconds and nanoseconds, 4 bytes each)
and a string frame_id; a string is a uint32 length then its bytes, in CDR counting a terminating
NUL. A transform is a header, a string child_frame_id and 7 float64 (translation, rotation).
"""

from __future__ import annotations

import enum
import math
import struct
from collections.abc import Callable, Sequence
from functools import cached_property

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.codecs.decoded import BytesLike, Clocks, DecodeError, FrameNames, Header, Headers
from tftools.sources.codecs.gather import bytes_at
from tftools.values import value

#: A frame_id longer than this is damage, not a name.
MAX_FRAME_ID = 4096
#: The bytes of a message that hold its header, at most: a seq, a stamp and a frame_id's length after
#: CDR's encapsulation and alignment, then the frame_id.
HEADER_BYTES = 24 + MAX_FRAME_ID
#: A time's bytes: seconds and nanoseconds.
TIME_SIZE = 8
#: A transform's translation and rotation: 7 float64.
VALUES_SIZE = 56


class Reason(enum.IntEnum):
    """Why a payload is not a well-formed message, numbered as native/tf_wire.hpp's ``Reason``; each
    with an offset into the message and a figure."""

    ENCAPSULATION = 0  # in none of the wires; figure: its first (at most 2) bytes, big endian
    TRUNCATED = 1  # a field runs past the end; offset: where the field starts, figure: its size
    COUNT = 2  # more transforms than the bytes can hold; figure: the count
    TRAILING = 3  # bytes after the last transform (ROS1); offset: where they start, figure: how many
    NOT_UTF8 = 4  # a frame id's bytes (told in Python, which decodes the names)
    LONG_FRAME_ID = 5  # a header's frame_id over MAX_FRAME_ID; figure: its size (``read_headers``)
    SHORT_CLOCK = 6  # too short for a time; figure: the bytes a time needs (``decode_times``)


def _head(length: int, head: int) -> str:
    return head.to_bytes(min(length, 2), "big").hex() or "missing"


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}{'s' * (count != 1)}"


#: Each reason in words, from the message's length, the offset and the figure.
REASONS: dict[Reason, Callable[[int, int, int], str]] = {
    Reason.ENCAPSULATION: lambda length, _, head: f"not a CDR payload (encapsulation {_head(length, head)})",
    Reason.TRUNCATED: lambda length, at, size: f"message ends at byte {length}, a field needs {at + size}",
    Reason.COUNT: lambda length, _, count: f"{_plural(count, 'transform')} cannot fit in {length} bytes",
    Reason.TRAILING: lambda _length, _, rest: f"{_plural(rest, 'byte')} after the last transform",
    Reason.NOT_UTF8: lambda *_: "a frame id is not UTF-8",
    Reason.LONG_FRAME_ID: lambda _length, _, size: f"a frame_id of {size} bytes",
    Reason.SHORT_CLOCK: lambda length, _, needed: f"message ends at byte {length}, a Clock needs {needed}",
}


def worded(reason: Reason, length: int, offset: int = 0, figure: int = 0) -> str:
    """Why a message of ``length`` bytes is not well-formed (``REASONS``)."""
    return REASONS[reason](length, offset, figure)


@value
class Wire:
    """How an encoding lays out its fields."""

    order: str  # "<" or ">"
    origin: int  # bytes before the fields (CDR's encapsulation), from which alignment counts
    align: int  # the largest alignment: 1 when packed (ROS1), 8 (CDR), 4 (XCDR2)
    seq: bool  # a header has a uint32 seq before its stamp (ROS1)
    signed_sec: bool  # int32 seconds (ROS 2) rather than uint32 (ROS1)
    nul: bool  # a string's length counts its terminating NUL (CDR)
    exact: bool  # nothing may follow the last field (ROS1); DDS may pad CDR samples
    encapsulation: int | None = None  # CDR: the payloads in this wire, by their second byte

    @property
    def smallest(self) -> int:
        """The fewest bytes a transform takes."""
        return 4 * self.seq + TIME_SIZE + 4 + 4 + VALUES_SIZE

    @cached_property
    def stamp(self) -> np.dtype[np.void]:
        """A time: seconds and nanoseconds."""
        return np.dtype([("sec", f"{self.order}{'i' if self.signed_sec else 'u'}4"), ("nsec", f"{self.order}u4")])

    @cached_property
    def compiled(self) -> tuple[int, bool, int, int, bool, bool, bool, bool]:
        """Its fields as the compiled reader takes them (``_wire.WireFields``; -1: no encapsulation)."""
        encapsulation = -1 if self.encapsulation is None else self.encapsulation
        big_endian = self.order == ">"
        return encapsulation, big_endian, self.origin, self.align, self.seq, self.signed_sec, self.nul, self.exact

    @cached_property
    def uint32(self) -> struct.Struct:
        return struct.Struct(f"{self.order}I")

    @cached_property
    def time(self) -> struct.Struct:
        return struct.Struct(f"{self.order}{'i' if self.signed_sec else 'I'}I")


class Cursor:
    """A position in one payload, ``raw[start:end]``, read field by field in a wire's layout;
    ``DecodeError`` where a field runs past the end."""

    def __init__(self, raw: BytesLike, wire: Wire, start: int = 0, end: int | None = None) -> None:
        self.raw = raw.data if isinstance(raw, np.ndarray) else raw
        self.wire = wire
        self.start = start
        self.end = len(raw) if end is None else end
        self.pos = start + wire.origin
        self._origin = self.pos
        self._align = wire.align
        self._uint32 = wire.uint32.unpack_from

    @property
    def rest(self) -> int:
        """The bytes after the position."""
        return self.end - self.pos

    def take(self, size: int, align: int = 1) -> int:
        """Where the next ``size`` bytes start, aligned to ``align`` (at most the wire's alignment);
        the position moves past them."""
        at = self.pos
        if align > 1 and self._align > 1:
            at += (self._origin - at) % min(align, self._align)
        if at + size > self.end:
            raise DecodeError(worded(Reason.TRUNCATED, self.end - self.start, at - self.start, size))
        self.pos = at + size
        return at

    def uint(self) -> int:
        return int(self._uint32(self.raw, self.take(4, 4))[0])

    def string(self) -> tuple[int, int]:
        """Where a string's bytes start, and how many (a NUL left out)."""
        length = self.uint()
        return self.take(length), max(length - self.wire.nul, 0)

    def header(self) -> tuple[int, int, int]:
        """A header's stamp (ns), and where its frame_id's bytes start and how many."""
        if self.wire.seq:
            self.take(4)
        sec, nsec = self.wire.time.unpack_from(self.raw, self.take(TIME_SIZE, 4))
        return sec * NS_PER_S + nsec, *self.string()


def encode_transforms(transforms: Sequence[Transform], wire: Wire) -> bytes:
    """``transforms`` as one ``tf2_msgs/TFMessage`` in ``wire`` (a ROS1 seq is 0; CDR starts with the
    wire's encapsulation header)."""
    body = bytearray()

    def aligned(field: bytes, align: int) -> None:
        body.extend(b"\0" * (-len(body) % min(align, wire.align)) + field)

    aligned(wire.uint32.pack(len(transforms)), 4)
    for t in transforms:
        if wire.seq:
            aligned(wire.uint32.pack(0), 4)
        aligned(wire.time.pack(*divmod(t.stamp, NS_PER_S)), 4)
        for name in (t.frame_id, t.child_frame_id):
            encoded = name.encode() + b"\0" * wire.nul
            aligned(wire.uint32.pack(len(encoded)) + encoded, 4)
        aligned(struct.pack(f"{wire.order}7d", *t.translation, *t.rotation), 8)
    encapsulation = b"" if wire.encapsulation is None else bytes((0, wire.encapsulation, 0, 0))
    return encapsulation + bytes(body)


def wire_of(raw: BytesLike, start: int, length: int, wires: Sequence[Wire]) -> Wire:
    """The wire of the payload ``raw[start : start + length]``: the one wire, or the one its CDR
    encapsulation names (``DecodeError`` for another)."""
    if wires[0].encapsulation is None:
        return wires[0]
    head = bytes(raw[start : start + min(length, 2)])
    for wire in wires:
        if length >= wire.origin and head == bytes((0, wire.encapsulation or 0)):
            return wire
    raise DecodeError(worded(Reason.ENCAPSULATION, length, 0, int.from_bytes(head, "big")))


def partition(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, wires: Sequence[Wire]
) -> list[tuple[Wire, Int64Array]]:
    """The payloads in each wire (indices into ``starts``), as ``wire_of`` would find them."""
    if wires[0].encapsulation is None:
        return [(wires[0], np.arange(len(starts), dtype=np.int64))]
    readable = lengths >= wires[0].origin
    head = bytes_at(raw, np.where(readable, starts, 0), 2) if len(raw) >= 2 else np.ones((len(starts), 2), np.uint8)
    plain = readable & (head[:, 0] == 0)
    found = [(wire, np.flatnonzero(plain & (head[:, 1] == wire.encapsulation))) for wire in wires]
    return [(wire, members) for wire, members in found if len(members)]


def read_headers(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, wires: Sequence[Wire]
) -> Headers:
    """The ``std_msgs/Header`` many messages start with, their frame_ids interned in ``frames``: only
    their bytes are read, never the rest (image pixels, points), so only the first ``HEADER_BYTES``
    of each message need be given."""
    return _read(raw, starts, lengths, frames, wires, stated=False)


def read_odometry(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, wires: Sequence[Wire]
) -> Headers:
    """``read_headers`` of ``nav_msgs/Odometry``, with what each message states beside its header: the transform
    from its header's frame to its child_frame_id, the string after the header, then its pose's position and
    orientation (7 float64, the first of its pose with covariance). Of a message given cut short (its first
    ``HEADER_BYTES``, a long frame_id), or whose child_frame_id is too long, the header alone (child -1, a NaN
    pose)."""
    return _read(raw, starts, lengths, frames, wires, stated=True)


def _read(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, wires: Sequence[Wire], *, stated: bool
) -> Headers:
    """The headers of ``read_headers``, and with ``stated`` what each message states beside it (``read_odometry``)."""
    view = raw.data
    read: list[int] = []
    stamps: list[int] = []
    ids: list[int] = []
    children: list[int] = []
    poses: list[tuple[float, ...]] = []
    failures: list[tuple[int, str]] = []
    for message, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            cursor = Cursor(view, wire_of(view, start, length, wires), start, start + length)
            stamp, frame_id = _header_at(cursor)
        except DecodeError as e:
            failures.append((message, str(e)))
            continue
        if stated:
            child, pose = _stated(cursor, frames)
            children.append(child)
            poses.append(pose)
        read.append(message)
        stamps.append(stamp)
        ids.append(frames.intern(frame_id))
    if not stated:
        return Headers(np.array(read, np.int64), np.array(stamps, np.int64), np.array(ids, np.int32), failures)
    return Headers(
        np.array(read, np.int64),
        np.array(stamps, np.int64),
        np.array(ids, np.int32),
        failures,
        np.array(children, np.int32),
        np.array(poses, np.float64).reshape(-1, 7),
    )


_UNKNOWN_POSE = (math.nan,) * 7


def _stated(cursor: Cursor, frames: FrameNames) -> tuple[int, tuple[float, ...]]:
    """The child frame (interned in ``frames``) and pose after the header ``cursor`` has read past; -1 and a NaN
    pose where the bytes end first or the child_frame_id is too long."""
    try:
        at, size = cursor.string()
        if size > MAX_FRAME_ID:
            return -1, _UNKNOWN_POSE
        named = bytes(cursor.raw[at : at + size]).decode("utf-8", "replace")
        pose = struct.unpack_from(f"{cursor.wire.order}7d", cursor.raw, cursor.take(VALUES_SIZE, 8))
    except DecodeError:
        return -1, _UNKNOWN_POSE
    return frames.intern(named), pose


def _header_at(cursor: Cursor) -> Header:
    """The header ``cursor`` stands at, read; the cursor moves past it."""
    stamp, at, size = cursor.header()
    if size > MAX_FRAME_ID:
        raise DecodeError(worded(Reason.LONG_FRAME_ID, cursor.end - cursor.start, at - cursor.start, size))
    return stamp, bytes(cursor.raw[at : at + size]).decode("utf-8", "replace")


# --- times --------------------------------------------------------------------------------------


def decode_times(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, wires: Sequence[Wire]) -> Clocks:
    """Messages whose first field is a time (``rosgraph_msgs/Clock``): those well-formed, their
    times (ns), and the (message, reason) of the others."""
    taken: list[Int64Array] = [np.zeros(0, np.int64)]
    times: list[Int64Array] = [np.zeros(0, np.int64)]
    for wire, members in partition(raw, starts, lengths, wires):
        members = members[lengths[members] >= wire.origin + TIME_SIZE]
        time = bytes_at(raw, starts[members] + wire.origin, TIME_SIZE).view(wire.stamp).reshape(-1)
        taken.append(members)
        times.append(time["sec"].astype(np.int64) * NS_PER_S + time["nsec"])
    messages = np.concatenate(taken)
    failed = np.ones(len(starts), bool)
    failed[messages] = False
    failures = []
    for message in np.flatnonzero(failed).tolist():
        start, length = int(starts[message]), int(lengths[message])
        try:
            needed = wire_of(raw, start, length, wires).origin + TIME_SIZE
            failures.append((message, worded(Reason.SHORT_CLOCK, length, 0, needed)))
        except DecodeError as e:
            failures.append((message, str(e)))
    order = np.argsort(messages, kind="stable")
    return messages[order], np.concatenate(times)[order], failures
