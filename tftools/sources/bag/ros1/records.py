"""The records of a ROS bag v2.0 file (http://wiki.ros.org/Bags/Format/2.0), read from a buffer."""

from __future__ import annotations

import struct

import numpy as np
import numpy.typing as npt

from tftools.core.time import NS_PER_S
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.formats import ROS1
from tftools.sources.storage.source import FileBytes

MAGIC = ROS1.magic

OP_MESSAGE = 0x02
OP_BAG_HEADER = 0x03
OP_INDEX = 0x04
OP_CHUNK = 0x05
OP_CHUNK_INFO = 0x06
OP_CONNECTION = 0x07

_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
_TIME = struct.Struct("<II")

#: A bag file (its source's buffer) or a chunk's data.
ByteSpan = FileBytes | memoryview


def u32(buf: ByteSpan, pos: int) -> int:
    if pos < 0 or pos + 4 > len(buf):
        raise DamageError(f"a length at byte {pos} lies beyond the end")
    return int(_U32.unpack(buf[pos : pos + 4])[0])


def header_fields(buf: ByteSpan, start: int, end: int) -> dict[str, bytes]:
    """The ``name=value`` fields of a record header (or connection header) in ``buf[start:end]``."""
    fields: dict[str, bytes] = {}
    pos = start
    while pos < end:
        size = u32(buf, pos)
        pos += 4
        if pos + size > end:
            raise DamageError(f"a header field at byte {pos - 4} runs past its header")
        item = bytes(buf[pos : pos + size])
        name, equals, value = item.partition(b"=")
        if not equals:
            raise DamageError(f"a header field at byte {pos - 4} has no '='")
        fields[name.decode("ascii", "replace")] = value
        pos += size
    return fields


class Record:
    """One record: its header's fields and where its data lies in the buffer."""

    __slots__ = ("data_end", "data_start", "fields", "op", "start")

    def __init__(self, op: int, fields: dict[str, bytes], start: int, data_start: int, data_end: int) -> None:
        self.op = op
        self.fields = fields
        self.start = start  # first byte of the record (its header length)
        self.data_start = data_start
        self.data_end = data_end

    def uint(self, name: str) -> int:
        value = self._field(name)
        if len(value) == 4:
            return int(_U32.unpack(value)[0])
        if len(value) == 8:
            return int(_U64.unpack(value)[0])
        raise DamageError(f"record field {name} has {len(value)} bytes")

    def time(self, name: str) -> int:
        value = self._field(name)
        if len(value) != 8:
            raise DamageError(f"record field {name} has {len(value)} bytes, not a time")
        sec, nsec = _TIME.unpack(value)
        return int(sec) * NS_PER_S + int(nsec)

    def text(self, name: str, default: str | None = None) -> str:
        if default is not None and name not in self.fields:
            return default
        return self._field(name).decode("utf-8", "replace")

    def _field(self, name: str) -> bytes:
        try:
            return self.fields[name]
        except KeyError:
            raise DamageError(f"record at byte {self.start} lacks its {name} field") from None


def read_record(buf: ByteSpan, pos: int, end: int | None = None) -> Record:
    """The record starting at ``pos``; ``DamageError`` if it is malformed or not all there."""
    limit = len(buf) if end is None else end
    header_len = u32(buf, pos)
    header_end = pos + 4 + header_len
    if header_end + 4 > limit:
        raise DamageError(f"the record at byte {pos} is cut short")
    fields = header_fields(buf, pos + 4, header_end)
    data_len = u32(buf, header_end)
    data_start = header_end + 4
    op = fields.get("op", b"")
    if len(op) != 1:
        raise DamageError(f"the record at byte {pos} has no op code")
    return Record(op[0], fields, pos, data_start, data_start + data_len)


#: Per op code, the header fields whose values differ from record to record (fixed-width ones):
#: the rest of a header repeats, so ``RecordReader`` matches it instead of parsing it.
_CHANGING = {
    OP_CHUNK: ("size",),
    OP_INDEX: ("conn", "count"),
    OP_CHUNK_INFO: ("chunk_pos", "start_time", "end_time", "count"),
}


class _Layout:
    """A record header's bytes, with where the changing fields' values lie."""

    def __init__(self, record: Record, header: bytes, changing: tuple[str, ...]) -> None:
        self.record = record
        self.length = len(header)
        self.places = sorted((value_at(header, name), len(record.fields[name]), name) for name in changing)
        bounds = [0, *(edge for at, width, _ in self.places for edge in (at, at + width)), len(header)]
        self.fixed = [(a, b, header[a:b]) for a, b in zip(bounds[::2], bounds[1::2], strict=True)]

    def read(self, buf: ByteSpan, pos: int) -> Record | None:
        """The record at ``pos`` if its header has this layout, else None."""
        header_end = pos + 4 + self.length
        if header_end + 4 > len(buf):
            return None
        header = buf[pos + 4 : header_end]
        if any(header[a:b] != expected for a, b, expected in self.fixed):
            return None
        fields = dict(self.record.fields)
        for at, width, name in self.places:
            fields[name] = bytes(header[at : at + width])
        data_start = header_end + 4
        return Record(self.record.op, fields, pos, data_start, data_start + u32(buf, header_end))


