"""ROS1 and CDR: fields of fixed kinds one after another, packed (ROS1) or aligned (CDR). Their
transform sequences decoded in step for many messages, field by field for a few, and their times.

A transform is a header (in ROS1 a uint32 seq first; a stamp: seconds and nanoseconds, 4 bytes
each; a string frame_id), a string child_frame_id and 7 float64 (translation, rotation); a string
is a uint32 length then its bytes, in CDR counting a terminating NUL. A TFMessage (and foxglove's
FrameTransforms) is a uint32 count of them, a foxglove FrameTransform a single one.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import numpy.typing as npt

from tftools.core.batch import BoolArray, FloatArray, Int32Array, Int64Array
from tftools.core.time import NS_PER_S
from tftools.sources.codecs.decoded import ByteArray, BytesLike, Clocks, Decoded, DecodeError, FrameTable, gathered

#: A message's header: its stamp (ns) and frame_id.
Header = tuple[int, str]
#: A frame_id longer than this is damage, not a name.
MAX_FRAME_ID = 4096
#: A time's bytes: seconds and nanoseconds.
TIME_SIZE = 8
_VALUES_SIZE = 56
#: When this few messages are left to read, each is read on its own, field by field: in step, one
#: message of a million transforms would take a million numpy rounds.
_FEW_MESSAGES = 8
#: Frame names this few are interned one by one rather than told apart by a hash of their bytes.
_FEW_NAMES = 32
_HASH_PRIME = np.uint64(0x100000001B3)
_PEELED = 16
_COUNTED_LENGTHS = 1 << 16


@dataclass(frozen=True)
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
        return 4 * self.seq + TIME_SIZE + 4 + 4 + _VALUES_SIZE

    @cached_property
    def stamp(self) -> np.dtype[np.void]:
        """A time: seconds and nanoseconds."""
        return np.dtype([("sec", f"{self.order}{'i' if self.signed_sec else 'u'}4"), ("nsec", f"{self.order}u4")])

    @cached_property
    def head(self) -> np.dtype[np.void]:
        """A stamp and the length of the string after it."""
        return np.dtype([*self.stamp.descr, ("length", f"{self.order}u4")])

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

    @property
    def rest(self) -> int:
        """The bytes after the position."""
        return self.end - self.pos

    def align(self, size: int) -> None:
        size = min(size, self.wire.align)
        self.pos += (self.start + self.wire.origin - self.pos) % size

    def take(self, size: int) -> int:
        """Where the next ``size`` bytes start; the position moves past them."""
        at = self.pos
        if at + size > self.end:
            raise DecodeError(f"message ends at byte {self.end - self.start}, a field needs {at + size - self.start}")
        self.pos += size
        return at

    def uint(self) -> int:
        self.align(4)
        return int(self.wire.uint32.unpack_from(self.raw, self.take(4))[0])

    def string(self) -> tuple[int, int]:
        """Where a string's bytes start, and how many (a NUL left out)."""
        length = self.uint()
        return self.take(length), max(length - self.wire.nul, 0)

    def header(self) -> tuple[int, int, int]:
        """A header's stamp (ns), and where its frame_id's bytes start and how many."""
        if self.wire.seq:
            self.take(4)
        self.align(4)
        sec, nsec = self.wire.time.unpack_from(self.raw, self.take(TIME_SIZE))
        return sec * NS_PER_S + nsec, *self.string()


def wire_of(raw: BytesLike, start: int, length: int, wires: Sequence[Wire]) -> Wire:
    """The wire of the payload ``raw[start : start + length]``: the one wire, or the one its CDR
    encapsulation names (``DecodeError`` for another)."""
    if wires[0].encapsulation is None:
        return wires[0]
    head = bytes(raw[start : start + min(length, 2)])
    for wire in wires:
        if length >= wire.origin and head == bytes((0, wire.encapsulation or 0)):
            return wire
    raise DecodeError(f"not a CDR payload (encapsulation {head.hex() or 'missing'})")


