"""MCAP records: opcodes, a bounds-checked reader of their contents, chunks unpacked, channels and their codecs."""

from __future__ import annotations

import struct
import zlib

from tftools.core.time import TIME_MAX
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.formats import MCAP
from tftools.sources.bag.scan import FileScan
from tftools.sources.bag.unpack import Budget, CompressionUnavailableError, unpack
from tftools.sources.codecs.select import AnyCodec, HeaderCodec, Wanted, copied, select
from tftools.sources.contents import Recorded
from tftools.sources.storage.source import ByteSource

MAGIC = MCAP.magic
HEADER, FOOTER, SCHEMA, CHANNEL, MESSAGE, CHUNK = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06
MESSAGE_INDEX, CHUNK_INDEX, STATISTICS, DATA_END = 0x07, 0x08, 0x0B, 0x0F
RECORD = struct.Struct("<BQ")  # opcode, content length
MESSAGE_HEAD = struct.Struct("<HIQQ")  # channel id, sequence, log time, publish time
U16, U32, U64, I64 = struct.Struct("<H"), struct.Struct("<I"), struct.Struct("<Q"), struct.Struct("<q")
CHUNK_HEAD = struct.Struct("<QQQI")  # start time, end time, uncompressed size, crc


def held(time: int) -> int:
    """An MCAP time (u64 ns) as tftools holds one: past the year 2262 (beyond an int64, damage), ``TIME_MAX``."""
    return time if time <= TIME_MAX else TIME_MAX


class ChunkIndex:
    """Where a chunk and its message indexes are, as the summary says."""

    __slots__ = ("compression", "index_length", "index_offsets", "length", "message_end", "message_start",
                 "offset", "records_length")  # fmt: skip

    def __init__(
        self,
        offset: int,
        length: int,
        index_offsets: dict[int, int],
        index_length: int,
        compression: str,
        records_length: int,
        message_start: int,
        message_end: int,
    ) -> None:
        self.offset = offset
        self.length = length
        self.index_offsets = index_offsets  # channel id -> file offset of its MessageIndex record
        self.index_length = index_length
        self.compression = compression
        self.records_length = records_length  # of its records as stored (compressed or not)
        self.message_start = message_start  # record (log) time of its first message, ns
        self.message_end = message_end  # and of its last

    @property
    def records_start(self) -> int:
        """The file offset of the chunk's records, after its fields (which end in the compression's name)."""
        return self.offset + RECORD.size + CHUNK_HEAD.size + U32.size + len(self.compression.encode()) + U64.size

    @property
    def end(self) -> int:
        """The file offset just past the chunk record, where its message indexes begin."""
        return self.offset + self.length


class Body:
    """A cursor over a record's content, raising ``DamageError`` past its end."""

    def __init__(self, data: bytes | memoryview) -> None:
        self.data = data
        self.pos = 0

    def take(self, fmt: struct.Struct) -> tuple[int, ...]:
        try:
            values = fmt.unpack_from(self.data, self.pos)
        except struct.error:
            raise DamageError("record shorter than its fields") from None
        self.pos += fmt.size
        return values

    def int(self, fmt: struct.Struct) -> int:
        return int(self.take(fmt)[0])

    def bytes(self, length_fmt: struct.Struct) -> bytes | memoryview:
        length = self.int(length_fmt)
        if self.pos + length > len(self.data):
            raise DamageError("field runs past its record")
        self.pos += length
        return self.data[self.pos - length : self.pos]

    def string(self) -> str:
        return bytes(self.bytes(U32)).decode("utf-8", "replace")


def profile_of(source: ByteSource) -> str:
    """The profile the file's header record names ("ros1", "ros2", ...), "" when none or unreadable
    (a damaged header is the readers' to report)."""
    head = source.read(len(MAGIC), len(MAGIC) + RECORD.size + U32.size + _PROFILE_BYTES)
    if len(head) < RECORD.size + U32.size or head[0] != HEADER:
        return ""
    (length,) = U32.unpack_from(head, RECORD.size)
    profile = head[RECORD.size + U32.size : RECORD.size + U32.size + length]
    return bytes(profile).decode("utf-8", "replace") if len(profile) == length else ""