def value_at(header: bytes, name: str) -> int:
    """Where the value of field ``name`` begins in a record header (its fields length-prefixed)."""
    pos, key = 0, name.encode() + b"="
    while pos < len(header):
        if header[pos + 4 : pos + 4 + len(key)] == key:
            return pos + 4 + len(key)
        pos += 4 + int.from_bytes(header[pos : pos + 4], "little")
    raise DamageError(f"no {name} field")


class RecordReader:
    """``read_record`` for many records of one file: the headers of chunks, index records and chunk
    infos, which a writer repeats but for a few values, are matched against one learnt from the
    first of each length instead of being parsed field by field."""

    def __init__(self, buf: ByteSpan) -> None:
        self.buf = buf
        self._layouts: dict[int, _Layout] = {}  # by header length

    def read(self, pos: int) -> Record:
        layout = self._layouts.get(u32(self.buf, pos))
        if layout is not None and (record := layout.read(self.buf, pos)) is not None:
            return record
        record = read_record(self.buf, pos)
        changing = _CHANGING.get(record.op, ())
        if changing and all(name in record.fields for name in changing):
            header = bytes(self.buf[pos + 4 : record.data_start - 4])
            self._layouts[len(header)] = _Layout(record, header, changing)
        return record


class BagHeader:
    __slots__ = ("chunk_count", "conn_count", "data_start", "encryptor", "index_pos")

    def __init__(self, index_pos: int, conn_count: int, chunk_count: int, encryptor: str, data_start: int) -> None:
        self.index_pos = index_pos  # 0: the bag was never closed (no index)
        self.conn_count = conn_count
        self.chunk_count = chunk_count
        self.encryptor = encryptor
        self.data_start = data_start  # where the first record after the bag header begins


def read_bag_header(buf: ByteSpan) -> BagHeader:
    if bytes(buf[: len(MAGIC)]) != MAGIC:
        raise DamageError("it does not start with #ROSBAG V2.0")
    record = read_record(buf, len(MAGIC))
    if record.op != OP_BAG_HEADER:
        raise DamageError("its first record is not a bag header")
    return BagHeader(
        record.uint("index_pos"),
        record.uint("conn_count"),
        record.uint("chunk_count"),
        record.text("encryptor", ""),
        record.data_end,
    )


class Connection:
    """A topic as one publisher (callerid) recorded it."""

    __slots__ = ("callerid", "definition", "id", "latching", "md5sum", "topic", "type")

    def __init__(
        self,
        id: int,
        topic: str,
        type: str,
        callerid: str,
        definition: str = "",
        md5sum: str = "",
        latching: bool = False,
    ) -> None:
        self.id = id
        self.topic = topic
        self.type = type
        self.callerid = callerid  # "" when the bag does not say
        self.definition = definition  # its type's message_definition
        self.md5sum = md5sum
        self.latching = latching


def read_connection(buf: ByteSpan, record: Record) -> Connection:
    data = header_fields(buf, record.data_start, record.data_end)
    topic = record.text("topic")
    return Connection(
        record.uint("conn"),
        topic,
        data.get("type", b"").decode("utf-8", "replace"),
        data.get("callerid", b"").decode("utf-8", "replace"),
        data.get("message_definition", b"").decode("utf-8", "replace"),
        data.get("md5sum", b"").decode("utf-8", "replace"),
        data.get("latching", b"0") == b"1",
    )


class ChunkInfo:
    """What the index says about one chunk: where, when, and how many messages per connection."""

    __slots__ = ("counts", "end", "pos", "start")

    def __init__(self, pos: int, start: int, end: int, counts: dict[int, int] | None = None) -> None:
        self.pos = pos
        self.start = start
        self.end = end
        self.counts = {} if counts is None else counts


def _entries(buf: ByteSpan, record: Record, width: int, what: str) -> npt.NDArray[np.uint32]:
    """The ``count`` entries of version 1 that a chunk info or index data ``record`` holds, one
    row of ``width`` uint32 each."""
    if record.uint("ver") != 1:
        raise DamageError(f"{what} version {record.uint('ver')} is unknown")
    count = record.uint("count")
    if record.data_end - record.data_start < count * 4 * width or record.data_end > len(buf):
        raise DamageError(f"the {what} at byte {record.start} is cut short")
    return np.frombuffer(buf[record.data_start : record.data_start + count * 4 * width], "<u4").reshape(count, width)


def read_chunk_info(buf: ByteSpan, record: Record) -> ChunkInfo:
    counts = dict(_entries(buf, record, 2, "chunk info").tolist())  # connection id -> messages
    pos = record.uint("chunk_pos")
    if pos >= len(buf):
        raise DamageError(f"the chunk info at byte {record.start} points past the end of the file")
    return ChunkInfo(pos, record.time("start_time"), record.time("end_time"), counts)


class Chunk:
    __slots__ = ("compression", "data_end", "data_start", "pos", "size")

    def __init__(self, pos: int, compression: str, size: int, data_start: int, data_end: int) -> None:
        self.pos = pos
        self.compression = compression
        self.size = size  # uncompressed bytes
        self.data_start = data_start
        self.data_end = data_end


def read_chunk(record: Record) -> Chunk:
    return Chunk(record.start, record.text("compression"), record.uint("size"), record.data_start, record.data_end)


def index_entries(buf: ByteSpan, record: Record) -> npt.NDArray[np.uint32]:
    """The entries of an index data record, a row per message it lists: its record time (seconds,
    nanoseconds), and where it begins in its chunk's data."""
    return _entries(buf, record, 3, "index data")