def partition(
    raw: ByteArray, starts: Int64Array, lengths: Int64Array, wires: Sequence[Wire]
) -> list[tuple[Wire, Int64Array]]:
    """The payloads in each wire (indices into ``starts``), as ``wire_of`` would find them."""
    if wires[0].encapsulation is None:
        return [(wires[0], np.arange(len(starts), dtype=np.int64))]
    readable = lengths >= wires[0].origin
    head = gathered(raw, np.where(readable, starts, 0), 2) if len(raw) >= 2 else np.ones((len(starts), 2), np.uint8)
    plain = readable & (head[:, 0] == 0)
    found = [(wire, np.flatnonzero(plain & (head[:, 1] == wire.encapsulation))) for wire in wires]
    return [(wire, members) for wire, members in found if len(members)]


def parse_header(raw: BytesLike, wires: Sequence[Wire]) -> Header | None:
    """The ``std_msgs/Header`` a message starts with (only its bytes are read, never the rest:
    image pixels, points); None where ``raw`` cannot start with one."""
    try:
        stamp, start, length = Cursor(raw, wire_of(raw, 0, len(raw), wires)).header()
    except DecodeError:
        return None
    if length > MAX_FRAME_ID:
        return None
    return stamp, bytes(raw[start : start + length]).decode("utf-8", "replace")


# --- times --------------------------------------------------------------------------------------


def decode_times(raw: ByteArray, starts: Int64Array, lengths: Int64Array, wires: Sequence[Wire]) -> Clocks:
    """Messages whose first field is a time (``rosgraph_msgs/Clock``): those well-formed, their
    times (ns), and the (message, reason) of the others."""
    taken: list[Int64Array] = []
    times: list[Int64Array] = []
    for wire, members in partition(raw, starts, lengths, wires):
        members = members[lengths[members] >= wire.origin + TIME_SIZE]
        time = gathered(raw, starts[members] + wire.origin, TIME_SIZE).view(wire.stamp).reshape(-1)
        taken.append(members)
        times.append(time["sec"].astype(np.int64) * NS_PER_S + time["nsec"])
    messages = np.concatenate(taken)
    failures = []
    for message in np.setdiff1d(np.arange(len(starts)), messages).tolist():
        start, length = int(starts[message]), int(lengths[message])
        try:
            needed = wire_of(raw, start, length, wires).origin + TIME_SIZE
            failures.append((message, f"message ends at byte {length}, a Clock needs {needed}"))
        except DecodeError as e:
            failures.append((message, str(e)))
    order = np.argsort(messages, kind="stable")
    return messages[order], np.concatenate(times)[order], failures


# --- transforms ---------------------------------------------------------------------------------


def decode_transforms(
    raw: ByteArray,
    starts: Int64Array,
    lengths: Int64Array,
    frames: FrameTable,
    wires: Sequence[Wire],
    *,
    counted: bool = True,
) -> Decoded:
    """The transform sequences at ``raw[starts[i] : starts[i] + lengths[i]]`` (``counted``: a
    TFMessage, else a single transform each), all at once.

    Messages are walked transform by transform in step: every message's j-th transform is read by
    the same few numpy operations. Those that do not walk to a well-formed end are read again one
    by one, to say why.
    """
    parts: list[Decoded] = []
    failed: list[Int64Array] = []
    walked = np.zeros(len(starts), bool)
    for wire, members in partition(raw, starts, lengths, wires):
        walked[members] = True
        decoded, bad = _in_step(raw, starts[members], lengths[members], frames, wire, counted)
        decoded.message = members[decoded.message]
        parts.append(decoded)
        failed.append(members[bad])
    failed.append(np.flatnonzero(~walked))
    for message in np.sort(np.concatenate(failed)).tolist():
        parts.append(_one(raw, int(starts[message]), int(lengths[message]), frames, wires, counted, message))
    return Decoded.joined(parts)


@dataclass
class _Step:
    """The j-th transforms of the messages that have one (or, read on its own, the j-th onwards of one)."""

    j: Int64Array
    message: Int64Array
    stamp: Int64Array
    frame: tuple[Int64Array, Int64Array]  # where the names' bytes start, how many
    child: tuple[Int64Array, Int64Array]
    values: FloatArray

    def kept(self, keep: BoolArray) -> _Step:
        """The step's rows where ``keep`` is true."""
        frame, child = self.frame, self.child
        return _Step(
            self.j[keep],
            self.message[keep],
            self.stamp[keep],
            (frame[0][keep], frame[1][keep]),
            (child[0][keep], child[1][keep]),
            self.values[keep],
        )


