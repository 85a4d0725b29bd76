"""A ROS1 bag read by its index: only the chunks holding wanted messages, and of uncompressed ones
only the wanted records.

A chunk's index records give the offset of every message in it, of every connection, so a
wanted record ends at the next offset (or at the chunk's end) and only those bytes need reading.
Records close together are read as one run (``ranges``): a chunk of transforms only is read
whole, one whose bulk is camera images costs little more than its transforms.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import BoolArray, Int64Array
from tftools.core.time import NS_PER_S
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.ros1.chunks import in_chunk, locate, walk
from tftools.sources.bag.ros1.file import BagFile
from tftools.sources.bag.ros1.records import (
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_INDEX,
    BagHeader,
    Chunk,
    ChunkInfo,
    Connection,
    Record,
    index_entries,
    read_chunk,
    read_chunk_info,
    read_connection,
)
from tftools.sources.bag.ros1.view import MAX_MESSAGES, view_order
from tftools.sources.bag.spans import Spans, bounded
from tftools.sources.bag.unpack import CompressionUnavailableError
from tftools.sources.codecs.gather import among, distinct
from tftools.sources.codecs.wire import HEADER_BYTES

#: Records of uncompressed chunks are gathered until there are this many, or their chunks hold
#: this many bytes, then read (a few megabytes of transforms; the cap bounds a batch of huge ones).
_SPAN_RECORDS, _SPAN_BYTES = 8192, 64 << 20
#: Bytes of a chunk record's header, at most, and of an index data record: a header, and 12 per message.
_CHUNK_HEADER_BYTES, _INDEX_RECORD_BYTES, _INDEX_ENTRY_BYTES = 4096, 128, 12
#: Bytes of a message record read for its message's header: its record header (a few dozen bytes of
#: op, conn and time; more is read whole) and the bytes that may hold the message's header.
_HEADED_BYTES = 256 + HEADER_BYTES


class BagIndex:
    """The connections and chunk infos (in file order) at a bag's end."""

    __slots__ = ("connections", "infos")

    def __init__(self, connections: list[Connection], infos: list[ChunkInfo]) -> None:
        self.connections = connections
        self.infos = infos


def read_index(bag: BagFile, header: BagHeader) -> BagIndex:
    """The connections and chunk infos at the bag's end; ``DamageError`` if damaged."""
    pos = header.index_pos
    bag.source.ahead(np.array([pos], np.int64), np.array([bag.size], np.int64))
    records = []
    for op, count in ((OP_CONNECTION, header.conn_count), (OP_CHUNK_INFO, header.chunk_count)):
        for _ in range(count):
            records.append(_record(bag, pos, op))
            pos = records[-1].data_end
    connections = [read_connection(bag.buf, r) for r in records[: header.conn_count]]
    infos = [read_chunk_info(bag.buf, r) for r in records[header.conn_count :]]
    return BagIndex(connections, sorted(infos, key=lambda info: info.pos))


def read_indexed(bag: BagFile, index: BagIndex, index_pos: int) -> None:
    """The wanted messages of the chunks the index describes (its connections met first)."""
    for connection in index.connections:
        bag.connect(connection)
    infos = index.infos
    counted = [info for info in infos if info.counts]
    scan = bag.scan
    scan.message_count = sum(sum(info.counts.values()) for info in counted)
    scan.start = min((info.start for info in counted), default=0)
    scan.end = max((info.end for info in counted), default=0)
    _prefetch(bag, infos, index_pos)
    gathered = _Gathered()
    for ordinal, info in enumerate(infos):
        wanted = _wanted_count(bag, info)
        if wanted:
            _read_chunk(bag, gathered, ordinal, info, wanted)
            bag.progress(min(info.pos, bag.size), bag.size)
    gathered.read(bag)


def _prefetch(bag: BagFile, infos: list[ChunkInfo], index_pos: int, every: bool = False) -> None:
    """Have the system fetch the headers and index records of the chunks holding wanted messages (with
    ``every``, of every chunk) all at once (one by one, each would wait for the disk or a remote store). A
    chunk's index records end where the next chunk (or the bag's index) begins, about ``_INDEX_ENTRY_BYTES``
    a message before it."""
    if not infos:
        return
    ends = [*(info.pos for info in infos[1:]), index_pos]
    starts: list[int] = []
    stops: list[int] = []
    for info, end in zip(infos, ends, strict=True):
        if every or _wanted_count(bag, info):
            index_bytes = sum(_INDEX_RECORD_BYTES + _INDEX_ENTRY_BYTES * n for n in info.counts.values())
            starts += [info.pos, max(info.pos, end - index_bytes)]
            stops += [info.pos + _CHUNK_HEADER_BYTES, end]
    bag.source.ahead(np.array(starts, np.int64), np.array(stops, np.int64))


def _wanted_count(bag: BagFile, info: ChunkInfo) -> int:
    """The wanted messages of a chunk, as its info counts them: none when it was recorded
    outside the window read."""
    if not bag.scan.messages.may_keep(info.start, info.end):
        return 0
    return sum(n for conn, n in info.counts.items() if conn in bag.channels)


