"""``MessageSet``: a file's transform, clock and stamped messages, whatever its format, decoded a few
megabytes at a time."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, UInt8Array
from tftools.core.batch import TransformBatch
from tftools.sources.bag.apart import TfTimes, spread_apart
from tftools.sources.bag.contents import RecordWindow, merged_clock
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.rows import Channel, Column, Rows
from tftools.sources.bag.spans import Spans
from tftools.sources.codecs.decoded import Decoded
from tftools.sources.codecs.select import AnyCodec, ClockCodec, Codec, CopyCodec, HeaderCodec, WholeCodec
from tftools.sources.codecs.wire import HEADER_BYTES, MAX_FRAME_ID, Reason, worded
from tftools.sources.contents import ClockSamples, SentMessages, StampedMessages, WholeMessages

if TYPE_CHECKING:
    from tftools.core._kernels import Spare
    from tftools.sources.codecs.stepped import Started

ChannelIds = int | Int32Array | Sequence[int]
Unpack = Callable[[bytes], bytes]
Failures = list[tuple[int, str]]  # (message, reason) of the messages that could not be decoded

#: Messages read whole held at most per kind (their ``key``: a joint state's names) once thinned: beyond,
#: every other one is let go, so that hours of joint states stay a few megabytes, evenly spread.
MAX_WHOLE = 20_000
#: Characters of text read whole (recorded /robot_description messages, 4 MiB each at most) held at most:
#: only the latest description is used, so past it the earliest read are let go (hundreds of descriptions
#: in a recording were all decoded and held: 2 to 3 GB).
MAX_WHOLE_TEXT = 16 << 20
_GROUP_BYTES = 4 << 20  # payload bytes gathered before they are decoded (and then freed)
_ALONE_BYTES = 512 << 10  # payload bytes of one codec handed at once that are decoded at once, uncopied
#: Rows read from which the buffer's block for them is brought in ahead (``Spare``): ~2 MiB, where it starts
#: on large pages.
_ROOM_FROM_ROWS = 24_000


def _cores() -> int:
    """The cores this process may run on (elsewhere than Linux, not asked: one)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1


def _a_core_free() -> bool:
    """Whether the ``Spare``'s thread would find a core of its own, or one shared with a single other thread, now:
    no more threads running or ready to run on the machine (``/proc/loadavg``'s, this one among them) than the
    cores this process may run on. Where more are, its thread would take the read's turns (a session's threads
    share one group's share of the CPU: ingest_pairs.py at load 4 to 5 on 2 cores, the read 7 ms longer in the
    median, waiting). Elsewhere than Linux, none is made."""
    try:
        with open("/proc/loadavg") as f:
            running = int(f.read().split()[3].split("/")[0])
        return running <= _cores()
    except (OSError, ValueError, IndexError):
        return False


def a_core_aside() -> bool:
    """Whether work may be done on another core than the caller's now, beside it: two cores or more, and one free
    (``_a_core_free``). On one core, or every core taken, a thread would only take the caller's turns."""
    return _cores() >= 2 and _a_core_free()


#: Payloads of one codec added together: their bytes, where each payload begins in them and how
#: long it is, and their message numbers.
_Piece = tuple[bytes, Int64Array, Int64Array, Int64Array]


def _joined(group: list[_Piece]) -> tuple[UInt8Array, Int64Array, Int64Array, Int64Array]:
    """A group's pieces as one: all the bytes, each payload's start and length in them, and its message number."""
    pieces, starts, lengths, ids = zip(*group, strict=True)
    bases = np.cumsum([0] + [len(p) for p in pieces[:-1]])
    at = np.concatenate([s + base for s, base in zip(starts, bases.tolist(), strict=True)])
    raw = np.frombuffer(pieces[0] if len(pieces) == 1 else b"".join(pieces), np.uint8)
    return raw, at, np.concatenate(lengths), np.concatenate(ids)


