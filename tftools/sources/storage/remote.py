"""Remote recordings read through fsspec: listed, and each file made a local sparse copy of its size
that the readers fill range by range through its ``RemoteSource``, so that only the ranges they read
are fetched (``.db3``, ``.zstd`` and metadata.yaml files whole). Credentials and endpoints come from each
filesystem's standard environment (``AWS_PROFILE``, ``GOOGLE_APPLICATION_CREDENTIALS``, ...). Nothing
at a URL is ever written.

Reads are bounded: every request has timeouts and asks at most ``PIECE_BYTES``, at most ``BATCH_BYTES``
are held at once, a reply longer than asked is refused (a shorter one leaves zeros the readers find
damaged), and no file is taken to be larger than ``MAX_FILE_BYTES``.
"""

from __future__ import annotations

import bisect
import os
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.sources.errors import BagError, BagNotFoundError, MissingExtraError, RemoteError
from tftools.sources.storage.locations import BAG_SUFFIXES, is_glob, recordings_in
from tftools.sources.storage.source import ByteSource

try:
    import fsspec
    from fsspec import AbstractFileSystem
    from fsspec.utils import merge_offset_ranges
except ImportError:  # pragma: no cover - the extra's absence is tested in a subprocess
    raise MissingExtraError("reading recordings by URL") from None

PIECE_BYTES = 8 << 20  # asked in one request
BATCH_BYTES = 64 << 20  # asked at once (the replies are held in memory until written)
GAP_BYTES = 64 << 10  # between two ranges fetched along with them: cheaper than one more request
MAX_FILE_BYTES = 1 << 40
CONNECT_TIMEOUT, READ_TIMEOUT = 10, 30  # seconds
REQUEST_DEADLINE = 300  # seconds one HTTP request may take in all (a piece is at most PIECE_BYTES)
LISTING_DEADLINE = 20  # seconds a listing or a file's size may take in all, retries included
MIN_RATE = 64 << 10  # bytes a second a read must keep up, over a whole call (a server trickling a byte at a time)
#: Fetched whole: SQLite reads a file through its own pages, a .zstd file is decompressed whole.
_WHOLE_SUFFIXES = (".db3", ".zstd", ".yaml")
#: Files of a ROS 2 bag directory worth copying.
_BAG_DIRECTORY_SUFFIXES = (*BAG_SUFFIXES, ".zstd", ".yaml")


def filesystem(url: str) -> tuple[AbstractFileSystem, str]:
    """The fsspec filesystem of ``url`` (with timeouts and few retries) and the path in it."""
    protocol = url.partition("://")[0].lower()
    try:
        fs, path = fsspec.core.url_to_fs(url, **_options(protocol))
    except ImportError:
        raise MissingExtraError(f"reading {protocol}:// URLs") from None
    except ValueError as e:  # an unknown protocol
        raise RemoteError(url, f"cannot be read ({e})") from None
    return fs, path


def _options(protocol: str) -> dict[str, Any]:
    if protocol == "s3":
        timeouts = {"connect_timeout": CONNECT_TIMEOUT, "read_timeout": READ_TIMEOUT}
        return {"config_kwargs": {**timeouts, "retries": {"max_attempts": 2}}}
    if protocol in ("http", "https"):
        import aiohttp  # fsspec's HTTP filesystem is built on it

        # A request has a deadline as a whole, not only per read (a server trickling a byte at a time);
        # replies are taken as sent, never inflated (a gzip "bomb" would be inflated in memory before
        # its length is checked).
        timeout = aiohttp.ClientTimeout(total=REQUEST_DEADLINE, sock_connect=CONNECT_TIMEOUT, sock_read=READ_TIMEOUT)
        session = {"timeout": timeout, "auto_decompress": False, "headers": {"Accept-Encoding": "identity"}}
        return {"client_kwargs": session}
    if protocol in ("gs", "gcs"):
        return {"requests_timeout": READ_TIMEOUT}
    return {}


def _deadline(fs: AbstractFileSystem, seconds: float) -> dict[str, float]:
    """The keyword that gives a call of an async filesystem (S3, GCS, HTTP, Azure) an overall deadline:
    fsspec's ``sync(timeout=)``; their own timeouts are per read and per attempt, and retried."""
    return {"timeout": seconds} if getattr(fs, "async_impl", False) else {}


