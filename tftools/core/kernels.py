"""The compiled core (``_kernels``, C++ from ``native/``): the buffer's state and the lookups over it.

``BufferCore`` owns a buffer's frames, publishers and histories (``native/core.hpp``) and takes every sample
through tf2's rules (``native/insert.hpp``); Python reads the histories through ``EdgeHistory``'s numpy views.
The compiled walk (``native/walk.hpp``) is the only one: it reports where it fails why (``walk.Failure``),
which ``walk.py`` words as tf2 does. ``Buffer.lookup`` and ``can_transform`` are methods in C, one crossing
per call; every change of the state (``set_transform``'s common case, ``insert``) holds the core's lock
(``native/lock.hpp``, ``Buffer.lock``) and wakes its waiters. The refusal log and ROS 2's duplicates are the
core's too, read as numpy views (``rejection.RejectionLog``, ``Buffer.duplicates``).
"""

from __future__ import annotations

import os
import sys
import threading
from typing import Any

import numpy as np
import numpy.typing as npt

from tftools.core._kernels import BufferCore
from tftools.core.arrays import BoolArray, FloatArray, Int64Array

#: Fewer times than this per thread are not worth a thread.
_TIMES_PER_THREAD = 50_000

#: A batch's answer, bytes a time: values (7 float64), the time used (int64), validity (bool).
_ROW_BYTES = 7 * 8 + 8 + 1
#: The answers' blocks BatchOutputs keeps: from ~16,000 times (below, malloc reuses freed memory itself)
#: to ~4M (a larger one is not held once let go).
_KEPT_BYTES = (1 << 20, 1 << 28)
#: Blocks kept, at most.
_KEPT_COUNT = 2


class BatchOutputs:
    """Where one buffer's batches write their answers: a block of memory for the three arrays, kept once the
    caller lets go of them, so that a later batch of a like size writes into pages already mapped. New memory
    costs the kernel a page fault and zeroing per page: 8.5 ms of a 1M-time batch's ~75 ms. The last two
    blocks are kept: in a loop that rebinds its answer (``b = buffer.lookup_many(...)``) the previous answer is
    still alive during each call, and the one before it is free."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._kept: list[npt.NDArray[np.uint8]] = []  # the least recently used first

    def arrays(self, n: int) -> tuple[Int64Array, FloatArray, BoolArray]:
        """Stamps (n,), values (n, 7) and validity (n,) to write a batch's answer into (any contents)."""
        size = n * _ROW_BYTES
        if not _KEPT_BYTES[0] <= size <= _KEPT_BYTES[1]:
            return np.empty(n, np.int64), np.empty((n, 7)), np.empty(n, bool)
        with self._lock:
            block = self._free_block(size)
            if block is None:
                block = np.empty(size, np.uint8)
                self._kept = [*self._kept[-(_KEPT_COUNT - 1) :], block]
        values = block[: 56 * n].view(np.float64).reshape(n, 7)
        return block[56 * n : 64 * n].view(np.int64), values, block[64 * n : size].view(np.bool_)

    def _free_block(self, size: int) -> npt.NDArray[np.uint8] | None:
        """A kept block of ``size`` to ``2 * size`` bytes that no array of an earlier answer holds (each holds
        its block: a view's base is the block itself), made the most recently used."""
        kept = self._kept
        for i in range(len(kept)):
            if _references(kept, i) == _ALONE and size <= kept[i].nbytes <= 2 * size:
                kept.append(kept.pop(i))
                return kept[-1]
        return None


def _references(items: list[Any], i: int) -> int:
    """``items[i]``'s reference count as seen from here (what the interpreter adds varies with its version)."""
    return sys.getrefcount(items[i])


#: The count of an object only a list holds.
_ALONE = _references([object()], 0)


def lookup_in_parallel(
    core: BufferCore, target_id: int, source_id: int, times: Int64Array, outputs: BatchOutputs | None = None
) -> tuple[Int64Array, FloatArray, BoolArray]:
    """``core.lookup_in_parallel`` over ``times``, on as many of the CPUs as they are worth, into
    ``outputs``' arrays (new ones without): the times used, values (N, 7) and validity, in the order of ``times``."""
    n = len(times)
    stamps, values, valid = (outputs or BatchOutputs()).arrays(n)
    core.lookup_in_parallel(target_id, source_id, np.ascontiguousarray(times), stamps, values, valid, threads_for(n))
    return stamps, values, valid


def threads_for(n: int) -> int:
    """The threads a batch of ``n`` times runs on: as many of the CPUs as they are worth."""
    return max(1, min(os.cpu_count() or 1, n // _TIMES_PER_THREAD))
