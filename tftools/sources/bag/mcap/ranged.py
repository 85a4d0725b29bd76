"""Uncompressed MCAP chunks read through their message indexes: only the byte ranges of the wanted messages."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.core.time import TIME_MAX
from tftools.sources.bag.mcap.records import (
    CHUNK,
    CHUNK_HEAD,
    MESSAGE,
    MESSAGE_HEAD,
    RECORD,
    U16,
    U32,
    U64,
    Channels,
    ChunkIndex,
)
from tftools.sources.bag.spans import Spans, bounded
from tftools.sources.codecs.gather import bytes_at
from tftools.sources.codecs.wire import HEADER_BYTES
from tftools.sources.storage.source import ByteSource

INDEX_ENTRY = np.dtype([("time", "<u8"), ("offset", "<u8")])  # of a message, offset in its chunk's records
PAYLOAD = RECORD.size + MESSAGE_HEAD.size  # a message's data, from the start of its record

_BATCH_BYTES = 64 << 20  # of chunks whose wanted ranges are gathered and read together
_SPARSE = 0.5  # the largest share of a chunk's records wanted for it to be read in ranges (else whole)
_HEAD = RECORD.size + U16.size  # a message record's opcode, length and channel id
_HEADED_BYTES = PAYLOAD + HEADER_BYTES  # of a message read for its header: its record's head and the header
_CRC_AT = CHUNK_HEAD.size - U32.size  # a chunk's CRC in its fields: after its start and end time and size


class Queued:
    """An uncompressed chunk waiting to be read in ranges."""

    __slots__ = ("chunk", "entries", "index", "number")

    def __init__(self, number: int, chunk: ChunkIndex, index: bytes, entries: dict[int, bytes]) -> None:
        self.number = number  # its place in the file, which orders its messages
        self.chunk = chunk
        self.index = index  # its message index records
        self.entries = entries  # the message index entries of every channel in it, by channel id


class RangedReader:
    """Uncompressed chunks queued to have their wanted messages read in ranges, a batch at a time.

    A chunk whose wanted messages fill most of it is read whole instead (its CRC checked), and so
    is one whose ranges do not hold what its indexes say: read whole, its damage is found and told.
    A chunk read in ranges is checked against its index and head; one whose head states a CRC is read
    whole after all, as its CRC covers every byte of it (rosbag2 states none: its chunks stay in ranges).
    """

    def __init__(self, source: ByteSource, channels: Channels, read_whole: Callable[[Queued], None]) -> None:
        self.source = source
        self.channels = channels
        self.read_whole = read_whole
        self.queued: list[Queued] = []
        self.queued_bytes = 0

    def queue(self, queued: Queued) -> None:
        """Queue a chunk; the queue is read when its chunks reach a batch's bytes."""
        self.queued.append(queued)
        self.queued_bytes += queued.chunk.length
        if self.queued_bytes >= _BATCH_BYTES:
            self.flush()

    def flush(self) -> None:
        """Read the queued chunks, in ranges or whole, their messages handed on in file order (in
        another order the message set would have to sort them all)."""
        batch, self.queued, self.queued_bytes = self.queued, [], 0
        if not batch:
            return
        records_start = np.array([q.chunk.records_start for q in batch], np.int64)
        records_end = records_start + np.array([q.chunk.records_length for q in batch], np.int64)
        entries = [(i, channel_id, part) for i, q in enumerate(batch) for channel_id, part in q.entries.items()]
        messages, whole = bounded(indexed(entries), records_start, records_end)
        messages = messages.rows(~whole[messages.chunk] & (messages.looked_up(self.channels.wanted) >= 0))
        # Of messages read for their header, only as far as it reaches: not the image after it.
        cut = np.isin(messages.channel, list(self.channels.headed)) & (messages.end - messages.start > _HEADED_BYTES)
        messages.end[cut] = messages.start[cut] + _HEADED_BYTES
        wanted_bytes = np.bincount(messages.chunk, messages.end - messages.start, len(batch))
        whole |= wanted_bytes > _SPARSE * (records_end - records_start)
        kept = ~whole[messages.chunk]
        messages, cut = messages.rows(kept), cut[kept]
        data, damaged = self._read(batch, messages, cut)
        whole |= damaged  # with those that state a CRC
        self._hand_on(batch, whole, messages.rows(~whole[messages.chunk]), data)

    def _read(self, batch: list[Queued], messages: Spans, cut: BoolArray) -> tuple[UInt8Array, BoolArray]:
        """The bytes of the messages' ranges (those ``cut``, as far as their header reaches) and of
        their chunks' heads, and which chunks are damaged or state a CRC (to be read whole); each
        message's ``start`` and ``end`` made its payload's in those bytes."""
        damaged = np.zeros(len(batch), bool)
        if not len(messages):
            return np.zeros(0, np.uint8), damaged
        chunks = np.flatnonzero(np.bincount(messages.chunk, minlength=len(batch)))
        heads = [batch[i].chunk for i in chunks.tolist()]
        starts = np.concatenate([[c.offset for c in heads], messages.start]).astype(np.int64)
        ends = np.concatenate([[c.records_start for c in heads], messages.end]).astype(np.int64)
        data, where, read = self.source.read_ranges(starts, ends)
        n = len(heads)
        for i, chunk, at, whole in zip(chunks.tolist(), heads, where[:n].tolist(), read[:n].tolist(), strict=True):
            damaged[i] = not whole or not _is_head_of(data, at, chunk) or _states_crc(data, at)
        fits = payloads(data, where[n:], messages, read[n:], cut)
        damaged[messages.chunk[~fits]] = True
        return data, damaged

    def _hand_on(self, batch: list[Queued], whole: BoolArray, messages: Spans, data: UInt8Array) -> None:
        """Add the messages read in ranges, and have the chunks to be read whole read between them."""
        numbers = np.array([q.number for q in batch], np.int64)
        wholes = np.flatnonzero(whole).tolist()
        ends = [*np.searchsorted(messages.chunk, wholes).tolist(), len(messages)]
        begin = 0
        for chunk, end in zip([*wholes, None], ends, strict=True):
            if end > begin:
                part = messages.rows(np.arange(begin, end))
                part.chunk = numbers[part.chunk]
                targets = part.looked_up(self.channels.wanted).astype(np.int32)
                self.channels.result.messages.add_spans(targets, part, data.data)
            if chunk is not None:
                self.read_whole(batch[chunk])
            begin = end


