"""An MCAP file read through its summary: the chunks holding wanted channels, found by their message indexes."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from tftools.sources.bag.contents import ProgressCallback
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.mcap.ranged import INDEX_ENTRY, Queued, RangedReader, indexed, payloads
from tftools.sources.bag.mcap.records import (
    CHANNEL,
    CHUNK,
    CHUNK_INDEX,
    FOOTER,
    I64,
    MAGIC,
    MESSAGE_INDEX,
    RECORD,
    SCHEMA,
    STATISTICS,
    U32,
    U64,
    Body,
    Channels,
    ChunkIndex,
    Salvaged,
    chunk_records,
    held,
    records,
    scan_records,
)
from tftools.sources.storage.source import ByteSource, FileSource

_FOOTER_RECORD = struct.Struct("<BQQQI")  # opcode, length, summary start, summary offset start, crc
_INDEX_HEAD = struct.Struct("<BQHI")  # a MessageIndex record's opcode, length, channel id, entries' length
_ID_OFFSET = struct.Struct("<HQ")


class Summary:
    """What an MCAP file's summary section says."""

    __slots__ = ("channels", "chunks", "schemas", "statistics")

    def __init__(self) -> None:
        self.schemas: list[bytes] = []
        self.channels: list[bytes] = []
        self.chunks: list[ChunkIndex] = []
        self.statistics: tuple[int, int, int] | None = None  # message count, start, end


def read_indexed(source: ByteSource, summary: Summary | None, channels: Channels, progress: ProgressCallback) -> bool:
    """Read through the ``summary`` (``summary_of``); False when it is missing or not enough, or when not
    one chunk read is where it says (a summary that lies, of another file: then stream instead)."""
    if summary is None or summary.statistics is None:
        return False
    try:
        for content in summary.schemas:
            channels.register(SCHEMA, content)
        for content in summary.channels:
            channels.register(CHANNEL, content)
    except DamageError:
        return False
    count, start, end = summary.statistics
    in_chunks = {c for chunk in summary.chunks for c in chunk.index_offsets}
    if (count and not summary.chunks) or not in_chunks <= channels.known:
        return False  # messages outside chunks, or unindexed
    result = channels.result
    chunks = sorted(summary.chunks, key=lambda c: c.offset)
    salvaged = Salvaged()
    lost, tried, misplaced = _read_chunks(source, chunks, channels, progress, salvaged)
    if tried and misplaced == tried:
        return False
    result.message_count, result.start, result.end = count, start, end
    if lost:
        result.note_problem(
            f"{len(lost)} of {len(chunks)} chunks could not be read ({lost[0]}); their messages are lost"
        )
    if salvaged.chunks:
        result.note_problem(salvaged.line(len(chunks)))
    return True


def _read_chunks(
    source: ByteSource, chunks: list[ChunkIndex], channels: Channels, progress: ProgressCallback, salvaged: Salvaged
) -> tuple[list[str], int, int]:
    """The wanted messages of the chunks (in file order): uncompressed ones with unwanted channels
    gathered to be read in ranges, the others read whole (a damaged one as far as its records still
    parse, noted in ``salvaged``). Returns what is wrong with each chunk that could not be read at all,
    how many were read, and of those how many are not where the summary says."""
    lost: dict[int, str] = {}
    tried = misplaced = 0

    def read_whole(number: int, chunk: ChunkIndex, index: bytes | None) -> None:
        nonlocal misplaced
        try:
            _read_chunk(source, chunk, number, channels, index, salvaged)
        except DamageError as e:
            lost[number] = str(e)
            misplaced += e.offset == chunk.offset
            channels.result.damaged.append((chunk.message_start, chunk.message_end))

    ranged = RangedReader(source, channels, lambda queued: read_whole(queued.number, queued.chunk, queued.index))
    indexed = [c for c in chunks if _in_window(c, channels) and _in_ranges(c, _wanted(c, channels), channels)]
    ends = np.array([c.end for c in indexed], np.int64)
    source.ahead(ends, ends + np.array([c.index_length for c in indexed], np.int64))
    for number, chunk in enumerate(chunks):
        if not _in_window(chunk, channels):
            continue
        wanted = _wanted(chunk, channels)
        tried += bool(wanted) or not chunk.index_offsets
        if _in_ranges(chunk, wanted, channels):
            index = source.read(chunk.end, chunk.end + chunk.index_length)
            try:
                entries = {c: _message_index(index, at - chunk.end) for c, at in chunk.index_offsets.items()}
            except DamageError:  # read whole, its damage is found and told
                ranged.flush()  # the chunks before first: messages are handed on in file order
                read_whole(number, chunk, index)
            else:
                ranged.queue(Queued(number, chunk, index, entries))
        elif wanted or not chunk.index_offsets:
            ranged.flush()
            read_whole(number, chunk, None)
        progress(chunk.end, source.size)
    ranged.flush()
    return [lost[number] for number in sorted(lost)], tried, misplaced


