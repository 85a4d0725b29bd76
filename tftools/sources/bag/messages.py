"""``MessageSet``: a file's transform and clock messages, whatever its format, decoded a few megabytes at a time."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from tftools.core.batch import TransformBatch
from tftools.sources.bag.decode.clock import ClockParts
from tftools.sources.bag.decode.codec import ClockCodec, Codec, Decoder
from tftools.sources.bag.decode.template import Block, DecodeError, IntArray, Parser, block_of, decode_group, gathered
from tftools.sources.bag.ros1_decode import decode_tf_messages
from tftools.sources.bag.rows import Channel, Int32Array, Rows
from tftools.sources.bag.spans import Spans
from tftools.sources.contents import ClockSamples

ChannelIds = int | Int32Array | Sequence[int]
Unpack = Callable[[bytes], bytes]
Failures = list[tuple[int, str]]  # (message, reason) of the messages that could not be decoded

_GROUP_BYTES = 4 << 20  # payload bytes gathered before they are decoded (and then freed)
_SLICE = 1 << 16  # messages decoded in step at once: bounds the temporary arrays
_LENGTH_BITS = 40  # a group's key: its codec's number << 40 | its payloads' length
_ANY_LENGTH = (1 << _LENGTH_BITS) - 1  # the length in the key of a group of payloads of every length


@dataclass
class _Group:
    """Payloads of one codec (and one length, unless decoded in step): bytes, where each payload
    begins in them and how long it is, and their message numbers."""

    pieces: list[bytes] = field(default_factory=list)
    starts: list[IntArray] = field(default_factory=list)
    lengths: list[IntArray] = field(default_factory=list)
    ids: list[IntArray] = field(default_factory=list)

    def add(self, piece: bytes, starts: IntArray, lengths: IntArray, ids: IntArray) -> None:
        self.pieces.append(piece)
        self.starts.append(starts)
        self.lengths.append(lengths)
        self.ids.append(ids)

    def joined(self) -> tuple[npt.NDArray[np.uint8], IntArray, IntArray, IntArray]:
        """All the bytes (the pieces let go), each payload's start and length in them, and its
        message number."""
        bases = np.cumsum([0] + [len(p) for p in self.pieces[:-1]])
        starts = np.concatenate([s + base for s, base in zip(self.starts, bases.tolist(), strict=True)])
        raw = np.frombuffer(self.pieces[0] if len(self.pieces) == 1 else b"".join(self.pieces), np.uint8)
        self.pieces.clear()
        return raw, starts, np.concatenate(self.lengths), np.concatenate(self.ids)


def _in_step(codec: Codec | ClockCodec) -> bool:
    """ROS1 TFMessages are decoded in step, every length at once (``ros1_decode``): a template per
    length, as for the other encodings, falls behind where their layouts vary message to message."""
    return isinstance(codec, Codec) and codec.encoding == "ros1"


class MessageSet:
    """The transform and clock messages of one file, added in any order; ``decode`` puts them in
    record time order, ties in channel ``tie`` then ``position`` order (their order in the file).

    Payloads are decoded with ``decoder`` a few megabytes at a time as they are added, so that
    a file's payloads are never all held at once; per message only its record time, position
    and channel are kept until ``decode``.
    """

    def __init__(self, unpack: Unpack | None = None, decoder: Decoder = "fast") -> None:
        self.unpack = unpack  # applied to every payload first, e.g. decompression
        self.decoder = decoder
        self.channels: list[Channel] = []
        self._channel_ids: dict[Channel, int] = {}
        self._codecs: list[Codec | ClockCodec] = []
        self._codec_key: list[int] = []  # per channel: its codec's number << 40, | _ANY_LENGTH if decoded in step
        self._times: list[IntArray] = []
        self._positions: list[IntArray] = []
        self._channel_of: list[Int32Array] = []
        self._groups: dict[int, _Group] = {}
        self._unpack_failed: dict[int, list[str]] = {}
        self._pending_bytes = 0
        self._rows = Rows(self.channels)
        self._failed: Failures = []
        self._clocks: list[tuple[IntArray, IntArray]] = []  # message numbers and clock values
        self.count = 0

    def emptied(self) -> MessageSet:
        """A set without messages but with the same channels (numbered alike), unpack and decoder."""
        fresh = MessageSet(self.unpack, self.decoder)
        for c in self.channels:
            fresh.channel(c.topic, c.codec, publisher=c.publisher, tie=c.tie)
        return fresh

    def channel(self, topic: str, codec: Codec | ClockCodec, *, publisher: str = "", tie: int = 0) -> int:
        """The number of the channel ``topic`` decoded with ``codec`` (see ``Channel``), to ``add``
        messages to."""
        key = Channel(topic, codec, publisher, tie)
        if key not in self._channel_ids:
            self._channel_ids[key] = len(self.channels)
            self.channels.append(key)
            if codec not in self._codecs:
                self._codecs.append(codec)
            step = _ANY_LENGTH if _in_step(codec) else 0
            self._codec_key.append(self._codecs.index(codec) << _LENGTH_BITS | step)
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

    def add_spans(self, channel: ChannelIds, spans: Spans, data: bytes | memoryview) -> None:
        """``add`` of the payloads ``data[spans.start[i] : spans.end[i]]``, of one channel (an int)
        or of several (one channel number per message), copied out in bulk rather than one by one."""
        lengths = spans.end - spans.start
        if self.unpack is not None:
            view = memoryview(data)
            pieces = [view[s : s + n] for s, n in zip(spans.start.tolist(), lengths.tolist(), strict=True)]
            self.add(channel, spans.time, spans.position, pieces)
            return
        channels = np.broadcast_to(np.asarray(channel, np.int32), (len(spans),))
        self._add_joined(channels, spans.time, spans.position, data, spans.start, lengths)

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
        keys = np.array(self._codec_key, np.int64)[channels]
        keys = np.where(keys & _ANY_LENGTH, keys, keys | lengths)
        order = np.argsort(keys, kind="stable")
        for part in np.split(order, np.flatnonzero(np.diff(keys[order])) + 1):
            self._group(int(keys[part[0]]), data, starts[part], lengths[part], ids[part])
        if self._pending_bytes >= _GROUP_BYTES:
            self._decode_groups()

    def _group(self, key: int, data: bytes | memoryview, starts: IntArray, lengths: IntArray, ids: IntArray) -> None:
        """Copy the payloads of one group out of ``data``, into that group."""
        length = key & _ANY_LENGTH
        if length == _ANY_LENGTH:
            piece, at = _copied(data, starts, lengths)
            self._pending_bytes += len(piece)  # counted twice: decoding in step takes as much again
        else:
            piece, at = gathered(np.frombuffer(data, np.uint8), starts, length).tobytes(), length * np.arange(len(ids))
        self._groups.setdefault(key, _Group()).add(piece, at, lengths, ids)
        self._pending_bytes += len(piece)

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

    def _decode_groups(self) -> None:
        """Decode the payloads gathered so far into rows, and let them go."""
        while self._groups:
            key, group = self._groups.popitem()
            codec, length = self._codecs[key >> _LENGTH_BITS], key & _ANY_LENGTH
            raw, starts, lengths, ids = group.joined()
            del group
            if isinstance(codec, ClockCodec):
                rows, values, failures = codec.decode(raw.reshape(len(ids), length))
                self._clocks.append((ids[rows], values))
            elif length == _ANY_LENGTH:
                failures = self._decode_in_step(raw, starts, lengths, ids, codec)
            elif self.decoder == "fast" and codec.templated:
                blocks, failures = decode_group(raw.reshape(len(ids), length), codec.parse)
                self._add_blocks(ids, blocks)
            else:
                failures = self._one_by_one(raw, starts, lengths, ids, range(len(ids)), codec)
            self._failed += [(int(ids[row]), reason) for row, reason in failures]
        self._rows.settle()
        self._pending_bytes = 0

    def _decode_in_step(
        self, raw: npt.NDArray[np.uint8], starts: IntArray, lengths: IntArray, ids: IntArray, codec: Codec
    ) -> Failures:
        """Payloads of every length decoded in step, those it cannot parse exactly left to the
        reference parser (which reads them, or says why not); one by one unless ``fast``."""
        if self.decoder != "fast":
            return self._one_by_one(raw, starts, lengths, ids, range(len(ids)), codec)
        failed = []
        for first in range(0, len(ids), _SLICE):
            part = slice(first, first + _SLICE)
            decoded = decode_tf_messages(raw, starts[part], lengths[part], self._rows.frames)
            self._rows.add_rows(
                ids[part][decoded.message], decoded.parent, decoded.child, decoded.stamp, decoded.values
            )
            failed.append(decoded.failed + first)
        return self._one_by_one(raw, starts, lengths, ids, np.concatenate(failed).tolist(), codec, codec.reference)

    def _one_by_one(
        self,
        raw: npt.NDArray[np.uint8],
        starts: IntArray,
        lengths: IntArray,
        ids: IntArray,
        rows: Sequence[int],
        codec: Codec,
        parse: Parser | None = None,
    ) -> Failures:
        """The payloads ``rows`` parsed in Python, by ``parse`` or else the decoder's parser."""
        blocks: list[Block] = []
        failures: Failures = []
        parse = parse or codec.parser(self.decoder)
        for row in rows:
            start = int(starts[row])
            try:
                blocks.append(block_of(row, parse(raw[start : start + int(lengths[row])].tobytes())))
            except DecodeError as e:
                failures.append((row, str(e)))
        self._add_blocks(ids, blocks)
        return failures

    def _add_blocks(self, ids: IntArray, blocks: list[Block]) -> None:
        for block in blocks:
            self._rows.add(ids[block.rows], block)

    def decode(self) -> tuple[list[TransformBatch], ClockSamples, list[str]]:
        """Every transform in record-time order, in consecutive batches; the clock; a line per
        topic with lost messages."""
        self._decode_groups()
        times = np.concatenate(self._times) if self.count else np.zeros(0, np.int64)
        channel_of = np.concatenate(self._channel_of) if self.count else np.zeros(0, np.int32)
        ties = np.array([c.tie for c in self.channels], np.int64)[channel_of]
        rank = _rank(times, ties, np.concatenate(self._positions) if self.count else times)
        clock = ClockParts()
        for ids, values in self._clocks:
            clock.add(channel_of[ids], times[ids], rank[ids], values)
        topics = [c.topic for c in self.channels]
        batches = self._rows.batches(times, channel_of, rank)
        return batches, clock.samples(topics), self._problems(channel_of, rank)

    def _problems(self, channel_of: Int32Array, rank: IntArray) -> list[str]:
        """A line per topic and codec with messages that could not be decompressed, and one with
        messages that could not be decoded (its first in record order named)."""
        totals: dict[tuple[str, str], int] = {}
        for index, count in enumerate(np.bincount(channel_of, minlength=len(self.channels)).tolist()):
            key = self._topic_and_codec(index)
            totals[key] = totals.get(key, 0) + count
        packed: dict[tuple[str, str], list[str]] = {}
        for index, reasons in sorted(self._unpack_failed.items()):
            packed.setdefault(self._topic_and_codec(index), []).extend(reasons)
        undecoded: dict[tuple[str, str], list[tuple[int, str]]] = {}
        for message, reason in self._failed:
            key = self._topic_and_codec(int(channel_of[message]))
            undecoded.setdefault(key, []).append((int(rank[message]), reason))
        lines = [
            f"{topic}: {len(reasons)} of {totals[topic, name] + len(reasons)} messages could not be decompressed,"
            f" skipped (first: {reasons[0]})"
            for (topic, name), reasons in packed.items()
        ]
        return lines + [
            f"{topic}: {len(undecoded[topic, name])} of {totals[topic, name]} messages could not be decoded as"
            f" {name}, skipped (first: {min(undecoded[topic, name])[1]})"
            for topic, name in totals  # in channel order
            if (topic, name) in undecoded
        ]

    def _topic_and_codec(self, channel: int) -> tuple[str, str]:
        return self.channels[channel].topic, self.channels[channel].codec.name


def _copied(data: bytes | memoryview, starts: IntArray, lengths: IntArray) -> tuple[bytes, IntArray]:
    """The payloads of every length at ``starts``: a copy of ``data`` whole when they are most of
    it, else of them one after the other; and where each begins in it."""
    if 2 * int(lengths.sum()) >= len(data):
        return bytes(data), starts
    view = memoryview(data)
    joined = b"".join([view[s : s + n] for s, n in zip(starts.tolist(), lengths.tolist(), strict=True)])
    return joined, np.cumsum(lengths) - lengths


def _rank(times: IntArray, ties: IntArray, positions: IntArray) -> IntArray:
    """Each message's place in (record time, tie, position) order."""
    if not len(times):
        return np.zeros(0, np.int64)
    keys = (times, ties, positions)
    later = np.zeros(len(times) - 1, bool)
    equal = np.ones(len(times) - 1, bool)
    for key in keys:
        step = np.diff(key)
        later |= equal & (step > 0)
        equal &= step == 0
    if later.all():
        return np.arange(len(times), dtype=np.int64)
    rank = np.empty(len(times), np.int64)
    rank[np.lexsort(keys[::-1])] = np.arange(len(times))
    return rank
