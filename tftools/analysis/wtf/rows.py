"""``Rows``: every transform read, in record order, as the checks see it: read in place from the
buffer's histories (the only copy of the transforms), never copied out of them whole."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Generic, NamedTuple, TypeVar

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, IntpArray, UInt8Array
from tftools.core.frames import Names, frame_name
from tftools.core.history import CHILD_HAD_SLASH, FROM_STATIC_TOPIC, PARENT_HAD_SLASH, EdgeHistory
from tftools.core.rejection import RejectionCode, code_bits
from tftools.sources.codecs.gather import distinct
from tftools.sources.recording import Recording

S = TypeVar("S", bound=np.generic)


class Segment(NamedTuple):
    """Rows held together (one history, or the refused rows), as the buffer keeps them: frames by
    tf2's ids, ``flags`` as ``EdgeHistory.flags``, ``sequence`` their arrival numbers."""

    parent: Int32Array
    child: Int32Array
    flags: UInt8Array
    stamp: Int64Array
    record_time: Int64Array
    values: FloatArray  # (N, 7): tx ty tz qx qy qz qw
    authority: Int32Array
    sequence: Int64Array
    refusals: UInt8Array  # what the buffer refused each row for (``RejectionLog.verdicts``): 0, stored


@dataclass(frozen=True)
class Layout:
    """Where each row (in record order) lies among the segments, laid end to end, and back."""

    segments: list[Segment]
    starts: Int64Array  # each segment's first place
    place: Int32Array  # row -> place
    row: Int32Array  # place -> row

    def __len__(self) -> int:
        return len(self.place)

    def gather(
        self, column: Callable[[Segment], npt.NDArray[S]], rows: IntpArray | Int32Array | BoolArray
    ) -> npt.NDArray[S]:
        """``column``'s values (of a segment) of ``rows``, in their order."""
        places = self.place[np.flatnonzero(rows) if rows.dtype == np.bool_ else rows]
        which = np.searchsorted(self.starts, places, side="right") - 1
        if not len(which) or (which[0] == which[-1] and (which == which[0]).all()):  # one history: the usual case
            s = int(which[0]) if len(which) else 0
            one: npt.NDArray[S] = column(self.segments[s])[places - self.starts[s]]
            return one
        order = np.argsort(which, kind="stable")  # each segment's rows together: linear, not rows x segments
        parts = np.split(order, np.flatnonzero(np.diff(which[order])) + 1)
        first = column(self.segments[int(which[order[0]])])
        out = np.empty((len(places), *first.shape[1:]), first.dtype)
        for mine in parts:
            s = int(which[mine[0]])
            out[mine] = column(self.segments[s])[places[mine] - self.starts[s]]
        return out

    def whole(self, column: Callable[[Segment], npt.NDArray[S]]) -> npt.NDArray[S]:
        """``column`` for every row, in record order (a copy)."""
        # each segment's put in place: the segments' concatenation, then its gather, held the column twice
        out: npt.NDArray[S] | None = None
        for start, segment in zip(self.starts.tolist(), self.segments, strict=True):
            part = column(segment)
            if out is None:
                out = np.empty((len(self.row), *part.shape[1:]), part.dtype)
            elif part.dtype != out.dtype:  # as the concatenation's: the wider type
                out = out.astype(np.result_type(out, part))
            out[self.row[start : start + len(part)]] = part
        assert out is not None  # the refused rows' segment is always there
        return out

    def groups(self, mask: BoolArray, by_parent: bool) -> Iterator[tuple[int, int, IntpArray]]:
        """(parent id, child id, rows) for each edge (or child, parent 0) among the ``mask`` rows, each
        in record order, in order of first arrival."""
        # a segment is one child's history (its parent changes seldom): its rows are found edge by edge from
        # the segments, and one edge's rows at a time are held. Sorting every row's key as one column held
        # ~0.1 GB at 4.1M transforms in every check that walks the edges (keys, their order, the sorted keys).
        first: dict[int, int] = {}  # key -> its first row
        pieces: dict[int, list[int | Int32Array]] = {}  # key -> the segments holding it whole, or its rows
        for s in range(len(self.segments)):
            chosen, keys = self._chosen(s, mask, by_parent)
            if not len(chosen):
                continue
            low, high = int(keys.min()), int(keys.max())
            if low == high:  # the usual: the segment is one edge's, found again when it is yielded
                first[low] = min(first.get(low, len(self.row)), int(chosen.min()))
                pieces.setdefault(low, []).append(s)
                continue
            order = np.argsort(keys, kind="stable")
            ordered, chosen = keys[order], chosen[order]
            bounds = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]])
            for key, low_row, part in zip(
                ordered[bounds].tolist(),
                np.minimum.reduceat(chosen, bounds).tolist(),
                np.split(chosen, bounds[1:]),
                strict=True,
            ):
                first[key] = min(first.get(key, len(self.row)), low_row)
                pieces.setdefault(key, []).append(part)
        for key in sorted(first, key=first.__getitem__):  # by first arrival
            parts = [self._chosen(p, mask, by_parent)[0] if isinstance(p, int) else p for p in pieces.pop(key)]
            yield key >> 32, key & 0xFFFFFFFF, np.sort(np.concatenate(parts)).astype(np.intp)

    def _chosen(self, s: int, mask: BoolArray, by_parent: bool) -> tuple[Int32Array, Int64Array]:
        """The ``mask`` rows of segment ``s`` (in its order), and each one's key: parent id << 32 | child id
        (``by_parent``), else the child id."""
        start = int(self.starts[s])
        segment = self.segments[s]
        rows = self.row[start : start + len(segment.stamp)]
        inside = mask[rows]
        keys = segment.child[inside].astype(np.int64)
        if by_parent:
            keys |= segment.parent[inside].astype(np.int64) << 32
        return rows[inside], keys


