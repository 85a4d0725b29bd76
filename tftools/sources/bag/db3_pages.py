"""The message records of a damaged rosbag2 .db3 read straight from its pages, where sqlite gives up."""

# A file cut short or with damaged pages loses b-tree pages that lead to the messages, so sqlite
# refuses every query that passes through them; the table's leaf pages that survive still hold whole
# records. A rosbag2 ``messages`` row is the only record of its shape in the file: (id as rowid,
# integer topic_id, integer timestamp, blob data).

from __future__ import annotations

import mmap
import struct
from dataclasses import dataclass, field

_TABLE_LEAF = 0x0D
_FILE_HEADER = 100  # on page 1, before its b-tree page header
_LEAF_HEADER = 8
_U16, _U32 = struct.Struct(">H"), struct.Struct(">I")
Buffer = bytes | mmap.mmap
_INT_SIZES = {1: 1, 2: 2, 3: 3, 4: 4, 5: 6, 6: 8}  # serial type -> bytes of a big-endian signed integer


@dataclass
class Salvaged:
    """The message rows found, in (record time, id) order, and what was lost on the way."""

    rows: list[tuple[int, int, int, bytes]] = field(default_factory=list)  # id, topic id, time, data
    lost: int = 0  # records whose data ran into a missing or damaged overflow page


class _MalformedError(Exception):
    """A cell that is not a well-formed messages record."""


def salvage(data: Buffer) -> Salvaged:
    """Every messages record in whole leaf pages of the database image ``data``."""
    found = Salvaged()
    if len(data) < _FILE_HEADER:
        return found
    page_size = _U16.unpack_from(data, 16)[0]
    page_size = 65536 if page_size == 1 else page_size
    if page_size < 512 or page_size & (page_size - 1):
        return found
    pages = _Pages(data, page_size, page_size - data[20])
    seen: dict[int, tuple[int, int, int, bytes]] = {}
    for number in range(1, len(data) // page_size + 1):
        for cell in pages.leaf_cells(number):
            try:
                row = pages.message(cell)
            except _MalformedError:
                continue
            except _LostOverflowError:
                found.lost += 1
                continue
            if row is not None:
                seen[row[0]] = row  # freed pages may repeat a row: it is the same row
    found.rows = sorted(seen.values(), key=lambda row: (row[2], row[0]))
    return found


class _LostOverflowError(Exception):
    """A record whose continuation pages are missing."""


class _Pages:
    def __init__(self, data: Buffer, page_size: int, usable: int) -> None:
        self.data, self.page_size, self.usable = data, page_size, usable
        self.max_local = usable - 35
        self.min_local = (usable - 12) * 32 // 255 - 23

    def leaf_cells(self, number: int) -> list[int]:
        """Offsets of the cells of page ``number`` if it is a table leaf."""
        base = (number - 1) * self.page_size
        header = base + (_FILE_HEADER if number == 1 else 0)
        if self.data[header] != _TABLE_LEAF:
            return []
        count = _U16.unpack_from(self.data, header + 3)[0]
        pointers = header + _LEAF_HEADER
        if pointers + 2 * count > base + self.page_size:
            return []
        cells = [base + offset for (offset,) in _U16.iter_unpack(self.data[pointers : pointers + 2 * count])]
        return [c for c in cells if pointers + 2 * count <= c < base + self.usable]

    def message(self, cell: int) -> tuple[int, int, int, bytes] | None:
        """(id, topic id, timestamp, data) of a messages record; None for other tables' records."""
        size, pos = _varint(self.data, cell)
        rowid, pos = _varint(self.data, pos)
        record = self._payload(pos, size)
        header_size, at = _varint(record, 0)
        types = []
        while at < header_size:
            serial, at = _varint(record, at)
            types.append(serial)
        if len(types) != 4 or types[0] != 0 or not _is_int(types[1]) or not _is_int(types[2]):
            return None
        if types[3] < 12 or types[3] % 2:
            return None  # not a blob
        topic_id, at = _integer(record, header_size, types[1])
        timestamp, at = _integer(record, at, types[2])
        length = (types[3] - 12) // 2
        if at + length != len(record):
            raise _MalformedError
        return rowid - (1 << 64) * (rowid >> 63), topic_id, timestamp, bytes(record[at:])

    def _payload(self, pos: int, size: int) -> bytes:
        """A cell's record: its local bytes, then those of its overflow pages."""
        local = size if size <= self.max_local else self._local(size)
        if size > len(self.data) or pos + local > len(self.data):
            raise _MalformedError
        parts = [self.data[pos : pos + local]]
        remaining = size - local
        if remaining:
            (page,) = _U32.unpack_from(self.data, pos + local)
            while remaining > 0:
                start = (page - 1) * self.page_size
                if page < 1 or start + self.usable > len(self.data):
                    raise _LostOverflowError
                (page,) = _U32.unpack_from(self.data, start)
                take = min(remaining, self.usable - 4)
                parts.append(self.data[start + 4 : start + 4 + take])
                remaining -= take
        return b"".join(parts)

    def _local(self, size: int) -> int:
        local = self.min_local + (size - self.min_local) % (self.usable - 4)
        return local if local <= self.max_local else self.min_local


def _is_int(serial: int) -> bool:
    return serial in _INT_SIZES or serial in (8, 9)


def _integer(record: bytes, at: int, serial: int) -> tuple[int, int]:
    if serial in (8, 9):
        return serial - 8, at
    size = _INT_SIZES[serial]
    if at + size > len(record):
        raise _MalformedError
    return int.from_bytes(record[at : at + size], "big", signed=True), at + size


def _varint(data: Buffer, pos: int) -> tuple[int, int]:
    """SQLite's big-endian varint (up to 9 bytes, the ninth contributing all 8 bits)."""
    value = 0
    for i in range(9):
        if pos + i >= len(data):
            raise _MalformedError
        byte = data[pos + i]
        if i == 8:
            return (value << 8) | byte, pos + 9
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, pos + i + 1
    raise _MalformedError  # unreachable: the loop returns by the ninth byte
