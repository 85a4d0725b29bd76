"""The messages of a damaged rosbag2 .db3 read straight from its intact pages, where sqlite gives up."""

# A file cut short or with damaged pages loses b-tree pages that lead to the messages, so sqlite
# refuses every query that passes through them; the table's leaf pages that survive still hold whole
# records. A rosbag2 ``messages`` row is the only record of its shape in the file: (id as rowid,
# integer topic_id, integer timestamp, blob data).
#
# From https://www.sqlite.org/fileformat2.html (integers big-endian): the 100-byte file header on
# page 1 gives the page size (u16 at 16, 1 meaning 65536) and the bytes reserved at each page's end
# (u8 at 20). A table leaf page starts (after that header on page 1) with its type, 0x0D, a u16 at 3
# counting its cells, and after its 8-byte header its cells' u16 offsets. A cell is a varint payload
# size, a varint rowid, the payload's first bytes (all of it when it fits), and if it spills the u32
# number of its first overflow page; an overflow page holds the next one's number, then bytes. A
# record is a varint header size (counting itself), a varint serial type per column, then the values.

from __future__ import annotations

import mmap
import struct
from array import array
from collections.abc import Callable, Collection, Iterator

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.sources.bag.damage import DamageError
from tftools.sources.bag.formats import ZSTD_MAGIC
from tftools.sources.bag.spans import Spans

Bytes = bytes | mmap.mmap
Row = tuple[int, int, bytes]  # topic id, record time, payload
Release = Callable[[int, int], None]  # bytes start:end read and not needed again (``ByteSource.release``)

_FILE_HEADER = 100
_TABLE_LEAF, _LEAF_HEADER = 0x0D, 8
_INT_SIZES = {1: 1, 2: 2, 3: 3, 4: 4, 5: 6, 6: 8}  # serial type -> bytes of a big-endian signed integer
_INT_CONSTANTS = (8, 9)  # serial types of the integers 0 and 1, stored in no bytes
_U16, _U32 = struct.Struct(">H"), struct.Struct(">I")
_RELEASE_BYTES = 4 << 20  # of pages scanned between releases of the map's pages


class Salvaged:
    """The wanted topics' messages found, as rows of ``spans`` (the topic id as channel, the rowid as offset, the
    payload at ``data[start:end]``) in (record time, id) order; the count and time span of every topic's; how many
    wanted ones lost their overflow pages; the record-time stretches whose messages are missing (``lost_stretches``)."""

    __slots__ = ("count", "data", "end", "lost", "missing", "spans", "start")

    def __init__(
        self,
        spans: Spans | None = None,
        data: bytes | bytearray = b"",
        count: int = 0,
        start: int = 0,
        end: int = 0,
        lost: int = 0,
        missing: list[tuple[int, int]] | None = None,
    ) -> None:
        self.spans = Spans.empty() if spans is None else spans
        self.data = data
        self.count = count
        self.start = start
        self.end = end
        self.lost = lost
        self.missing = [] if missing is None else missing

    @property
    def rows(self) -> list[Row]:
        """(topic id, record time, payload) of each message found, in order."""
        s = self.spans
        return [
            (topic, time, bytes(self.data[start:end]))
            for topic, time, start, end in zip(
                s.channel.tolist(), s.time.tolist(), s.start.tolist(), s.end.tolist(), strict=True
            )
        ]


def salvage(
    data: Bytes,
    topic_ids: Collection[int],
    headed: Collection[int] = (),
    header_bytes: int = 0,
    release: Release | None = None,
) -> Salvaged:
    """Every messages record in the whole leaf pages of the database image ``data``, with the
    payloads of those of ``topic_ids`` (of ``headed`` ones, read for their header, the first ``header_bytes``
    but where compressed, as sqlite hands them over). Reads no byte outside ``data``, follows no overflow
    chain round a loop, and in all no more overflow pages than the file holds (however many records
    claim the same ones). ``release`` (a map's ``FileSource.release``) is told of the bytes scanned as it goes.
    Rows are held in flat arrays and one buffer of payloads (a Python object per message would double the read's
    memory)."""
    pages = _Pages.of(data)
    if pages is None:
        return Salvaged()
    every = (array("q"), array("q"))  # rowid, record time of every message: freed pages may repeat a row
    found = (array("q"), array("q"), array("q"), array("q"))  # rowid, topic id, time, payload start of wanted ones
    payloads = bytearray()
    lost = 0
    for number in pages.numbers(release):
        for cell in pages.leaf_cells(number):
            try:
                message = pages.message(cell, topic_ids)
            except DamageError as e:  # a malformed cell is skipped; one whose data is lost, counted
                lost += e.what == _LOST_OVERFLOW
                continue
            if message is None:
                continue
            rowid, topic_id, time, payload = message
            every[0].append(rowid)
            every[1].append(time)
            if payload is None:
                continue
            if topic_id in headed and payload[:4] != ZSTD_MAGIC:
                payload = payload[:header_bytes]  # not a camera's image held whole (memory)
            for column, value in zip(found, (rowid, topic_id, time, len(payloads)), strict=True):
                column.append(value)
            payloads += payload
    if not every[0]:
        return Salvaged(lost=lost)
    ids, times = _last_of_each(np.frombuffer(every[0], np.int64), np.frombuffer(every[1], np.int64))
    rowids, topics, recorded, starts = (np.frombuffer(column, np.int64) for column in found)
    ends = np.append(starts[1:], len(payloads)).astype(np.int64)
    kept = np.zeros(0, np.int64)
    if len(rowids):
        _, last = _last_of_each(rowids, np.arange(len(rowids), dtype=np.int64))
        kept = last[np.lexsort((rowids[last], recorded[last]))]
    spans = Spans(np.zeros(len(kept), np.int64), rowids[kept], topics[kept], recorded[kept], starts[kept], ends[kept])
    return Salvaged(spans, payloads, len(ids), int(times.min()), int(times.max()), lost, _missing(ids, times))