def _in_window(chunk: ChunkIndex, channels: Channels) -> bool:
    """Whether the chunk may hold messages recorded in the window read."""
    return channels.result.messages.may_keep(chunk.message_start, chunk.message_end)


def _wanted(chunk: ChunkIndex, channels: Channels) -> list[int]:
    return [c for c in chunk.index_offsets if c in channels.wanted]


def _in_ranges(chunk: ChunkIndex, wanted: list[int], channels: Channels) -> bool:
    """Whether the chunk may be read in ranges: uncompressed, with channels wanted and others not, or
    some wanted for their messages' headers only."""
    some = 0 < len(wanted) < len(chunk.index_offsets) or any(c in channels.headed for c in wanted)
    return chunk.compression == "" and some


def summary_of(source: ByteSource) -> Summary | None:
    """The summary section; None without a footer (a cut file) or with a damaged summary."""
    size = source.size
    tail = _FOOTER_RECORD.size + len(MAGIC)
    if size < len(MAGIC) + tail:
        return None
    footer = source.read(size - tail, size)
    opcode, length, summary_start, _, _ = _FOOTER_RECORD.unpack_from(footer)
    if footer[-len(MAGIC) :] != MAGIC or opcode != FOOTER or length != 20:
        return None
    if not len(MAGIC) <= summary_start <= size - tail:
        return None
    data = source.read(summary_start, size - tail)
    summary = Summary()
    try:
        for opcode, start, end in records(data):
            content = data[start:end]
            if opcode == SCHEMA:
                summary.schemas.append(content)
            elif opcode == CHANNEL:
                summary.channels.append(content)
            elif opcode == CHUNK_INDEX:
                summary.chunks.append(_chunk_index(content, size))
            elif opcode == STATISTICS:
                body = Body(content)
                count = body.int(I64)
                body.pos += 2 + 4 * 4  # schema, channel, attachment, metadata and chunk counts
                summary.statistics = (max(0, count), held(body.int(U64)), held(body.int(U64)))
    except DamageError:
        return None
    return summary


def chunks_compressed(path: Path) -> bool:
    """Whether the MCAP file at ``path`` compresses its chunks (rosbag2's mcap storage presets, e.g. zstd_fast),
    as its summary's chunk indexes say: False without a summary."""
    with FileSource(path) as source:
        summary = summary_of(source)
    return summary is not None and any(chunk.compression for chunk in summary.chunks)


def _chunk_index(content: bytes, size: int) -> ChunkIndex:
    """A chunk index of a file of ``size`` bytes; ``DamageError`` where it cannot be trusted."""
    body = Body(content)
    message_start, message_end = held(body.int(U64)), held(body.int(U64))
    offset, length = body.int(U64), body.int(U64)
    entries = body.bytes(U32)
    if len(entries) % _ID_OFFSET.size:
        raise DamageError("bad message index offsets")
    offsets = dict(_ID_OFFSET.iter_unpack(entries))
    index_length = body.int(U64)
    compression = body.string()
    chunk = ChunkIndex(offset, length, offsets, index_length, compression, body.int(U64), message_start, message_end)
    # A chunk may run past the end of a file cut short (it is then lost), but no more than the file holds.
    if not len(MAGIC) <= chunk.offset < size or chunk.length > size or chunk.index_length > size:
        raise DamageError("a chunk index points outside the file")
    if any(not chunk.end <= at < chunk.end + chunk.index_length for at in chunk.index_offsets.values()):
        raise DamageError("a chunk's message indexes are not after it")
    return chunk


