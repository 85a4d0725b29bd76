"""Transform sequences of ROS1 and CDR decoded in bulk: every message read field by field in C++
(``_wire``, compiled from native/tf_wire.hpp), each field checked against its message's end; a
message that does not read to a well-formed end is told why there (``wire.Reason``), and worded here.

A ``tf2_msgs/TFMessage`` (and foxglove's FrameTransforms, the same bytes) is a uint32 count of
transforms, a foxglove FrameTransform a single one.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs import _wire
from tftools.sources.codecs.decoded import Decoded, FrameNames
from tftools.sources.codecs.wire import Reason, Wire, worded


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
    (``counted``: a count of transforms first, else a single transform each), and why each of the
    others is not well-formed: a field past its end, a count its bytes cannot hold, bytes after the
    last transform (ROS1), an encapsulation of none of the wires, or a frame id that is not UTF-8."""
    columns = _wire.decode_transforms(raw, *_offsets(starts, lengths), _compiled(wires), counted)
    return _finished(raw, lengths, frames, columns)


class SteppedDecoder:
    """``decode_transforms`` of one set of wires (a ``BulkDecoder``), which may also be started on a
    thread of its own (``start``) while its caller reads on."""

    def __init__(self, wires: Sequence[Wire], *, counted: bool = True) -> None:
        self.wires, self.counted = tuple(wires), counted

    def __call__(self, raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
        return decode_transforms(raw, starts, lengths, frames, self.wires, counted=self.counted)

    def start(self, raw: UInt8Array, starts: Int64Array, lengths: Int64Array) -> Started:
        """The payloads' fields read on another thread (the bytes held until then); their names are
        interned by ``finish``, on the caller's, in the order the decodes are finished."""
        decoding = _wire.Decoding(raw, *_offsets(starts, lengths), _compiled(self.wires), self.counted)
        return Started(raw, lengths, decoding)


class Started:
    """A ``SteppedDecoder``'s decode under way."""

    def __init__(self, raw: UInt8Array, lengths: Int64Array, decoding: _wire.Decoding) -> None:
        self._raw, self._lengths, self._decoding = raw, lengths, decoding

    def finish(self, frames: FrameNames) -> Decoded:
        """The rows, as ``decode_transforms`` gives them, once the thread is done."""
        return _finished(self._raw, self._lengths, frames, self._decoding.result())


def _offsets(starts: Int64Array, lengths: Int64Array) -> tuple[Int64Array, Int64Array]:
    return np.ascontiguousarray(starts, np.int64), np.ascontiguousarray(lengths, np.int64)


def _compiled(wires: Sequence[Wire]) -> list[_wire.WireFields]:
    return [wire.compiled for wire in wires]


def _finished(raw: UInt8Array, lengths: Int64Array, frames: FrameNames, columns: _wire.Columns) -> Decoded:
    """The native decode's ``columns`` as rows, their names interned in ``frames``, each failure worded."""
    message, stamp, translation, rotation, parent, child, name_start, name_length, failed = columns
    failures = [
        (m, worded(Reason(reason), int(lengths[m]), offset, figure)) for m, reason, offset, figure in failed.tolist()
    ]
    ids, undecodable = frames.intern_all(raw, name_start, name_length)
    broken = undecodable[parent] | undecodable[child] if undecodable.any() else np.zeros(0, bool)
    if broken.any():
        lost = np.unique(message[broken])
        kept = ~np.isin(message, lost)
        message, stamp, parent, child = message[kept], stamp[kept], parent[kept], child[kept]
        translation, rotation = translation[kept], rotation[kept]
        failures = sorted(failures + [(m, worded(Reason.NOT_UTF8, int(lengths[m]))) for m in lost.tolist()])
    if len(ids) and int(ids[0]) == 0 and int(ids[-1]) == len(ids) - 1 and bool(np.all(ids[1:] > ids[:-1])):
        return Decoded(message, parent, child, stamp, translation, rotation, failures)  # ids the table's already
    return Decoded(message, ids[parent], ids[child], stamp, translation, rotation, failures)
