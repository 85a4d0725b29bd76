"""SQLite file-format facts the .db3 page readers share: the file header, page layout, varints, serial types."""

# From https://www.sqlite.org/fileformat2.html. A table b-tree page starts with its header (after
# the 100-byte file header on page 1): its type, u16 first freeblock, u16 cell count, u16 start of
# the cell content area, u8 fragmented bytes, and on interior pages a u32 right-most child; then the
# cells' u16 offsets in key order. Integers are big-endian.

from __future__ import annotations

import mmap
import struct
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

IntArray = npt.NDArray[np.int64]
Buffer = bytes | bytearray | mmap.mmap

MAGIC = b"SQLite format 3\x00"
FILE_HEADER = 100  # on page 1, before its b-tree page header
TABLE_INTERIOR, TABLE_LEAF = 0x05, 0x0D
INTERIOR_HEADER, LEAF_HEADER = 12, 8
CELL_COUNT = 3  # offset of a b-tree page's u16 cell count
RIGHT_CHILD = 8  # offset of an interior page's u32 right-most child
INT_SIZES = {1: 1, 2: 2, 3: 3, 4: 4, 5: 6, 6: 8}  # serial type -> bytes of a big-endian signed integer
INT_CONSTANTS = (8, 9)  # serial types of the integers 0 and 1, stored in no bytes
U16, U32 = struct.Struct(">H"), struct.Struct(">I")


class MalformedError(Exception):
    """Bytes that do not follow the file format."""


@dataclass(frozen=True)
class PageLayout:
    """A database's page size and usable size, and the local payload sizes they give."""

    page_size: int
    usable: int  # the page size less the bytes reserved at the end of each page

    @classmethod
    def of(cls, header: Buffer) -> PageLayout | None:
        """The layout the file header states; None when it states none that is valid."""
        if len(header) < FILE_HEADER:
            return None
        page_size = U16.unpack_from(header, 16)[0]
        page_size = 65536 if page_size == 1 else page_size
        if page_size < 512 or page_size & (page_size - 1):
            return None
        return cls(page_size, page_size - header[20])

    @property
    def max_local(self) -> int:
        """A table leaf cell's payload larger than this spills into overflow pages."""
        return self.usable - 35

    @property
    def min_local(self) -> int:
        return (self.usable - 12) * 32 // 255 - 23

    def local_size(self, size: int) -> int:
        """The bytes of a table leaf cell's ``size``-byte payload kept on the leaf page itself."""
        if size <= self.max_local:
            return size
        local = self.min_local + (size - self.min_local) % (self.usable - 4)
        return local if local <= self.max_local else self.min_local

    def local_sizes(self, sizes: IntArray) -> IntArray:
        """``local_size`` of each of ``sizes``."""
        local = self.min_local + (sizes - self.min_local) % (self.usable - 4)
        spilled = np.where(local <= self.max_local, local, self.min_local)
        return np.where(sizes <= self.max_local, sizes, spilled)


def varint(data: Buffer, pos: int) -> tuple[int, int]:
    """SQLite's big-endian varint at ``pos`` (up to 9 bytes, the ninth contributing all 8 bits),
    and the position after it."""
    value = 0
    for i in range(9):
        if pos + i >= len(data):
            raise MalformedError
        byte = data[pos + i]
        if i == 8:
            return (value << 8) | byte, pos + 9
        value = (value << 7) | (byte & 0x7F)
        if byte < 0x80:
            return value, pos + i + 1
    raise MalformedError  # unreachable: the loop returns by the ninth byte
