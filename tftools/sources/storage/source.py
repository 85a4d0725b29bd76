"""``ByteSource``: one file's bytes read by range, whether it is local (``pread``) or remote (fsspec's
ranged reads, ``remote.RemoteSource``): the readers of every format read through one.

Byte ranges are read in few calls: ranges close together share one read, and the system is asked to
fetch them all first, so a file not in the page cache costs one disk wait, not one per range.
"""

from __future__ import annotations

import os
import stat
from contextlib import suppress
from pathlib import Path
from typing import BinaryIO

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.sources.errors import CorruptBagError

MAX_GAP = 16 << 10  # bytes between two wanted ranges read along with them: cheaper than one more read


class ByteSource:
    """A local file's bytes, read by range. ``path`` is where the file is on this machine, for what
    must open it by name (SQLite); ``fileno`` for what maps it. ``close`` lets its descriptor go (a
    read after it opens the file again: a bag of a thousand files need not hold a thousand open)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._fd = -1
        self.size = self._open()

    def _open(self) -> int:
        """Open the file (a regular one only), and return its size."""
        try:  # not blocking: a FIFO would wait for a writer
            fd = os.open(self.path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
        except OSError as e:
            raise CorruptBagError(str(self.path), e.strerror or str(e)) from None
        status = os.fstat(fd)
        if not stat.S_ISREG(status.st_mode):
            os.close(fd)
            raise CorruptBagError(str(self.path), "not a regular file (a FIFO, socket or device)")
        self._fd = fd
        return status.st_size

    @property
    def fd(self) -> int:
        if self._fd < 0:
            self._open()
        return self._fd

    def fileno(self) -> int:
        return self.fd

    def close(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1

    def __enter__(self) -> ByteSource:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def fetch(self, starts: Int64Array, ends: Int64Array) -> None:
        """Have ``starts[i]:ends[i]`` here before they are read: a remote file's are fetched."""

    def ahead(self, starts: Int64Array, ends: Int64Array) -> None:
        """These byte ranges will be read soon: a remote file's are fetched now, a local file's read
        ahead by the system (one by one, each would wait for the disk)."""
        self.fetch(starts, ends)
        self._advise(starts, ends)

    def _advise(self, starts: Int64Array, ends: Int64Array) -> None:
        """Have the system start reading these byte ranges, all at once."""
        if not hasattr(os, "posix_fadvise"):
            return
        for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
            if 0 <= start < end:  # a damaged index may give any range: a hint is only ever skipped
                with suppress(OSError, OverflowError):  # OverflowError: past what an off_t holds
                    os.posix_fadvise(self.fd, start, end - start, os.POSIX_FADV_WILLNEED)

    def need(self, start: int, end: int) -> None:
        """``start:end`` is read next (a remote file's is fetched; a local file's is there)."""

    def whole(self) -> None:
        """Every byte is read next (a file read without an index)."""
        self.need(0, self.size)

    def stream(self) -> BinaryIO:
        """The whole file as a file object to read through in order (fetched whole first)."""
        self.whole()
        return open(os.dup(self.fd), "rb")

    def read(self, start: int, end: int) -> bytes:
        """The bytes ``start:end`` (fewer where the file ends first)."""
        self.need(start, end)
        return os.pread(self.fd, max(0, end - start), start)

    def read_ranges(self, starts: Int64Array, ends: Int64Array) -> tuple[UInt8Array, Int64Array, BoolArray]:
        """The bytes ``starts[i]:ends[i]``, read in runs (ranges closer than ``MAX_GAP`` share one
        read): the runs' bytes, where each range begins in them, and whether it was read whole."""
        if not len(starts):
            return np.zeros(0, np.uint8), starts, np.zeros(0, bool)
        order = np.argsort(starts, kind="stable")
        low, high = starts[order], ends[order]
        reach = np.maximum.accumulate(high)
        first = np.append(True, low[1:] - reach[:-1] > MAX_GAP)
        firsts = np.flatnonzero(first)
        run = np.cumsum(first) - 1
        run_start, run_end = low[firsts], np.maximum.reduceat(high, firsts)
        placed = np.cumsum(run_end - run_start) - (run_end - run_start)  # where each run goes in the bytes
        self.fetch(run_start, run_end)
        self._advise(run_start, run_end)
        data = np.empty(int((run_end - run_start).sum()), np.uint8)
        view = data.data  # the array's bytes, read into in place
        complete = np.array(
            [
                self.read_into(view[at : at + end - start], start)
                for start, end, at in zip(run_start.tolist(), run_end.tolist(), placed.tolist(), strict=True)
            ],
            bool,
        )
        where = np.empty(len(starts), np.int64)
        where[order] = placed[run] + low - run_start[run]
        read = np.empty(len(starts), bool)
        read[order] = complete[run]
        return data, where, read

    def read_into(self, view: memoryview, offset: int) -> bool:
        """Fill ``view`` from the file at ``offset``; False when the file ends first."""
        while len(view):
            if hasattr(os, "preadv"):
                got = os.preadv(self.fd, [view], offset)
            else:  # a system without it (e.g. an older macOS): read, then copy
                part = os.pread(self.fd, len(view), offset)
                view[: len(part)] = part
                got = len(part)
            if not got:
                return False
            view, offset = view[got:], offset + got
        return True