def replay_order(bag: BagFile, infos: list[ChunkInfo], index_pos: int) -> tuple[Int64Array, Int64Array] | None:
    """The order ``rosbag play`` replays the bag in (``view_order``), as the positions (``Spans.position``)
    of every message, sorted, and each one's place: None where no transform shares its record time with a
    message of another connection (then record time order is that order for what is read), the bag has
    more than ``MAX_MESSAGES`` or an index cannot be read. Its connections are met (``BagFile.connect``)."""
    if not 0 < sum(sum(info.counts.values()) for info in infos) <= MAX_MESSAGES:
        return None
    _prefetch(bag, infos, index_pos, every=True)
    indexes = []
    for info in infos:
        try:
            index = _chunk_index(bag, _record(bag, info.pos, OP_CHUNK), info)
        except DamageError:
            return None
        if index is None:
            return None
        indexes.append(index)
    every = _indexed(indexes)
    if not 0 < len(every) <= MAX_MESSAGES:
        return None
    order = np.argsort(every.time, kind="stable")  # rosbag's index: by time, then as the file lists them
    time, conn = every.time[order], every.channel[order]
    if not _transform_ties(time, conn, bag.transform_connections):
        return None
    connections = distinct(conn)
    places = view_order([time[conn == c] for c in connections.tolist()])
    place = np.empty(len(order), np.int64)
    for c, placed in zip(connections.tolist(), places, strict=True):
        place[order[conn == c]] = placed
    position = every.position
    by_position = np.argsort(position, kind="stable")
    return position[by_position], place[by_position]


def _transform_ties(time: Int64Array, conn: Int64Array, transforms: set[int]) -> bool:
    """Whether messages in record time order (``time``, of connections ``conn``) hold a transform (one of
    the ``transforms`` connections) recorded at the same time as a message of another connection."""
    firsts = np.flatnonzero(np.diff(time, prepend=time[0] - 1) != 0)
    held = np.isin(conn, list(transforms)).astype(np.int8)
    mixed = np.minimum.reduceat(conn, firsts) != np.maximum.reduceat(conn, firsts)
    return bool((mixed & (np.maximum.reduceat(held, firsts) > 0)).any())


def _record(bag: BagFile, pos: int, op: int) -> Record:
    record = bag.records.read(pos)
    if record.op != op or record.data_end > bag.size:
        raise DamageError(f"no readable record with op {op} at byte {pos}")
    return record


def _read_chunk(bag: BagFile, gathered: _Gathered, ordinal: int, info: ChunkInfo, wanted: int) -> None:
    """The wanted messages of a chunk: an uncompressed one's gathered to be read with others', a
    compressed one's read now, located by its index (or, when that is unreadable, by walking it)."""
    try:
        record = _record(bag, info.pos, OP_CHUNK)
        chunk = read_chunk(record)
    except DamageError as e:
        bag.damage.note(info.pos, str(e), wanted, span=(info.start, info.end))
        return
    index = _chunk_index(bag, record, info)
    if chunk.compression == "none" and index is not None:
        gathered.add(bag, _Pending(ordinal, wanted, index, chunk, (info.start, info.end)))
        return
    indexed = None if index is None else _indexed([index])  # read before the index's pages are let go
    bag.release(info.pos, record.data_start if index is None else index.end)
    gathered.read(bag)  # what was gathered comes first: the messages stay in record order
    try:
        unpacked = bag.unpacked(chunk, chunk.data_end)
    except CompressionUnavailableError as e:
        bag.damage.note(info.pos, str(e), wanted)
        return
    data = unpacked.data
    if indexed is None:
        messages, _, first_error = locate(data, walk(data, ordinal), follow=False)
    else:
        offsets = distinct(indexed.offset[_wanted(bag, indexed)])  # once each
        messages, _, first_error = locate(data, in_chunk(offsets, ordinal, len(data)), follow=True)
    got = int(bag.add(data, messages).sum())
    bag.release(info.pos, record.data_end)
    if got < wanted or unpacked.loss:  # a chunk decompressed past damage may give every message, some wrong
        reason = unpacked.loss or first_error or "its index points at no message"
        listed = None if indexed is None else indexed.rows(_wanted(bag, indexed))
        span = (info.start, info.end) if listed is None else lost_span(listed.time, listed.offset, messages.offset)
        bag.damage.note(info.pos, reason, wanted - got, doubtful=bool(unpacked.loss) and got > 0, span=span)


def lost_span(times: Int64Array, listed: Int64Array, read: Int64Array) -> tuple[int, int] | None:
    """The record times, first and last, of the messages an index lists (``times``, at ``listed``) that were not
    read (none at ``read``): where a damaged chunk lost them; None when every one was read."""
    lost = times[~among(listed, read)]
    return (int(lost.min()), int(lost.max())) if len(lost) else None


def _wanted(bag: BagFile, spans: Spans) -> BoolArray:
    """Which records the index lists under a wanted connection."""
    return spans.looked_up(bag.channels) >= 0