class Column(Generic[S]):
    """One column of the rows, in record order: ``column[rows]`` reads just those rows (a copy)."""

    def __init__(self, layout: Layout, of: Callable[[Segment], npt.NDArray[S]]) -> None:
        self._layout = layout
        self._of = of

    def __getitem__(self, rows: IntpArray | Int32Array | BoolArray) -> npt.NDArray[S]:
        return self._layout.gather(self._of, rows)

    def whole(self) -> npt.NDArray[S]:
        """Every row's (a copy: for a check that looks at all rows at once)."""
        return self._layout.whole(self._of)


#: The checks of tf2's ``setTransform`` on the frames of a sample.
FRAME_REFUSALS = (RejectionCode.SELF_TRANSFORM, RejectionCode.NO_FRAME_ID, RejectionCode.NO_CHILD_FRAME_ID)
#: And on its values.
VALUE_REFUSALS = (RejectionCode.NAN_INPUT, RejectionCode.DENORMALIZED_QUATERNION)


class Rows:
    """Every transform read (refused ones too) in arrival order, its frames under tf2's names
    (one leading ``/`` dropped; the empty name kept), and what the buffer's tf2 said of it at
    insertion (``refusals``: the codes of its rejections).

    The columns read the buffer's histories where they lie; only a few flags per row are held."""

    def __init__(self, layout: Layout, names: list[str], authorities: list[str]) -> None:
        self.names = names  # tf2's frame names; ``parent``/``child`` index them
        self.raw_names = [*names, *("/" + n for n in names)]  # as sent; ``raw_parent``/``raw_child`` index them
        self.authorities = authorities
        self._layout = layout
        slashed = len(names)
        self.parent: Column[np.int32] = Column(layout, lambda s: s.parent)
        self.child: Column[np.int32] = Column(layout, lambda s: s.child)
        self.raw_parent: Column[np.int32] = Column(
            layout, lambda s: np.where(s.flags & PARENT_HAD_SLASH, s.parent + slashed, s.parent).astype(np.int32)
        )
        self.raw_child: Column[np.int32] = Column(
            layout, lambda s: np.where(s.flags & CHILD_HAD_SLASH, s.child + slashed, s.child).astype(np.int32)
        )
        self.stamp: Column[np.int64] = Column(layout, lambda s: s.stamp)
        self.record_time: Column[np.int64] = Column(layout, lambda s: s.record_time)
        self.values: Column[np.float64] = Column(layout, lambda s: s.values)
        self.authority: Column[np.int32] = Column(layout, lambda s: s.authority)
        self.flags: Column[np.uint8] = Column(layout, lambda s: s.flags)  # ``EdgeHistory.flags``
        self.refusals: Column[np.uint8] = Column(layout, lambda s: s.refusals)  # ``RejectionLog.verdicts``

    def __len__(self) -> int:
        return len(self._layout)

    def of_values(self, compute: Callable[[FloatArray], npt.NDArray[S]]) -> npt.NDArray[S]:
        """``compute`` of the values (N, 7), for every row in record order, computed a segment at a time."""
        return self._layout.whole(lambda s: compute(s.values))

    def by_edge(self, mask: BoolArray) -> Iterator[tuple[str, str, IntpArray]]:
        """(parent, child, rows) for each edge among the ``mask`` rows, in order of first arrival."""
        for parent, child, rows in self._layout.groups(mask, by_parent=True):
            yield self.names[parent], self.names[child], rows

    def by_child(self, mask: BoolArray) -> Iterator[tuple[str, IntpArray]]:
        """(child, rows) for each child frame among the ``mask`` rows, in order of first arrival."""
        for _, child, rows in self._layout.groups(mask, by_parent=False):
            yield self.names[child], rows

    def of_edge(self, parent: str, child: str) -> IntpArray:
        """The rows of ``parent -> child`` on /tf, in record order."""
        key = self.names.index(parent) << 32 | self.names.index(child)
        return np.flatnonzero((self._edge_keys == key) & ~self.static)

    def edge_publishers(self, parent: str, child: str) -> Iterator[tuple[int, IntpArray]]:
        """(publisher, rows) for each publisher of ``parent -> child`` on /tf, by publisher id, each one's rows
        in record order: the edge as each of its publishers sent it."""
        mine = self.of_edge(parent, child)
        authority = self.authority[mine]
        for publisher in distinct(authority.astype(np.int64)).tolist():
            yield publisher, mine[authority == publisher]

    @cached_property
    def _edge_keys(self) -> Int64Array:
        """Each row's edge as one number, parent id << 32 | child id."""
        parents = self._layout.whole(lambda s: s.parent).astype(np.int64)
        keys: Int64Array = parents << 32 | self._layout.whole(lambda s: s.child)
        return keys

    @cached_property
    def static(self) -> BoolArray:
        """Received on /tf_static."""
        return self._layout.whole(lambda s: (s.flags & FROM_STATIC_TOPIC) != 0)

    def refused_for(self, *codes: RejectionCode) -> BoolArray:
        """The rows the buffer refused for any of ``codes``."""
        bits = code_bits(*codes)
        return self._layout.whole(lambda s: np.asarray(s.refusals & bits != 0, bool))

    @cached_property
    def named(self) -> BoolArray:
        """The rows tf2 did not refuse for their frames: both named, and not the same frame."""
        return ~self.refused_for(*FRAME_REFUSALS)

    @cached_property
    def usable(self) -> BoolArray:
        """The rows tf2 did not refuse on their face (for their stamps at most)."""
        return ~self.refused_for(*FRAME_REFUSALS, *VALUE_REFUSALS)


