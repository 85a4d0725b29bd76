"""The decoded clock messages of a file gathered into its ``ClockSamples``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.arrays import Int32Array, Int64Array
from tftools.sources.bag.contents import merged_clock
from tftools.sources.contents import ClockSamples


class ClockParts:
    """The decoded clock messages of one file, channel by channel, until made samples."""

    def __init__(self) -> None:
        #: Per part: each message's channel, record time, position (orders equal record times), value.
        self._parts: list[tuple[Int32Array, Int64Array, Int64Array, Int64Array]] = []

    def add(self, channel: Int32Array, record_time: Int64Array, position: Int64Array, value: Int64Array) -> None:
        if len(value):
            self._parts.append((channel, record_time, position, value))

    def samples(self, topics: Sequence[str]) -> ClockSamples:
        """The clock of the file (``topics``: each channel's), in record order: ``/clock``, or
        the clock topic with the most messages."""
        if not self._parts:
            return ClockSamples.empty()
        channel, time, position, value = (np.concatenate(column) for column in zip(*self._parts, strict=True))
        names = list(dict.fromkeys(topics))
        topic_of = np.array([names.index(t) for t in topics], np.int32)[channel]
        found = []
        for number in np.unique(topic_of).tolist():
            rows = np.flatnonzero(topic_of == number)
            if not _in_order(time[rows], position[rows]):
                rows = rows[np.lexsort((position[rows], time[rows]))]
            found.append(ClockSamples(names[number], time[rows], value[rows]))
        return merged_clock(found)


def _in_order(time: Int64Array, position: Int64Array) -> bool:
    step = np.diff(time)
    return bool(np.all((step > 0) | ((step == 0) & (np.diff(position) > 0))))
