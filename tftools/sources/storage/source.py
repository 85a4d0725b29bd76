"""``ByteSource``: one file's bytes read by range, whether it is local (``FileSource``: ``pread``, and
a map for record headers) or remote (``remote.RemoteSource``: fsspec's ranged reads): the readers of
every format read through one. ``Files``: the files a recording is made of (a file, or a ROS 2 bag
directory), wherever they are, each opened as a ``ByteSource``.

Byte ranges are read in few calls: ranges close together share one read (``runs``, the one merging
of ranges, local and remote: fsspec's ``merge_offset_ranges`` does the same, but fsspec is only there
for URLs), and a reader says what it will read soon (``ahead``): a local file's ranges are then asked
of the disk all at once, a remote file's fetched in few requests.
"""

from __future__ import annotations

import io
import mmap
import os
import stat
from abc import ABC, abstractmethod
from contextlib import suppress
from pathlib import Path
from typing import Any, BinaryIO, Protocol

import numpy as np

from tftools.core.arrays import BoolArray, Int64Array, UInt8Array
from tftools.sources import user_files
from tftools.sources.contents import Fetched
from tftools.sources.errors import BagNotFoundError, CorruptBagError, UnreadableFileError

MAX_GAP = 16 << 10  # bytes between two wanted ranges of a local file read along with them: cheaper than one more read
#: Bytes of cached pages the kernel maps along with a page of a file faulted in (Linux's fault-around: 64 KiB
#: by default), on either side of it: let go with a range of a map, or they stay resident (about a page a chunk
#: of a ROS1 bag read, 13 MB of a 4 h one's replay).
FAULT_AROUND = 64 << 10


class FileBytes(Protocol):
    """A whole file's bytes as record parsers read them: its length, slices and searches (a local
    file's map, a remote file's cached pieces, or bytes)."""

    def __len__(self) -> int: ...

    def __getitem__(self, key: slice, /) -> bytes: ...

    def find(self, sub: bytes, start: int, end: int, /) -> int: ...


def runs(starts: Int64Array, ends: Int64Array, gap: int) -> tuple[Int64Array, Int64Array, Int64Array, Int64Array]:
    """Ranges ``starts[i]:ends[i]`` joined where they are closer than ``gap`` (or overlap): each run's
    start and end (sorted), the run each range falls in, and the order that sorts the ranges."""
    order = np.argsort(starts, kind="stable")
    low, high = starts[order], ends[order]
    if not len(low):
        return low, high, np.zeros(0, np.int64), order
    reach = np.maximum.accumulate(high)
    first = np.append(True, low[1:] - reach[:-1] > gap)
    firsts = np.flatnonzero(first)
    run = np.empty(len(starts), np.int64)
    run[order] = np.cumsum(first) - 1
    return low[firsts], np.maximum.reduceat(high, firsts), run, order


class ByteSource(ABC):
    """A file's bytes, read by range; ``name`` to say which file, ``size`` its bytes. A context
    manager: ``close`` lets what it holds go (a local file's descriptor is opened again by a read after
    it: a bag of a thousand files need not hold a thousand open)."""

    name: str
    size: int
    gap = MAX_GAP  # bytes between two ranges read along with them (``read_ranges``)

    @abstractmethod
    def read(self, start: int, end: int) -> bytes:
        """The bytes ``start:end`` (fewer where the file ends first)."""

    @abstractmethod
    def read_into(self, view: memoryview, offset: int) -> bool:
        """Fill ``view`` from the file at ``offset``; False when the file ends first."""

    @abstractmethod
    def ahead(self, starts: Int64Array, ends: Int64Array) -> None:
        """These byte ranges will be read soon (in this order): a local file's are asked of the disk
        all at once, a remote file's fetched together as they are reached (one by one, each would wait)."""

    @abstractmethod
    def buffer(self) -> FileBytes:
        """The file's bytes for record parsers that read a header here and there (a ROS 1 bag's)."""

    @abstractmethod
    def release(self, start: int, end: int) -> None:
        """Bytes ``start:end`` have been read and are not needed again: what holds them may let go."""

    @abstractmethod
    def close(self) -> None:
        """Let go of what the source holds."""

    def __enter__(self) -> ByteSource:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def stream(self) -> BinaryIO:
        """The whole file as a file object to read through in order (a file read without an index)."""
        self.ahead(np.zeros(1, np.int64), np.full(1, self.size, np.int64))
        return io.BufferedReader(_Raw(self), 1 << 20)

    def read_ranges(self, starts: Int64Array, ends: Int64Array) -> tuple[UInt8Array, Int64Array, BoolArray]:
        """The bytes ``starts[i]:ends[i]``, read in runs (``runs``: ranges closer than ``gap`` share one
        read): the runs' bytes, where each range begins in them, and whether it was read whole."""
        if not len(starts):
            return np.zeros(0, np.uint8), starts, np.zeros(0, bool)
        run_start, run_end, run, _ = runs(starts, ends, self.gap)
        placed = np.cumsum(run_end - run_start) - (run_end - run_start)  # where each run goes in the bytes
        self.ahead(run_start, run_end)
        data = np.empty(int((run_end - run_start).sum()), np.uint8)
        view = data.data  # the array's bytes, read into in place
        complete = np.array(
            [
                self.read_into(view[at : at + end - start], start)
                for start, end, at in zip(run_start.tolist(), run_end.tolist(), placed.tolist(), strict=True)
            ],
            bool,
        )
        return data, placed[run] + starts - run_start[run], complete[run]


