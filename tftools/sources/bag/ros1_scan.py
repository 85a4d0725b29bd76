"""Finding a ROS1 bag's wanted messages: by its index, or chunk after chunk when it has none."""

from __future__ import annotations

import mmap
import os
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from tftools.sources.bag.contents import ProgressCallback
from tftools.sources.bag.ranges import prefetch
from tftools.sources.bag.ros1_chunks import (
    IntArray,
    Located,
    locate,
    walk,
)
from tftools.sources.bag.ros1_format import (
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_INDEX,
    OP_MESSAGE,
    BagHeader,
    Buffer,
    Chunk,
    ChunkInfo,
    Connection,
    FileBuffer,
    FormatError,
    Record,
    RecordReader,
    distinct,
    index_offsets,
    read_chunk,
    read_chunk_info,
    read_connection,
    read_record,
)
from tftools.sources.bag.ros1_messages import MessageCollector
from tftools.sources.bag.ros1_spans import ChunkSpans
from tftools.sources.bag.unpack import Budget, CompressionUnavailableError, Unpacked, unpack
from tftools.sources.codecs.select import CLOCK_TYPES
from tftools.sources.codecs.select import ROS1_TF_TYPES as TF_TYPES

_REPAIR = "run `rosbag reindex` on a copy to repair it"
_CHUNK_HEADER_OP = b"\x04\x00\x00\x00op=\x05"  # the op field of a chunk record header
_HEADER_REACH = 96  # how far before its op field a chunk record header may start
#: Records of uncompressed chunks are gathered until there are this many, or their chunks hold
#: this many bytes, then read (a few megabytes of transforms; the cap bounds a batch of huge ones).
_SPAN_RECORDS, _SPAN_BYTES = 8192, 64 << 20
#: Bytes of a chunk record's header, at most, and of an index data record: a header, and 12 per message.
_CHUNK_HEADER_BYTES, _INDEX_RECORD_BYTES, _INDEX_ENTRY_BYTES = 4096, 128, 12


@dataclass
class _ChunkIndex:
    """What a chunk's index records say: the offsets of its wanted messages, of every message, and
    where the records end."""

    wanted: IntArray
    every: IntArray
    end: int


@dataclass
class _Damage:
    """Chunks (or bytes between them) that could not be read: how many, the first, messages lost."""

    places: int = 0
    first: str = ""
    lost: int = 0
    lost_known: bool = True  # the index says how many messages each chunk held

    def note(self, pos: int, reason: str, lost: int | None) -> None:
        self.places += 1
        self.first = self.first or f"first at byte {pos}: {reason}"
        if lost is None:
            self.lost_known = False
        else:
            self.lost += lost


def _joined(offsets: list[npt.NDArray[np.uint32]]) -> IntArray:
    return np.concatenate(offsets, dtype=np.int64) if offsets else np.zeros(0, np.int64)


