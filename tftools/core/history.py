"""``EdgeHistory``: one child frame's samples (tf2's TimeCache/StaticCache), a read-only view of columns the
buffer's compiled core owns (``native/core.hpp``'s ``Store``): ``stamps``, ``values`` (N, 7), ``translations``,
``rotations``, ``parents``, ``authorities``, ``record_times``, ``sequence``, ``flags`` (numpy arrays that
keep the columns alive), ``latest_stamp``, ``oldest_stamp``, ``latest_parent``, ``parent_at(time)``,
``static``, ``replaced`` (the history ROS 2's tf2 replaced by this one) and ``len``."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

# The core's: the bytes of one sample in a history's columns (stamp, values, parent, authority, record
# time, sequence, flags), the largest bulk load whose histories' block comes in large pages, the
# ``EdgeHistory.flags`` bits, and ``Extrapolation.kind`` (why a history has no sample at a time: tf2's
# three extrapolation errors).
from tftools.core._kernels import CHILD_HAD_SLASH as CHILD_HAD_SLASH
from tftools.core._kernels import FROM_STATIC_TOPIC as FROM_STATIC_TOPIC
from tftools.core._kernels import FUTURE as FUTURE
from tftools.core._kernels import LARGE_PAGES_UP_TO as LARGE_PAGES_UP_TO
from tftools.core._kernels import NO_DATA as NO_DATA
from tftools.core._kernels import ONLY_ONE as ONLY_ONE
from tftools.core._kernels import PARENT_HAD_SLASH as PARENT_HAD_SLASH
from tftools.core._kernels import PAST as PAST
from tftools.core._kernels import ROW_BYTES as ROW_BYTES
from tftools.core._kernels import EdgeHistory as EdgeHistory
from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.batch import TransformBatch


def rows_as_sent(names: Sequence[str], authorities: Sequence[str], columns: Mapping[str, Any]) -> TransformBatch:
    """Samples as a buffer keeps them back as the rows that were sent: a name that had a leading ``/``
    has it again, and rows from ``/tf_static`` are static. ``columns``: ``parent`` and ``child`` (ids into
    tf2's ``names``), ``flags`` (as ``EdgeHistory.flags``), ``stamp``, ``values`` (N, 7), ``record_time``
    and ``authority`` (into ``authorities``)."""
    parent, child, flags, values = columns["parent"], columns["child"], columns["flags"], columns["values"]
    slashed = len(names)  # a name that had a slash: the stripped name's id, shifted past every stripped name
    return TransformBatch(
        frame_names=[*names, *("/" + n for n in names)],
        authorities=authorities,
        parent=np.where(flags & PARENT_HAD_SLASH, parent + slashed, parent).astype(np.int32, copy=False),
        child=np.where(flags & CHILD_HAD_SLASH, child + slashed, child).astype(np.int32, copy=False),
        stamp=columns["stamp"],
        translation=values[:, :3],
        rotation=values[:, 3:],
        static=(flags & FROM_STATIC_TOPIC) != 0,
        record_time=columns["record_time"],
        authority=columns["authority"],
    )


def old_data(
    stamps: Int64Array, cache_time: int, static: BoolArray | None = None, keeps_first_cache: bool = True
) -> BoolArray:
    """Which of one frame's samples, stamped ``stamps`` in the order they arrived, tf2's ``TimeCache::insertData``
    refuses as ``TF_OLD_DATA`` with a cache ``cache_time`` long (ROS 1 and ROS 2 alike): stamped more than that
    behind the newest sample it holds, checked before it compares their stamps with its samples' (so such a
    sample is never a repeat). The newest it holds is the newest stamp offered to that cache before: a refused
    sample is never newer. ``static``: which came on /tf_static (none, if not given); a ``StaticCache`` refuses
    none. Where tf2 keeps a frame's first kind of cache (``Dialect.keeps_first_cache``: ROS 1's), every sample
    goes to the cache the first made, a /tf_static one into a ``TimeCache`` with its stamp; ROS 2's replaces the
    frame's cache with an empty one of the new kind at each change of kind."""
    static = np.zeros(len(stamps), np.bool_) if static is None else static
    old = np.zeros(len(stamps), np.bool_)
    if not len(stamps):
        return old
    if keeps_first_cache:
        starts = np.zeros(1, np.intp)
    else:
        starts = np.concatenate([[0], np.flatnonzero(static[1:] != static[:-1]) + 1])
    for start, end in zip(starts.tolist(), [*starts[1:].tolist(), len(stamps)], strict=True):
        if not static[start]:  # a TimeCache, from its first sample on
            mine = stamps[start:end]
            old[start + 1 : end] = mine[1:] + cache_time < np.maximum.accumulate(mine)[:-1]
    return old


class Extrapolation(NamedTuple):
    """Why a history cannot answer at ``time``: empty, one sample at another ``stamp``, or
    ``time`` after the newest or before the oldest ``stamp``. The compiled walk finds it, ``walk.error``
    words it (``Dialect``)."""

    kind: int
    time: int
    stamp: int
