"""Transform sequences of ROS1 and CDR decoded in bulk: every message read field by field in C++
(``_wire``, compiled from native/tf_wire.hpp), each field checked against its message's end; a
message that does not read to a well-formed end is read again here, on its own, to say why.

A ``tf2_msgs/TFMessage`` (and foxglove's FrameTransforms, the same bytes) is a uint32 count of
transforms, a foxglove FrameTransform a single one.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs import _wire
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames
from tftools.sources.codecs.gather import bytes_at
from tftools.sources.codecs.wire import VALUES_SIZE, Cursor, Wire, wire_of


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
    decoded, bad = _compiled(raw, starts, lengths, frames, wires, counted)
    alone = [read_alone(raw, int(starts[m]), int(lengths[m]), frames, wires, counted, m) for m in bad.tolist()]
    return Decoded.joined([decoded, *alone])


def _compiled(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, wires: Sequence[Wire], counted: bool
) -> tuple[Decoded, Int64Array]:
    """The rows of the messages that read to a well-formed end in one of ``wires``, and which
    messages are left to be read alone (the others, and those with a frame id that is not UTF-8)."""
    message, stamp, values, parent, child, name_start, name_length, bad = _wire.decode_transforms(
        raw,
        np.ascontiguousarray(starts, np.int64),
        np.ascontiguousarray(lengths, np.int64),
        [wire.compiled for wire in wires],
        counted,
    )
    ids, undecodable = frames.intern_all(raw, name_start, name_length)
    broken = undecodable[parent] | undecodable[child] if undecodable.any() else np.zeros(0, bool)
    if broken.any():
        lost = np.zeros(len(starts), bool)
        lost[message[broken]] = True
        kept = ~lost[message]
        message, stamp, values, parent, child = message[kept], stamp[kept], values[kept], parent[kept], child[kept]
        bad = np.sort(np.concatenate([bad, np.flatnonzero(lost)]))
    return Decoded(message, ids[parent], ids[child], stamp, values), bad


def read_alone(
    raw: UInt8Array, start: int, length: int, frames: FrameNames, wires: Sequence[Wire], counted: bool, message: int
) -> Decoded:
    """One message read field by field in Python (``wire.Cursor``): its rows, or why it is not
    well-formed. The reference the compiled reader is tested against."""
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