def _without_long_names(decoded: Decoded, long: dict[int, str]) -> Decoded:
    """``decoded`` less the messages naming a frame of ``long`` (by id: those longer than ``MAX_FRAME_ID``
    characters, damage, not names, as a header's frame_id is, and as a live source drops them), each failed with
    the name's size: every encoding's transforms, so that no command prints a megabyte as a frame."""
    if not long or not len(decoded.message):
        return decoded
    ids = np.array(list(long), np.int32)
    named = np.isin(decoded.parent, ids) | np.isin(decoded.child, ids)
    if not named.any():
        return decoded
    failed: dict[int, int] = {}
    for message, parent, child in zip(
        *(c[named].tolist() for c in (decoded.message, decoded.parent, decoded.child)), strict=True
    ):
        size = max(len(long[i].encode("utf-8", "replace")) for i in (parent, child) if i in long)
        failed[message] = max(failed.get(message, 0), size)
    kept = np.flatnonzero(~np.isin(decoded.message, np.array(list(failed), np.int64)))
    reasons = [(message, worded(Reason.LONG_FRAME_ID, 0, 0, size)) for message, size in failed.items()]
    return Decoded(
        decoded.message[kept], decoded.parent[kept], decoded.child[kept], decoded.stamp[kept],
        decoded.translation[kept], decoded.rotation[kept], sorted(decoded.failures + reasons),
    )  # fmt: skip


