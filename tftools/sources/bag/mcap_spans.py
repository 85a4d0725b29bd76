"""Uncompressed MCAP chunks read through their message indexes: only the byte ranges of the wanted messages."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.sources.bag.mcap_records import (
    CHUNK,
    MESSAGE,
    MESSAGE_HEAD,
    RECORD,
    U16,
    U32,
    U64,
    Channels,
    ChunkIndex,
)
from tftools.sources.bag.ranges import read_ranges

IntArray = npt.NDArray[np.int64]
INDEX_ENTRY = np.dtype([("time", "<u8"), ("offset", "<u8")])  # of a message, offset in its chunk's records

_BATCH_BYTES = 64 << 20  # of chunks whose wanted ranges are gathered and read together
_SPARSE = 0.5  # the largest share of a chunk's records wanted for it to be read in ranges (else whole)
_PAYLOAD = RECORD.size + MESSAGE_HEAD.size  # a message's data, from the start of its record
_HEAD = RECORD.size + U16.size  # a message record's opcode, length and channel id


@dataclass
class Queued:
    """An uncompressed chunk waiting to be read in ranges."""

    number: int  # its place in the file, which orders its messages
    chunk: ChunkIndex
    index: bytes  # its message index records
    entries: dict[int, bytes]  # the message index entries of every channel in it, by channel id


@dataclass
class _Messages:
    """The indexed messages of a batch of chunks, one row each."""

    chunk: IntArray  # the chunk's place in the batch
    offset: IntArray  # in the chunk's records
    time: IntArray
    channel: IntArray  # MCAP channel id
    target: IntArray  # MessageSet channel, -1 when not wanted
    start: IntArray  # file offset of the record
    end: IntArray  # how far it may reach: the next record indexed, or the end of the chunk's records

    def rows(self, which: npt.NDArray[np.bool_] | IntArray) -> _Messages:
        return _Messages(
            self.chunk[which], self.offset[which], self.time[which], self.channel[which],
            self.target[which], self.start[which], self.end[which],
        )  # fmt: skip


class SpanReader:
    """Uncompressed chunks queued to have their wanted messages read in ranges, a batch at a time.

    A chunk whose wanted messages fill most of it is read whole instead (its CRC checked), and so
    is one whose ranges do not hold what its indexes say: read whole, its damage is found and told.
    A chunk read in ranges is checked against its index and head, not its CRC (that needs it all).
    """

    def __init__(self, fd: int, channels: Channels, read_whole: Callable[[Queued], None]) -> None:
        self.fd = fd
        self.channels = channels
        self.read_whole = read_whole
        self.queued: list[Queued] = []
        self.queued_bytes = 0

    def queue(self, queued: Queued) -> None:
        self.queued.append(queued)
        self.queued_bytes += queued.chunk.length

    @property
    def full(self) -> bool:
        return self.queued_bytes >= _BATCH_BYTES

    def flush(self) -> None:
        """Read the queued chunks, in ranges or whole, their messages handed on in file order (in
        another order the message set would have to sort them all)."""
        batch, self.queued, self.queued_bytes = self.queued, [], 0
        if not batch:
            return
        records_start = np.array([q.chunk.records_start for q in batch], np.int64)
        records_end = records_start + np.array([q.chunk.records_length for q in batch], np.int64)
        messages, whole = _bounded(_indexed(batch, self.channels.wanted), records_start, records_end)
        messages = messages.rows(messages.target >= 0)
        wanted_bytes = np.bincount(messages.chunk, messages.end - messages.start, len(batch))
        whole |= wanted_bytes > _SPARSE * (records_end - records_start)
        messages = messages.rows(~whole[messages.chunk])
        data, where, lengths, damaged = self._read(batch, messages)
        whole |= damaged
        keep = ~whole[messages.chunk]
        self._hand_on(batch, whole, messages.rows(keep), data, where[keep], lengths[keep])

    def _read(
        self, batch: list[Queued], messages: _Messages
    ) -> tuple[npt.NDArray[np.uint8], IntArray, IntArray, npt.NDArray[np.bool_]]:
        """The bytes of the messages' ranges and of their chunks' heads, where each message begins in
        them, its payload's length, and which chunks are damaged."""
        damaged = np.zeros(len(batch), bool)
        if not len(messages.start):
            return np.zeros(0, np.uint8), messages.start, messages.start, damaged
        chunks = np.flatnonzero(np.bincount(messages.chunk, minlength=len(batch)))
        heads = [batch[i].chunk for i in chunks.tolist()]
        starts = np.concatenate([[c.offset for c in heads], messages.start]).astype(np.int64)
        ends = np.concatenate([[c.records_start for c in heads], messages.end]).astype(np.int64)
        data, where, read = read_ranges(self.fd, starts, ends)
        n = len(heads)
        for i, chunk, at, whole in zip(chunks.tolist(), heads, where[:n].tolist(), read[:n].tolist(), strict=True):
            damaged[i] = not whole or not _is_head_of(data, at, chunk)
        where = where[n:]
        lengths, fits = _message_lengths(data, where, messages, read[n:])
        damaged[messages.chunk[~fits]] = True
        return data, where, lengths, damaged

    def _hand_on(
        self,
        batch: list[Queued],
        whole: npt.NDArray[np.bool_],
        messages: _Messages,
        data: npt.NDArray[np.uint8],
        where: IntArray,
        lengths: IntArray,
    ) -> None:
        """Add the messages read in ranges, and have the chunks to be read whole read between them."""
        numbers = np.array([q.number for q in batch], np.int64)
        wholes = np.flatnonzero(whole).tolist()
        ends = [*np.searchsorted(messages.chunk, wholes).tolist(), len(messages.chunk)]
        begin = 0
        for chunk, end in zip([*wholes, None], ends, strict=True):
            if end > begin:
                part = slice(begin, end)
                self.channels.result.messages.add_spans(
                    messages.target[part].astype(np.int32),
                    messages.time[part],
                    (numbers[messages.chunk[part]] << 32) + messages.offset[part],
                    data.data,
                    where[part] + _PAYLOAD,
                    lengths[part],
                )
            if chunk is not None:
                self.read_whole(batch[chunk])
            begin = end