def _in_step(
    raw: ByteArray, starts: Int64Array, lengths: Int64Array, frames: FrameTable, wire: Wire, counted: bool
) -> tuple[Decoded, Int64Array]:
    """The well-formed messages' rows, and the messages that are not."""
    ends = starts + lengths
    if counted:
        readable = lengths >= wire.origin + 4
        counts = np.zeros(len(starts), np.int64)
        at = starts[readable] + wire.origin
        counts[readable] = gathered(raw, at, 4).view(f"{wire.order}u4").reshape(-1)
        bad = ~readable | (counts * wire.smallest > lengths - wire.origin - 4)
        if wire.exact:
            bad |= (counts == 0) & (lengths != wire.origin + 4)
        cursor = starts + wire.origin + 4
    else:
        counts = np.ones(len(starts), np.int64)
        bad = np.zeros(len(starts), bool)
        cursor = starts + wire.origin
    counts[bad] = 0
    steps = _walk(raw, starts, cursor, ends, counts, bad, wire)
    counts[bad] = 0
    keep = [~bad[step.message] for step in steps]
    decoded, lost = _assemble(raw, steps, keep, counts, frames)
    bad[lost] = True
    return decoded, np.flatnonzero(bad)


def _walk(
    raw: ByteArray,
    starts: Int64Array,
    cursor: Int64Array,
    ends: Int64Array,
    counts: Int64Array,
    bad: BoolArray,
    wire: Wire,
) -> list[_Step]:
    # Messages sorted by count, most first: those with a j-th transform are a prefix.
    order = np.argsort(-counts, kind="stable")
    starts, cursor, ends, sorted_counts = starts[order], cursor[order], ends[order], counts[order]
    origin = starts + wire.origin
    size = len(raw)
    steps: list[_Step] = []
    active = int(np.count_nonzero(sorted_counts))
    j = 0
    while active:
        if active <= _FEW_MESSAGES:
            for k in range(active):
                message = int(order[k])
                try:
                    read = Cursor(raw, wire, int(starts[k]), int(ends[k]))
                    read.pos = int(cursor[k])
                    steps.append(_fields(raw, read, j, int(sorted_counts[k]), message))
                    cursor[k] = read.pos
                except DecodeError:
                    bad[message] = True
                    cursor[k] = ends[k]
            break
        at, end = cursor[:active] + 4 * wire.seq, ends[:active]
        ok = at + 12 <= end
        head = gathered(raw, np.where(ok, at, 0), 12).view(wire.head).reshape(-1)
        frame_start = at + 12
        frame_length = head["length"].astype(np.int64)
        child_at = _aligned(frame_start + frame_length, origin[:active], 4, wire)
        ok &= child_at + 4 <= end
        child_start = child_at + 4
        child_length = gathered(raw, np.where(ok, child_at, 0), 4).view(f"{wire.order}u4").reshape(-1).astype(np.int64)
        values_at = _aligned(child_start + child_length, origin[:active], 8, wire)
        ok &= values_at + _VALUES_SIZE <= end
        values_at = np.where(ok, values_at, 0)
        values = gathered(raw, np.minimum(values_at, size - _VALUES_SIZE), _VALUES_SIZE).view(f"{wire.order}f8")
        messages = order[:active]
        bad[messages[~ok]] = True
        names = (np.maximum(frame_length - wire.nul, 0), np.maximum(child_length - wire.nul, 0))
        steps.append(
            _Step(
                np.full(active, j),
                messages,
                head["sec"].astype(np.int64) * NS_PER_S + head["nsec"],
                (frame_start, names[0]),
                (child_start, names[1]),
                values,
            )
        )
        cursor[:active] = values_at + _VALUES_SIZE
        j += 1
        while active and sorted_counts[active - 1] <= j:
            active -= 1
    if wire.exact and len(order):
        bad[order[(sorted_counts > 0) & (cursor != ends)]] = True
    return steps