def _last_of_each(ids: Int64Array, values: Int64Array) -> tuple[Int64Array, Int64Array]:
    """The distinct ``ids`` in order, each with the value of its last row (a row a freed page repeats)."""
    unique, first_from_end = np.unique(ids[::-1], return_index=True)
    return unique, values[::-1][first_from_end]


def _missing(ids: Int64Array, times: Int64Array) -> list[tuple[int, int]]:
    """The record-time stretches of the messages missing between those read: rosbag2 numbers its messages from 1
    as they come, so a run of missing ids is messages lost with their pages, from the time of the one read before
    them to that of the one after (not before the first read or after the last: nothing marks those)."""
    gaps = np.flatnonzero(np.diff(ids) > 1)
    before, after = times[gaps], times[gaps + 1]
    return list(zip(np.minimum(before, after).tolist(), np.maximum(before, after).tolist(), strict=True))


def salvage_topics(data: Bytes, release: Release | None = None) -> list[tuple[int, str, str, str, str, str]]:
    """The rows of rosbag2's topics table in the whole leaf pages of the database image ``data``: (id, name,
    type, serialization format, offered QoS profiles, type hash), by id. A topics record is its id as rowid,
    then four texts, or five (Iron on); it is told from message_definitions' (as many texts) by its name,
    which begins with a slash, where a type does not."""
    pages = _Pages.of(data)
    found: dict[int, tuple[int, str, str, str, str, str]] = {}
    if pages is None:
        return []
    for number in pages.numbers(release):
        for cell in pages.leaf_cells(number):
            try:
                row = pages.texts(cell)
            except DamageError:
                continue
            if row is None:
                continue
            rowid, texts = row
            if len(texts) in (4, 5) and texts[0].startswith("/") and "/" in texts[1] and texts[2]:
                name, kind, encoding, qos = texts[:4]
                found.setdefault(rowid, (rowid, name, kind, encoding, qos, texts[4] if len(texts) == 5 else ""))
    return [found[rowid] for rowid in sorted(found)]


_MALFORMED = "bytes that do not follow the file format"
_LOST_OVERFLOW = "a record whose overflow pages are missing or damaged"


