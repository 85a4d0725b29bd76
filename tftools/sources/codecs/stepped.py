"""Transform sequences of ROS1 and CDR decoded in step: every message's j-th transform read by the
same few numpy operations. A few messages are read field by field, each on its own, and so is a
message that does not read to a well-formed end, to say why.

A ``tf2_msgs/TFMessage`` (and foxglove's FrameTransforms, the same bytes) is a uint32 count of
transforms, a foxglove FrameTransform a single one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.core.time import NS_PER_S
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames
from tftools.sources.codecs.gather import bytes_at
from tftools.sources.codecs.wire import VALUES_SIZE, Cursor, Wire, partition, wire_of

#: This few messages are read each on its own, field by field; so are those left when no more
#: remain with ``_MANY_STEPS`` transforms still to read: in step, one message of a million
#: transforms would take a million numpy rounds.
_FEW_MESSAGES = 8
_MANY_STEPS = 64


def decode_transforms(
    raw: UInt8Array,
    starts: Int64Array,
    lengths: Int64Array,
    frames: FrameNames,
    wires: Sequence[Wire],
    *,
    counted: bool = True,
) -> Decoded:
    """The transform sequences at ``raw[starts[i] : starts[i] + lengths[i]]`` in one of ``wires``
    (``counted``: a count of transforms first, else a single transform each)."""
    parts: list[Decoded] = []
    alone: Sequence[int] = range(len(starts))
    if len(starts) > _FEW_MESSAGES:
        walked = np.zeros(len(starts), bool)
        left: list[Int64Array] = []
        for wire, members in partition(raw, starts, lengths, wires):
            walked[members] = True
            decoded, bad = _in_step(raw, starts[members], lengths[members], frames, wire, counted)
            parts.append(decoded.renumbered(members))
            left.append(members[bad])
        alone = np.sort(np.concatenate([*left, np.flatnonzero(~walked)])).tolist()
    for message in alone:
        parts.append(_alone(raw, int(starts[message]), int(lengths[message]), frames, wires, counted, message))
    return Decoded.joined(parts)


@dataclass
class _Step:
    """The j-th transforms of the messages that have one."""

    j: int
    message: Int64Array
    stamp: Int64Array
    frame_start: Int64Array  # where the name's bytes start in ``raw``
    frame_length: Int64Array
    child_start: Int64Array
    child_length: Int64Array
    values_at: Int64Array  # where the 7 float64 start


def _in_step(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, wire: Wire, counted: bool
) -> tuple[Decoded, Int64Array]:
    """The rows of the messages read to a well-formed end, and which messages are left to be read alone."""
    if counted:
        readable = lengths >= wire.origin + 4
        counts = np.zeros(len(starts), np.int64)
        counts[readable] = bytes_at(raw, starts[readable] + wire.origin, 4).view(f"{wire.order}u4").reshape(-1)
        bad = ~readable | (counts * wire.smallest > lengths - wire.origin - 4)
        if wire.exact:
            bad |= (counts == 0) & (lengths != wire.origin + 4)
    else:
        counts = np.ones(len(starts), np.int64)
        bad = np.zeros(len(starts), bool)
    counts[bad] = 0
    steps = _walk(raw, starts, starts + wire.origin + 4 * counted, starts + lengths, counts, bad, wire)
    counts[bad] = 0  # of those found bad on the way too: their rows take no place
    decoded, lost = _assemble(raw, steps, [~bad[step.message] for step in steps], counts, frames, wire)
    bad[lost] = True
    return decoded, np.flatnonzero(bad)


def _walk(
    raw: UInt8Array,
    starts: Int64Array,
    cursor: Int64Array,
    ends: Int64Array,
    counts: Int64Array,
    bad: BoolArray,
    wire: Wire,
) -> list[_Step]:
    """The messages' transforms, marking in ``bad`` those that do not read to a well-formed end (and
    the few read last, to be read alone)."""
    # Messages sorted by count, most first: those with a j-th transform are a prefix.
    order = np.argsort(-counts, kind="stable")
    starts, cursor, ends, sorted_counts = starts[order], cursor[order], ends[order], counts[order]
    origin = starts + wire.origin
    steps: list[_Step] = []
    active = int(np.count_nonzero(sorted_counts))
    j = 0
    while active and (active > _FEW_MESSAGES or sorted_counts[0] - j <= _MANY_STEPS):
        at, end = cursor[:active] + 4 * wire.seq, ends[:active]
        ok = at + 12 <= end
        head = bytes_at(raw, _within(at, ok), 12).view(wire.head).reshape(-1)
        frame_length = head["length"].astype(np.int64)
        child_at = _aligned(at + 12 + frame_length, origin[:active], 4, wire)
        ok &= child_at + 4 <= end
        child_length = bytes_at(raw, _within(child_at, ok), 4).view(f"{wire.order}u4").reshape(-1).astype(np.int64)
        values_at = _aligned(child_at + 4 + child_length, origin[:active], 8, wire)
        ok &= values_at + VALUES_SIZE <= end
        if not ok.all():
            bad[order[:active][~ok]] = True
        step = _Step(
            j,
            order[:active],
            head["sec"].astype(np.int64) * NS_PER_S + head["nsec"],
            at + 12,
            np.maximum(frame_length - 1, 0) if wire.nul else frame_length,
            child_at + 4,
            np.maximum(child_length - 1, 0) if wire.nul else child_length,
            values_at,
        )
        steps.append(step)
        cursor[:active] = values_at + VALUES_SIZE
        j += 1
        while active and sorted_counts[active - 1] <= j:
            active -= 1
    bad[order[:active]] = True  # those left
    if wire.exact:  # of the messages read to their last transform, those that go on
        bad[order[active:][(sorted_counts[active:] > 0) & (cursor[active:] != ends[active:])]] = True
    return steps


def _within(at: Int64Array, ok: BoolArray) -> Int64Array:
    """``at``, where ``ok`` (0 elsewhere: a place to read that is in ``raw``)."""
    return at if ok.all() else np.where(ok, at, 0)


def _aligned(at: Int64Array, origin: Int64Array, size: int, wire: Wire) -> Int64Array:
    """``at`` moved on to the next multiple of ``size`` (at most the wire's alignment) from ``origin``."""
    size = min(size, wire.align)
    return at if size == 1 else at + (origin - at) % size


def _alone(
    raw: UInt8Array, start: int, length: int, frames: FrameNames, wires: Sequence[Wire], counted: bool, message: int
) -> Decoded:
    """One message read field by field: its rows, or why it is not well-formed."""
    try:
        cursor = Cursor(raw, wire_of(raw, start, length, wires), start, start + length)
        count = cursor.uint() if counted else 1
        if count * cursor.wire.smallest > cursor.rest:
            raise DecodeError(f"{count} transform{'s' * (count != 1)} cannot fit in {length} bytes")
        rows = [_transform(cursor) for _ in range(count)]
        if cursor.wire.exact and cursor.rest:
            raise DecodeError(f"{cursor.rest} byte{'s' * (cursor.rest > 1)} after the last transform")
    except DecodeError as e:
        return Decoded.empty([(message, str(e))])
    if not rows:
        return Decoded.empty()
    stamp, frame_start, frame_length, child_start, child_length, values_at = zip(*rows, strict=True)
    ids, undecodable = frames.intern_all(
        raw, np.array(frame_start + child_start, np.int64), np.array(frame_length + child_length, np.int64)
    )
    if undecodable.any():
        return Decoded.empty([(message, "a frame id is not UTF-8")])
    values = bytes_at(raw, np.array(values_at, np.int64), VALUES_SIZE).view(f"{cursor.wire.order}f8")
    return Decoded(
        np.full(count, message), ids[:count], ids[count:], np.array(stamp, np.int64), values.astype(np.float64)
    )


def _transform(cursor: Cursor) -> tuple[int, int, int, int, int, int]:
    """A transform's stamp, where its names' bytes start and how many, and where its values start."""
    stamp, frame_start, frame_length = cursor.header()
    child_start, child_length = cursor.string()
    return stamp, frame_start, frame_length, child_start, child_length, cursor.take(VALUES_SIZE, 8)


def _assemble(
    raw: UInt8Array, steps: list[_Step], keep: list[BoolArray], counts: Int64Array, frames: FrameNames, wire: Wire
) -> tuple[Decoded, Int64Array]:
    """The kept rows of the steps in message order (``counts`` of each message), and the messages
    lost to a frame id that is not UTF-8."""
    total = int(counts.sum())
    if not total:
        return Decoded.empty(), np.zeros(0, np.int64)
    steps = [
        s if k.all() else _Step(s.j, *(getattr(s, c.name)[k] for c in fields(_Step)[1:]))
        for s, k in zip(steps, keep, strict=True)
    ]
    # Each step's rows go to their places message by message; names are interned step by step,
    # where they repeat.
    first = np.cumsum(counts) - counts  # each message's first row
    places = [first[s.message] + s.j for s in steps]
    message, stamp, values_at = np.empty(total, np.int64), np.empty(total, np.int64), np.empty(total, np.int64)
    for step, place in zip(steps, places, strict=True):
        message[place], stamp[place], values_at[place] = step.message, step.stamp, step.values_at
    values = bytes_at(raw, values_at, VALUES_SIZE).view(f"{wire.order}f8").astype(np.float64, copy=False)
    starts = np.concatenate([s.frame_start for s in steps] + [s.child_start for s in steps])
    ids, undecodable = frames.intern_all(
        raw, starts, np.concatenate([s.frame_length for s in steps] + [s.child_length for s in steps])
    )
    place = np.concatenate(places)
    parent, child, broken = np.empty(total, np.int32), np.empty(total, np.int32), np.empty(total, bool)
    parent[place], child[place], broken[place] = ids[:total], ids[total:], undecodable[:total] | undecodable[total:]
    lost = np.zeros(len(counts), bool)
    lost[message[broken]] = True
    if broken.any():
        kept = ~lost[message]
        message, parent, child, stamp, values = message[kept], parent[kept], child[kept], stamp[kept], values[kept]
    return Decoded(message, parent, child, stamp, values), np.flatnonzero(lost)