#: The longest header profile read: the profiles the MCAP specification names are a few letters.
_PROFILE_BYTES = 64


def known(opcode: int) -> bool:
    """Whether ``opcode`` is a record type of the format (0x01 to 0x0F) or a private one (0x80 up)."""
    return 0 < opcode < 0x10 or opcode >= 0x80


def records(data: bytes) -> list[tuple[int, int, int]]:
    """(opcode, content start, content end) of the records that fill ``data``."""
    out = []
    pos = 0
    while pos + RECORD.size <= len(data):
        opcode, length = RECORD.unpack_from(data, pos)
        start = pos + RECORD.size
        if start + length > len(data):
            raise DamageError(f"record at byte {pos} runs past its section")
        out.append((opcode, start, start + length))
        pos = start + length
    return out


def chunk_records(content: bytes | memoryview, budget: Budget | None = None) -> tuple[bytes | memoryview, str]:
    """The records inside a chunk, decompressed up to its declared size, and what is wrong with them ("" when
    they are whole and pass the chunk's CRC check): as far as they go when the chunk is cut short or damaged; a
    view into ``content`` when it is a view and the chunk is not compressed. Raises ``DamageError`` for a
    compression that cannot be read here."""
    body = Body(content)
    _, _, uncompressed, crc = body.take(CHUNK_HEAD)
    compression = body.string()
    length = body.int(U64)
    data = content[body.pos : body.pos + length]
    damage = "chunk shorter than it says" if len(data) < length else ""
    records = data
    if compression:
        try:
            unpacked = unpack(compression, data, uncompressed, budget)
        except CompressionUnavailableError as e:
            raise DamageError(f"unsupported chunk compression {compression!r} ({e})") from None
        if unpacked.loss:
            damage = damage or f"{compression} chunk cannot be decompressed whole ({unpacked.loss})"
        records = unpacked.data
    if not damage and crc and zlib.crc32(records) != crc:  # a CRC of 0 is none
        damage = "chunk fails its CRC check"
    return records, damage


class Salvaged:
    """Damaged chunks of which some messages were still read: what is wrong with the first, how many
    messages were read of them and how many lost (None: not known, a chunk without message indexes)."""

    def __init__(self) -> None:
        self.chunks = 0
        self.first = ""
        self.read = 0
        self.lost: int | None = 0

    def note(self, damage: str, read: int, lost: int | None) -> None:
        self.chunks += 1
        self.first = self.first or damage
        self.read += read
        self.lost = None if lost is None or self.lost is None else self.lost + lost

    def line(self, of: int | None = None) -> str:
        """The problem line (``of``: the file's chunks, when known); "" when no chunk is damaged."""
        if not self.chunks:
            return ""
        many = self.chunks > 1 or of is not None
        which = f"{self.chunks}{f' of {of}' if of else ''} chunk{'s' if many else ''}"
        which += f" {'are' if self.chunks > 1 else 'is'} damaged ({self.first})"
        its, doubt = ("their" if self.chunks > 1 else "its"), "a value among them may be wrong"
        parsed = "read from the records that still parse"
        if self.lost is None:
            return f"{which}: {self.read} of {its} messages {parsed} ({doubt}); any after the damage are lost"
        if not self.lost:
            return f"{which}: all {self.read} of {its} messages still parse and are read, but {doubt}"
        total = self.read + self.lost
        return f"{which}: {self.read} of {its} {total} messages {parsed} ({doubt}), {self.lost} lost"


#: Schema encodings whose data is a .msg definition (nested types included).
_MSG_DEFINITIONS = ("ros1msg", "ros2msg")


