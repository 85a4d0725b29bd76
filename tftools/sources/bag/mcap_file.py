"""MCAP files: the transforms of their tf and foxglove channels, through the summary's index or record by record."""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

import numpy as np

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback
from tftools.sources.bag.decode import FileScan, MessageSet, Unpack, file_result
from tftools.sources.bag.mcap_records import (
    CHANNEL,
    CHUNK,
    CHUNK_INDEX,
    FOOTER,
    I64,
    MAGIC,
    MESSAGE,
    MESSAGE_HEAD,
    MESSAGE_INDEX,
    RECORD,
    SCHEMA,
    STATISTICS,
    U32,
    U64,
    Body,
    Channels,
    ChunkIndex,
    McapDamageError,
    chunk_records,
    records,
    scan_records,
)
from tftools.sources.bag.mcap_spans import INDEX_ENTRY, IntArray, Queued, SpanReader
from tftools.sources.bag.mcap_stream import UnreadableError, stream
from tftools.sources.bag.ranges import prefetch
from tftools.sources.errors import CorruptBagError

_FOOTER_RECORD = struct.Struct("<BQQQI")  # opcode, length, summary start, summary offset start, crc
_PAYLOAD = RECORD.size + MESSAGE_HEAD.size  # a message's data, from the start of its record
_INDEX_HEAD = struct.Struct("<BQHI")  # a MessageIndex record's opcode, length, channel id, entries' length
_ID_OFFSET = struct.Struct("<HQ")


def read(path: Path, topics: tuple[str, ...], progress: ProgressCallback) -> tuple[list[TransformBatch], BagFileInfo]:
    """The transforms of a bare ``.mcap`` file (see ``reader.read_bag``)."""
    return file_result(path, "mcap", [scan(path, topics, progress)])


def scan(
    path: Path,
    topics: tuple[str, ...],
    progress: ProgressCallback,
    unpack: Unpack | None = None,
) -> FileScan:
    """The transform messages and description of one MCAP file, undecoded.

    Raises ``CorruptBagError`` when nothing could be read; a damaged file is read up to the damage.
    """
    result = FileScan(MessageSet(unpack))
    try:
        with path.open("rb") as f:
            size = path.stat().st_size
            if f.read(len(MAGIC)) != MAGIC:
                raise CorruptBagError(str(path), "no MCAP magic at the start")
            channels = Channels(topics, result, size)
            if not _read_indexed(f, size, channels, progress):
                stream(f, size, channels, result, progress)
    except OSError as e:
        raise CorruptBagError(str(path), e.strerror or str(e)) from None
    except UnreadableError as e:
        raise CorruptBagError(str(path), str(e)) from None
    return result


@dataclass
class _Summary:
    schemas: list[bytes] = field(default_factory=list)
    channels: list[bytes] = field(default_factory=list)
    chunks: list[ChunkIndex] = field(default_factory=list)
    statistics: tuple[int, int, int] | None = None  # message count, start, end


def _read_indexed(f: BinaryIO, size: int, channels: Channels, progress: ProgressCallback) -> bool:
    """Read through the summary; False when it is missing or not enough (then stream instead)."""
    summary = _summary(f, size)
    if summary is None or summary.statistics is None:
        return False
    try:
        for content in summary.schemas:
            channels.register(SCHEMA, content)
        for content in summary.channels:
            channels.register(CHANNEL, content)
    except McapDamageError:
        return False
    count, start, end = summary.statistics
    in_chunks = {c for chunk in summary.chunks for c in chunk.index_offsets}
    if (count and not summary.chunks) or not in_chunks <= channels.known:
        return False  # messages outside chunks, or unindexed
    result = channels.result
    result.message_count, result.start, result.end = count, start, end
    chunks = sorted(summary.chunks, key=lambda c: c.offset)
    lost = _read_chunks(f, chunks, channels, progress, size)
    if lost:
        result.note_problem(
            f"{len(lost)} of {len(chunks)} chunks could not be read ({lost[0]}); their messages are lost"
        )
    return True


