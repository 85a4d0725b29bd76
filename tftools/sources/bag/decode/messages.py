"""Transform (and clock) messages of a file, grouped by codec and length, decoded a few megabytes at a time."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import Int64Array as IntArray
from tftools.core.arrays import UInt8Array
from tftools.core.batch import TransformBatch
from tftools.sources.bag.decode.clock import ClockParts
from tftools.sources.bag.decode.rows import Channel, Rows
from tftools.sources.codecs.decoded import gathered
from tftools.sources.codecs.select import ClockCodec, Codec
from tftools.sources.contents import ClockSamples

Int32Array = npt.NDArray[np.int32]
ChannelIds = int | Int32Array | Sequence[int]
Unpack = Callable[[bytes], bytes]

_GROUP_BYTES = 4 << 20  # payload bytes gathered before they are decoded (and then freed)
_LENGTH_MASK = (1 << 40) - 1  # a group's key: its codec's number << 40 | its payloads' length


@dataclass
class _Group:
    """Payloads of one codec, gathered length by length: concatenated bytes, and their message numbers."""

    pieces: list[bytes] = field(default_factory=list)
    lengths: list[IntArray] = field(default_factory=list)
    ids: list[IntArray] = field(default_factory=list)

    def payloads(self) -> tuple[UInt8Array, IntArray, IntArray, IntArray]:
        """The bytes, and each payload's start and length in them and message number, in message order."""
        lengths, ids = np.concatenate(self.lengths), np.concatenate(self.ids)
        raw = np.frombuffer(b"".join(self.pieces), np.uint8)
        self.pieces.clear()
        order = np.argsort(ids, kind="stable")
        return raw, (np.cumsum(lengths) - lengths)[order], lengths[order], ids[order]


