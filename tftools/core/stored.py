"""The samples a buffer holds, back as a ``TransformBatch``: its histories are the only copy."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.core.batch import TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.history import EdgeHistory, rows_as_sent


def stored_rows(buffer: Buffer) -> tuple[TransformBatch, Int64Array]:
    """Every sample ``buffer`` stored, in arrival order, and each one's arrival number.

    The rows are as they were inserted: frame names with the leading ``/`` tf2 strips where
    they had one, static where they came from ``/tf_static``; with them, the rows of caches ROS
    2's tf2 replaced (``EdgeHistory.replaced``). Refused samples are not stored (see
    ``Buffer.rejections``, whose ``sequence`` numbers the same arrivals), nor ROS 2's ignored
    duplicates (``Buffer.duplicates``).
    """
    with buffer.lock:
        names = ["", *buffer.frames]  # index = the buffer's frame id
        ids = {name: frame_id for frame_id, name in enumerate(names)}
        histories = [(ids[name], h) for name, hist in buffer.histories() for h in with_replaced(hist)]
        authorities = list(buffer.authorities)
        if not histories:
            return TransformBatch.empty(), np.zeros(0, np.int64)
        sequence = np.concatenate([h.sequence for _, h in histories])
        order = np.argsort(sequence, kind="stable")
        child = np.concatenate([np.full(len(h), frame_id, np.int32) for frame_id, h in histories])[order]
        columns = {
            name: np.concatenate([getattr(h, of) for _, h in histories])[order] for name, of in SENT_COLUMNS.items()
        }
        batch = rows_as_sent(names, authorities, {**columns, "child": child})
    return batch, sequence[order]


#: ``rows_as_sent``'s columns, and the ``EdgeHistory`` views they are read from.
SENT_COLUMNS = {
    "parent": "parents",
    "flags": "flags",
    "stamp": "stamps",
    "values": "values",
    "record_time": "record_times",
    "authority": "authorities",
}


def with_replaced(hist: EdgeHistory) -> Iterator[EdgeHistory]:
    """``hist`` and the histories it replaced, newest first: every sample sent, whatever tf2 then kept."""
    current: EdgeHistory | None = hist
    while current is not None:
        yield current
        current = current.replaced
