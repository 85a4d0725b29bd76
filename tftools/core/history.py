"""``EdgeHistory``: one child frame's samples in contiguous arrays (tf2's TimeCache/StaticCache)."""

from __future__ import annotations

import mmap
from bisect import bisect_right
from collections.abc import Iterable, Mapping, Sequence
from itertools import accumulate, pairwise
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import FloatArray, Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch

#: ``EdgeHistory.flags`` bits.
FROM_STATIC_TOPIC = 1
PARENT_HAD_SLASH = 2
CHILD_HAD_SLASH = 4


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


#: The bytes of one sample in each of a history's columns: stamp, values, parent, authority, record
#: time, sequence, flags (in this order in a history's block, each column aligned to its items).
_COLUMN_BYTES = (8, 7 * 8, 4, 4, 8, 8, 1)
ROW_BYTES = sum(_COLUMN_BYTES)

_Columns = tuple[Int64Array, FloatArray, Int32Array, Int32Array, Int64Array, Int64Array, UInt8Array]


def block_bytes(capacity: int) -> int:
    """The bytes of a history's block for ``capacity`` rows, rounded up to a cache line (blocks laid one
    after another stay aligned)."""
    return -(-capacity * ROW_BYTES // 64) * 64


def _columns_in(block: UInt8Array, capacity: int) -> _Columns:
    """The columns of ``capacity`` rows laid one after another in ``block``."""
    ends = [0, *accumulate(size * capacity for size in _COLUMN_BYTES)]  # not np.split: 10x its cost a history
    stamps, values, parents, authorities, record_times, sequence, flags = (
        block[start:end] for start, end in pairwise(ends)
    )
    return (
        stamps.view(np.int64),
        values.view(np.float64).reshape(capacity, 7),
        parents.view(np.int32),
        authorities.view(np.int32),
        record_times.view(np.int64),
        sequence.view(np.int64),
        flags,
    )


#: A large page: the memory a fault brings in for a block numpy asks large pages for (4 MiB and up).
_LARGE_PAGE = 2 << 20

#: The largest block for a bulk load's histories that comes in large pages (see RoomForHistories).
_LARGE_PAGES_UP_TO = 64 << 20


class RoomForHistories:
    """One block for the histories of a bulk load, each taking its part as it is made.

    Up to ``_LARGE_PAGES_UP_TO`` the block comes in large pages, a fault each, not page by page
    (faults are most of a bulk load's cost otherwise). The price is that each column's large page
    is resident from its first row on, while the rows not yet inserted are still held: a 258k-transform
    load peaks 13 MiB higher. A larger block stays in small pages, or that price would grow with the
    histories (2 MiB a column: a 4.1M-transform load would hold 136 B a transform, not 112).
    """

    def __init__(self, capacities: Iterable[int]) -> None:
        size = sum(block_bytes(c) for c in capacities)
        if size > _LARGE_PAGES_UP_TO:
            memory = mmap.mmap(-1, size)
            memory.madvise(mmap.MADV_NOHUGEPAGE)
            self._block: UInt8Array = np.frombuffer(memory, np.uint8)
        else:
            block = np.empty(size + _LARGE_PAGE, np.uint8)
            start = -block.ctypes.data % _LARGE_PAGE  # the block's first whole large page
            self._block = block[start : start + size]
        self._used = 0

    def take(self, capacity: int) -> UInt8Array | None:
        """A block for a history of ``capacity`` rows; None where there is no room left."""
        size = block_bytes(capacity)
        if self._used + size > len(self._block):
            return None
        self._used += size
        return self._block[self._used - size : self._used]


#: ``Gap.kind``: why a history has no sample at a time (tf2's three extrapolation errors).
NO_DATA, ONLY_ONE, FUTURE, PAST = range(4)


class Gap(NamedTuple):
    """Why a history cannot answer at ``time``: empty, one sample at another ``stamp``, or
    ``time`` after the newest or before the oldest ``stamp``. The compiled walk finds it, ``walk.error``
    words it (``Dialect``)."""

    kind: int
    time: int
    stamp: int


class EdgeHistory:
    """The samples of one child frame: stamps, values, parents, and where each came from.

    A dynamic history is sorted by stamp, like tf2's ``TimeCache``: with no stamp twice under
    ROS 1's tf2, several samples of one stamp in arrival order under ROS 2's. A static history
    keeps every sample in arrival order and answers with the last one at every time, like tf2's
    ``StaticCache`` (which keeps only that one). Each row stores the parent, so a frame can
    change parent over time. The arrays (one block, or a part of a bulk load's
    ``RoomForHistories``) grow in amortized chunks, and pruning (a finite cache time) drops a
    prefix by moving ``start``. ``replaced`` is the history this one replaced when
    ROS 2's tf2 turned the frame static or dynamic (kept only where every sample is kept).
    """

    __slots__ = (
        "_authorities",
        "_end",
        "_flags",
        "_parents",
        "_record_times",
        "_sequence",
        "_stamp_index",
        "_stamps",
        "_start",
        "_values",
        "replaced",
        "static",
    )

    def __init__(
        self,
        static: bool,
        capacity: int = 8,
        replaced: EdgeHistory | None = None,
        room: RoomForHistories | None = None,
    ) -> None:
        self.static = static
        self.replaced = replaced
        self._start = 0
        self._end = 0
        capacity = max(capacity, 1)
        self._allocate(capacity, room.take(capacity) if room is not None else None)

    def _allocate(self, capacity: int, block: UInt8Array | None = None) -> None:
        """Columns for ``capacity`` rows, in ``block`` if given (of ``block_bytes(capacity)``),
        holding the rows in use."""
        n = self._end - self._start
        columns = _columns_in(np.empty(block_bytes(capacity), np.uint8) if block is None else block, capacity)
        if n:  # (a new history has no columns yet)
            new: tuple[npt.NDArray[Any], ...] = columns
            held: tuple[npt.NDArray[Any], ...] = self._columns()
            for column, old in zip(new, held, strict=True):
                column[:n] = old[self._start : self._end]
        self._stamps, self._values, self._parents, self._authorities = columns[:4]
        self._record_times, self._sequence, self._flags = columns[4:]
        self._stamp_index = self._stamps.data  # bisect on it yields Python ints, no numpy scalars
        self._start, self._end = 0, n

    # --- views -------------------------------------------------------------------------------

    def __len__(self) -> int:
        return self._end - self._start

    @property
    def stamps(self) -> Int64Array:
        return self._stamps[self._start : self._end]

    @property
    def values(self) -> FloatArray:
        """(N, 7): tx ty tz qx qy qz qw."""
        return self._values[self._start : self._end]

    @property
    def translations(self) -> FloatArray:
        return self._values[self._start : self._end, :3]

    @property
    def rotations(self) -> FloatArray:
        return self._values[self._start : self._end, 3:]

    @property
    def parents(self) -> Int32Array:
        return self._parents[self._start : self._end]

    @property
    def authorities(self) -> Int32Array:
        return self._authorities[self._start : self._end]

    @property
    def record_times(self) -> Int64Array:
        return self._record_times[self._start : self._end]

    @property
    def sequence(self) -> Int64Array:
        """Arrival order across the whole buffer, to tell when stamps went backwards."""
        return self._sequence[self._start : self._end]

    @property
    def flags(self) -> UInt8Array:
        return self._flags[self._start : self._end]

    @property
    def latest_stamp(self) -> int:
        """tf2's ``getLatestTimestamp``: 0 for a static edge or an empty history."""
        if self.static or self._end == self._start:
            return 0
        return self._stamp_index[self._end - 1]

    @property
    def oldest_stamp(self) -> int:
        if self.static or self._end == self._start:
            return 0
        return self._stamp_index[self._start]

    @property
    def latest_parent(self) -> int:
        """The parent of the newest sample (the current one, for a static edge); 0 if empty."""
        return int(self._parents[self._end - 1]) if self._end > self._start else 0

    def storage(
        self,
    ) -> tuple[Int64Array, FloatArray, Int32Array, Int32Array, Int64Array, Int64Array, UInt8Array, int, int]:
        """The whole backing arrays (stamps, values, parents, authorities, record times, sequence,
        flags) and the rows in use, ``start:end``.

        For the compiled calls (``EdgeTable.update``), which read the arrays, store samples after
        ``end`` (and merge them in by stamp) and move ``_start`` and ``_end``; the arrays move when
        the history grows or is pruned.
        """
        return (*self._columns(), self._start, self._end)

    def _columns(self) -> _Columns:
        """The backing arrays, one row per sample, in ``storage``'s order."""
        return (
            self._stamps,
            self._values,
            self._parents,
            self._authorities,
            self._record_times,
            self._sequence,
            self._flags,
        )

    # --- room for samples (``EdgeTable.insert`` and ``set_transform`` store them) ------------

    def grow(self, rows: int) -> None:
        """Room for ``rows`` more samples and as many again (the arrays move): amortized growth."""
        self._allocate(max(2 * (len(self) + rows), 8))

    def prune(self, cache_time: int, latest: int | None = None) -> None:
        """Drop samples older than ``cache_time`` before ``latest`` (default: the newest), as
        tf2's ``pruneList``."""
        if self.static or self._end == self._start:
            return
        if latest is None:
            latest = self._stamp_index[self._end - 1]
        self._start = bisect_right(self._stamp_index, latest - cache_time - 1, self._start, self._end)
        if self._start > len(self._stamps) // 2:
            self._allocate(len(self._stamps))

    # --- lookups (tf2's TimeCache::getParent) ----------------------------------------------

    def parent_at(self, time: int) -> int | None:
        """The parent at ``time`` (of the older of the two samples around it), or None where the
        history has no sample then (the walk says why: native/walk.hpp).

        Where samples share a stamp (ROS 2), tf2's newest-first list makes the last to arrive
        count, except at the oldest stamp, which is the list's back: there the first one.
        """
        start, end, stamps = self._start, self._end, self._stamp_index
        if end == start:
            return None
        if self.static or time == 0 or time == stamps[end - 1]:
            row = end - 1
        elif time == stamps[start]:
            row = start
        elif stamps[start] < time < stamps[end - 1]:
            row = bisect_right(stamps, time, start, end) - 1
        else:
            return None
        return int(self._parents[row])