def _read_chunks(
    f: BinaryIO, chunks: list[ChunkIndex], channels: Channels, progress: ProgressCallback, size: int
) -> list[str]:
    """The wanted messages of the chunks (in file order): uncompressed ones with unwanted channels
    gathered to be read in ranges, the others read whole. Returns what is wrong with each chunk
    that could not be read."""
    lost: dict[int, str] = {}

    def read_whole(number: int, chunk: ChunkIndex, wanted: list[int], index: bytes | None) -> None:
        try:
            _read_chunk(f, chunk, number, wanted, channels, index)
        except McapDamageError as e:
            lost[number] = str(e)

    def read_queued_whole(queued: Queued) -> None:
        read_whole(queued.number, queued.chunk, _wanted(queued.chunk, channels), queued.index)

    spans = SpanReader(f.fileno(), channels, read_queued_whole)
    indexed = [c for c in chunks if _in_ranges(c, _wanted(c, channels))]
    ends = np.array([c.end for c in indexed], np.int64)
    prefetch(f.fileno(), ends, ends + np.array([c.index_length for c in indexed], np.int64))
    for number, chunk in enumerate(chunks):
        wanted = _wanted(chunk, channels)
        if _in_ranges(chunk, wanted):
            index = _read_at(f, chunk.end, chunk.index_length)
            entries = _message_indexes(index, chunk)
            if entries is not None:
                spans.queue(Queued(number, chunk, index, entries))
            else:
                spans.flush()  # the chunks before first: messages are handed on in file order
                read_whole(number, chunk, wanted, index)
        elif wanted or not chunk.index_offsets:
            spans.flush()
            read_whole(number, chunk, wanted, None)
        if spans.full:
            spans.flush()
        progress(chunk.end, size)
    spans.flush()
    return [lost[number] for number in sorted(lost)]


def _wanted(chunk: ChunkIndex, channels: Channels) -> list[int]:
    return [c for c in chunk.index_offsets if c in channels.wanted]


def _in_ranges(chunk: ChunkIndex, wanted: list[int]) -> bool:
    """Whether the chunk may be read in ranges: uncompressed, with channels wanted and others not."""
    return chunk.compression == "" and 0 < len(wanted) < len(chunk.index_offsets)


def _read_at(f: BinaryIO, offset: int, length: int) -> bytes:
    f.seek(offset)
    return f.read(length)


def _summary(f: BinaryIO, size: int) -> _Summary | None:
    """The summary section, or None without a footer (a cut file) or with a damaged summary."""
    tail = _FOOTER_RECORD.size + len(MAGIC)
    if size < len(MAGIC) + tail:
        return None
    f.seek(size - tail)
    footer = f.read(tail)
    opcode, length, summary_start, _, _ = _FOOTER_RECORD.unpack_from(footer)
    if footer[-len(MAGIC) :] != MAGIC or opcode != FOOTER or length != 20:
        return None
    if not len(MAGIC) <= summary_start <= size - tail:
        return None
    f.seek(summary_start)
    try:
        return _parse_summary(f.read(size - tail - summary_start), size)
    except McapDamageError:
        return None


def _parse_summary(data: bytes, size: int) -> _Summary:
    """The summary's records; ``McapDamageError`` if a chunk index points outside the file (of ``size``
    bytes) or declares more bytes than it holds: it cannot be trusted."""
    summary = _Summary()
    for opcode, start, end in records(data):
        content = data[start:end]
        if opcode == SCHEMA:
            summary.schemas.append(content)
        elif opcode == CHANNEL:
            summary.channels.append(content)
        elif opcode == CHUNK_INDEX:
            chunk = _chunk_index(content)
            index_end = chunk.end + chunk.index_length
            # A chunk may run past the end of a file cut short (it is then lost), but no more than the file holds.
            if not len(MAGIC) <= chunk.offset < size or chunk.length > size or chunk.index_length > size:
                raise McapDamageError("a chunk index points outside the file")
            if any(not chunk.end <= at < index_end for at in chunk.index_offsets.values()):
                raise McapDamageError("a chunk's message indexes are not after it")
            summary.chunks.append(chunk)
        elif opcode == STATISTICS:
            body = Body(content)
            count = body.int(I64)
            body.pos += 2 + 4 * 4  # schema, channel, attachment, metadata and chunk counts
            summary.statistics = (max(0, count), body.int(I64), body.int(I64))
    return summary


