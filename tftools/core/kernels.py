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

import numpy as np

from tftools.core._kernels import BufferCore
from tftools.core.arrays import BoolArray, FloatArray, Int64Array

#: Fewer times than this per thread are not worth a thread.
_TIMES_PER_THREAD = 50_000


def lookup_in_parallel(
    core: BufferCore, target_id: int, source_id: int, times: Int64Array
) -> tuple[Int64Array, FloatArray, BoolArray]:
    """``core.lookup_in_parallel`` over ``times``, on as many of the CPUs as they are worth: the times
    used, values (N, 7) and validity, in the order of ``times``."""
    n = len(times)
    stamps, values, valid = np.empty(n, np.int64), np.empty((n, 7)), np.empty(n, bool)
    threads = max(1, min(os.cpu_count() or 1, n // _TIMES_PER_THREAD))
    core.lookup_in_parallel(target_id, source_id, np.ascontiguousarray(times), stamps, values, valid, threads)
    return stamps, values, valid