def _aligned(at: Int64Array, origin: Int64Array, size: int, wire: Wire) -> Int64Array:
    """``at`` moved on to the next multiple of ``size`` (at most the wire's alignment) from ``origin``."""
    size = min(size, wire.align)
    return at if size == 1 else at + (origin - at) % size


def _fields(raw: ByteArray, cursor: Cursor, first: int, count: int, message: int) -> _Step:
    """Transforms ``first`` to ``count`` of one message, from the cursor on: their places found
    field by field, their bytes gathered at once."""
    rows = count - first
    stamps, frame_at, frame_len, child_at, child_len, values_at = ([0] * rows for _ in range(6))
    for row in range(rows):
        stamps[row], frame_at[row], frame_len[row] = cursor.header()
        child_at[row], child_len[row] = cursor.string()
        cursor.align(8)
        values_at[row] = cursor.take(_VALUES_SIZE)
    if cursor.wire.exact and cursor.rest:
        raise DecodeError(f"{cursor.rest} byte{'s' * (cursor.rest > 1)} after the last transform")
    array = np.array
    return _Step(
        np.arange(first, count),
        np.full(rows, message),
        array(stamps, np.int64),
        (array(frame_at, np.int64), array(frame_len, np.int64)),
        (array(child_at, np.int64), array(child_len, np.int64)),
        gathered(raw, array(values_at, np.int64), _VALUES_SIZE).view(f"{cursor.wire.order}f8"),
    )


def _one(
    raw: ByteArray, start: int, length: int, frames: FrameTable, wires: Sequence[Wire], counted: bool, message: int
) -> Decoded:
    """One message read field by field: its rows, or why it is not well-formed."""
    try:
        cursor = Cursor(raw, wire_of(raw, start, length, wires), start, start + length)
        count = cursor.uint() if counted else 1
        if count * cursor.wire.smallest > cursor.rest:
            raise DecodeError(f"{count} transform{'s' * (count != 1)} cannot fit in {length} bytes")
        decoded, lost = _assemble(
            raw, [_fields(raw, cursor, 0, count, 0)], [np.ones(count, bool)], np.array([count]), frames
        )
        if len(lost):
            raise DecodeError("a frame id is not UTF-8")
    except DecodeError as e:
        return Decoded.empty([(message, str(e))])
    decoded.message[:] = message
    return decoded


def _assemble(
    raw: ByteArray, steps: list[_Step], keep: list[BoolArray], counts: Int64Array, frames: FrameTable
) -> tuple[Decoded, Int64Array]:
    """The kept rows of the steps in message order, and the messages lost to a frame id that is not UTF-8."""
    first = np.cumsum(counts) - counts  # each message's first row
    total = int(counts.sum())
    if not total:
        return Decoded.empty(), np.zeros(0, np.int64)
    steps = [s if k.all() else s.kept(k) for s, k in zip(steps, keep, strict=True)]
    place = np.concatenate([first[s.message] + s.j for s in steps])
    message = np.empty(total, np.int64)
    stamp = np.empty(total, np.int64)
    values = np.empty((total, 7), np.float64)
    message[place] = np.concatenate([s.message for s in steps])
    stamp[place] = np.concatenate([s.stamp for s in steps])
    values[place] = np.concatenate([s.values for s in steps])
    names = [(s.frame, s.child) for s in steps]
    starts = np.concatenate([part[0] for pair in names for part in pair])
    ids, undecodable = intern(raw, starts, np.concatenate([part[1] for pair in names for part in pair]), frames)
    # The names came step by step, each step's frame ids then its child ids: (from, middle, to).
    sizes = [len(s.message) for s in steps]
    bounds = np.cumsum([0] + [2 * s for s in sizes]).tolist()
    spans = [(bounds[i], bounds[i] + sizes[i], bounds[i + 1]) for i in range(len(sizes))]
    parent = np.empty(total, np.int32)
    child = np.empty(total, np.int32)
    parent[place] = np.concatenate([ids[a:b] for a, b, _ in spans])
    child[place] = np.concatenate([ids[b:c] for _, b, c in spans])
    decoded = Decoded(message, parent, child, stamp, values)
    if not undecodable.any():
        return decoded, np.zeros(0, np.int64)
    bad_row = np.zeros(total, bool)
    bad_row[place] = np.concatenate([undecodable[a:b] | undecodable[b:c] for a, b, c in spans])
    lost = np.unique(message[bad_row])
    kept = ~np.isin(message, lost)
    return Decoded(message[kept], parent[kept], child[kept], stamp[kept], values[kept]), lost


