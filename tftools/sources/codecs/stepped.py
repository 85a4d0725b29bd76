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
    message, stamp, translation, rotation, parent, child, name_start, name_length, failed = _wire.decode_transforms(
        raw,
        np.ascontiguousarray(starts, np.int64),
        np.ascontiguousarray(lengths, np.int64),
        [wire.compiled for wire in wires],
        counted,
    )
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