def rows_of(recording: Recording) -> Rows:
    """The rows of ``recording``: its buffer's histories (the histories they replaced too), and the
    rows the buffer refused, under one table of names (``""`` first) and one of publishers."""
    buffer = recording.buffer
    with buffer.lock:
        names, authorities = Names(), Names()
        for name in ("", *buffer.frames):  # id = the buffer's frame id
            names.intern(name)
        for name in buffer.authorities:
            authorities.intern(name)
        segments = [
            _history_segment(names.intern(child), h) for child, hist in buffer.histories() for h in _chain(hist)
        ]
        segments.append(_refused_segment(recording, names, authorities))
    return Rows(_layout(_coalesced(segments)), names.names, authorities.names)


#: Histories of at most this many rows are read from one copy of them all: each segment costs every column
#: read a Python step, and 100,000 static edges of one row each made the checks take a minute.
SMALL_SEGMENT = 16


def _coalesced(segments: list[Segment]) -> list[Segment]:
    """``segments``, the small ones (``SMALL_SEGMENT`` rows at most) copied into one: a copy of at most
    ``SMALL_SEGMENT`` rows per history, whatever the recording's length."""
    small = [s for s in segments if len(s.stamp) <= SMALL_SEGMENT]
    if len(small) < 2:
        return segments
    merged = Segment(*(np.concatenate(column) for column in zip(*small, strict=True)))
    return [*(s for s in segments if len(s.stamp) > SMALL_SEGMENT), merged]