class MessageSet:
    """The transform, clock and stamped messages of one file, added in any order; ``decode`` puts them in
    record time order, ties in channel ``tie`` then ``position`` order (their order in the file).

    Payloads are decoded by their codecs a few megabytes at a time as they are added, so that
    a file's payloads are never all held at once; per message only its record time, position
    and channel are kept until ``decode``. With a ``window``, messages recorded outside it are
    left out as they are added.
    """

    def __init__(self, unpack: Unpack | None = None, window: RecordWindow | None = None) -> None:
        self.unpack = unpack  # applied to every payload first, e.g. decompression
        self.window = window
        self.channels: list[Channel] = []
        self._channel_ids: dict[Channel, int] = {}
        self._codecs: list[AnyCodec] = []
        self._codec_of: list[int] = []  # per channel: its codec's number
        #: Per part added: its messages' record times, positions and channels.
        self._messages: list[tuple[Int64Array, Int64Array, Int32Array]] = [
            (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int32))
        ]
        self._groups: dict[int, list[_Piece]] = {}  # by codec
        self._unpack_failed: dict[int, list[str]] = {}
        self._pending_bytes = 0
        self._rows = Rows(self.channels)
        self._failed: Failures = []
        self._long_names: dict[int, str] = {}  # frame names over MAX_FRAME_ID, by id
        self._names_seen = 0  # of the frame names, those looked at for length
        self._clocks: list[tuple[Int64Array, Int64Array]] = []  # message numbers and clock values
        self._headers: list[tuple[Int64Array, Int64Array, Int32Array]] = []  # message numbers, stamps, frames
        #: Of messages that state a transform beside their header (Odometry): message numbers, child frames, poses.
        self._stated: list[tuple[Int64Array, Int32Array, FloatArray]] = []
        self._whole: list[tuple[Int64Array, list[object]]] = []  # message numbers, values
        #: The messages read whole (``Wanted.whole``), per topic in record order, once ``decode`` ran.
        self.whole: list[WholeMessages] = []
        self.count = 0
        self.headers_lost: list[str] = []  # once decoded: a line per topic whose headers were lost
        self.tf_messages: dict[str, tuple[int, int]] = {}  # once decoded: per tf topic, its messages and the empty
        #: once decoded: per tf topic, the publishers of its empty messages (where the file names them) and how many
        self.tf_empty_from: dict[str, dict[str, int]] = {}
        self.sent = SentMessages.empty()  # once decoded: the tf messages that held a transform
        #: once decoded, where its record times lie a year apart (``apart``; else none): per tf channel, its topic,
        #: publisher, and its messages' record times and which were empty, for ``strays`` to count those it leaves out
        self.tf_times: list[TfTimes] = []
        #: Where a format replays messages of one record time in an order of its own (a ROS1 bag, as ``rosbag
        #: play`` does): the positions of its messages, sorted, and each one's place in that order.
        self.replayed: tuple[Int64Array, Int64Array] | None = None
        #: Where the whole file is read (no window: a bulk load's) and another core is free, the buffer's block for
        #: the rows read so far, brought in on another thread as they are read.
        self.room: Spare | None = None
        self._room_asked = False  # whether a core was asked for it (once)
        #: A decode under way on another thread while the next payloads are read (``_started``), and its
        #: messages' numbers; its rows are added and settled before anything else is decoded.
        self._under_way: tuple[Started, Int64Array] | None = None
        self._ahead: bool | None = None  # whether payloads are decoded ahead (``_started``), once asked
        #: Per channel whose codec keeps a few headers (``HeaderCodec.limit``): its limit, and its messages kept.
        self._limits: dict[int, list[int]] = {}

    def emptied(self) -> MessageSet:
        """A set without messages but with the same channels (numbered alike) and unpack."""
        fresh = MessageSet(self.unpack, self.window)
        for c in self.channels:
            fresh.channel(c.topic, c.codec, publisher=c.publisher, tie=c.tie)
        return fresh

    @property
    def full(self) -> bool:
        """Whether every channel keeps only its first few headers (``HeaderCodec.limit``) and has them: the set
        leaves out whatever else the file holds, so its reader may stop there."""
        limits = self._limits.values()
        return len(self._limits) == len(self.channels) > 0 and all(kept >= limit for limit, kept in limits)

    def may_keep(self, start: int, end: int) -> bool:
        """Whether messages recorded from ``start`` to ``end`` (both included) may be kept: a format
        whose index says so of a part of its file reads the part only then."""
        return self.window is None or self.window.overlaps(start, end)

    def channel(self, topic: str, codec: AnyCodec, *, publisher: str = "", tie: int = 0) -> int:
        """The number of the channel ``topic`` decoded with ``codec`` (see ``Channel``), to ``add`` to."""
        key = Channel(topic, codec, publisher, tie)
        if key not in self._channel_ids:
            self._channel_ids[key] = len(self.channels)
            self.channels.append(key)
            if codec not in self._codecs:
                self._codecs.append(codec)
            self._codec_of.append(self._codecs.index(codec))
            if isinstance(codec, HeaderCodec) and codec.limit is not None:
                self._limits[len(self.channels) - 1] = [codec.limit, 0]
            if isinstance(codec, CopyCodec):
                codec.sink.channel(codec.recorded)
        return self._channel_ids[key]

    def add(
        self,
        channel: ChannelIds,
        record_times: Int64Array | Sequence[int],
        positions: Int64Array | Sequence[int],
        payloads: Sequence[bytes | memoryview],
    ) -> None:
        """Messages of one channel (an int) or of several (one channel number per message)."""
        channels = np.broadcast_to(np.asarray(channel, np.int32), (len(payloads),))
        times, where = np.asarray(record_times, np.int64), np.asarray(positions, np.int64)
        if self.unpack is not None:
            payloads, unpacked = self._unpacked(channels, payloads)
            channels, times, where = channels[unpacked], times[unpacked], where[unpacked]
        headed = np.array([isinstance(c, HeaderCodec) for c in self._codecs], bool)[self._codec_of][channels]
        if headed.any():  # of stamped messages, only the bytes that may hold their header are joined
            payloads = [
                memoryview(p)[:HEADER_BYTES] if h else p for p, h in zip(payloads, headed.tolist(), strict=True)
            ]
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
        times: Int64Array,
        where: Int64Array,
        data: bytes | memoryview,
        starts: Int64Array,
        lengths: Int64Array,
    ) -> None:
        """Number the messages (those in the window) and group their payloads by codec; hand those of
        copied channels on as they are."""
        if self.window is not None:
            inside = self.window.holds(times)
            channels, times, where = channels[inside], times[inside], where[inside]
            starts, lengths = starts[inside], lengths[inside]
        if self._limits:  # past a channel's limit, its messages are left out before they are copied
            within = self._within_limits(channels)
            channels, times, where = channels[within], times[within], where[within]
            starts, lengths = starts[within], lengths[within]
        copied = np.array([isinstance(c, CopyCodec) for c in self._codecs], bool)[self._codec_of][channels]
        if copied.any():
            self._hand_on(channels[copied], times[copied], data, starts[copied], lengths[copied])
            kept = ~copied
            channels, times, where, starts, lengths = (a[kept] for a in (channels, times, where, starts, lengths))
        if not len(starts):
            return
        ids = np.arange(self.count, self.count + len(channels), dtype=np.int64)  # the messages' numbers
        self.count += len(channels)
        self._messages.append((times, where, channels.copy()))
        codecs = np.array(self._codec_of, np.int64)[channels]
        if codecs.min() == codecs.max():  # one codec (a bag of tf alone): the messages as they are
            self._group(int(codecs[0]), data, starts, lengths, ids)
        else:
            order = np.argsort(codecs, kind="stable")
            for part in np.split(order, np.flatnonzero(np.diff(codecs[order])) + 1):
                self._group(int(codecs[part[0]]), data, starts[part], lengths[part], ids[part])
        if self._pending_bytes >= _GROUP_BYTES:
            self._decode_groups()

    def _within_limits(self, channels: Int32Array) -> BoolArray:
        """Which of these messages (of ``channels``) are within their channel's limit, counting those kept before."""
        kept = np.ones(len(channels), bool)
        for channel, counts in self._limits.items():
            mine = np.flatnonzero(channels == channel)
            room = max(counts[0] - counts[1], 0)
            kept[mine[room:]] = False
            counts[1] += min(room, len(mine))
        return kept

    def _hand_on(
        self, channels: Int32Array, times: Int64Array, data: bytes | memoryview, starts: Int64Array, lengths: Int64Array
    ) -> None:
        """Each message of a copied channel to its codec's ``take``, its payload a view of ``data``."""
        view = memoryview(data)
        for c, time, s, n in zip(channels.tolist(), times.tolist(), starts.tolist(), lengths.tolist(), strict=True):
            codec = self.channels[c].codec
            assert isinstance(codec, CopyCodec)
            codec.sink.message(codec.recorded, time, view[s : s + n])

    def _group(
        self, codec: int, data: bytes | memoryview, starts: Int64Array, lengths: Int64Array, ids: Int64Array
    ) -> None:
        """Decode the payloads of one codec at once, straight from ``data``, when they are many;
        else copy them out of ``data`` into its group: of stamped messages, only the bytes that may
        hold their header."""
        if isinstance(self._codecs[codec], HeaderCodec):
            lengths = np.minimum(lengths, HEADER_BYTES)
        if int(lengths.sum()) >= _ALONE_BYTES:
            self._decode_groups()  # those added before first: the rows stay in message order
            raw = np.frombuffer(data, np.uint8)
            if not self._started(codec, raw, starts, lengths, ids):
                self._decode(codec, raw, starts, lengths, ids)
                self._settled()
            return
        piece, at = _copied(data, starts, lengths)
        self._groups.setdefault(codec, []).append((piece, at, lengths, ids))
        self._pending_bytes += 2 * len(piece)  # counted twice: decoding takes as much again

    def _unpacked(self, channels: Int32Array, payloads: Sequence[bytes | memoryview]) -> tuple[list[bytes], BoolArray]:
        """The payloads that could be unpacked, and which ones they are; the others are noted."""
        assert self.unpack is not None
        kept: list[bytes] = []
        unpacked = np.ones(len(payloads), bool)
        for i, payload in enumerate(payloads):
            try:
                kept.append(self.unpack(bytes(payload)))  # bytes as they are, not copied
            except Exception as e:  # any decompressor error: this message is lost
                unpacked[i] = False
                reason = str(e) if isinstance(e, DamageError) else f"{type(e).__name__}: {e}"
                self._unpack_failed.setdefault(int(channels[i]), []).append(reason)
        return kept, unpacked

    def _started(self, number: int, raw: UInt8Array, starts: Int64Array, lengths: Int64Array, ids: Int64Array) -> bool:
        """Whether codec ``number``'s payloads were started on another thread (``SteppedDecoder.start``), to be
        finished by the next decode: where the whole file is read (a bulk load's: a window's reads stay as
        they were) on two cores or more, one of them free when first asked, so that decoding them overlaps
        reading the next. On one core, or every core taken, the thread would only take the reader's turns."""
        from tftools.sources.codecs.stepped import SteppedDecoder  # imported already: the codec's module

        codec = self._codecs[number]
        if self.window is not None or not isinstance(codec, Codec) or not isinstance(codec.decode, SteppedDecoder):
            return False
        if self._ahead is None:
            self._ahead = a_core_aside()
        if not self._ahead:
            return False
        self._under_way = codec.decode.start(raw, starts, lengths), ids
        return True

    def _finish_under_way(self) -> None:
        """The rows of the decode under way added and settled, as if decoded when it was started."""
        if self._under_way is not None:
            started, ids = self._under_way
            self._under_way = None
            self._add_decoded(ids, started.finish(self._rows.frames))
            self._settled()

    def _settled(self) -> None:
        self._rows.settle()
        self._room_ahead()

    def _decode_groups(self) -> None:
        """Decode the payloads gathered so far into rows, each codec's at once, and let them go (the decode
        under way first)."""
        self._finish_under_way()
        while self._groups:
            number, group = self._groups.popitem()
            raw, starts, lengths, ids = _joined(group)
            del group  # the pieces let go before decoding
            self._decode(number, raw, starts, lengths, ids)
        self._pending_bytes = 0
        self._settled()

    def _room_ahead(self) -> None:
        """The block for the rows read so far, and a part's ahead, brought in (``room``), where the whole file
        is read and a core was free when the rows were first enough for it."""
        rows = self._rows.held
        if self.room is None:
            if self.window is not None or rows < _ROOM_FROM_ROWS or self._room_asked:
                return
            self._room_asked = True
            if not _a_core_free():
                return
            from tftools.core._kernels import Spare  # a reader of a few transforms does without

            self.room = Spare()
        self.room.ahead(rows)

    def _decode(self, number: int, raw: UInt8Array, starts: Int64Array, lengths: Int64Array, ids: Int64Array) -> None:
        """Decode codec ``number``'s payloads of messages ``ids`` into rows, clock values or headers."""
        codec = self._codecs[number]
        if isinstance(codec, ClockCodec):
            rows, values, failures = codec.decode(raw, starts, lengths)
            self._clocks.append((ids[rows], values))
        elif isinstance(codec, WholeCodec):
            read, objects, failures = codec.decode(raw, starts, lengths)
            self._whole.append((ids[np.array(read, np.int64)], objects))
            if sum(len(part) for _, part in self._whole) > 2 * MAX_WHOLE:
                self._thin_whole()
            if any(isinstance(value, str) for value in objects):
                self._keep_latest_texts()
        elif isinstance(codec, HeaderCodec):
            headers = codec.decode(raw, starts, lengths, self._rows.frames)
            self._headers.append((ids[headers.message], headers.stamp, headers.frame))
            if len(headers.child):
                self._stated.append((ids[headers.message], headers.child, headers.pose))
            failures = headers.failures
        else:
            assert not isinstance(codec, CopyCodec)  # their messages are handed on, never grouped
            self._add_decoded(ids, codec.decode(raw, starts, lengths, self._rows.frames))
            return
        self._failed += [(int(ids[row]), reason) for row, reason in failures]

    def _add_decoded(self, ids: Int64Array, decoded: Decoded) -> None:
        """The rows of messages ``ids`` decoded, and their failures."""
        names = self._rows.frames.names
        self._long_names.update(
            (i, names[i]) for i in range(self._names_seen, len(names)) if len(names[i]) > MAX_FRAME_ID
        )
        self._names_seen = len(names)
        decoded = _without_long_names(decoded, self._long_names)
        self._rows.add_rows(_numbered(ids, decoded.message), decoded)
        self._failed += [(int(ids[row]), reason) for row, reason in decoded.failures]

    def decode(self) -> tuple[list[TransformBatch], ClockSamples, list[StampedMessages], list[str]]:
        """Every transform in record-time order, in consecutive batches; the clock; the headers of
        each topic read so; a line per transform or clock topic with lost messages (and in
        ``headers_lost``, one per topic whose headers were lost)."""
        self._decode_groups()
        times, positions, channel_of = (np.concatenate(column) for column in zip(*self._messages, strict=True))
        self._messages = [(times, positions, channel_of)]  # the parts let go: held once while the rows are made
        rank = _rank(times, self._ties(channel_of, positions), positions)
        self.tf_messages = self._tf_messages(channel_of, times)
        self.sent = self._rows.sent(times, channel_of, rank)
        rows_before = _rows_before(rank, self._rows.runs)
        batches = self._rows.batches(times, channel_of, rank)
        clock, stamped = self._clock(times, channel_of, rank), self._stamped(times, channel_of, rank, rows_before)
        self.whole = self._whole_messages(times, channel_of, rank)
        lines = self._problems(channel_of, rank)
        headed = {c.topic for c in self.channels if isinstance(c.codec, HeaderCodec)}
        self.headers_lost = [line for topic, line in lines if topic in headed]
        return batches, clock, stamped, [line for topic, line in lines if topic not in headed]

    def _ties(self, channel_of: Int32Array, positions: Int64Array) -> Int64Array:
        """What orders each message among those of its record time (``_rank``): its channel's tie, or its place
        in ``rosbag play``'s order (``replayed``)."""
        ties = np.array([c.tie for c in self.channels], np.int64)[channel_of]
        return ties if self.replayed is None else _placed(self.replayed, positions, ties)

    def _tf_messages(self, channel_of: Int32Array, times: Int64Array) -> dict[str, tuple[int, int]]:
        """Per transform topic: its messages, and those decoded that held no transform (an empty TFMessage)."""
        transforms = [i for i, c in enumerate(self.channels) if isinstance(c.codec, Codec)]
        if not transforms:
            return {}
        held = np.zeros(len(channel_of), np.bool_)
        for messages in self._rows.messages_with_rows():
            held[messages] = True
        held[[message for message, _ in self._failed]] = True  # not read: not known to be empty
        counts: dict[str, tuple[int, int]] = {}
        self.tf_empty_from = {}
        apart = spread_apart(times)
        for i in transforms:
            mine = channel_of == i
            topic, publisher, empty = self.channels[i].topic, self.channels[i].publisher, int((mine & ~held).sum())
            if apart:
                self.tf_times.append(TfTimes(topic, publisher, times[mine], ~held[mine]))
            before = counts.get(topic, (0, 0))
            counts[topic] = (before[0] + int(mine.sum()), before[1] + empty)
            if empty and publisher:
                senders = self.tf_empty_from.setdefault(topic, {})
                senders[publisher] = senders.get(publisher, 0) + empty
        return counts

    def _clock(self, times: Int64Array, channel_of: Int32Array, rank: Int64Array) -> ClockSamples:
        """The clock messages read, in record order: ``/clock``'s, else the clock topic's with the most."""
        none = np.zeros(0, np.int64)
        ids, values = _in_record_order(self._clocks or [(none, none)], rank)
        topic_of = np.array([c.topic for c in self.channels], object)[channel_of[ids]]
        topics = dict.fromkeys(topic_of.tolist())
        return merged_clock([ClockSamples(t, times[ids[topic_of == t]], values[topic_of == t]) for t in topics])

    def _stamped(
        self, times: Int64Array, channel_of: Int32Array, rank: Int64Array, rows_before: _RowsBefore
    ) -> list[StampedMessages]:
        """The headers read, per topic in record order (one for every topic read so, even without
        any), their frames ids of every frame name of the file, and the transforms read before each."""
        headed = [c for c in self.channels if isinstance(c.codec, HeaderCodec)]
        none = np.zeros(0, np.int64)
        ids, stamps, frames = _in_record_order(self._headers or [(none, none, none.astype(np.int32))], rank)
        topic_of = np.array([c.topic for c in self.channels], object)[channel_of[ids]]
        stated = _in_record_order(self._stated or [(none, none.astype(np.int32), np.zeros((0, 7)))], rank)
        stated_topic = np.array([c.topic for c in self.channels], object)[channel_of[stated[0]]]
        streams = []
        for topic, type_name in dict((c.topic, c.codec.type_name) for c in headed).items():
            mine = topic_of == topic
            names = self._rows.frames.names
            before = rows_before(rank[ids[mine]])
            stream = StampedMessages(topic, type_name, times[ids[mine]], stamps[mine], frames[mine], names, before)
            theirs = stated_topic == topic
            if theirs.any():  # every message of the topic has its row, in the same record order
                stream = dataclasses.replace(stream, child=stated[1][theirs], pose=stated[2][theirs], child_ids=names)
            streams.append(stream)
        return streams

    def _thin_whole(self) -> None:
        """Of each kind of message read whole with more than ``MAX_WHOLE``, every other one let go until it has
        no more (every 2**k-th kept: the same stride over all that kind's messages, evenly spread)."""
        ids = np.concatenate([i for i, _ in self._whole])
        values = [v for _, part in self._whole for v in part]
        kinds: dict[object, list[int]] = {}
        for k, value in enumerate(values):
            kinds.setdefault(getattr(value, "key", None), []).append(k)
        for kind, members in kinds.items():
            while len(members) > MAX_WHOLE:
                members = members[::2]
            kinds[kind] = members
        kept = sorted(k for members in kinds.values() for k in members)
        self._whole = [(ids[np.array(kept, np.int64)], [values[k] for k in kept])]

    def _keep_latest_texts(self) -> None:
        """The texts read whole, the latest read first, kept while they hold at most ``MAX_WHOLE_TEXT``
        characters (the latest always); the others let go. Messages are numbered as they are read: in
        the file's order, which is the recorder's."""
        ids = np.concatenate([i for i, _ in self._whole])
        values = [v for _, part in self._whole for v in part]
        held, dropped = 0, set()
        for k in np.argsort(ids, kind="stable")[::-1].tolist():
            if isinstance(values[k], str):
                held += len(values[k])
                if held > MAX_WHOLE_TEXT and held > len(values[k]):
                    dropped.add(k)
        if dropped:
            kept = [k for k in range(len(values)) if k not in dropped]
            self._whole = [(ids[np.array(kept, np.int64)], [values[k] for k in kept])]

    def _whole_messages(self, times: Int64Array, channel_of: Int32Array, rank: Int64Array) -> list[WholeMessages]:
        """The messages read whole, per topic in record order."""
        if not self._whole:
            return []
        ids = np.concatenate([i for i, _ in self._whole])
        values = [v for _, part in self._whole for v in part]
        order = np.argsort(rank[ids], kind="stable")
        ids = ids[order]
        topic_of = [self.channels[c].topic for c in channel_of[ids].tolist()]
        found = []
        for channel in dict.fromkeys(c for c in self.channels if isinstance(c.codec, WholeCodec)):
            mine = [k for k, t in enumerate(topic_of) if t == channel.topic]
            kept = [values[int(order[k])] for k in mine]
            found.append(WholeMessages(channel.topic, channel.codec.type_name, times[ids[mine]], kept))
        return found

    def _problems(self, channel_of: Int32Array, rank: Int64Array) -> list[tuple[str, str]]:
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
            (
                topic,
                f"{topic}: {len(reasons)} of {totals[topic, name] + len(reasons)} messages could not be decompressed,"
                f" skipped (first: {reasons[0]})",
            )
            for (topic, name), reasons in packed.items()
        ]
        return lines + [
            (
                topic,
                f"{topic}: {len(undecoded[topic, name])} of {totals[topic, name]} messages could not be decoded as"
                f" {name}, skipped (first: {min(undecoded[topic, name])[1]})",
            )
            for topic, name in totals  # in channel order
            if (topic, name) in undecoded
        ]

    def _topic_and_codec(self, channel: int) -> tuple[str, str]:
        return self.channels[channel].topic, self.channels[channel].codec.name