def indexed(entries: list[tuple[int, int, bytes]]) -> Spans:
    """The messages that (chunk, channel id, message index entries) list, without file ranges yet."""
    counts = np.fromiter((len(part) // INDEX_ENTRY.itemsize for _, _, part in entries), np.int64, len(entries))
    table = np.frombuffer(b"".join(part for _, _, part in entries), INDEX_ENTRY)
    offsets = table["offset"].astype(np.int64)  # an offset past 2**63 turns negative: caught as outside
    chunk, channel = (np.repeat(np.array([e[i] for e in entries], np.int64), counts) for i in (0, 1))
    times = np.minimum(table["time"], TIME_MAX).astype(np.int64)  # past 2262: damage, held as TIME_MAX
    return Spans(chunk, offsets, channel, times, offsets, offsets)


def _is_head_of(data: UInt8Array, at: int, chunk: ChunkIndex) -> bool:
    """Whether ``data[at:]`` begins with the chunk record the summary describes."""
    head = data[at : at + chunk.records_start - chunk.offset].tobytes()
    opcode, length = RECORD.unpack_from(head)
    name = chunk.compression.encode()
    fields = U32.pack(len(name)) + name + U64.pack(chunk.records_length)
    return opcode == CHUNK and length == chunk.length - RECORD.size and head.endswith(fields)


def _states_crc(data: UInt8Array, at: int) -> bool:
    """Whether the chunk record at ``data[at:]`` states a CRC of its records (0: none)."""
    return bool(data[at + RECORD.size + _CRC_AT : at + RECORD.size + _CRC_AT + U32.size].any())


def payloads(
    data: UInt8Array, where: Int64Array, messages: Spans, complete: BoolArray, cut: BoolArray | None = None
) -> BoolArray:
    """Whether each message is a whole message record of its channel inside its range (read to
    ``where`` in ``data``; one ``cut``, read for its header, may go on past it); its ``start`` and
    ``end`` made its payload's there."""
    room = messages.end - messages.start
    fits = complete & (where >= 0) & (room >= PAYLOAD)  # else the range cannot hold a record head
    head = bytes_at(data, where[fits], _HEAD)  # a row of _HEAD bytes gathered as one item, not byte by byte
    lengths = np.zeros(len(where), np.int64)
    lengths[fits] = head[:, 1:9].copy().view("<u8").ravel().astype(np.int64)
    fits[fits] = (head[:, 0] == MESSAGE) & (head[:, 9:].copy().view("<u2").ravel() == messages.channel[fits])
    cut = np.zeros(len(where), bool) if cut is None else cut
    fits &= (lengths >= MESSAGE_HEAD.size) & ((lengths <= room - RECORD.size) | cut)
    messages.start = where + PAYLOAD
    messages.end = messages.start + np.minimum(lengths - MESSAGE_HEAD.size, np.where(cut, room - PAYLOAD, lengths))
    return fits
