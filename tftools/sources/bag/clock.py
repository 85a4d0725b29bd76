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
        self._channel: list[Int32Array] = []
        self._time: list[Int64Array] = []
        self._position: list[Int64Array] = []  # orders messages of equal record time
        self._value: list[Int64Array] = []

    def add(self, channel: Int32Array, record_time: Int64Array, position: Int64Array, value: Int64Array) -> None:
        if len(value):
            self._channel.append(channel)
            self._time.append(record_time)
            self._position.append(position)
            self._value.append(value)

    def channels(self) -> Int32Array:
        """The channel of every message kept."""
        return np.concatenate(self._channel) if self._channel else np.zeros(0, np.int32)

    def samples(self, topics: Sequence[str]) -> ClockSamples:
        """The clock of the file (``topics``: each channel's), in record order: ``/clock``, or
        the clock topic with the most messages."""
        if not self._value:
            return ClockSamples.empty()
        channel = self.channels()
        time, position, value = (np.concatenate(c) for c in (self._time, self._position, self._value))
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
