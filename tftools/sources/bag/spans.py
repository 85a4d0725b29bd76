"""``Spans``: message records, one row each, as every bag format finds them and the message set takes them."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array


class Spans:
    """Message records, one row each: where each sits in its file, its channel and record time,
    and the bytes it spans. Those are first where its record lies in the file (its end: as far as
    it may reach), then in the bytes read, and once its header is read, where its payload lies."""

    __slots__ = ("channel", "chunk", "end", "offset", "start", "time")

    def __init__(
        self,
        chunk: Int64Array,
        offset: Int64Array,
        channel: Int64Array,
        time: Int64Array,
        start: Int64Array,
        end: Int64Array,
    ) -> None:
        self.chunk = chunk  # the ordinal of its chunk in the file
        self.offset = offset  # where its record begins in its chunk's records
        self.channel = channel  # as the format numbers them (a ROS1 connection, an MCAP channel id)
        self.time = time  # record time (ns)
        self.start = start
        self.end = end

    @classmethod
    def empty(cls) -> Spans:
        none = np.zeros(0, np.int64)
        return cls(none, none, none, none, none, none)

    def __len__(self) -> int:
        return len(self.start)

    def rows(self, which: BoolArray | Int64Array) -> Spans:
        """The rows ``which`` (a mask, or indices) selects, in its order. Where that is every row in
        order, as a read that lost nothing selects, the columns are this one's, not copies (a caller
        that writes into a column writes into both): ~6 instructions a value less, 6 columns a call."""
        if selects_all(which, len(self)):
            return Spans(*(getattr(self, name) for name in _COLUMNS))
        return Spans(*(getattr(self, name)[which] for name in _COLUMNS))

    def looked_up(self, table: dict[int, int]) -> Int64Array:
        """Each row's ``table[channel]``, -1 where its channel is not in ``table``."""
        keys = np.array(sorted(table), np.int64)
        if not len(keys):
            return np.full(len(self), -1, np.int64)
        at = np.minimum(np.searchsorted(keys, self.channel), len(keys) - 1)
        values = np.array([table[k] for k in keys.tolist()], np.int64)
        return np.where(keys[at] == self.channel, values[at], -1)

    @property
    def position(self) -> Int64Array:
        """Each record's place in the file: orders the messages of equal record time."""
        return (self.chunk << 32) + self.offset


#: ``Spans``' columns, in the order its constructor takes them.
_COLUMNS = ("chunk", "offset", "channel", "time", "start", "end")


def selects_all(which: BoolArray | Int64Array, n: int) -> bool:
    """Whether ``which`` (a mask, or indices) selects every one of ``n`` rows, in order."""
    if len(which) != n:
        return False
    if which.dtype == np.bool_:
        return bool(which.all())
    # n strictly increasing indices from 0 to n - 1 are 0, 1, ..., n - 1.
    return n == 0 or (int(which[0]) == 0 and int(which[-1]) == n - 1 and bool(np.all(which[1:] > which[:-1])))


def joined(parts: Sequence[Spans]) -> Spans:
    """The rows of every part, one after the other."""
    if not parts:
        return Spans.empty()
    return Spans(*(np.concatenate([getattr(p, name) for p in parts]) for name in _COLUMNS))


def bounded(spans: Spans, records_start: Int64Array, records_end: Int64Array) -> tuple[Spans, BoolArray]:
    """The records of chunks whose records lie at ``records_start[chunk]:records_end[chunk]`` of the
    file, as their index lists them (every record, of every channel): in file order, with the file
    range each may take, up to the next record indexed or the end of its chunk's records. Also
    which chunks have an index that cannot be trusted: with an entry outside their records (left
    out) or two at one offset."""
    outside = (spans.offset < 0) | (spans.offset >= (records_end - records_start)[spans.chunk])
    start = records_start[spans.chunk] + spans.offset  # past int64 only where outside
    damaged = np.zeros(len(records_start), bool)
    damaged[spans.chunk[outside]] = True
    inside = np.flatnonzero(~outside)
    placed = start if len(inside) == len(start) else start[inside]
    in_order = bool(np.all(placed[1:] >= placed[:-1]))  # as an index lists its chunk's records: no sort
    order = inside if in_order else inside[np.argsort(placed, kind="stable")]
    spans = spans.rows(order)
    spans.start = placed if in_order else start[order]
    twice = spans.start[1:] == spans.start[:-1]
    damaged[spans.chunk[1:][twice]] = True
    # The next record further on (past those at the same offset) begins in this chunk, or after its end: with
    # no two at one offset, the next row's (no search: ~160 instructions a record).
    ahead = np.append(spans.start, np.iinfo(np.int64).max)
    further = ahead[np.searchsorted(spans.start, spans.start, side="right")] if twice.any() else ahead[1:]
    spans.end = np.minimum(further, records_end[spans.chunk])
    return spans, damaged