class _Raw(io.RawIOBase):
    """A ``ByteSource`` as a raw file object (buffered by ``ByteSource.stream``)."""

    def __init__(self, source: ByteSource) -> None:
        self.source, self.pos = source, 0

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        self.pos = max(0, offset + (0, self.pos, self.source.size)[whence])
        return self.pos

    def tell(self) -> int:
        return self.pos

    def readinto(self, buffer: Any) -> int:
        data = self.source.read(self.pos, self.pos + len(buffer))
        memoryview(buffer).cast("B")[: len(data)] = data
        self.pos += len(data)
        return len(data)


class FileSource(ByteSource):
    """A local file's bytes: read with ``pread``, its record headers through a map of it."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.name = str(path)
        self._fd = -1
        self._map: mmap.mmap | None = None
        self.size = self._open()

    def _open(self) -> int:
        """Open the file (a regular one only), and return its size."""
        try:  # not blocking: a FIFO would wait for a writer
            fd = os.open(self.path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
        except PermissionError as e:
            raise UnreadableFileError(str(self.path), e.strerror or str(e)) from None
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

    def close(self) -> None:
        if self._map is not None:
            with suppress(BufferError):  # a view still alive: the map closes when it is freed
                self._map.close()
            self._map = None
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1

    def buffer(self) -> FileBytes:
        return self.mapped()

    def mapped(self) -> mmap.mmap:
        """The file's map (``buffer``), as the map it is: for parsers that unpack from it in place."""
        if self._map is None:
            try:
                self._map = mmap.mmap(self.fd, 0, access=mmap.ACCESS_READ)
            except (OSError, ValueError) as e:  # ValueError: an empty file cannot be mapped
                raise CorruptBagError(str(self.path), getattr(e, "strerror", None) or str(e)) from None
        return self._map

    def release(self, start: int, end: int) -> None:
        """Unmap the pages read, and those the kernel mapped beside them (``FAULT_AROUND``): the file's
        pages then stay in the page cache instead of counting towards this process's resident memory."""
        if self._map is None or not hasattr(mmap, "MADV_DONTNEED"):
            return
        start = max(0, start - start % mmap.PAGESIZE - FAULT_AROUND)
        end = min(end + FAULT_AROUND, self.size)
        if end > start:
            self._map.madvise(mmap.MADV_DONTNEED, start, end - start)

    def stream(self) -> BinaryIO:
        return open(os.dup(self.fd), "rb")

    def ahead(self, starts: Int64Array, ends: Int64Array) -> None:
        if not hasattr(os, "posix_fadvise"):
            return
        for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
            if 0 <= start < end:  # a damaged index may give any range: a hint is only ever skipped
                with suppress(OSError, OverflowError):  # OverflowError: past what an off_t holds
                    os.posix_fadvise(self.fd, start, end - start, os.POSIX_FADV_WILLNEED)

    def read(self, start: int, end: int) -> bytes:
        return os.pread(self.fd, max(0, end - start), start)

    def read_into(self, view: memoryview, offset: int) -> bool:
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


class Files(ABC):
    """The files a recording is made of (``root``: a file, or a ROS 2 bag directory), wherever they
    are, named by paths below ``root``; a context manager (what was fetched is let go on leaving)."""

    root: Path

    @abstractmethod
    def is_dir(self, path: Path) -> bool: ...

    @abstractmethod
    def exists(self, path: Path) -> bool: ...

    @abstractmethod
    def size(self, path: Path) -> int:
        """The file's bytes; 0 when it cannot be told."""

    @abstractmethod
    def listing(self, directory: Path) -> list[Path]:
        """The files directly inside ``directory``."""

    @abstractmethod
    def load_yaml(self, path: Path) -> Any:
        """The document of a YAML file (within ``user_files``'s limits; ``UserFileError``)."""

    @abstractmethod
    def open(self, path: Path) -> ByteSource:
        """The file's bytes."""

    @abstractmethod
    def local(self, path: Path) -> Path:
        """The file on this machine, for what opens a file by name (SQLite); valid while this is open."""

    def fetched(self) -> Fetched | None:
        """What was fetched of remote files (None for local ones)."""
        return None

    def said(self, text: str) -> str:
        """``text`` with the files' names as the user gave them."""
        return text

    @abstractmethod
    def close(self) -> None:
        """Let go of what was fetched."""

    def __enter__(self) -> Files:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


class LocalFiles(Files):
    """A recording on this machine."""

    def __init__(self, root: Path) -> None:
        if not _exists(root):
            raise BagNotFoundError(str(root))
        self.root = root

    def is_dir(self, path: Path) -> bool:
        return path.is_dir()

    def exists(self, path: Path) -> bool:
        return _exists(path)

    def size(self, path: Path) -> int:
        try:
            return path.stat().st_size
        except (OSError, ValueError):
            return 0

    def listing(self, directory: Path) -> list[Path]:
        return [p for p in directory.iterdir() if not p.is_dir()]

    def load_yaml(self, path: Path) -> Any:
        return user_files.load(path)

    def open(self, path: Path) -> ByteSource:
        return FileSource(path)

    def local(self, path: Path) -> Path:
        return path

    def close(self) -> None:
        pass


def _exists(path: Path) -> bool:
    """Whether ``path`` exists; False for a name the system refuses (too long, say)."""
    try:
        return path.exists()
    except (OSError, ValueError):
        return False