def _chunk_index(content: bytes) -> ChunkIndex:
    body = Body(content)
    body.pos += 16  # message start and end times
    offset, length = body.int(U64), body.int(U64)
    entries = body.bytes(U32)
    if len(entries) % _ID_OFFSET.size:
        raise McapDamageError("bad message index offsets")
    offsets = dict(_ID_OFFSET.iter_unpack(entries))
    index_length = body.int(U64)
    compression = body.string()
    return ChunkIndex(offset, length, offsets, index_length, compression, body.int(U64))


def _read_chunk(
    f: BinaryIO, chunk: ChunkIndex, number: int, wanted: list[int], channels: Channels, index: bytes | None
) -> None:
    """The wanted channels' messages of one chunk read whole, found through its message indexes
    (``index``, read here when None) or, in a chunk without them, by walking its records."""
    raw = _read_at(f, chunk.offset, chunk.length)
    opcode, _ = RECORD.unpack_from(raw) if len(raw) >= RECORD.size else (0, 0)
    if opcode != CHUNK:
        raise McapDamageError(f"no chunk at byte {chunk.offset}")
    data = chunk_records(memoryview(raw)[RECORD.size :], partial=False, budget=channels.budget)  # no copy of the chunk
    if not chunk.index_offsets:
        damage = scan_records(data, number, channels, None)
        if damage:
            raise McapDamageError(damage)
        return
    if index is None:
        index = f.read(chunk.index_length)
    found = [_located(data, _message_index(index, chunk.index_offsets[c] - chunk.end), c) for c in wanted]
    if not found:
        return
    targets = np.repeat([channels.wanted[c] for c in wanted], [len(times) for times, *_ in found]).astype(np.int32)
    times, offsets, starts, lengths = (np.concatenate(column) for column in zip(*found, strict=True))
    order = np.argsort(offsets, kind="stable")  # handed on in file order, every channel's at once
    channels.result.messages.add_spans(
        targets[order], times[order], (number << 32) + offsets[order], data, starts[order], lengths[order]
    )


def _message_indexes(index: bytes, chunk: ChunkIndex) -> dict[int, bytes] | None:
    """Every channel's message index entries in the chunk, or None when one is damaged."""
    try:
        return {c: _message_index(index, at - chunk.end) for c, at in chunk.index_offsets.items()}
    except McapDamageError:
        return None


def _message_index(index: bytes, at: int) -> bytes:
    """The entries of the MessageIndex record at ``index[at:]``."""
    if not 0 <= at <= len(index) - _INDEX_HEAD.size:
        raise McapDamageError("bad message index")
    opcode, _, _, length = _INDEX_HEAD.unpack_from(index, at)
    start = at + _INDEX_HEAD.size
    if opcode != MESSAGE_INDEX or length % INDEX_ENTRY.itemsize or start + length > len(index):
        raise McapDamageError("bad message index")
    return index[start : start + length]


def _located(
    data: bytes | memoryview, index_entries: bytes, channel_id: int
) -> tuple[IntArray, IntArray, IntArray, IntArray]:
    """The indexed messages' record times, offsets, payload starts and lengths in the chunk's
    records, the index checked against them."""
    entries = np.frombuffer(index_entries, INDEX_ENTRY)
    offsets = entries["offset"].astype(np.int64)
    raw = np.frombuffer(data, np.uint8)
    if len(offsets) and (offsets.min() < 0 or offsets.max() + _PAYLOAD > len(raw) or (raw[offsets] != MESSAGE).any()):
        raise McapDamageError("message index does not match its chunk")
    head = raw[offsets[:, None] + np.arange(1, 11)]  # record length (8 bytes), channel id (2)
    lengths = head[:, :8].copy().view("<u8").ravel().astype(np.int64) - MESSAGE_HEAD.size
    ids = head[:, 8:].copy().view("<u2").ravel()
    starts = offsets + _PAYLOAD
    if (ids != channel_id).any() or (lengths < 0).any() or (starts + lengths > len(raw)).any():
        raise McapDamageError("message index does not match its chunk")
    return entries["time"].astype(np.int64), offsets, starts, lengths
