"""The wanted messages of a ROS1 bag as they are found, then decoded into one batch in record order."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import is_static_topic
from tftools.sources.bag.ros1_chunks import IntArray, Located, pieces
from tftools.sources.bag.ros1_decode import Decoded, FrameTable, decode_tf_messages, reference_transforms
from tftools.sources.bag.ros1_format import Buffer, Connection

#: "fast": numpy over many messages at once; "reference": rosbags' deserializer, message by message.
Decoder = Literal["fast", "reference"]

_SLICE = 1 << 16  # messages decoded together: bounds the temporary arrays


@dataclass
class _Found:
    """Wanted messages of one chunk."""

    channel: IntArray
    time: IntArray
    chunk: int  # ordinal of the chunk in the file
    offset: IntArray
    starts: IntArray  # of each message in ``payload``
    lengths: IntArray
    payload: bytes


class MessageCollector:
    """Wanted messages (transform topics) gathered chunk by chunk, undecoded."""

    def __init__(self) -> None:
        self.channels: list[Connection] = []  # the connections read, by channel number
        self._channel_of: dict[int, int] = {}
        self._found: list[_Found] = []
        self.count = 0

    def want(self, connection: Connection) -> None:
        if connection.id not in self._channel_of:
            self._channel_of[connection.id] = len(self.channels)
            self.channels.append(connection)

    def wants(self, conn: int) -> bool:
        return conn in self._channel_of

    def add(self, chunk: int, data: Buffer, located: Located) -> int:
        """Keep the wanted messages among ``located`` (records of ``data``); returns how many."""
        channel = self._channels(located.conn)
        keep = np.flatnonzero(channel >= 0)
        if not len(keep):
            return 0
        starts, lengths = located.data_start[keep], located.data_len[keep]
        if 2 * int(lengths.sum()) >= len(data):  # mostly transforms: keep the chunk whole, copy nothing
            payload = bytes(data)
        else:
            payload = b"".join(pieces(data, starts, lengths))
            starts = np.cumsum(lengths) - lengths
        found = _Found(channel[keep], located.time[keep], chunk, located.offset[keep], starts, lengths, payload)
        self._found.append(found)
        self.count += len(keep)
        return len(keep)

    def _channels(self, conn: IntArray) -> IntArray:
        if not len(conn):
            return np.zeros(0, np.int64)
        distinct, inverse = np.unique(conn, return_inverse=True)
        table = np.array([self._channel_of.get(c, -1) for c in distinct.tolist()], np.int64)
        return table[inverse.reshape(-1)]

    def decode(self, decoder: Decoder) -> tuple[TransformBatch, list[str]]:
        """Every transform in record order (as rosbag plays them); a line per topic with messages
        that could not be decoded."""
        if not self._found:
            return TransformBatch.empty(), []
        found, self._found = self._found, []
        channel = np.concatenate([f.channel for f in found])
        time = np.concatenate([f.time for f in found])
        lengths = np.concatenate([f.lengths for f in found])
        bases = np.cumsum([0] + [len(f.payload) for f in found])
        starts = np.concatenate([f.starts + base for f, base in zip(found, bases.tolist(), strict=False)])
        raw = np.frombuffer(b"".join(f.payload for f in found), np.uint8)
        frames = FrameTable()
        if decoder == "fast":
            decoded, failures = self._fast(raw, starts, lengths, channel, frames)
        else:
            decoded, failures = self._reference(raw, starts, lengths, channel, range(len(channel)), frames)
        chunk = np.concatenate([np.full(len(f.channel), f.chunk, np.int64) for f in found])
        offset = np.concatenate([f.offset for f in found])
        conn = np.array([c.id for c in self.channels], np.int64)[channel]
        batch = self._batch(decoded, channel, time, _rank(time, conn, chunk, offset), frames)
        return batch, self._problems(failures, channel)

    def _fast(
        self, raw: npt.NDArray[np.uint8], starts: IntArray, lengths: IntArray, channel: IntArray, frames: FrameTable
    ) -> tuple[list[Decoded], dict[int, tuple[int, str]]]:
        parts: list[Decoded] = []
        failed: list[IntArray] = []
        for first in range(0, len(starts), _SLICE):
            part = decode_tf_messages(raw, starts[first : first + _SLICE], lengths[first : first + _SLICE], frames)
            part.message += first
            parts.append(part)
            failed.append(part.failed + first)
        # What numpy could not parse, rosbags either parses (then its rows count) or explains.
        again, failures = self._reference(raw, starts, lengths, channel, np.concatenate(failed).tolist(), frames)
        return parts + again, failures

    def _reference(
        self,
        raw: npt.NDArray[np.uint8],
        starts: IntArray,
        lengths: IntArray,
        channel: IntArray,
        messages: range | list[int],
        frames: FrameTable,
    ) -> tuple[list[Decoded], dict[int, tuple[int, str]]]:
        rows: list[tuple[int, int, int, int, tuple[float, ...]]] = []
        failures: dict[int, tuple[int, str]] = {}  # channel -> (count, first reason)
        for index in messages:
            payload = raw[starts[index] : starts[index] + lengths[index]].tobytes()
            type_name = self.channels[channel[index]].type
            try:
                transforms = reference_transforms(payload, type_name)
            except ValueError as e:
                count, reason = failures.get(int(channel[index]), (0, str(e)))
                failures[int(channel[index])] = (count + 1, reason)
                continue
            rows += [(index, frames.id(p), frames.id(c), stamp, values) for p, c, stamp, values in transforms]
        if not rows:
            return [], failures
        message, parent, child, stamp, values = zip(*rows, strict=True)
        decoded = Decoded(
            np.array(message, np.int64),
            np.array(parent, np.int32),
            np.array(child, np.int32),
            np.array(stamp, np.int64),
            np.array(values, np.float64).reshape(-1, 7),
            np.zeros(0, np.int64),
        )
        return [decoded], failures

    def _batch(
        self, parts: list[Decoded], channel: IntArray, time: IntArray, rank: IntArray | None, frames: FrameTable
    ) -> TransformBatch:
        parts = [p for p in parts if len(p.message)]
        if not parts:
            return TransformBatch.empty()
        message = np.concatenate([p.message for p in parts])
        order: IntArray | slice = slice(None)
        if rank is not None or (len(parts) > 1 and np.any(np.diff(message) < 0)):
            order = np.argsort(message if rank is None else rank[message], kind="stable")
        message = message[order]
        values = np.concatenate([p.values for p in parts])[order]
        authorities = list(dict.fromkeys(c.callerid or c.topic for c in self.channels))
        authority_of = np.array([authorities.index(c.callerid or c.topic) for c in self.channels], np.int32)
        static_of = np.array([is_static_topic(c.topic) for c in self.channels], bool)
        row_channel = channel[message]
        return TransformBatch(
            frame_names=frames.names,
            authorities=authorities,
            parent=np.concatenate([p.parent for p in parts])[order],
            child=np.concatenate([p.child for p in parts])[order],
            stamp=np.concatenate([p.stamp for p in parts])[order],
            translation=np.ascontiguousarray(values[:, :3]),
            rotation=np.ascontiguousarray(values[:, 3:]),
            static=static_of[row_channel],
            record_time=time[message],
            authority=authority_of[row_channel],
        )

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