def _read_chunk(
    source: ByteSource, chunk: ChunkIndex, number: int, channels: Channels, index: bytes | None, salvaged: Salvaged
) -> None:
    """The wanted channels' messages of one chunk read whole, found through its message indexes
    (``index``, read here when None) or, in a chunk without them, by walking its records. A damaged
    chunk (cut short, failing to decompress or its CRC check) gives the messages whose records still
    parse, noted in ``salvaged``; ``DamageError`` when none does."""
    raw = source.read(chunk.offset, chunk.end)
    opcode, _ = RECORD.unpack_from(raw) if len(raw) >= RECORD.size else (0, 0)
    if opcode != CHUNK:
        raise DamageError(f"no chunk at byte {chunk.offset}", chunk.offset)
    data, damage = chunk_records(memoryview(raw)[RECORD.size :], channels.budget)  # no copy of the chunk
    if not chunk.index_offsets:
        _walked(data, number, channels, chunk, damage, salvaged)
        return
    if index is None:
        index = source.read(chunk.end, chunk.end + chunk.index_length)
    try:
        entries = [(number, c, _message_index(index, at - chunk.end)) for c, at in chunk.index_offsets.items()]
    except DamageError as error:  # its index, not its messages: they are found by walking the chunk
        _walked(data, number, channels, chunk, damage, salvaged, str(error))
        return
    every = indexed(entries)
    every = every.rows(np.argsort(every.offset, kind="stable"))  # handed on in file order, every channel's at once
    every.end = np.full(len(every), len(data), np.int64)
    fits = payloads(np.frombuffer(data, np.uint8), every.offset, every, np.ones(len(every), bool))
    if not fits.all():
        damage = damage or "message index does not match its chunk"
    if damage and not fits.any():
        raise DamageError(damage)
    found = every.rows(fits & (every.looked_up(channels.wanted) >= 0))
    channels.result.messages.add_spans(found.looked_up(channels.wanted).astype(np.int32), found, data)
    if damage:
        read = int(np.count_nonzero(fits))
        salvaged.note(damage, read, len(fits) - read)
        if read < len(fits):  # the stretch of the messages lost (a pause there is the file's)
            lost = every.time[~fits]
            channels.result.damaged.append((int(lost.min()), int(lost.max())))


def _walked(
    data: bytes | memoryview,
    number: int,
    channels: Channels,
    chunk: ChunkIndex,
    damage: str,
    salvaged: Salvaged,
    index_damage: str = "",
) -> None:
    """The wanted messages of a chunk without (readable) message indexes, found by walking its records; a
    damaged chunk's, or one whose ``index_damage`` is said, noted in ``salvaged``."""
    walked, read = scan_records(data, number, channels, counted=False)
    if not (damage or walked or index_damage):
        return
    if not read:
        raise DamageError(damage or walked or index_damage)
    lost = damage or walked
    salvaged.note(lost or index_damage, read, None if lost else 0)
    if lost:
        channels.result.damaged.append((chunk.message_start, chunk.message_end))


def _message_index(index: bytes, at: int) -> bytes:
    """The entries of the MessageIndex record at ``index[at:]``."""
    if not 0 <= at <= len(index) - _INDEX_HEAD.size:
        raise DamageError("bad message index")
    opcode, _, _, length = _INDEX_HEAD.unpack_from(index, at)
    start = at + _INDEX_HEAD.size
    if opcode != MESSAGE_INDEX or length % INDEX_ENTRY.itemsize or start + length > len(index):
        raise DamageError("bad message index")
    return index[start : start + length]