@contextmanager
def _remote(url: str, doing: str) -> Iterator[None]:
    """Any failure of a remote call as one ``RemoteError`` line: the filesystems raise their own
    libraries' exceptions (botocore's, aiohttp's, ...), not only ``OSError``."""
    try:
        yield
    except (BagError, MissingExtraError):  # said already
        raise
    except FileNotFoundError:
        raise BagNotFoundError(url) from None
    except Exception as e:
        detail = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise RemoteError(url, f"{doing} failed ({detail})") from None


def expand(url: str) -> list[str]:
    """The recordings ``url`` names (see ``locations.expand``): a glob's matches, a prefix's
    recordings, or the one recording (file or ROS 2 bag directory) it is, which must exist."""
    fs, path = filesystem(url)
    with _remote(url, "listing"):
        if is_glob(path):
            matches = sorted(fs.glob(path, **_deadline(fs, LISTING_DEADLINE)))
            if not matches:
                raise BagNotFoundError(url)
            return [found for match in matches for found in _below(fs, match, url)]
        if url.endswith("/"):
            found = _below(fs, path.rstrip("/"), url)
            if not found:
                raise BagNotFoundError(url)
            return found
        if not fs.exists(path, **_deadline(fs, LISTING_DEADLINE)):
            raise BagNotFoundError(url)
    return [url]


def _below(fs: AbstractFileSystem, path: str, url: str) -> list[str]:
    """The recordings at or below ``path``: itself when it is a file."""
    if not fs.isdir(path, **_deadline(fs, LISTING_DEADLINE)):
        return [fs.unstrip_protocol(path)] if path.endswith(BAG_SUFFIXES) else []
    files = [PurePosixPath(f).relative_to(path).as_posix() for f in fs.find(path, **_deadline(fs, LISTING_DEADLINE))]
    return [fs.unstrip_protocol(f"{path}/{name}" if name else path) for name in recordings_in(files)]


@dataclass
class RemoteCopy:
    """A remote file's local sparse copy (of its listed size), filled range by range."""

    fs: AbstractFileSystem
    url: str
    path: str  # in ``fs``
    size: int
    fd: int
    target: Path  # the local copy
    fetched: int = 0  # bytes received
    requests: int = 0  # ranges asked for
    _have_starts: list[int] = field(default_factory=list)  # the ranges fetched, sorted, apart
    _have_ends: list[int] = field(default_factory=list)

    def fill(self, starts: Sequence[int], ends: Sequence[int]) -> None:
        """Fetch what of ``starts[i]:ends[i]`` is not here yet (ranges closer than ``GAP_BYTES``
        fetched as one), ``BATCH_BYTES`` at a time."""
        runs = _merged([(max(0, int(s)), min(self.size, int(e))) for s, e in zip(starts, ends, strict=True)], GAP_BYTES)
        missing = [gap for start, end in runs for gap in self._missing(start, end)]
        pieces = [(s, min(s + PIECE_BYTES, end)) for start, end in missing for s in range(start, end, PIECE_BYTES)]
        batch: list[tuple[int, int]] = []
        for piece in pieces:
            if batch and sum(e - s for s, e in batch) + piece[1] - piece[0] > BATCH_BYTES:
                self._fetch(batch)
                batch = []
            batch.append(piece)
        if batch:
            self._fetch(batch)

    def _missing(self, start: int, end: int) -> Iterator[tuple[int, int]]:
        i = bisect.bisect_right(self._have_ends, start)
        while start < end:
            if i == len(self._have_starts) or self._have_starts[i] >= end:
                yield start, end
                return
            if self._have_starts[i] > start:
                yield start, self._have_starts[i]
            start = max(start, self._have_ends[i])
            i += 1

    def _fetch(self, pieces: list[tuple[int, int]]) -> None:
        self.requests += len(pieces)
        with _remote(self.url, "reading"):
            asked = sum(end - start for start, end in pieces)
            replies = self.fs.cat_ranges(
                [self.path] * len(pieces),
                [s for s, _ in pieces],
                [e for _, e in pieces],
                on_error="return",
                **_deadline(self.fs, CONNECT_TIMEOUT * len(pieces) + asked / MIN_RATE),  # a request a piece
            )
        for (start, end), reply in zip(pieces, replies, strict=True):
            if isinstance(reply, BaseException):
                with _remote(self.url, f"reading bytes {start}-{end}"):
                    raise reply
            if len(reply) > end - start:
                raise RemoteError(self.url, f"the server sent {len(reply)} bytes for {end - start} asked")
            os.pwrite(self.fd, reply, start)
            self.fetched += len(reply)
        merged = _merged([*zip(self._have_starts, self._have_ends, strict=True), *pieces], 0)
        self._have_starts = [s for s, _ in merged]
        self._have_ends = [e for _, e in merged]