class BagScan:
    """One bag file read: its wanted messages (undecoded), description and problems."""

    def __init__(
        self,
        name: str,
        buf: FileBuffer,
        topics: tuple[str, ...],
        progress: ProgressCallback,
        fd: int | None = None,
    ) -> None:
        self.name = name
        self.buf = buf
        self.records = RecordReader(buf)
        self.fd = fd  # the file ``buf`` maps, to read chunks from without mapping their pages
        self.size = len(buf)
        self.budget = Budget(self.size)  # what its chunks may decompress to in all
        self.wanted_topics = topics
        self.progress = progress
        self.messages = MessageCollector()
        self.topics: dict[str, str] = {}
        self.connections: dict[int, Connection] = {}
        self.start = self.end = self.message_count = 0
        self.problems: list[str] = []
        self.skipped: list[str] = []
        self.damage = _Damage()
        self.chunk_ordinal = 0
        self.spans = ChunkSpans()  # wanted records of uncompressed chunks, until read
        self.expected: dict[int, tuple[int, int]] = {}  # their chunks: ordinal -> (position, messages wanted)
        self.gathered_end = 0  # where the index of the last chunk gathered ends
        self.scanned = 0  # where the scan of the chunks stopped
        self.tail = ""  # what the scan could not read at the end

    def read(self, header: BagHeader) -> None:
        if header.index_pos == 0:
            self._scan(header.data_start, self.size)
            self._note_scan("has no index (its recording was not closed)")
        elif header.index_pos > self.size:
            self._scan(header.data_start, self.size)
            self._note_truncated(header)
        else:
            try:
                infos = self._read_index(header)
            except FormatError as e:
                self._scan(header.data_start, header.index_pos)
                self._note_scan(f"has a damaged index ({e})")
            else:
                self._prefetch(infos, header.index_pos)
                self._read_indexed(infos)
        self._note_damage()

    # Connections and what they mean.

    def _connect(self, connection: Connection) -> None:
        if connection.id in self.connections:
            return
        self.connections[connection.id] = connection
        self.topics.setdefault(connection.topic, connection.type)
        if connection.type in CLOCK_TYPES:
            self.messages.want(connection, clock=True)
            return
        if connection.topic not in self.wanted_topics:
            return
        if connection.type in TF_TYPES:
            self.messages.want(connection)
        else:
            line = f"{connection.topic}: {connection.type or 'no type'} is not a transform message, skipped"
            if line not in self.skipped:
                self.skipped.append(line)

    # Reading by the index.

    def _read_index(self, header: BagHeader) -> list[ChunkInfo]:
        pos = header.index_pos
        connections: list[Connection] = []
        infos: list[ChunkInfo] = []
        for _ in range(header.conn_count):
            record = self._record(pos, OP_CONNECTION)
            connections.append(read_connection(self.buf, record))
            pos = record.data_end
        for _ in range(header.chunk_count):
            record = self._record(pos, OP_CHUNK_INFO)
            infos.append(read_chunk_info(self.buf, record))
            pos = record.data_end
        for connection in connections:
            self._connect(connection)
        return sorted(infos, key=lambda info: info.pos)

    def _prefetch(self, infos: list[ChunkInfo], index_pos: int) -> None:
        """Have the system fetch the headers and index records of the chunks holding wanted
        messages all at once: read one by one from a file not in the page cache, each would wait
        for the disk. A chunk's index records end where the next chunk (or the bag's index) begins,
        about ``_INDEX_ENTRY_BYTES`` a message before it."""
        if self.fd is None:
            return
        ends = [*(info.pos for info in infos[1:]), index_pos]
        starts: list[int] = []
        stops: list[int] = []
        for info, end in zip(infos, ends, strict=True):
            if any(self.messages.wants(conn) for conn in info.counts):
                index_bytes = sum(_INDEX_RECORD_BYTES + _INDEX_ENTRY_BYTES * n for n in info.counts.values())
                starts += [info.pos, max(info.pos, end - index_bytes)]
                stops += [info.pos + _CHUNK_HEADER_BYTES, end]
        prefetch(self.fd, np.array(starts, np.int64), np.array(stops, np.int64))

    def _record(self, pos: int, op: int) -> Record:
        record = self.records.read(pos)
        if record.op != op or record.data_end > self.size:
            raise FormatError(f"no readable record with op {op} at byte {pos}")
        return record

    def _read_indexed(self, infos: list[ChunkInfo]) -> None:
        counted = [info for info in infos if info.counts]
        self.message_count = sum(sum(info.counts.values()) for info in counted)
        self.start = min((info.start for info in counted), default=0)
        self.end = max((info.end for info in counted), default=0)
        for ordinal, info in enumerate(infos):
            wanted = sum(n for conn, n in info.counts.items() if self.messages.wants(conn))
            if wanted:
                self._indexed_chunk(ordinal, info, wanted)
                self.progress(min(info.pos, self.size), self.size)
        self._read_spans()

    def _indexed_chunk(self, ordinal: int, info: ChunkInfo, wanted: int) -> None:
        try:
            record = self._record(info.pos, OP_CHUNK)
            chunk = read_chunk(record)
        except FormatError as e:
            self.damage.note(info.pos, str(e), wanted)
            return
        index = self._chunk_index(record.data_end, info)
        if chunk.compression == "none" and index is not None and self.fd is not None:
            self._gather(ordinal, info.pos, chunk, index, wanted)
            return
        self._release(info.pos, record.data_start if index is None else index.end)
        self._read_spans()  # what was gathered comes first: the messages stay in record order
        try:
            unpacked = self._unpacked(chunk, chunk.data_end)
        except CompressionUnavailableError as e:
            self.damage.note(info.pos, str(e), wanted)
            return
        if index is None:
            located = locate(unpacked.data, walk(unpacked.data)[0], follow=False)
        else:
            located = locate(unpacked.data, distinct(index.wanted), follow=True)
        got = int(self.messages.add(ordinal, unpacked.data, located).sum())
        self._release(info.pos, record.data_end)
        if got < wanted:
            reason = unpacked.loss or located.first_error or "its index points at no message"
            self.damage.note(info.pos, reason, wanted - got)

    def _chunk_index(self, pos: int, info: ChunkInfo) -> _ChunkIndex | None:
        """The message offsets in the chunk's data, from the index records after it; None when
        those are unreadable."""
        wanted: list[npt.NDArray[np.uint32]] = []
        every: list[npt.NDArray[np.uint32]] = []
        try:
            for _ in range(len(info.counts)):
                record = self._record(pos, OP_INDEX)
                offsets = index_offsets(self.buf, record)
                every.append(offsets)
                if self.messages.wants(record.uint("conn")):
                    wanted.append(offsets)
                pos = record.data_end
        except FormatError:
            return None
        return _ChunkIndex(_joined(wanted), _joined(every), pos)

    def _gather(self, ordinal: int, pos: int, chunk: Chunk, index: _ChunkIndex, wanted: int) -> None:
        """Note the wanted records of an uncompressed chunk, to be read with other chunks' (and
        its header's and index's pages released with theirs)."""
        self.spans.add(ordinal, chunk.data_start, chunk.data_end - chunk.data_start, index.wanted, index.every)
        self.expected[ordinal] = (pos, wanted)
        self.gathered_end = index.end
        if self.spans.records >= _SPAN_RECORDS or self.spans.nbytes >= _SPAN_BYTES:
            self._read_spans()

    def _read_spans(self) -> None:
        """Read the wanted records gathered from uncompressed chunks; a record must end before the
        next one its chunk's index knows of."""
        if not self.spans:
            return
        self._release(next(iter(self.expected.values()))[0], self.gathered_end)
        batch = self.spans.read(self.fd or 0)
        located = locate(batch.data, batch.offsets, follow=True)
        row = np.searchsorted(batch.offsets, located.offset, side="right") - 1
        within = located.data_start + located.data_len <= batch.ends[row]
        kept = self.messages.add(batch.chunk[row[within]], batch.data, located.taken(within))
        chunks, counts = np.unique(batch.chunk[row[within][kept]], return_counts=True)
        got = dict(zip(chunks.tolist(), counts.tolist(), strict=True))
        reason = located.first_error or "its index points at no message"
        for ordinal, (pos, wanted) in self.expected.items():
            if got.get(ordinal, 0) < wanted:
                self.damage.note(pos, reason, wanted - got.get(ordinal, 0))
        self.expected.clear()

    # Reading chunk after chunk.

    def _scan(self, pos: int, stop: int) -> None:
        """Read the records from ``pos`` to ``stop`` one after the other, over damage if need be."""
        self.scanned = pos
        while pos < stop:
            try:
                pos = self._scanned_record(pos, stop)
            except FormatError as e:
                found = self._resync(pos + 1, stop)
                if found is None:
                    self.tail = f"the last {stop - pos} bytes are no readable record"
                    break
                self.damage.note(pos, f"{found - pos} unreadable bytes skipped ({e})", None)
                pos = found
            self.scanned = min(pos, stop)
            self.progress(self.scanned, self.size)

    def _scanned_record(self, pos: int, stop: int) -> int:
        """Read the record at ``pos``; returns where the next one begins."""
        record = read_record(self.buf, pos, stop)
        if record.op == OP_CHUNK:
            return self._scanned_chunk(record, stop)
        if record.op == OP_MESSAGE:  # an unfinished chunk's records follow its header
            self._records(memoryview(self.buf)[pos:stop])
            return stop
        if record.op == OP_CONNECTION and record.data_end <= stop:
            self._connect(read_connection(self.buf, record))
        return record.data_end

    def _scanned_chunk(self, record: Record, stop: int) -> int:
        chunk = read_chunk(record)
        unfinished = chunk.data_end == chunk.data_start and chunk.size == 0
        if unfinished and chunk.compression == "none":
            return chunk.data_end  # its records are next, outside any chunk
        end = min(chunk.data_end, stop)
        if unfinished:
            end = stop
            self.tail = f"its unfinished last chunk ({chunk.compression}) is read as far as it can be"
        elif chunk.data_end > stop:  # cut short, or its length is damaged: up to the next chunk
            end = self._resync(chunk.data_start, stop) or stop
        try:
            unpacked = self._unpacked(chunk, end)
        except CompressionUnavailableError as e:
            self.damage.note(chunk.pos, str(e), None)
            return end
        if unpacked.loss and chunk.data_end <= stop:
            self.damage.note(chunk.pos, unpacked.loss, None)
        self._records(unpacked.data)
        self._release(chunk.pos, end)
        return end

    def _release(self, start: int, end: int) -> None:
        """Unmap the pages of a chunk that has been read: the file's pages then stay in the page
        cache instead of counting towards this process's resident memory (the messages wanted
        are copied out by then)."""
        if not isinstance(self.buf, mmap.mmap) or not hasattr(mmap, "MADV_DONTNEED"):
            return
        start -= start % mmap.PAGESIZE
        if end > start:
            self.buf.madvise(mmap.MADV_DONTNEED, start, min(end, self.size) - start)

    def _unpacked(self, chunk: Chunk, end: int) -> Unpacked:
        """The chunk's data up to ``end``, uncompressed."""
        return unpack(chunk.compression, self._bytes(chunk.data_start, end), chunk.size, self.budget)

    def _bytes(self, start: int, end: int) -> bytes | memoryview:
        """``buf[start:end]``: read from the file when it is known (faulting in the pages of a
        mapping costs more than the copy a read makes, and they would count as resident)."""
        if self.fd is not None:
            return os.pread(self.fd, max(0, min(end, self.size) - start), start)
        return memoryview(self.buf)[start:end]

    def _records(self, data: Buffer) -> None:
        offsets, _ = walk(data)
        located = locate(data, offsets, follow=False)
        for connection in located.connections:
            self._connect(connection)
        self._count(located)
        self.messages.add(self.chunk_ordinal, data, located)
        self.chunk_ordinal += 1

    def _count(self, located: Located) -> None:
        if not len(located.time):
            return
        first, last = int(located.time.min()), int(located.time.max())
        self.start = min(self.start, first) if self.message_count else first
        self.end = max(self.end, last)
        self.message_count += len(located.time)

    def _resync(self, pos: int, stop: int) -> int | None:
        """Where the next readable chunk record begins after damage at ``pos``."""
        while (hit := self.buf.find(_CHUNK_HEADER_OP, pos, stop)) >= 0:
            for start in range(max(pos, hit - _HEADER_REACH), hit - 3):
                try:
                    record = read_record(self.buf, start, stop)
                except FormatError:
                    continue
                if record.op == OP_CHUNK:
                    return start
            pos = hit + 1
        return None

    # Problems, one line each.

    def _note_scan(self, why: str) -> None:
        n = self.messages.count
        tail = f"; {self.tail}" if self.tail else ""
        self.problems.append(
            f"{self.name}: {why}; read {n} transform messages by scanning its chunks{tail} ({_REPAIR})"
        )

    def _note_truncated(self, header: BagHeader) -> None:
        n = self.messages.count
        span, seen = header.index_pos - header.data_start, self.scanned - header.data_start
        expected = f"~{round(n * span / seen)}" if seen > 0 and n else "an unknown number of"
        self.problems.append(
            f"{self.name}: truncated after {self.size} of more than {header.index_pos} bytes; "
            f"read {n} of {expected} transform messages ({_REPAIR})"
        )

    def _note_damage(self) -> None:
        d = self.damage
        if not d.places:
            return
        what = "a damaged part" if d.places == 1 else f"{d.places} damaged parts"
        if d.lost_known:
            lost = f"{d.lost} transform messages lost"
        else:
            lost = f"at least {d.lost} transform messages lost" if d.lost else "the transform messages there are lost"
        self.problems.append(f"{self.name}: {what} could not be read ({d.first}); {lost}")