def intern(raw: ByteArray, starts: Int64Array, lengths: Int64Array, frames: FrameTable) -> tuple[Int32Array, BoolArray]:
    """The frame ids of the strings ``raw[starts:starts+lengths]``, and which are not UTF-8.

    Strings of one length are told apart by a 64-bit hash of their bytes, checked byte for byte
    afterwards (a collision falls back to sorting the bytes themselves).
    """
    ids = np.zeros(len(starts), np.int32)
    undecodable = np.zeros(len(starts), bool)
    if len(starts) <= _FEW_NAMES:
        for i, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
            try:
                ids[i] = frames.id(raw[start : start + length].tobytes().decode("utf-8"))
            except UnicodeDecodeError:
                undecodable[i] = True
        return ids, undecodable
    for length in _distinct_values(lengths):
        rows = np.flatnonzero(lengths == length)
        if length == 0:
            ids[rows] = frames.id("")
            continue
        matrix = gathered(raw, starts[rows], length)
        firsts, inverse = _distinct(matrix)
        table = np.zeros(len(firsts), np.int32)
        broken = np.zeros(len(firsts), bool)
        for i, row in enumerate(firsts.tolist()):
            try:
                table[i] = frames.id(matrix[row].tobytes().decode("utf-8"))
            except UnicodeDecodeError:
                broken[i] = True
        ids[rows] = table[inverse]
        undecodable[rows] = broken[inverse]
    return ids, undecodable


def _distinct_values(lengths: Int64Array) -> list[int]:
    """The distinct lengths, counted where they are short (names are) rather than sorted."""
    found = np.flatnonzero(np.bincount(lengths)) if int(lengths.max()) < _COUNTED_LENGTHS else np.unique(lengths)
    values: list[int] = found.tolist()
    return values


def _distinct(matrix: ByteArray) -> tuple[Int64Array, Int64Array]:
    """A first row of each distinct row of ``matrix``, and each row's index among them."""
    n, width = matrix.shape
    padded = np.zeros((n, -(-width // 8) * 8), np.uint8)
    padded[:, :width] = matrix
    words = padded.view("<u8")
    key = np.full(n, width, np.uint64)
    for column in words.T:
        key = key * _HASH_PRIME ^ column
    firsts, inverse = _peel(key)
    if np.array_equal(matrix[firsts][inverse], matrix):
        return firsts, inverse
    rows = np.ascontiguousarray(matrix).view(f"V{width}").reshape(-1)
    _, firsts, inverse = np.unique(rows, return_index=True, return_inverse=True)
    return firsts, inverse.reshape(-1)


def _peel(key: npt.NDArray[np.uint64]) -> tuple[Int64Array, Int64Array]:
    """A first row of each distinct value of ``key``, and each row's index among them.

    Frame names are few and repeat, so the rows of each value are picked out in turn (a pass
    each, no sort); past ``_PEELED`` values, the rest are sorted out by ``np.unique``."""
    n = len(key)
    inverse = np.empty(n, np.int64)
    firsts: list[int] = []
    rows = np.arange(n)
    rest = key
    while len(rows) and len(firsts) < _PEELED:
        same = rest == rest[0]
        inverse[rows[same]] = len(firsts)
        firsts.append(int(rows[0]))
        rows, rest = rows[~same], rest[~same]
    if len(rows):
        _, more, index = np.unique(rest, return_index=True, return_inverse=True)
        inverse[rows] = len(firsts) + index.reshape(-1)
        return np.concatenate([np.array(firsts, np.int64), rows[more]]), inverse
    return np.array(firsts, np.int64), inverse