def _merged(ranges: list[tuple[int, int]], gap: int) -> list[tuple[int, int]]:
    """``ranges`` sorted, those closer than ``gap`` (or touching) joined (fsspec's
    ``merge_offset_ranges``); empty ones left out."""
    kept = [(start, end) for start, end in ranges if start < end]
    if not kept:
        return []
    _, starts, ends = merge_offset_ranges(["f"] * len(kept), [s for s, _ in kept], [e for _, e in kept], gap)
    return [(int(start), int(end)) for start, end in zip(starts, ends, strict=True) if end is not None]


@dataclass
class LocalView:
    """A remote recording as the readers see it: ``path``, a local file or ROS 2 bag directory of
    sparse copies; what was fetched of how much, and whether some file had to be fetched whole."""

    path: Path
    copies: list[RemoteCopy]
    whole: bool

    def source(self, path: Path) -> ByteSource:
        """The file at ``path`` (one of the copies), read through fetches of what is read."""
        for copy in self.copies:
            if copy.target == path:
                return RemoteSource(copy)
        return ByteSource(path)  # a file made here (a decompressed one)

    @property
    def requests(self) -> int:
        return sum(c.requests for c in self.copies)

    @property
    def fetched(self) -> int:
        return sum(c.fetched for c in self.copies)

    @property
    def size(self) -> int:
        return sum(c.size for c in self.copies)


@contextmanager
def local_view(url: str) -> Iterator[LocalView]:
    """``url`` (a file or ROS 2 bag directory) as local sparse copies in a temporary directory, for
    as long as the context lasts: files fetched whole are fetched now, the others as read."""
    fs, path = filesystem(url.rstrip("/"))
    with ExitStack() as stack:
        folder = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="tftools-remote-")))
        with _remote(url, "listing"):
            if fs.isdir(path, **_deadline(fs, LISTING_DEADLINE)):
                local = folder / (PurePosixPath(path).name or "bag")
                local.mkdir()
                found = fs.find(path, maxdepth=1, **_deadline(fs, LISTING_DEADLINE))
                listed = [f for f in found if f.endswith(_BAG_DIRECTORY_SUFFIXES)]
                files = [(f, local / PurePosixPath(f).name) for f in listed]
            else:
                local = folder / (PurePosixPath(path).name or "recording")
                files = [(path, local)]
            sizes = [_size(fs, url, f) for f, _ in files]
        made = [
            stack.enter_context(_copy(fs, url, f, target, size)) for (f, target), size in zip(files, sizes, strict=True)
        ]
        whole = [c for c, (f, _) in zip(made, files, strict=True) if f.endswith(_WHOLE_SUFFIXES)]
        for copy in whole:
            copy.fill([0], [copy.size])
        yield LocalView(local, made, any(not c.path.endswith(".yaml") for c in whole))


@contextmanager
def whole_copy(url: str) -> Iterator[Path]:
    """``url`` (a file or ROS 2 bag directory) fetched whole into a temporary directory, for as long
    as the context lasts: for what reads every byte of a recording (a bag copier)."""
    with local_view(url) as view:
        for copy in view.copies:
            copy.fill([0], [copy.size])
        yield view.path


def _size(fs: AbstractFileSystem, url: str, path: str) -> int:
    size = fs.info(path, **_deadline(fs, LISTING_DEADLINE)).get("size")
    if not isinstance(size, int) or not 0 <= size <= MAX_FILE_BYTES:
        raise RemoteError(url, f"{PurePosixPath(path).name} has no usable size ({size!r})")
    return size


@contextmanager
def _copy(fs: AbstractFileSystem, url: str, path: str, target: Path, size: int) -> Iterator[RemoteCopy]:
    """A sparse copy of ``path`` at ``target``, while the context lasts."""
    fd = os.open(target, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o600)
    try:
        os.ftruncate(fd, size)
        copy = RemoteCopy(fs, url, path, size, fd, target)
        copy.fill([0], [min(size, GAP_BYTES)])  # its magic and header: how it is recognised
        yield copy
    finally:
        os.close(fd)


class RemoteSource(ByteSource):
    """A remote file's bytes: its local sparse copy, each range fetched before it is read."""

    def __init__(self, copy: RemoteCopy) -> None:
        super().__init__(copy.target)
        self.copy = copy

    def fetch(self, starts: Int64Array, ends: Int64Array) -> None:
        self.copy.fill(np.asarray(starts).tolist(), np.asarray(ends).tolist())

    def need(self, start: int, end: int) -> None:
        self.copy.fill([start], [end])
