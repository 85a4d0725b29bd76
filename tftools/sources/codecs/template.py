"""Template decoding of protobuf messages: one parse learns a message's layout, numpy applies it to
its look-alikes (payloads of the same length with the same structural bytes)."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int64Array, UInt8Array
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames
from tftools.sources.codecs.gather import bytes_at, grouped
from tftools.sources.codecs.parsed import Parsed, one_by_one

#: After this many templates in a row that each matched almost nothing, the rest goes one by one.
_MAX_POOR_TEMPLATES = 3
_POOR_MATCH = 8
_MAX_SECONDS = 9_223_372_030  # beyond, a stamp may not fit in int64 nanoseconds (checked one by one)


@dataclass(frozen=True)
class Varint:
    """An integer field of a layout: ``size`` bytes at ``offset``, 64 or 32 ``bits`` wide; size
    0 when absent (then it is 0)."""

    offset: int
    size: int
    bits: int


ABSENT = Varint(0, 0, 64)


@dataclass
class Layout:
    """Where one message's numbers sit, and which bytes fix that (same in every look-alike)."""

    exact: list[tuple[int, int]] = field(default_factory=list)  # byte ranges that must be equal
    varints: list[tuple[int, int]] = field(default_factory=list)  # continuation bits must be equal
    sec: list[Varint] = field(default_factory=list)  # per transform
    nsec: list[Varint] = field(default_factory=list)
    values: list[list[int]] = field(default_factory=list)  # 7 float64 offsets each; -1: absent


#: Parses one message, learning its layout; raises ``DecodeError``.
Learner = Callable[[bytes], tuple[Parsed, Layout]]


def decode_templated(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, learn: Learner
) -> Decoded:
    """The payloads decoded by templates ``learn`` teaches, payloads of each length together."""
    return Decoded.joined(
        [
            _decode_group(bytes_at(raw, starts[g], int(lengths[g[0]])), frames, learn).renumbered(g)
            for g in grouped(lengths)
        ]
    )


class _Template:
    """A layout compiled against its sample message, to test and decode a byte matrix."""

    def __init__(self, layout: Layout, sample: bytes, parsed: Parsed, frames: FrameNames) -> None:
        exact = _positions(layout.exact)
        loose = _positions(layout.varints)
        self.positions = np.concatenate([exact, loose])
        self.masks = np.concatenate([np.full(len(exact), 0xFF, np.uint8), np.full(len(loose), 0x80, np.uint8)])
        self.expected = np.frombuffer(sample, np.uint8)[self.positions] & self.masks
        self.layout = layout
        self.parents = np.array([frames.intern(name) for name in parsed.parents], np.int32)
        self.children = np.array([frames.intern(name) for name in parsed.children], np.int32)

    def matches(self, block: UInt8Array) -> BoolArray:
        return np.asarray(((np.take(block, self.positions, axis=1) & self.masks) == self.expected).all(axis=1))

    def decode(self, rows: Int64Array, block: UInt8Array) -> tuple[Decoded, Int64Array]:
        """The rows of messages ``rows`` (their bytes in ``block``), and the messages left out:
        those with seconds too far out for int64 nanoseconds, to be parsed apart."""
        sec, nsec = _varints(block, self.layout.sec), _varints(block, self.layout.nsec)
        fits = (np.abs(sec) <= _MAX_SECONDS).all(axis=1)
        left_out = rows[~fits]
        rows, block, sec, nsec = rows[fits], block[fits], sec[fits], nsec[fits]
        n, k = sec.shape
        decoded = Decoded.of_values(
            np.repeat(rows, k),
            np.tile(self.parents, n),
            np.tile(self.children, n),
            (sec * 1_000_000_000 + nsec).reshape(-1),
            _floats(block, self.layout).reshape(-1, 7),
        )
        return decoded, left_out


def _decode_group(matrix: UInt8Array, frames: FrameNames, learn: Learner) -> Decoded:
    """Messages of equal length (rows of ``matrix``): a template learnt from the first undecoded
    row takes every row that has its fixed bytes; the stragglers are parsed one by one."""
    parts: list[Decoded] = []
    failures: list[tuple[int, str]] = []
    remaining = np.arange(len(matrix), dtype=np.int64)
    stragglers: list[Int64Array] = []
    poor = 0
    while len(remaining) and poor < _MAX_POOR_TEMPLATES:
        sample = matrix[remaining[0]].tobytes()
        try:
            parsed, layout = learn(sample)
        except DecodeError as e:
            failures.append((int(remaining[0]), str(e)))
            remaining = remaining[1:]
            continue
        template = _Template(layout, sample, parsed, frames)
        candidates = matrix if len(remaining) == len(matrix) else matrix[remaining]
        hit = template.matches(candidates)
        decoded, left_out = template.decode(remaining[hit], candidates[hit])
        parts.append(decoded)
        stragglers.append(left_out)
        poor = poor + 1 if hit.sum() < _POOR_MATCH else 0
        remaining = remaining[~hit]
    rest = np.concatenate([remaining, *stragglers])
    width = matrix.shape[1]
    stragglers_decoded = one_by_one(
        matrix.reshape(-1), rest * width, np.full(len(rest), width), frames, lambda data: learn(data)[0]
    )
    return Decoded.joined([*parts, stragglers_decoded.renumbered(rest), Decoded.empty(failures)])


def _positions(ranges: list[tuple[int, int]]) -> Int64Array:
    if not ranges:
        return np.zeros(0, np.int64)
    return np.concatenate([np.arange(a, b, dtype=np.int64) for a, b in ranges])


def _varints(block: UInt8Array, numbers: list[Varint]) -> Int64Array:
    """The (n, k) integers of ``numbers`` in every row; gathered by width and size in one go."""
    out = np.zeros((len(block), len(numbers)), np.int64)
    by_kind: dict[tuple[int, int], list[int]] = defaultdict(list)
    for j, number in enumerate(numbers):
        if number.size:
            by_kind[(number.bits, number.size)].append(j)
    for (bits, size), cols in by_kind.items():
        starts = np.array([numbers[j].offset for j in cols], np.int64)
        raw = np.take(block, (starts[:, None] + np.arange(size)).ravel(), axis=1).reshape(len(block), len(cols), size)
        shifts = 7 * np.arange(size, dtype=np.uint64)
        value = ((raw & 0x7F).astype(np.uint64) << shifts).sum(axis=2, dtype=np.uint64)
        if bits == 32:  # an int32 is truncated first
            out[:, cols] = value.astype(np.uint32).view(np.int32)
        else:
            out[:, cols] = value.view(np.int64)
    return out


def _floats(block: UInt8Array, layout: Layout) -> FloatArray:
    offsets = np.array(layout.values, np.int64).reshape(-1)
    present = np.flatnonzero(offsets >= 0)
    out = np.zeros((len(block), len(offsets)), np.float64)
    if len(present):
        columns = (offsets[present][:, None] + np.arange(8)).ravel()
        out[:, present] = np.take(block, columns, axis=1).view("<f8")
    return out
