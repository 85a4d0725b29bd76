"""The compiled lookups (``_kernels``, C++ from ``native/``) over a buffer's edge histories.

``walk.py`` stays the reference and the one place tf2's error messages are made: the compiled
walk takes its steps with its formulas in its order, and reports only success or failure, on
which the buffer asks the Python walk why. A compiled call pays for every array it is given, so
the lookups read one ``EdgeTable``: per frame, its history's bounds and arrays (which the table
holds, so a row can at worst be stale, never dangling). The buffer updates a frame's row
whenever it stores into that frame's history (which may move its arrays).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Sequence

import numpy as np

from tftools.core._kernels import EdgeTable
from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.history import EdgeHistory


def edge_table(histories: Sequence[EdgeHistory | None]) -> EdgeTable:
    """A table describing ``histories`` (indexed by frame id) as they are now."""
    table = EdgeTable()
    for frame_id, hist in enumerate(histories):
        if hist is not None:
            track(table, frame_id, hist)
    return table


def track(table: EdgeTable, frame_id: int, hist: EdgeHistory) -> None:
    """Describe ``hist``, the history of ``frame_id``, in ``table`` as it is now."""
    table.update(frame_id, hist.static, *hist.storage())


#: Fewer times than this per thread are not worth a thread.
_TIMES_PER_THREAD = 50_000


def lookup_in_parallel(
    table: EdgeTable,
    target_id: int,
    source_id: int,
    times: Int64Array,
) -> tuple[Int64Array, FloatArray, BoolArray]:
    """``table.lookup_many`` over ``times``, split across the CPUs.

    Each thread takes a span of time, so that it streams through its own part of the
    histories; the kernel is fastest over ascending times. Unless the times are ascending
    already (then the spans are contiguous parts), they are partitioned by rank and each
    thread sorts its part and walks it, the kernel writing each answer to its row (numpy's
    sorting and the kernel let go of the GIL, so all of it runs in parallel). Returns the times used,
    values (N, 7) and validity, in the order of ``times``.
    """
    n = len(times)
    times = np.ascontiguousarray(times)
    ascending = n < 2 or bool(np.all(times[1:] >= times[:-1]))
    outputs = np.empty(n, np.int64), np.empty((n, 7)), np.empty(n, bool)
    threads = max(1, min(os.cpu_count() or 1, n // _TIMES_PER_THREAD))
    bounds = np.linspace(0, n, threads + 1).astype(int)
    ranked = None
    if not ascending:  # the k-th thread's rows: ranked[bounds[k]:bounds[k + 1]], unsorted
        ranked = np.argpartition(times, bounds[1:-1]) if threads > 1 else np.arange(n)

    def run(part: int) -> None:
        start, end = int(bounds[part]), int(bounds[part + 1])
        if ranked is None:
            rows, ordered = np.arange(start, end), times[start:end]
        else:
            rows = ranked[start:end]
            order, ordered = _sorted(times[rows])
            rows = rows[order]
        table.lookup_many(target_id, source_id, ordered, rows, *outputs)

    helpers = [threading.Thread(target=run, args=(part,)) for part in range(1, threads)]
    for helper in helpers:
        helper.start()
    run(0)
    for helper in helpers:
        helper.join()
    return outputs


def _sorted(values: Int64Array) -> tuple[Int64Array, Int64Array]:
    """``np.argsort(values)`` and the values in that order.

    When their span leaves room, each value and its index are packed in one int64 and sorted as
    plain integers, several times faster than an argsort (ties come out by index, as a stable
    sort would give them)."""
    n = len(values)
    bits = max(1, (n - 1).bit_length())
    low = int(values.min()) if n else 0
    if n < 2 or int(values.max()) - low >= 1 << (63 - bits):
        order = np.argsort(values, kind="stable")
        return order, values[order]
    packed = ((values - low) << bits) | np.arange(n, dtype=np.int64)
    packed.sort()
    return packed & ((1 << bits) - 1), (packed >> bits) + low
