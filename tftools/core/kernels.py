"""The compiled lookups (``_kernels``, C++ from ``native/``) over a buffer's edge histories.

The compiled walk (``native/walk.hpp``) is the only one: it reports where it fails why
(``walk.Failure``), which ``walk.py`` words as tf2 does. A compiled call pays for every array it is given, so
the lookups read one ``EdgeTable``: per frame, its history's bounds and arrays (which the table
holds, so a row can at worst be stale, never dangling). The buffer updates a frame's row
whenever it stores into that frame's history (which may move its arrays).

The table also answers ``Buffer.lookup`` and ``can_transform`` from the frames' names, building
the ``Transform`` itself, and stores ``set_transform``'s common case in place (``EdgeTable.set_transform``):
one crossing per call, the buffer's lock held around it.
"""

from __future__ import annotations

import os

import numpy as np

from tftools.core._kernels import EdgeTable
from tftools.core.arrays import BoolArray, FloatArray, Int64Array

#: Fewer times than this per thread are not worth a thread.
_TIMES_PER_THREAD = 50_000


def lookup_in_parallel(
    table: EdgeTable, target_id: int, source_id: int, times: Int64Array
) -> tuple[Int64Array, FloatArray, BoolArray]:
    """``table.lookup_in_parallel`` over ``times``, on as many of the CPUs as they are worth: the times
    used, values (N, 7) and validity, in the order of ``times``."""
    n = len(times)
    stamps, values, valid = np.empty(n, np.int64), np.empty((n, 7)), np.empty(n, bool)
    threads = max(1, min(os.cpu_count() or 1, n // _TIMES_PER_THREAD))
    table.lookup_in_parallel(target_id, source_id, np.ascontiguousarray(times), stamps, values, valid, threads)
    return stamps, values, valid
