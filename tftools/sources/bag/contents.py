"""What bag readers share: progress callbacks, record order, the merged /clock, and their names for a description."""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.batch import TransformBatch, concat_batches, take_rows
from tftools.core.time import TIME_MAX
from tftools.sources.contents import ClockSamples, RecordingContents, SourceInfo
from tftools.values import value

#: Called with (bytes done, bytes in all) as bags are read, for progress bars.
ProgressCallback = Callable[[int, int], None]

#: The topic preferred when a recording has several of rosgraph_msgs/Clock.
CLOCK_TOPIC = "/clock"


@value
class RecordWindow:
    """Record times ``[first, last)`` (ns): what a windowed read keeps of a recording; ``[first, last]`` where
    ``last`` is the last time (``TIME_MAX``), which a damaged time past it is held as: no window left it out."""

    first: int
    last: int

    @property
    def closed(self) -> bool:
        """Whether the window holds ``last`` too (it is ``TIME_MAX``)."""
        return self.last >= TIME_MAX

    def overlaps(self, start: int, end: int) -> bool:
        """Whether messages recorded from ``start`` to ``end`` (both included) may lie in the window."""
        return (
            self.first < self.last and (start <= self.last if self.closed else start < self.last) and end >= self.first
        )

    def holds(self, record_time: Int64Array) -> BoolArray:
        below = record_time <= self.last if self.closed else record_time < self.last
        held: BoolArray = (record_time >= self.first) & below
        return held


def in_turn(progress: ProgressCallback, sizes: Sequence[int]) -> Iterator[ProgressCallback]:
    """Progress over parts of ``sizes`` bytes read one after the other: per part, a callback that reports
    its (done, of) as its share of the whole; and the part reported done once the next is asked for."""
    total, before = sum(sizes), 0
    for size in sizes:
        yield functools.partial(_share, progress, before, size, total)
        before += size
        progress(before, total)


def _share(progress: ProgressCallback, before: int, size: int, total: int, done: int, of: int) -> None:
    progress(before + size * done // max(of, 1), total)


def in_record_order(batches: list[TransformBatch]) -> list[TransformBatch]:
    """``batches`` (each in record order) as consecutive parts in record order: as they are when
    they follow each other, else merged into one batch, sorted (ties keep their order)."""
    batches = [b for b in batches if len(b)]
    if all(int(a.record_time[-1]) <= int(b.record_time[0]) for a, b in itertools.pairwise(batches)):
        return batches
    merged = concat_batches(batches)
    return [take_rows(merged, np.argsort(merged.record_time, kind="stable"))]


def merged_clock(clocks: Sequence[ClockSamples]) -> ClockSamples:
    """One clock of several (a split recording's files, or a file's clock topics): the samples of
    ``/clock``, else of the topic with the most, in record order (ties keep their order)."""
    clocks = [c for c in clocks if len(c)]
    if not clocks:
        return ClockSamples.empty()
    counts: dict[str, int] = {}
    for c in clocks:
        counts[c.topic] = counts.get(c.topic, 0) + len(c)
    topic = CLOCK_TOPIC if CLOCK_TOPIC in counts else max(sorted(counts), key=counts.__getitem__)
    chosen = [c for c in clocks if c.topic == topic]
    if len(chosen) == 1:
        return chosen[0]
    record_time = np.concatenate([c.record_time for c in chosen])
    clock = np.concatenate([c.clock for c in chosen])
    if np.any(record_time[1:] < record_time[:-1]):
        order = np.argsort(record_time, kind="stable")
        record_time, clock = record_time[order], clock[order]
    return ClockSamples(topic, record_time, clock)


#: What reading bags yields, under the names bag readers use: each file's ``SourceInfo``, and the
#: ``RecordingContents`` of them all.
BagFileInfo = SourceInfo
BagContents = RecordingContents