def _numbered(ids: Int64Array, rows: Int64Array) -> Int64Array:
    """``ids[rows]``, the numbers of the messages ``rows`` index: an addition where ``ids`` are consecutive (the
    messages of one codec handed on at once), not a gather."""
    if len(ids) and int(ids[-1]) - int(ids[0]) == len(ids) - 1 and bool(np.all(ids[1:] > ids[:-1])):
        return rows + int(ids[0])
    return ids[rows]


def _copied(data: bytes | memoryview, starts: Int64Array, lengths: Int64Array) -> tuple[bytes, Int64Array]:
    """The payloads of every length at ``starts``: a copy of ``data`` whole when they are most of
    it, else of them one after the other; and where each begins in it."""
    if 2 * int(lengths.sum()) >= len(data):
        return bytes(data), starts
    view = memoryview(data)
    joined = b"".join([view[s : s + n] for s, n in zip(starts.tolist(), lengths.tolist(), strict=True)])
    return joined, np.cumsum(lengths) - lengths


def _in_record_order(parts: Sequence[tuple[Column, ...]], rank: Int64Array) -> list[Column]:
    """Parts of columns, the first of each the messages' numbers, joined and put in record order."""
    columns = [np.concatenate(column) for column in zip(*parts, strict=True)]
    order = np.argsort(rank[columns[0]], kind="stable")
    return [column[order] for column in columns]


