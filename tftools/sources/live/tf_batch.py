"""What a ROS1 or ROS2 TFMessage decoder found, gathered into a ``TransformBatch``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.batch import TransformBatch
from tftools.core.time import NS_PER_S

#: Translation xyz then rotation xyzw, float64 each, contiguous in both serializations.
VALUES_SIZE = 7 * 8
_VALUE_BYTES = np.arange(VALUES_SIZE)


def tf_batch(
    data: bytes,
    names: Sequence[bytes],
    ids: Sequence[int],
    times: Sequence[int],
    value_offsets: Sequence[int],
    byte_order: str,
    *,
    static: bool,
    authority: str,
    record_time: int,
) -> TransformBatch:
    """One message's transforms: ``ids`` are (parent, child) pairs into ``names``, ``times``
    (sec, nsec) pairs, ``value_offsets`` where each transform's seven float64 start in ``data``."""
    count = len(value_offsets)
    raw = np.frombuffer(data, np.uint8)
    values = raw[np.array(value_offsets, np.intp).reshape(-1, 1) + _VALUE_BYTES].copy().view(f"{byte_order}f8")
    pairs = np.array(ids, np.int32).reshape(-1, 2)
    stamp = np.array(times, np.int64).reshape(-1, 2)
    return TransformBatch(
        frame_names=[n.decode("utf-8", "replace") for n in names],
        authorities=[authority],
        parent=pairs[:, 0].copy(),
        child=pairs[:, 1].copy(),
        stamp=stamp[:, 0] * NS_PER_S + stamp[:, 1],
        translation=values[:, :3].astype(np.float64),
        rotation=values[:, 3:].astype(np.float64),
        static=np.full(count, static),
        record_time=np.full(count, record_time, np.int64),
        authority=np.zeros(count, np.int32),
    )
