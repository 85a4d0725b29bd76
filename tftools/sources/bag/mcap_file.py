"""MCAP files: the transforms of their tf and foxglove channels, through the summary's index or record by record."""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

import numpy as np
import numpy.typing as npt

from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo, ProgressCallback
from tftools.sources.bag.decode import Decoder, FileScan, MessageSet, Unpack, file_result
from tftools.sources.bag.mcap_records import (
    CHANNEL,
    CHUNK,
    CHUNK_INDEX,
    FOOTER,
    MAGIC,
    MESSAGE,
    MESSAGE_HEAD,
    MESSAGE_INDEX,
    RECORD,
    SCHEMA,
    STATISTICS,
    U16,
    U32,
    U64,
    Body,
    Channels,
    McapDamageError,
    chunk_records,
    records,
    scan_records,
)
from tftools.sources.bag.mcap_stream import UnreadableError, stream
from tftools.sources.errors import CorruptBagError

_FOOTER_RECORD = struct.Struct("<BQQQI")  # opcode, length, summary start, summary offset start, crc
_PAYLOAD = RECORD.size + MESSAGE_HEAD.size  # a message's data, from the start of its record
_INDEX_ENTRY = np.dtype([("time", "<u8"), ("offset", "<u8")])
_ID_OFFSET = struct.Struct("<HQ")


def read(
    path: Path, topics: tuple[str, ...], progress: ProgressCallback, *, decoder: Decoder = "fast"
) -> tuple[list[TransformBatch], BagFileInfo]:
    """The transforms of a bare ``.mcap`` file (see ``reader.read_bag``)."""
    return file_result(path, "mcap", [scan(path, topics, progress, decoder=decoder)])


def scan(
    path: Path,
    topics: tuple[str, ...],
    progress: ProgressCallback,
    unpack: Unpack | None = None,
    *,
    decoder: Decoder = "fast",
) -> FileScan:
    """The transform messages and description of one MCAP file, undecoded.

    Raises ``CorruptBagError`` when nothing could be read; a damaged file is read up to the damage.
    """
    result = FileScan(MessageSet(unpack, decoder))
    try:
        with path.open("rb") as f:
            size = path.stat().st_size
            if f.read(len(MAGIC)) != MAGIC:
                raise CorruptBagError(str(path), "no MCAP magic at the start")
            channels = Channels(topics, result)
            if not _read_indexed(f, size, channels, progress):
                stream(f, size, channels, result, progress)
    except OSError as e:
        raise CorruptBagError(str(path), e.strerror or str(e)) from None
    except UnreadableError as e:
        raise CorruptBagError(str(path), str(e)) from None
    return result


@dataclass
class _ChunkIndex:
    offset: int
    length: int
    index_offsets: dict[int, int]  # channel id -> file offset of its MessageIndex record
    index_length: int


@dataclass
class _Summary:
    schemas: list[bytes] = field(default_factory=list)
    channels: list[bytes] = field(default_factory=list)
    chunks: list[_ChunkIndex] = field(default_factory=list)
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
    lost: list[str] = []
    chunks = sorted(summary.chunks, key=lambda c: c.offset)
    for number, chunk in enumerate(chunks):
        wanted = [c for c in chunk.index_offsets if c in channels.wanted]
        if wanted or not chunk.index_offsets:
            try:
                _read_chunk(f, chunk, number, wanted, channels)
            except McapDamageError as e:
                lost.append(str(e))
        progress(chunk.offset + chunk.length, size)
    if lost:
        result.note_problem(
            f"{len(lost)} of {len(chunks)} chunks could not be read ({lost[0]}); their messages are lost"
        )
    return True


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
        return _parse_summary(f.read(size - tail - summary_start))
    except McapDamageError:
        return None


def _parse_summary(data: bytes) -> _Summary:
    summary = _Summary()
    for opcode, start, end in records(data):
        content = data[start:end]
        if opcode == SCHEMA:
            summary.schemas.append(content)
        elif opcode == CHANNEL:
            summary.channels.append(content)
        elif opcode == CHUNK_INDEX:
            summary.chunks.append(_chunk_index(content))
        elif opcode == STATISTICS:
            body = Body(content)
            count = body.int(U64)
            body.pos += 2 + 4 * 4  # schema, channel, attachment, metadata and chunk counts
            summary.statistics = (count, body.int(U64), body.int(U64))
    return summary


def _chunk_index(content: bytes) -> _ChunkIndex:
    body = Body(content)
    body.pos += 16  # message start and end times
    offset, length = body.int(U64), body.int(U64)
    entries = body.bytes(U32)
    if len(entries) % _ID_OFFSET.size:
        raise McapDamageError("bad message index offsets")
    offsets = dict(_ID_OFFSET.iter_unpack(entries))
    return _ChunkIndex(offset, length, offsets, body.int(U64))


def _read_chunk(f: BinaryIO, chunk: _ChunkIndex, number: int, wanted: list[int], channels: Channels) -> None:
    """The wanted channels' messages of one chunk, found through its message indexes (or, in a
    chunk without them, by walking its records)."""
    f.seek(chunk.offset)
    raw = f.read(chunk.length)
    opcode, _ = RECORD.unpack_from(raw) if len(raw) >= RECORD.size else (0, 0)
    if opcode != CHUNK:
        raise McapDamageError(f"no chunk at byte {chunk.offset}")
    data = chunk_records(memoryview(raw)[RECORD.size :], partial=False)  # no copy of the chunk
    if not chunk.index_offsets:
        damage = scan_records(data, number, channels, None)
        if damage:
            raise McapDamageError(damage)
        return
    index = f.read(chunk.index_length)
    for channel_id in wanted:
        at = chunk.index_offsets[channel_id] - chunk.offset - chunk.length
        _take_messages(data, _message_index(index, at), number, channel_id, channels)


def _message_index(index: bytes, at: int) -> npt.NDArray[np.void]:
    body = Body(index, at)
    opcode, _ = body.take(RECORD)
    body.int(U16)
    entries = body.bytes(U32)
    if opcode != MESSAGE_INDEX or len(entries) % _INDEX_ENTRY.itemsize:
        raise McapDamageError("bad message index")
    return np.frombuffer(entries, _INDEX_ENTRY)


def _take_messages(
    data: bytes | memoryview, entries: npt.NDArray[np.void], number: int, channel_id: int, channels: Channels
) -> None:
    """Slice the indexed messages' payloads out of the chunk's records, checking the index against them."""
    if not len(entries):
        return
    offsets = entries["offset"].astype(np.int64)
    raw = np.frombuffer(data, np.uint8)
    if offsets.min() < 0 or offsets.max() + _PAYLOAD > len(raw) or (raw[offsets] != MESSAGE).any():
        raise McapDamageError("message index does not match its chunk")
    head = raw[offsets[:, None] + np.arange(1, 11)]  # record length (8 bytes), channel id (2)
    lengths = head[:, :8].copy().view("<u8").ravel().astype(np.int64) - MESSAGE_HEAD.size
    ids = head[:, 8:].copy().view("<u2").ravel()
    starts = offsets + _PAYLOAD
    if (ids != channel_id).any() or (lengths < 0).any() or (starts + lengths > len(raw)).any():
        raise McapDamageError("message index does not match its chunk")
    times = entries["time"].astype(np.int64)
    channels.result.messages.add_spans(
        channels.wanted[channel_id], times, (number << 32) + offsets, data, starts, lengths
    )
