"""The message records of a damaged rosbag2 .db3 read straight from its pages, where sqlite gives up."""

# A file cut short or with damaged pages loses b-tree pages that lead to the messages, so sqlite
# refuses every query that passes through them; the table's leaf pages that survive still hold whole
# records. A rosbag2 ``messages`` row is the only record of its shape in the file: (id as rowid,
# integer topic_id, integer timestamp, blob data).

from __future__ import annotations

from dataclasses import dataclass, field

from tftools.sources.bag.db3_format import (
    FILE_HEADER,
    INT_CONSTANTS,
    INT_SIZES,
    LEAF_HEADER,
    TABLE_LEAF,
    U16,
    U32,
    Buffer,
    MalformedError,
    PageLayout,
    varint,
)


@dataclass
class Salvaged:
    """The message rows found, in (record time, id) order, and what was lost on the way."""

    rows: list[tuple[int, int, int, bytes]] = field(default_factory=list)  # id, topic id, time, data
    lost: int = 0  # records whose data ran into a missing or damaged overflow page


def salvage(data: Buffer) -> Salvaged:
    """Every messages record in whole leaf pages of the database image ``data``."""
    found = Salvaged()
    layout = PageLayout.of(data)
    if layout is None:
        return found
    pages = _Pages(data, layout)
    seen: dict[int, tuple[int, int, int, bytes]] = {}
    for number in range(1, len(data) // layout.page_size + 1):
        for cell in pages.leaf_cells(number):
            try:
                row = pages.message(cell)
            except MalformedError:
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
    def __init__(self, data: Buffer, layout: PageLayout) -> None:
        self.data, self.layout = data, layout
        self.page_size, self.usable = layout.page_size, layout.usable

    def leaf_cells(self, number: int) -> list[int]:
        """Offsets of the cells of page ``number`` if it is a table leaf."""
        base = (number - 1) * self.page_size
        header = base + (FILE_HEADER if number == 1 else 0)
        if self.data[header] != TABLE_LEAF:
            return []
        count = U16.unpack_from(self.data, header + 3)[0]
        pointers = header + LEAF_HEADER
        if pointers + 2 * count > base + self.page_size:
            return []
        cells = [base + offset for (offset,) in U16.iter_unpack(self.data[pointers : pointers + 2 * count])]
        return [c for c in cells if pointers + 2 * count <= c < base + self.usable]

    def message(self, cell: int) -> tuple[int, int, int, bytes] | None:
        """(id, topic id, timestamp, data) of a messages record; None for other tables' records."""
        size, pos = varint(self.data, cell)
        rowid, pos = varint(self.data, pos)
        record = self._payload(pos, size)
        header_size, at = varint(record, 0)
        types = []
        while at < header_size:
            serial, at = varint(record, at)
            types.append(serial)
        if len(types) != 4 or types[0] != 0 or not _is_int(types[1]) or not _is_int(types[2]):
            return None
        if types[3] < 12 or types[3] % 2:
            return None  # not a blob
        topic_id, at = _integer(record, header_size, types[1])
        timestamp, at = _integer(record, at, types[2])
        length = (types[3] - 12) // 2
        if at + length != len(record):
            raise MalformedError
        return rowid - (1 << 64) * (rowid >> 63), topic_id, timestamp, bytes(record[at:])

    def _payload(self, pos: int, size: int) -> bytes:
        """A cell's record: its local bytes, then those of its overflow pages."""
        local = self.layout.local_size(size)
        if size > len(self.data) or pos + local > len(self.data):
            raise MalformedError
        parts = [self.data[pos : pos + local]]
        remaining = size - local
        if remaining:
            (page,) = U32.unpack_from(self.data, pos + local)
            while remaining > 0:
                start = (page - 1) * self.page_size
                if page < 1 or start + self.usable > len(self.data):
                    raise _LostOverflowError
                (page,) = U32.unpack_from(self.data, start)
                take = min(remaining, self.usable - 4)
                parts.append(self.data[start + 4 : start + 4 + take])
                remaining -= take
        return b"".join(parts)


def _is_int(serial: int) -> bool:
    return serial in INT_SIZES or serial in INT_CONSTANTS


def _integer(record: bytes, at: int, serial: int) -> tuple[int, int]:
    if serial in INT_CONSTANTS:
        return serial - 8, at
    size = INT_SIZES[serial]
    if at + size > len(record):
        raise MalformedError
    return int.from_bytes(record[at : at + size], "big", signed=True), at + size
