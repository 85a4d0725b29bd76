"""A ROS1 bag's wanted messages, decoded a few megabytes at a time as found, into batches in record order."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.core.batch import TransformBatch
from tftools.sources.bag.columns import ColumnParts
from tftools.sources.bag.decode.clock import ClockParts
from tftools.sources.bag.ros1_chunks import IntArray, Located, pieces
from tftools.sources.bag.ros1_format import Buffer, Connection
from tftools.sources.codecs.decoded import Decoded, FrameNames
from tftools.sources.codecs.ros1 import decode_clocks, decode_tf
from tftools.sources.contents import ClockSamples, is_static_topic

_SLICE = 1 << 16  # messages decoded together: bounds the temporary arrays
_GROUP_BYTES = 2 << 20  # payload bytes gathered before they are decoded (and then freed)


@dataclass
class _Found:
    """Wanted messages of one chunk, until their group is decoded."""

    channel: IntArray
    starts: IntArray  # of each message in ``payload``
    lengths: IntArray
    payload: bytes


_COLUMNS = ("parent", "child", "stamp", "translation", "rotation")


class MessageCollector:
    """Wanted messages (transform topics) gathered chunk by chunk and decoded a few megabytes at a
    time, so that neither the bag nor all its payloads are ever held at once; clock messages
    (``want(connection, clock=True)``) are decoded as they come.

    Per message only its channel, record time, place (chunk, offset) and row count are kept, to
    put the rows in rosbag's playback order at the end.
    """

    def __init__(self) -> None:
        self.channels: list[Connection] = []  # the connections read, by channel number
        self._channel_of: dict[int, int] = {}
        self._is_clock: list[bool] = []  # per channel
        self._clock = ClockParts()
        self._pending: list[_Found] = []
        self._pending_bytes = 0
        self._channel: list[IntArray] = []
        self._time: list[IntArray] = []
        self._chunk: list[IntArray] = []
        self._offset: list[IntArray] = []
        self._rows: list[IntArray] = []  # per message, its transforms decoded
        self._columns = ColumnParts(_COLUMNS)
        self._frames = FrameNames()
        self._failures: dict[int, tuple[int, str]] = {}  # channel -> (count, first reason)
        self.count = 0

    def want(self, connection: Connection, *, clock: bool = False) -> None:
        if connection.id not in self._channel_of:
            self._channel_of[connection.id] = len(self.channels)
            self.channels.append(connection)
            self._is_clock.append(clock)

    def wants(self, conn: int) -> bool:
        return conn in self._channel_of

    def add(self, chunk: int | IntArray, data: Buffer, located: Located) -> npt.NDArray[np.bool_]:
        """Keep the wanted messages among ``located`` (records of ``data``, in chunk ``chunk``, or
        each in its own); returns which were kept.

        Their payloads are copied out of ``data``, which the caller may then release."""
        channel = self._channels(located.conn)
        kept = channel >= 0
        clock = np.array([*self._is_clock, False], bool)[channel]  # channel -1: the appended False
        if clock.any():
            self._add_clocks(chunk, data, located, channel, clock)
        keep = np.flatnonzero(kept & ~clock)
        if not len(keep):
            return kept
        starts, lengths = located.data_start[keep], located.data_len[keep]
        if 2 * int(lengths.sum()) >= len(data):  # mostly transforms: one copy of the chunk
            payload = bytes(data)
        else:
            payload = b"".join(pieces(data, starts, lengths))
            starts = np.cumsum(lengths) - lengths
        self._pending.append(_Found(channel[keep], starts, lengths, payload))
        self._pending_bytes += len(payload)
        self._channel.append(channel[keep])
        self._time.append(located.time[keep])
        self._chunk.append(np.broadcast_to(np.asarray(chunk, np.int64), len(channel))[keep])
        self._offset.append(located.offset[keep])
        self.count += len(keep)
        if self._pending_bytes >= _GROUP_BYTES:
            self._decode_pending()
        return kept

    def _add_clocks(
        self, chunk: int | IntArray, data: Buffer, located: Located, channel: IntArray, clock: npt.NDArray[np.bool_]
    ) -> None:
        """Decode the clock messages among ``located``."""
        which = np.flatnonzero(clock)
        position = (np.broadcast_to(np.asarray(chunk, np.int64), len(channel))[which] << 32) + located.offset[which]
        raw = np.frombuffer(data, np.uint8)
        rows, values, failures = decode_clocks(raw, located.data_start[which], located.data_len[which])
        taken = which[rows]
        self._clock.add(channel[taken].astype(np.int32), located.time[taken], position[rows], values)
        for row, reason in failures:
            index = int(channel[which[row]])
            before, first = self._failures.get(index, (0, reason))
            self._failures[index] = (before + 1, first)

    def _channels(self, conn: IntArray) -> IntArray:
        if not len(conn):
            return np.zeros(0, np.int64)
        distinct, inverse = np.unique(conn, return_inverse=True)
        table = np.array([self._channel_of.get(c, -1) for c in distinct.tolist()], np.int64)
        return table[inverse.reshape(-1)]

    def _decode_pending(self) -> None:
        """Decode the gathered payloads into columns and let them go."""
        found, self._pending, self._pending_bytes = self._pending, [], 0
        if not found:
            return
        channel = np.concatenate([f.channel for f in found])
        lengths = np.concatenate([f.lengths for f in found])
        bases = np.cumsum([0] + [len(f.payload) for f in found])
        starts = np.concatenate([f.starts + base for f, base in zip(found, bases.tolist(), strict=False)])
        raw = np.frombuffer(b"".join(f.payload for f in found), np.uint8)
        del found
        parts = []
        for first in range(0, len(starts), _SLICE):
            part = decode_tf(raw, starts[first : first + _SLICE], lengths[first : first + _SLICE], self._frames)
            part.message += first
            parts.append(part)
            for message, reason in part.failures:
                index = int(channel[first + message])
                before, first_reason = self._failures.get(index, (0, reason))
                self._failures[index] = (before + 1, first_reason)
        decoded = Decoded.joined(parts)
        self._rows.append(np.bincount(decoded.message, minlength=len(channel)))
        if not len(decoded.message):
            return
        values = decoded.values
        self._columns.add(
            parent=decoded.parent,
            child=decoded.child,
            stamp=decoded.stamp,
            translation=np.ascontiguousarray(values[:, :3]),
            rotation=np.ascontiguousarray(values[:, 3:]),
        )

    def decode(self) -> tuple[list[TransformBatch], ClockSamples, list[str]]:
        """Every transform in record order (as rosbag plays them), in consecutive batches; the
        clock; a line per topic with messages that could not be decoded."""
        self._decode_pending()
        clock = self._clock.samples([c.topic for c in self.channels])
        channel = np.concatenate(self._channel) if self.count else np.zeros(0, np.int64)
        problems = self._problems(self._failures, np.concatenate([channel, self._clock.channels()]))
        if not self.count:
            return [], clock, problems
        time = np.concatenate(self._time)
        rows = np.concatenate(self._rows)
        rank = _rank(time, np.array([c.id for c in self.channels], np.int64)[channel], *self._places())
        if not int(rows.sum()):
            return [], clock, problems
        # Each row's message: the messages' rows are consecutive, in the order decoded.
        message = np.repeat(np.arange(len(rows)), rows)
        order = None if rank is None else np.argsort(rank[message], kind="stable")
        if order is not None:
            message = message[order]
        transforms = [c for c, clock in zip(self.channels, self._is_clock, strict=True) if not clock]
        authorities = list(dict.fromkeys(c.callerid or c.topic for c in transforms))
        authority_of = np.array(
            [
                -1 if clock else authorities.index(c.callerid or c.topic)
                for c, clock in zip(self.channels, self._is_clock, strict=True)
            ],
            np.int32,
        )
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)
        batches = []
        first = 0
        for columns in self._columns.take_parts() if order is None else [self._columns.take_whole(order)]:
            part = message[first : first + len(columns["stamp"])]
            first += len(part)
            batches.append(
                TransformBatch(
                    frame_names=self._frames.names,
                    authorities=authorities,
                    static=static_of[channel[part]],
                    record_time=time[part],
                    authority=authority_of[channel[part]],
                    **columns,
                )
            )
        return batches, clock, problems

    def _places(self) -> tuple[IntArray, IntArray]:
        return np.concatenate(self._chunk), np.concatenate(self._offset)

    def _problems(self, failures: dict[int, tuple[int, str]], channel: IntArray) -> list[str]:
        """One line per topic and type: how many of its messages were lost, and the first reason."""
        totals: dict[tuple[str, str], int] = {}
        for index, count in enumerate(np.bincount(channel, minlength=len(self.channels)).tolist()):
            key = (self.channels[index].topic, self.channels[index].type)
            totals[key] = totals.get(key, 0) + count
        lost: dict[tuple[str, str], tuple[int, str]] = {}
        for index, (count, reason) in sorted(failures.items()):
            key = (self.channels[index].topic, self.channels[index].type)
            before, first = lost.get(key, (0, reason))
            lost[key] = (before + count, first)
        return [
            f"{topic}: {count} of {totals[topic, type_name]} messages could not be decoded as {type_name}, "
            f"skipped (first: {reason})"
            for (topic, type_name), (count, reason) in lost.items()
        ]


def _rank(time: IntArray, conn: IntArray, chunk: IntArray, offset: IntArray) -> IntArray | None:
    """Each message's place in rosbag's playback order, None when they are in it already.

    rosbag merges the connections' indexes by record time: a tie goes to the lower connection
    id, then to the message written first.
    """
    if len(time) < 2:
        return None
    keys = (time, conn, chunk, offset)
    later = np.zeros(len(time) - 1, bool)
    equal = np.ones(len(time) - 1, bool)
    for key in keys:
        step = np.diff(key)
        later |= equal & (step > 0)
        equal &= step == 0
    if later.all():
        return None
    rank = np.empty(len(time), np.int64)
    rank[np.lexsort(keys[::-1])] = np.arange(len(time))
    return rank
