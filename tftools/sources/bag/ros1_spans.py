"""The wanted records of uncompressed chunks, read from the file by their index instead of whole.

A chunk's index records give the offset of every message in it, of every connection, so a
wanted record ends at the next offset (or at the chunk's end) and only those bytes need reading.
Records close together are read as one run (``ranges``): a chunk of transforms only is read
whole, one whose bulk is camera images costs little more than its transforms.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tftools.sources.bag.ranges import read_ranges
from tftools.sources.bag.ros1_chunks import IntArray
from tftools.sources.bag.ros1_format import distinct


@dataclass
class SpanBatch:
    """Wanted records of several chunks, read into one buffer."""

    data: memoryview
    offsets: IntArray  # where each record begins in ``data``, ascending
    ends: IntArray  # where it must end: where the chunk's next indexed record begins, or the chunk does
    chunk: IntArray  # the ordinal of its chunk


@dataclass
class ChunkSpans:
    """The wanted records of uncompressed chunks, gathered chunk by chunk (in file order) until read."""

    ordinals: list[int] = field(default_factory=list)
    data_starts: list[int] = field(default_factory=list)  # where each chunk's data begins in the file
    sizes: list[int] = field(default_factory=list)
    wanted: list[IntArray] = field(default_factory=list)
    indexed: list[IntArray] = field(default_factory=list)
    records: int = 0  # offsets wanted (about what reading them will take, whatever else the chunks hold)
    nbytes: int = 0  # their chunks' data: at most what reading them will take

    def __bool__(self) -> bool:
        return bool(self.ordinals)

    def add(self, ordinal: int, data_start: int, size: int, wanted: IntArray, indexed: IntArray) -> None:
        """The records at the ``wanted`` offsets of a chunk whose data (``size`` bytes) begins at
        ``data_start``; each ends where the next of the ``indexed`` offsets (those of every
        connection) begins."""
        self.ordinals.append(ordinal)
        self.data_starts.append(data_start)
        self.sizes.append(size)
        self.wanted.append(wanted)
        self.indexed.append(indexed)
        self.records += len(wanted)
        self.nbytes += size

    def read(self, fd: int) -> SpanBatch:
        """Read the gathered records from the file ``fd``, and start gathering anew. Records cut
        short by the end of the file are left out."""
        starts, ends, chunk = self._ranges()
        self._clear()
        data, where, complete = read_ranges(fd, starts, ends)
        where, length = where[complete], (ends - starts)[complete]
        return SpanBatch(data.data, where, where + length, chunk[complete])

    def _clear(self) -> None:
        self.ordinals, self.data_starts, self.sizes, self.wanted, self.indexed = [], [], [], [], []
        self.records = self.nbytes = 0

    def _ranges(self) -> tuple[IntArray, IntArray, IntArray]:
        """Where each wanted record begins and ends in the file, and its chunk's ordinal, in file
        order. Offsets outside their chunk (a damaged index) are left out."""
        data_starts, sizes = np.array(self.data_starts, np.int64), np.array(self.sizes, np.int64)
        wanted = _in_file(self.wanted, data_starts, sizes)
        # The chunks' data do not overlap, so every chunk's offsets and end sort as one list.
        bounds = np.sort(np.concatenate([_in_file(self.indexed, data_starts, sizes), data_starts + sizes]))
        starts = distinct(wanted)
        ends = bounds[np.searchsorted(bounds, starts, side="right")]  # a chunk's end is past its offsets
        chunk = np.array(self.ordinals, np.int64)[np.searchsorted(data_starts, starts, side="right") - 1]
        return starts, ends, chunk


def _in_file(offsets: list[IntArray], data_starts: IntArray, sizes: IntArray) -> IntArray:
    """Each chunk's ``offsets`` that lie inside its data, as positions in the file."""
    counts = [len(o) for o in offsets]
    relative = np.concatenate(offsets)
    inside = (relative >= 0) & (relative < np.repeat(sizes, counts))
    placed: IntArray = (relative + np.repeat(data_starts, counts))[inside]
    return placed
