"""``EdgeTable``: where each frame's history lies in memory, one int64 row per frame, for the kernels.

A compiled call pays for every array it is given, so the kernels take this one table instead
of each history's arrays: a row holds a history's bounds and the addresses of its stamps,
values and parents. The buffer updates a row whenever it stores into that frame's history
(which may move its arrays); the table also keeps the arrays it points to alive, so a row
can at worst be stale, never dangling. Nothing here imports numba: ``compiled()`` does, once it pays.
"""

from __future__ import annotations

import importlib
import math
import os
import threading
from collections.abc import Sequence
from types import ModuleType

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.history import EdgeHistory

#: Columns of a row. A frame without history (a root, or not yet seen) has HAS == 0.
HAS, STATIC, START, END, STAMPS, VALUES, PARENTS = range(7)
COLUMNS = 7


class EdgeTable:
    """One row per frame id describing its history's storage (see the module docstring)."""

    def __init__(self, histories: Sequence[EdgeHistory | None]) -> None:
        self.rows: Int64Array = np.zeros((max(len(histories), 8), COLUMNS), np.int64)
        self._pinned: list[object] = [None] * len(self.rows)
        for frame_id, hist in enumerate(histories):
            if hist is not None:
                self.update(frame_id, hist)

    def update(self, frame_id: int, hist: EdgeHistory) -> None:
        """Describe ``hist``, the history of ``frame_id``, as it is now."""
        if frame_id >= len(self.rows):
            self._grow(frame_id + 1)
        stamps, values, parents, start, end = hist.storage()
        self._pinned[frame_id] = (stamps, values, parents)
        self.rows[frame_id] = (
            1,
            hist.static,
            start,
            end,
            stamps.ctypes.data,
            values.ctypes.data,
            parents.ctypes.data,
        )

    def _grow(self, frames: int) -> None:
        rows = np.zeros((max(frames, 2 * len(self.rows)), COLUMNS), np.int64)
        rows[: len(self.rows)] = self.rows
        self._pinned += [None] * (len(rows) - len(self.rows))
        self.rows = rows


#: What loading the kernels costs, about (mostly numba's import; the machine code is cached).
LOAD_SECONDS = 0.5
#: What the Python walk takes, about: per lookup (or time of a batch) and per ``can_transform``.
WALK_LOOKUP_S, WALK_CAN_TRANSFORM_S = 50e-6, 15e-6

_compiled: ModuleType | None = None
_tried = False
_walked = 0.0  # what the Python walk took so far, by estimate, while the kernels were not loaded


def compiled(walk_seconds: float = math.inf) -> ModuleType | None:
    """The compiled kernels (``tftools.core.kernels``) if they are loaded or worth loading, else None.

    ``walk_seconds`` is what the Python walk would take for the call at hand. The kernels are
    loaded once the walk's time so far reaches what loading them costs, as one rents skis until
    the rent would have bought them: a command that looks up a few hundred times never pays for
    numba, a loop of lookups pays once, early, and never more than twice what the best choice in
    hindsight would have cost. None also where numba cannot be imported (the walk answers alone).
    """
    global _compiled, _tried, _walked
    if _tried:
        return _compiled
    _walked += walk_seconds
    if _walked < LOAD_SECONDS:
        return None
    _tried = True
    try:
        _compiled = importlib.import_module("tftools.core.kernels")
    except ImportError:  # numba missing on this platform
        _compiled = None
    return _compiled


#: Fewer times than this per thread are not worth a thread.
_TIMES_PER_THREAD = 50_000


def lookup_in_parallel(
    kernels: ModuleType,
    table: Int64Array,
    target_id: int,
    source_id: int,
    times: Int64Array,
) -> tuple[Int64Array, FloatArray, BoolArray]:
    """``kernels.lookup_many`` over ``times``, split across the CPUs.

    Each thread takes a span of time, so that it streams through its own part of the
    histories; the kernel is fastest over ascending times. Unless the times are ascending
    already (then the spans are contiguous parts), they are partitioned by rank and each
    thread sorts its part and walks it, the kernel writing each answer to its row (numpy's
    sorting lets go of the GIL, so all of it runs in parallel). Returns the times used,
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
        kernels.lookup_many(table, target_id, source_id, ordered, rows, *outputs)

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
