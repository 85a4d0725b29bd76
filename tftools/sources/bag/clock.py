"""The decoded clock messages of a file gathered into its ``ClockSamples``."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import Int64Array as IntArray
from tftools.sources.bag.contents import merged_clock
from tftools.sources.contents import ClockSamples


class ClockParts:
    """The decoded clock messages of one file, channel by channel, until made samples."""

    def __init__(self) -> None:
        self._channel: list[npt.NDArray[np.int32]] = []
        self._time: list[IntArray] = []
        self._position: list[IntArray] = []  # orders messages of equal record time
        self._value: list[IntArray] = []

    def add(self, channel: npt.NDArray[np.int32], record_time: IntArray, position: IntArray, value: IntArray) -> None:
        if len(value):
            self._channel.append(channel)
            self._time.append(record_time)
            self._position.append(position)
            self._value.append(value)

    def channels(self) -> npt.NDArray[np.int32]:
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


def _in_order(time: IntArray, position: IntArray) -> bool:
    step = np.diff(time)
    return bool(np.all((step > 0) | ((step == 0) & (np.diff(position) > 0))))