class _Index:
    """The index records after a chunk: each one's connection and entries (rows of the record
    time's seconds and nanoseconds, and the offset in the chunk's data, of each message), and
    where they end."""

    __slots__ = ("conns", "end", "entries")

    def __init__(self, conns: list[int], entries: list[npt.NDArray[np.uint32]], end: int) -> None:
        self.conns = conns
        self.entries = entries
        self.end = end


def _chunk_index(bag: BagFile, chunk: Record, info: ChunkInfo) -> _Index | None:
    """The index records after a chunk; None when they are unreadable."""
    index = _Index([], [], chunk.data_end)
    try:
        for _ in range(len(info.counts)):
            record = _record(bag, index.end, OP_INDEX)
            index.conns.append(record.uint("conn"))
            index.entries.append(index_entries(bag.buf, record))
            index.end = record.data_end
    except DamageError:
        return None
    return index


def _indexed(indexes: list[_Index]) -> Spans:
    """Every message the indexes of some chunks list (its chunk: the place of its index in
    ``indexes``), without file ranges yet."""
    parts = [entries for index in indexes for entries in index.entries]
    if not parts:
        return Spans.empty()
    counts = [len(p) for p in parts]
    entries = np.concatenate(parts)
    offset = entries[:, 2].astype(np.int64)
    chunk = np.repeat(np.arange(len(indexes)), [len(index.entries) for index in indexes])
    conn = np.array([c for index in indexes for c in index.conns], np.int64)
    time = entries[:, 0].astype(np.int64) * NS_PER_S + entries[:, 1]
    return Spans(np.repeat(chunk, counts), offset, np.repeat(conn, counts), time, offset, offset)


class _Pending:
    """An uncompressed chunk whose wanted records wait to be read."""

    __slots__ = ("chunk", "index", "ordinal", "span", "wanted")

    def __init__(self, ordinal: int, wanted: int, index: _Index, chunk: Chunk, span: tuple[int, int]) -> None:
        self.span = span  # its messages' record times, first and last, as its chunk info says
        self.ordinal = ordinal
        self.wanted = wanted  # messages, as its chunk info counts them
        self.index = index
        self.chunk = chunk


class _Gathered:
    """Uncompressed chunks, gathered in file order until their wanted records are read together."""

    __slots__ = ("chunks", "nbytes", "records")

    def __init__(self) -> None:
        self.chunks: list[_Pending] = []
        self.records = 0  # wanted (about what reading them will take, whatever else the chunks hold)
        self.nbytes = 0  # the chunks' data: at most what reading them will take

    def add(self, bag: BagFile, pending: _Pending) -> None:
        """Note an uncompressed chunk, to be read with others (and its header's and index's pages
        released with theirs)."""
        self.chunks.append(pending)
        self.records += pending.wanted
        self.nbytes += pending.chunk.data_end - pending.chunk.data_start
        if self.records >= _SPAN_RECORDS or self.nbytes >= _SPAN_BYTES:
            self.read(bag)

    def read(self, bag: BagFile) -> None:
        """Read the wanted records gathered, and start gathering anew. A record must end before
        the next one its chunk's index knows of; records cut short by the end of the file are
        left out (and counted lost)."""
        chunks, self.chunks, self.records, self.nbytes = self.chunks, [], 0, 0
        if not chunks:
            return
        indexed = _indexed([c.index for c in chunks])  # read before the indexes' pages are let go
        bag.release(chunks[0].chunk.pos, chunks[-1].index.end)
        starts, ends = np.array([[c.chunk.data_start, c.chunk.data_end] for c in chunks], np.int64).T
        records, _ = bounded(indexed, starts, ends)
        records = records.rows(_wanted(bag, records))
        records = records.rows(np.diff(records.start, prepend=-1) != 0)  # once each
        # Of messages read for their header, only as far as it reaches: not the image after it.
        cut = np.isin(records.channel, list(bag.headed)) & (records.end - records.start > _HEADED_BYTES)
        records.end[cut] = records.start[cut] + _HEADED_BYTES
        data, where, complete = bag.source.read_ranges(records.start, records.end)
        records, cut = records.rows(complete), cut[complete]
        records.start, records.end = where[complete], where[complete] + records.end - records.start
        messages, _, first_error = locate(data.data, records, follow=True, cut=cut)
        in_batch, messages.chunk = messages.chunk, np.array([c.ordinal for c in chunks], np.int64)[messages.chunk]
        got = np.bincount(in_batch[bag.add(data.data, messages)], minlength=len(chunks))
        keys = records.chunk * (1 << 40) + records.offset  # each record's chunk in the batch and place in it
        found = among(keys, in_batch * (1 << 40) + messages.offset)
        for i, (pending, count) in enumerate(zip(chunks, got.tolist(), strict=True)):
            if count < pending.wanted:
                lost = pending.wanted - count
                reason = first_error or "its index points at no message"
                mine = records.chunk == i
                span = lost_span(records.time[mine], keys[mine], keys[mine][found[mine]]) or pending.span
                bag.damage.note(pending.chunk.pos, reason, lost, span=span)