class _Pages:
    def __init__(self, data: Bytes, page_size: int, usable: int) -> None:
        self.data, self.page_size, self.usable = data, page_size, usable
        self.count = len(data) // page_size
        self.overflow_budget = self.count  # overflow pages still to be read

    @classmethod
    def of(cls, data: Bytes) -> _Pages | None:
        """The pages of ``data``, if its header states a valid page size."""
        if len(data) < _FILE_HEADER:
            return None
        size = _U16.unpack_from(data, 16)[0]
        size = 65536 if size == 1 else size
        if size < 512 or size & (size - 1) or size - data[20] < 480:
            return None
        return cls(data, size, size - data[20])

    def numbers(self, release: Release | None) -> Iterator[int]:
        """Every page's number, in order; every ``_RELEASE_BYTES`` the bytes read so far (overflow pages too,
        wherever they are) ``release``d: a map's pages read once would stay resident, the whole file."""
        step = max(1, _RELEASE_BYTES // self.page_size)
        for number in range(1, self.count + 1):
            yield number
            if release is not None and (number % step == 0 or number == self.count):
                release(0, len(self.data))

    def leaf_cells(self, number: int) -> list[int]:
        """Offsets of the cells of page ``number`` if it is a table leaf."""
        base = (number - 1) * self.page_size
        header = base + (_FILE_HEADER if number == 1 else 0)
        if self.data[header] != _TABLE_LEAF:
            return []
        pointers = header + _LEAF_HEADER
        end = pointers + 2 * _U16.unpack_from(self.data, header + 3)[0]
        if end > base + self.usable:
            return []
        cells = [base + offset for (offset,) in _U16.iter_unpack(self.data[pointers:end])]
        return [cell for cell in cells if end <= cell < base + self.usable]

    def message(self, cell: int, topic_ids: Collection[int]) -> tuple[int, int, int, bytes | None] | None:
        """(id, topic id, record time, payload) of the messages record at ``cell``, the payload only
        for ``topic_ids``; None for other tables' records."""
        size, rowid, at, record, header_size, _, types = self._record(cell, 5)
        integers = all(t in _INT_SIZES or t in _INT_CONSTANTS for t in types[1:3])
        if types[:1] != [0] or len(types) != 4 or not integers or types[3] < 12 or types[3] % 2:  # a blob: even, >= 12
            return None
        topic_id, head = _integer(record, header_size, types[1])
        time, head = _integer(record, head, types[2])
        if head + (types[3] - 12) // 2 != size:
            raise DamageError(_MALFORMED)
        rowid -= (1 << 64) * (rowid >> 63)
        if topic_id not in topic_ids:
            return rowid, topic_id, time, None
        return rowid, topic_id, time, record[head:] + self._spilled(at, len(record), size)

    def texts(self, cell: int) -> tuple[int, list[str]] | None:
        """(rowid, its texts) of a record at ``cell`` that is its rowid (a NULL) and texts alone; None for
        others. Its overflow pages are followed (a topic's QoS profiles may spill)."""
        size, rowid, at, record, header_size, head, types = self._record(cell, 7)
        if types[:1] != [0] or head != header_size or not all(t >= 13 and t % 2 for t in types[1:]):
            return None
        whole = record + self._spilled(at, len(record), size)
        texts, at = [], header_size
        for serial in types[1:]:
            length = (serial - 13) // 2
            if at + length > len(whole):
                raise DamageError(_MALFORMED)
            texts.append(whole[at : at + length].decode("utf-8", "replace"))
            at += length
        return rowid, texts

    def _record(self, cell: int, most: int) -> tuple[int, int, int, bytes, int, int, list[int]]:
        """The table leaf cell at ``cell``: its payload's size, its rowid, where its payload starts, the bytes of
        it in the cell, and of its record header the size, how far ``most`` serial types reach, and those types;
        ``DamageError`` where the cell does not fit its page."""
        page_end = cell - cell % self.page_size + self.usable
        size, at = _varint(self.data, cell, page_end)
        rowid, at = _varint(self.data, at, page_end)
        local = self._local_size(size)
        if at + local + 4 * (local < size) > page_end or size > len(self.data):
            raise DamageError(_MALFORMED)
        record = bytes(self.data[at : at + local])  # an mmap slice is bytes already: not copied again
        header_size, head = _varint(record, 0, len(record))
        types: list[int] = []
        while head < header_size and len(types) < most:
            serial, head = _varint(record, head, header_size)
            types.append(serial)
        return size, rowid, at, record, header_size, head, types

    def _spilled(self, at: int, local: int, size: int) -> bytes:
        """The bytes of a payload of ``size`` starting at ``at`` past the ``local`` ones in its cell: from its
        overflow pages."""
        return self._overflow(_U32.unpack_from(self.data, at + local)[0], size - local) if local < size else b""

    def _local_size(self, size: int) -> int:
        """The bytes of a table leaf cell's ``size``-byte payload kept in the cell itself."""
        max_local = self.usable - 35
        if size <= max_local:
            return size
        min_local = (self.usable - 12) * 32 // 255 - 23
        local = min_local + (size - min_local) % (self.usable - 4)
        return local if local <= max_local else min_local

    def _overflow(self, page: int, remaining: int) -> bytes:
        """``remaining`` bytes of the overflow chain from ``page`` on."""
        parts = []
        seen = set()
        while remaining > 0:
            start = (page - 1) * self.page_size
            if not 2 <= page <= self.count or page in seen or self.overflow_budget <= 0:
                raise DamageError(_LOST_OVERFLOW, start)
            seen.add(page)
            self.overflow_budget -= 1
            take = min(remaining, self.usable - 4)
            parts.append(self.data[start + 4 : start + 4 + take])
            (page,) = _U32.unpack_from(self.data, start)
            remaining -= take
        return b"".join(parts)


def _varint(data: Bytes, pos: int, end: int) -> tuple[int, int]:
    """SQLite's big-endian varint at ``pos``, before ``end`` (up to 9 bytes, the ninth contributing
    all 8 bits), and the position after it."""
    value = 0
    for i in range(9):
        if pos + i >= min(end, len(data)):
            raise DamageError(_MALFORMED)
        byte = data[pos + i]
        if i == 8:
            return (value << 8) | byte, pos + 9
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, pos + i + 1
    raise DamageError(_MALFORMED)  # unreachable: the loop returns by the ninth byte


def _integer(record: bytes, at: int, serial: int) -> tuple[int, int]:
    if serial in _INT_CONSTANTS:
        return serial - 8, at
    size = _INT_SIZES[serial]
    if at + size > len(record):
        raise DamageError(_MALFORMED)
    return int.from_bytes(record[at : at + size], "big", signed=True), at + size