def _indexed(batch: list[Queued], wanted: dict[int, int]) -> _Messages:
    """Every message the batch's indexes list, in no particular order, without file ranges yet."""
    parts: list[bytes] = []
    chunk_of: list[int] = []
    channel_of: list[int] = []
    for i, queued in enumerate(batch):
        for channel_id, part in queued.entries.items():
            parts.append(part)
            chunk_of.append(i)
            channel_of.append(channel_id)
    counts = np.fromiter((len(part) // INDEX_ENTRY.itemsize for part in parts), np.int64, len(parts))
    entries = np.frombuffer(b"".join(parts), INDEX_ENTRY)
    offsets = entries["offset"].astype(np.int64)  # an offset past 2**63 turns negative: caught as outside
    channels = np.array(channel_of, np.int64)
    targets = np.array([wanted.get(c, -1) for c in channel_of], np.int64)
    return _Messages(
        np.repeat(np.array(chunk_of, np.int64), counts), offsets, entries["time"].astype(np.int64),
        np.repeat(channels, counts), np.repeat(targets, counts), offsets, offsets,
    )  # fmt: skip


def _bounded(
    messages: _Messages, records_start: IntArray, records_end: IntArray
) -> tuple[_Messages, npt.NDArray[np.bool_]]:
    """The messages in file order with the file range each may take, and which chunks have an index
    entry outside their records (their messages are left out)."""
    start = records_start[messages.chunk] + messages.offset
    outside = (messages.offset < 0) | (start >= records_end[messages.chunk])
    damaged = np.zeros(len(records_start), bool)
    damaged[messages.chunk[outside]] = True
    order = np.argsort(start, kind="stable")
    order = order[~damaged[messages.chunk[order]]]
    messages = messages.rows(order)
    messages.start = start[order]
    following = np.append(messages.chunk[1:] == messages.chunk[:-1], False)
    messages.end = np.where(following, np.append(messages.start[1:], 0), records_end[messages.chunk])
    return messages, damaged


def _is_head_of(data: npt.NDArray[np.uint8], at: int, chunk: ChunkIndex) -> bool:
    """Whether ``data[at:]`` begins with the chunk record the summary describes."""
    head = data[at : at + chunk.records_start - chunk.offset].tobytes()
    opcode, length = RECORD.unpack_from(head)
    name = chunk.compression.encode()
    fields = U32.pack(len(name)) + name + U64.pack(chunk.records_length)
    return opcode == CHUNK and length == chunk.length - RECORD.size and head.endswith(fields)


def _message_lengths(
    data: npt.NDArray[np.uint8], where: IntArray, messages: _Messages, complete: npt.NDArray[np.bool_]
) -> tuple[IntArray, npt.NDArray[np.bool_]]:
    """The messages' payload lengths, and whether each is a whole message record of its channel
    inside its range."""
    room = messages.end - messages.start
    fits = complete & (room >= _PAYLOAD)
    at = np.where(fits, where, 0)  # a range too short to hold a record head is not looked into
    head = data[at[:, None] + np.arange(_HEAD)]
    opcodes = head[:, 0]
    lengths = head[:, 1:9].copy().view("<u8").ravel().astype(np.int64)
    ids = head[:, 9:].copy().view("<u2").ravel()
    fits &= (opcodes == MESSAGE) & (ids == messages.channel)
    fits &= (lengths >= MESSAGE_HEAD.size) & (lengths <= room - RECORD.size)
    return lengths - MESSAGE_HEAD.size, fits
