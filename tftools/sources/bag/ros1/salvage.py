"""A ROS1 bag without a readable index (its recording was not closed, it was cut short, or its index
is damaged) read chunk after chunk, over damage: whatever can be read of it."""

from __future__ import annotations

import numpy as np

from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.ros1.chunks import locate, walk
from tftools.sources.bag.ros1.file import BagFile
from tftools.sources.bag.ros1.records import (
    OP_CHUNK,
    OP_CONNECTION,
    OP_MESSAGE,
    BagHeader,
    Record,
    read_chunk,
    read_connection,
    read_record,
)
from tftools.sources.bag.unpack import CompressionUnavailableError

_REPAIR = "run `rosbag reindex` on a copy to repair it"
_CHUNK_HEADER_OP = b"\x04\x00\x00\x00op=\x05"  # the op field of a chunk record header
_HEADER_REACH = 96  # how far before its op field a chunk record header may start


def read_unindexed(bag: BagFile, header: BagHeader, index_damage: str = "") -> None:
    """Read the bag's records one after the other, up to its index when ``index_damage`` says
    what is wrong with it (else there is none, or it lies past the end of the file), and say so."""
    scanner = _Scanner(bag)
    bag.scan.windowed = False
    bag.source.ahead(np.array([header.data_start], np.int64), np.array([bag.size], np.int64))  # every record
    truncated = header.index_pos > bag.size
    scanner.scan(header.data_start, header.index_pos if index_damage else bag.size)
    n = bag.transform_messages
    if truncated:
        span, seen = header.index_pos - header.data_start, scanner.scanned - header.data_start
        expected = f"~{round(n * span / seen)}" if seen > 0 and n else "an unknown number of"
        line = f"truncated after {bag.size} of more than {header.index_pos} bytes; read {n} of {expected}"
        line += f" {bag.counted}{f'; {scanner.tail}' if scanner.tail else ''}"
    else:
        why = f"has a damaged index ({index_damage})" if index_damage else "has no index (its recording was not closed)"
        tail = f"; {scanner.tail}" if scanner.tail else ""
        line = f"{why}; read {n} {bag.counted} by scanning its chunks{tail}"
    bag.scan.note_problem(f"{bag.name}: {line} ({_REPAIR})")


class _Scanner:
    """Records read one after the other; a chunk's messages located by walking its records."""

    def __init__(self, bag: BagFile) -> None:
        self.bag = bag
        self.chunk_ordinal = 0
        self.scanned = 0  # where the scan stopped
        self.tail = ""  # what could not be read at the end

    def scan(self, pos: int, stop: int) -> None:
        """Read the records from ``pos`` to ``stop`` one after the other, over damage if need be."""
        bag = self.bag
        self.scanned = pos
        while pos < stop:
            try:
                pos = self._record(pos, stop)
            except DamageError as e:
                found = self._resync(pos + 1, stop)
                if found is None:
                    self.tail = f"the last {stop - pos} bytes are no readable record"
                    break
                bag.damage.note(pos, f"{found - pos} unreadable bytes skipped ({e})", None)
                bag.scan.note_lost()
                pos = found
            self.scanned = min(pos, stop)
            bag.progress(self.scanned, bag.size)

    def _record(self, pos: int, stop: int) -> int:
        """Read the record at ``pos``; returns where the next one begins."""
        buf = self.bag.buf
        record = read_record(buf, pos, stop)
        if record.op == OP_CHUNK:
            return self._chunk(record, stop)
        if record.op == OP_MESSAGE:  # an unfinished chunk's records follow its header
            self._messages(buf[pos:stop])
            return stop
        if record.op == OP_CONNECTION and record.data_end <= stop:
            self.bag.connect(read_connection(buf, record))
        return record.data_end

    def _chunk(self, record: Record, stop: int) -> int:
        bag = self.bag
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
            unpacked = bag.unpacked(chunk, end)
        except CompressionUnavailableError as e:
            bag.damage.note(chunk.pos, str(e), None)
            bag.scan.note_lost()
            return end
        read = self._messages(unpacked.data)
        if chunk.data_end > stop and not len(unpacked.data) and chunk.compression == "bz2":
            self.tail = (
                "its last chunk (bz2) is cut short, and bz2 gives nothing of a block cut short: its messages are lost"
            )
        if unpacked.loss and chunk.data_end <= stop:
            bag.damage.note(chunk.pos, unpacked.loss, None, doubtful=read > 0)
            bag.scan.note_lost()
        bag.release(chunk.pos, end)
        return end

    def _messages(self, data: bytes | memoryview) -> int:
        """The messages of a chunk's records (every one counted; the wanted ones kept); how many there are."""
        bag = self.bag
        messages, connections, _ = locate(data, walk(data, self.chunk_ordinal), follow=False)
        self.chunk_ordinal += 1
        for connection in connections:
            bag.connect(connection)
        if len(messages):
            bag.scan.note_times(int(messages.time.min()), int(messages.time.max()), len(messages))
        bag.add(data, messages)
        return len(messages)

    def _resync(self, pos: int, stop: int) -> int | None:
        """Where the next readable chunk record begins after damage at ``pos``."""
        buf = self.bag.buf
        while (hit := buf.find(_CHUNK_HEADER_OP, pos, stop)) >= 0:
            for start in range(max(pos, hit - _HEADER_REACH), hit - 3):
                try:
                    record = read_record(buf, start, stop)
                except DamageError:
                    continue
                if record.op == OP_CHUNK:
                    return start
            pos = hit + 1
        return None