class Channels:
    """Schemas and channels as they are met, and which channels are read as transforms."""

    def __init__(self, asked: Wanted, result: FileScan, file_size: int = 0) -> None:
        self.asked = asked
        self.result = result
        self.budget = Budget(file_size)  # what the file's chunks may decompress to in all
        self.schemas: dict[int, tuple[str, str]] = {}  # schema id -> type name, .msg definition ("": none)
        self.known: set[int] = set()
        self.wanted: dict[int, int] = {}  # MCAP channel id -> MessageSet channel
        self.headed: set[int] = set()  # MCAP channel ids read for their messages' headers only

    def register(self, opcode: int, content: bytes | memoryview) -> None:
        """A schema or channel record."""
        body = Body(content)
        if opcode == SCHEMA:
            schema_id, name, encoding = body.int(U16), body.string(), body.string()
            definition = body.string() if encoding in _MSG_DEFINITIONS else ""
            self.schemas[schema_id] = (name, definition)
            return
        channel_id, schema_id = body.int(U16), body.int(U16)
        topic, encoding = body.string(), body.string()
        if channel_id in self.known:
            return
        self.known.add(channel_id)
        type_name, definition = self.schemas.get(schema_id, ("", ""))
        self.result.topics[topic] = type_name
        metadata = _metadata(body)
        # The ros1 profile's channels keep the connection's callerid (``mcap convert`` of a ROS 1 bag):
        # the publisher, as a ROS 1 bag names it.
        publisher = metadata.get("callerid", "")
        qos = metadata.get("offered_qos_profiles", "")
        if "offered_qos_profiles" in metadata:  # rosbag2's MCAP storage keeps what its metadata.yaml says
            self.result.offered_qos[topic] = qos
        codec: AnyCodec | None
        if self.asked.copy is not None:
            recorded = Recorded(topic, type_name, encoding, definition, publisher=publisher, qos=qos)
            codec, unread = copied(recorded, self.asked.copy), None
        else:
            codec, unread = select(topic, type_name, encoding, self.asked, definition)
        self.result.note_skipped(unread)
        if codec is not None:
            self.wanted[channel_id] = self.result.messages.channel(topic, codec, publisher=publisher)
            if isinstance(codec, HeaderCodec):
                self.headed.add(channel_id)


def _metadata(body: Body) -> dict[str, str]:
    """A channel's metadata (a map of strings, the rest of its record)."""
    found: dict[str, str] = {}
    pairs = Body(body.bytes(U32))
    while pairs.pos < len(pairs.data):
        key = pairs.string()
        found[key] = pairs.string()
    return found


def scan_records(data: bytes | memoryview, number: int, channels: Channels, *, counted: bool) -> tuple[str, int]:
    """Take the wanted messages of a chunk's records (chunk ``number`` of the file), walking them
    one by one (with ``counted``, every message is counted in the description); returns what was
    wrong if they end in damage (else "") and how many messages were walked."""
    found: dict[int, tuple[list[int], list[int], list[bytes | memoryview]]] = {}
    times: list[int] = []
    pos, size, damage = 0, len(data), ""
    while pos < size:
        if pos + RECORD.size > size:
            damage = "record cut short"
            break
        opcode, length = RECORD.unpack_from(data, pos)
        start, end = pos + RECORD.size, pos + RECORD.size + length
        if not known(opcode):
            damage = f"unknown record type {opcode:#04x} in a chunk"
            break
        if end > size or (opcode == MESSAGE and length < MESSAGE_HEAD.size):
            damage = "record cut short"
            break
        if opcode == MESSAGE:
            channel_id, _, log_time, _ = MESSAGE_HEAD.unpack_from(data, start)
            log_time = held(log_time)
            times.append(log_time)
            if channel_id in channels.wanted:
                log_times, positions, payloads = found.setdefault(channel_id, ([], [], []))
                log_times.append(log_time)
                positions.append((number << 32) + pos)
                payloads.append(data[start + MESSAGE_HEAD.size : end])
        elif opcode in (SCHEMA, CHANNEL):
            try:
                channels.register(opcode, data[start:end])
            except DamageError as e:
                damage = str(e)
                break
        pos = end
    if counted and times:
        channels.result.note_times(min(times), max(times), len(times))
    for channel_id, (log_times, positions, payloads) in found.items():
        channels.result.messages.add(channels.wanted[channel_id], log_times, positions, payloads)
    return damage, len(times)