def _placed(replayed: tuple[Int64Array, Int64Array], positions: Int64Array, ties: Int64Array) -> Int64Array:
    """Each message's place in the format's own order (``MessageSet.replayed``); ``ties`` unchanged where
    a message is not in it."""
    known, places = replayed
    if not len(known):
        return ties
    at = np.minimum(np.searchsorted(known, positions), len(known) - 1)
    return np.where(known[at] == positions, places[at], ties)


_RowsBefore = Callable[[Int64Array], Int64Array]


def _rows_before(rank: Int64Array, runs: Sequence[tuple[Int64Array, Int64Array]]) -> _RowsBefore:
    """For messages of ``rank`` s, how many transforms (``Rows.runs``: messages, and their rows) come before
    each in record order: its place among them. Worked out at the first call: only a topic read for its
    headers asks (a recording of tf alone does not, and spares ~3 ms of CPU for 78,001 messages)."""
    runs = list(runs)  # as they are now: the rows' runs are handed on, and emptied, before the first call
    found: list[tuple[Int64Array, Int64Array]] = []

    def counted(of: Int64Array) -> Int64Array:
        if not found:
            messages = np.concatenate([m for m, _ in runs]) if runs else np.zeros(0, np.int64)
            counts = np.concatenate([c for _, c in runs]) if runs else np.zeros(0, np.int64)
            order = np.argsort(rank[messages], kind="stable")
            found.append((rank[messages][order], np.concatenate([[0], np.cumsum(counts[order])]).astype(np.int64)))
        ranks, before = found[0]
        return before[np.searchsorted(ranks, of, side="left")]

    return counted


def _rank(times: Int64Array, ties: Int64Array, positions: Int64Array) -> Int64Array:
    """Each message's place in (record time, tie, position) order."""
    if not len(times):
        return np.zeros(0, np.int64)
    keys = (times, ties, positions)
    later = np.zeros(len(times) - 1, bool)
    equal = np.ones(len(times) - 1, bool)
    for key in keys:  # compared, not subtracted: no int64 steps made (nor overflowed)
        later |= equal & (key[1:] > key[:-1])
        equal &= key[1:] == key[:-1]
    if later.all():
        return np.arange(len(times), dtype=np.int64)
    rank = np.empty(len(times), np.int64)
    rank[np.lexsort(keys[::-1])] = np.arange(len(times))
    return rank