class MessageSet:
    """The transform and clock messages of one file, added in any order; ``decode`` puts them in
    record time order, ties in ``position`` order (their order in the file).

    Payloads are decoded a few megabytes at a time as they are added, so that
    a file's payloads are never all held at once; per message only its record time, position
    and channel are kept until ``decode``.
    """

    def __init__(self, unpack: Unpack | None = None) -> None:
        self.unpack = unpack  # applied to every payload first, e.g. decompression
        self.channels: list[Channel] = []
        self._channel_ids: dict[Channel, int] = {}
        self._codecs: list[Codec | ClockCodec] = []
        self._codec_of: list[int] = []  # per channel
        self._times: list[IntArray] = []
        self._positions: list[IntArray] = []
        self._channel_of: list[Int32Array] = []
        self._groups: dict[Codec | ClockCodec, _Group] = {}
        self._unpack_failed: dict[int, list[str]] = {}
        self._pending_bytes = 0
        self._rows = Rows(self.channels)
        self._failed: list[tuple[int, str]] = []  # (message, reason) of the undecodable ones
        self._clocks: list[tuple[IntArray, IntArray]] = []  # message numbers and clock values
        self.count = 0

    def __len__(self) -> int:
        return self.count

    def emptied(self) -> MessageSet:
        """A set without messages but with the same channels (numbered alike) and unpack."""
        fresh = MessageSet(self.unpack)
        for channel in self.channels:
            fresh.channel(channel.topic, channel.codec)
        return fresh

    def channel(self, topic: str, codec: Codec | ClockCodec) -> int:
        """The number of the channel ``topic`` decoded with ``codec``, to ``add`` messages to."""
        key = Channel(topic, codec)
        if key not in self._channel_ids:
            self._channel_ids[key] = len(self.channels)
            self.channels.append(key)
            if codec not in self._codecs:
                self._codecs.append(codec)
            self._codec_of.append(self._codecs.index(codec))
        return self._channel_ids[key]

    def add(
        self,
        channel: ChannelIds,
        record_times: IntArray | Sequence[int],
        positions: IntArray | Sequence[int],
        payloads: Sequence[bytes | memoryview],
    ) -> None:
        """Messages of one channel (an int) or of several (one channel number per message)."""
        channels = np.broadcast_to(np.asarray(channel, np.int32), (len(payloads),))
        times, where = np.asarray(record_times, np.int64), np.asarray(positions, np.int64)
        if self.unpack is not None:
            payloads, unpacked = self._unpacked(channels, payloads)
            channels, times, where = channels[unpacked], times[unpacked], where[unpacked]
        lengths = np.fromiter(map(len, payloads), np.int64, len(payloads))
        self._add_joined(channels, times, where, b"".join(payloads), np.cumsum(lengths) - lengths, lengths)

    def add_spans(
        self,
        channel: ChannelIds,
        record_times: IntArray,
        positions: IntArray,
        data: bytes | memoryview,
        starts: IntArray,
        lengths: IntArray,
    ) -> None:
        """``add`` of the payloads ``data[starts[i] : starts[i] + lengths[i]]``, of one channel (an
        int) or of several (one channel number per message), copied out length by length in bulk
        rather than sliced one by one."""
        if self.unpack is not None:
            view = memoryview(data)
            pieces = [view[s : s + n] for s, n in zip(starts.tolist(), lengths.tolist(), strict=True)]
            self.add(channel, record_times, positions, pieces)
            return
        channels = np.broadcast_to(np.asarray(channel, np.int32), (len(starts),))
        times, where = np.asarray(record_times, np.int64), np.asarray(positions, np.int64)
        self._add_joined(channels, times, where, data, starts, lengths)

    def _add_joined(
        self,
        channels: Int32Array,
        times: IntArray,
        where: IntArray,
        data: bytes | memoryview,
        starts: IntArray,
        lengths: IntArray,
    ) -> None:
        """Group the payloads ``data[starts[i] : starts[i] + lengths[i]]`` by codec and length."""
        if not len(starts):
            return
        ids = self._numbered(channels, times, where)
        raw = np.frombuffer(data, np.uint8)
        keys = (np.array(self._codec_of, np.int64)[channels] << 40) | lengths
        order = np.argsort(keys, kind="stable")
        for part in np.split(order, np.flatnonzero(np.diff(keys[order])) + 1):
            key = int(keys[part[0]])
            self._group(key, gathered(raw, starts[part], key & _LENGTH_MASK).tobytes(), ids[part])
        if self._pending_bytes >= _GROUP_BYTES:
            self._decode_groups()

    def _numbered(self, channels: Int32Array, times: IntArray, where: IntArray) -> IntArray:
        """Note the messages' channels, record times and positions; their message numbers."""
        n = len(channels)
        ids = np.arange(self.count, self.count + n, dtype=np.int64)
        self._times.append(times)
        self._positions.append(where)
        self._channel_of.append(channels.copy())
        self.count += n
        return ids

    def _unpacked(
        self, channels: Int32Array, payloads: Sequence[bytes | memoryview]
    ) -> tuple[list[bytes], npt.NDArray[np.bool_]]:
        """The payloads that could be unpacked, and which ones they are; the others are noted."""
        assert self.unpack is not None
        kept: list[bytes] = []
        unpacked = np.ones(len(payloads), bool)
        for i, payload in enumerate(payloads):
            try:
                kept.append(self.unpack(bytes(payload)))  # bytes as they are, not copied
            except Exception as e:  # any decompressor error: this message is lost
                unpacked[i] = False
                self._unpack_failed.setdefault(int(channels[i]), []).append(f"{type(e).__name__}: {e}")
        return kept, unpacked

    def _group(self, key: int, joined: bytes, ids: IntArray) -> None:
        codec, length = self._codecs[key >> 40], key & _LENGTH_MASK
        group = self._groups.setdefault(codec, _Group())
        group.pieces.append(joined)
        group.lengths.append(np.full(len(ids), length, np.int64))
        group.ids.append(ids)
        self._pending_bytes += len(joined)

    def _decode_groups(self) -> None:
        """Decode the payloads gathered so far into rows, each codec's at once, and let them go."""
        while self._groups:
            codec, group = self._groups.popitem()
            raw, starts, lengths, ids = group.payloads()
            if isinstance(codec, ClockCodec):
                rows, values, failures = codec.decode(raw, starts, lengths)
                self._clocks.append((ids[rows], values))
            else:
                decoded = codec.decode(raw, starts, lengths, self._rows.frames)
                self._rows.add(ids[decoded.message], decoded)
                failures = decoded.failures
            self._failed += [(int(ids[row]), reason) for row, reason in failures]
        self._rows.settle()
        self._pending_bytes = 0

    def decode(self) -> tuple[list[TransformBatch], ClockSamples, list[str]]:
        """Every transform in record-time order, in consecutive batches; the clock; a line per
        channel with lost messages."""
        self._decode_groups()
        times = np.concatenate(self._times) if self.count else np.zeros(0, np.int64)
        channel_of = np.concatenate(self._channel_of) if self.count else np.zeros(0, np.int32)
        rank = _rank(times, self._positions)
        failed: dict[int, list[tuple[int, str]]] = {}  # channel -> (rank, reason) of its undecodable messages
        for message, reason in self._failed:
            failed.setdefault(int(channel_of[message]), []).append((int(rank[message]), reason))
        clock = ClockParts()
        for ids, values in self._clocks:
            clock.add(channel_of[ids], times[ids], rank[ids], values)
        topics = [c.topic for c in self.channels]
        return self._rows.batches(times, channel_of, rank), clock.samples(topics), self._problems(failed, channel_of)

    def _problems(self, failed: dict[int, list[tuple[int, str]]], channel_of: Int32Array) -> list[str]:
        totals = np.bincount(channel_of, minlength=len(self.channels))
        lines = [
            f"{self.channels[index].topic}: {len(reasons)} of {totals[index] + len(reasons)} messages could not be"
            f" decompressed, skipped (first: {reasons[0]})"
            for index, reasons in sorted(self._unpack_failed.items())
        ]
        for index, reasons in sorted(failed.items()):
            channel = self.channels[index]
            lines.append(
                f"{channel.topic}: {len(reasons)} of {totals[index]} messages could not be decoded "
                f"as {channel.codec.name}, skipped (first: {min(reasons)[1]})"
            )
        return lines


def _rank(times: IntArray, positions: list[IntArray]) -> IntArray:
    """Each message's place in (record time, position) order."""
    if not len(times):
        return np.zeros(0, np.int64)
    where = np.concatenate(positions)
    step, after = np.diff(times), np.diff(where)
    if np.all((step > 0) | ((step == 0) & (after > 0))):
        return np.arange(len(times), dtype=np.int64)
    rank = np.empty(len(times), np.int64)
    rank[np.lexsort((where, times))] = np.arange(len(times))
    return rank