def _chain(hist: EdgeHistory) -> Iterator[EdgeHistory]:
    """``hist``, then the histories it replaced (ROS 2), newest first."""
    current: EdgeHistory | None = hist
    while current is not None:
        yield current
        current = current.replaced


def _history_segment(child: int, hist: EdgeHistory) -> Segment:
    n = len(hist)
    columns = (hist.flags, hist.stamps, hist.record_times, hist.values, hist.authorities, hist.sequence)
    if n <= SMALL_SEGMENT:  # np.full is ~20 times faster than broadcast_to for a few rows
        return Segment(hist.parents, np.full(n, child, np.int32), *columns, np.zeros(n, np.uint8))
    child_ids: Int32Array = np.broadcast_to(np.int32(child), (n,))
    return Segment(hist.parents, child_ids, *columns, np.broadcast_to(np.uint8(0), (n,)))


def _refused_segment(recording: Recording, names: Names, authorities: Names) -> Segment:
    """The rows the buffer refused (or, ROS 2, took for identical ones it holds), under tf2's names, with
    the flags a history would give them and the codes of their rejections."""
    batch = recording.refused
    raw = batch.frame_names
    stripped = np.array([names.intern(frame_name(n)) for n in raw] or [0], np.int32)
    slash = np.array([n.startswith("/") for n in raw] or [False])
    publishers = np.array([authorities.intern(a) for a in batch.authorities] or [0], np.int32)
    flags = (
        np.where(batch.static, FROM_STATIC_TOPIC, 0)
        | np.where(slash[batch.parent], PARENT_HAD_SLASH, 0)
        | np.where(slash[batch.child], CHILD_HAD_SLASH, 0)
    ).astype(np.uint8)
    return Segment(
        stripped[batch.parent],
        stripped[batch.child],
        flags,
        batch.stamp,
        batch.record_time,
        np.concatenate([batch.translation, batch.rotation], axis=1),
        publishers[batch.authority],
        recording.refused_sequence,
        recording.buffer.rejections.verdicts(recording.refused_sequence),
    )


def _layout(segments: list[Segment]) -> Layout:
    """The segments' rows in record order: by arrival number."""
    lengths = np.array([len(s.stamp) for s in segments], np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
    total = int(lengths.sum())
    place = np.full(total, -1, np.int32)
    top = max((int(s.sequence.max()) for s in segments if len(s.sequence)), default=-1)
    if top == total - 1:  # arrival numbers 0..N-1, each once: a row's number is its place in record order
        for start, segment in zip(starts.tolist(), segments, strict=True):
            place[segment.sequence] = np.arange(start, start + len(segment.sequence), dtype=np.int32)
    if (place < 0).any():  # numbers missing (a live buffer dropped old samples) or twice
        place = np.argsort(np.concatenate([s.sequence for s in segments]), kind="stable").astype(np.int32)
    row = np.empty(total, np.int32)
    row[place] = np.arange(total, dtype=np.int32)
    return Layout(segments, starts, place, row)


def split(rows: IntpArray, keys: npt.NDArray[Any]) -> Iterator[tuple[int, IntpArray]]:
    """Per value of ``keys`` (one per row of ``rows``), first seen first: it, and its rows."""
    for key in dict.fromkeys(keys.tolist()):
        yield key, rows[keys == key]
