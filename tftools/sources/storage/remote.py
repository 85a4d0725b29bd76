"""Remote recordings read through fsspec: listed, and each file read by range through its
``RemoteSource`` (fsspec's ranged reads, held in memory, never in a file), so that only the ranges
the readers need are fetched; a ``.db3`` file is fetched whole into a private temporary directory,
removed when the recording is closed (SQLite opens a file by name: see ``RemoteFiles.local``), and a
``.zstd`` file is read whole to be decompressed. Credentials and endpoints come from each
filesystem's standard environment (``AWS_PROFILE``, ``GOOGLE_APPLICATION_CREDENTIALS``, ...).
Nothing at a URL is ever written.

Reads are bounded: every request has timeouts and asks at most ``PIECE_BYTES``, at most ``BATCH_BYTES``
are asked at once, at most ``CACHE_BYTES`` of fetched pieces are kept for reads to come, a reply longer
than asked is refused (a shorter one leaves zeros the readers find damaged), and no file is taken to
be larger than ``MAX_FILE_BYTES``.
"""

from __future__ import annotations

import bisect
import shutil
import tempfile
from collections import deque
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager, nullcontext
from pathlib import Path, PurePosixPath
from typing import Any

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.sources import user_files
from tftools.sources.contents import Fetched
from tftools.sources.errors import BagError, BagNotFoundError, MissingExtraError, RemoteError
from tftools.sources.storage.locations import BAG_DIRECTORY_SUFFIXES, BAG_SUFFIXES, is_glob, recordings_in
from tftools.sources.storage.source import ByteSource, Files, FileSource, runs

try:
    import fsspec
    from fsspec import AbstractFileSystem
except ImportError:  # pragma: no cover - the extra's absence is tested in a subprocess
    raise MissingExtraError("reading recordings by URL") from None

PIECE_BYTES = 8 << 20  # asked in one request
BATCH_BYTES = 64 << 20  # asked at once (the replies are held in memory until read)
CACHE_BYTES = 64 << 20  # of pieces fetched kept for reads to come (the oldest let go first)
GAP_BYTES = 64 << 10  # between two ranges fetched along with them: cheaper than one more request
BLOCK_BYTES = 64 << 10  # fetched at least for a small read (a record header: the next ones are near)
MAX_FILE_BYTES = 1 << 40
CONNECT_TIMEOUT, READ_TIMEOUT = 10, 30  # seconds
REQUEST_DEADLINE = 300  # seconds one HTTP request may take in all (a piece is at most PIECE_BYTES)
LISTING_DEADLINE = 20  # seconds a listing or a file's size may take in all, retries included
MIN_RATE = 64 << 10  # bytes a second a read must keep up, over a whole call (a server trickling a byte at a time)
#: Fetched whole into a local file: SQLite opens a file by name (Python's sqlite3 has no virtual file system).
_LOCAL_SUFFIXES = (".db3",)


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


class RemoteSource(ByteSource):
    """A remote file's bytes, fetched by range as they are read: ranges closer than ``GAP_BYTES``
    fetched as one, a small read's ``BLOCK_BYTES`` after it with it, what a reader said it will read
    (``ahead``) fetched ``BATCH_BYTES`` at a time as the reads reach it; what was fetched is kept
    (``CACHE_BYTES`` at most, the oldest let go first) so that no byte is fetched twice while kept.
    ``fetched`` bytes were received in ``requests`` ranged reads. (fsspec's file caches fetch a block a
    request, without the overall deadline a call here has, and cannot be told what a reader will read.)"""

    gap = GAP_BYTES

    def __init__(self, fs: AbstractFileSystem, url: str, path: str, size: int) -> None:
        self.fs, self.url, self.path, self.size = fs, url, path, size
        self.name = url
        self.fetched = self.requests = 0
        self._starts: list[int] = []  # the pieces kept: sorted, apart
        self._pieces: list[bytes] = []
        self._order: deque[int] = deque()  # their starts, oldest first
        self._kept = 0
        self._plan: list[tuple[int, int]] = []  # ranges to be read soon, not fetched yet: sorted, apart

    def ahead(self, starts: Int64Array, ends: Int64Array) -> None:
        begin, stop = np.clip(starts, 0, self.size), np.clip(ends, 0, self.size)
        planned = np.array(self._plan, np.int64).reshape(-1, 2)
        keep = begin < stop
        run_start, run_end, _, _ = runs(
            np.concatenate([begin[keep], planned[:, 0]]), np.concatenate([stop[keep], planned[:, 1]]), self.gap
        )
        self._plan = list(zip(run_start.tolist(), run_end.tolist(), strict=True))

    def read(self, start: int, end: int) -> bytes:
        start, end = max(0, start), min(self.size, end)
        if end <= start:
            return b""
        small = end - start < BLOCK_BYTES
        if next(self._missing(start, end), None) is not None:
            self._keep(self._from_plan(start, end))
            if small and next(self._missing(start, end), None) is not None:
                self._keep([(start, min(self.size, start + BLOCK_BYTES))])
        return self._assemble(start, end, self._get([(start, end)]))

    def read_into(self, view: memoryview, offset: int) -> bool:
        """Fill ``view``, and let the pieces read go: ranges read into place are read once."""
        data = self.read(offset, offset + len(view))
        view[: len(data)] = data
        self._drop(offset, offset + len(data))
        return len(data) == len(view)

    def buffer(self) -> _Buffer:
        return _Buffer(self)

    def release(self, start: int, end: int) -> None:
        """Nothing: what a reader is done with may be near what it reads next (a chunk's index, the
        next chunk's header) and is let go with the oldest pieces, past ``CACHE_BYTES``."""

    def _drop(self, start: int, end: int) -> None:
        """Let go of the pieces kept inside ``start:end``."""
        first = bisect.bisect_left(self._starts, start)
        last = first
        while last < len(self._starts) and self._starts[last] + len(self._pieces[last]) <= end:
            self._kept -= len(self._pieces[last])
            last += 1
        del self._starts[first:last], self._pieces[first:last]

    def close(self) -> None:
        self._starts, self._pieces, self._plan, self._kept = [], [], [], 0
        self._order.clear()

    def _missing(self, start: int, end: int) -> Iterator[tuple[int, int]]:
        """The parts of ``start:end`` not kept."""
        i = max(0, bisect.bisect_right(self._starts, start) - 1)
        while start < end:
            if i == len(self._starts) or self._starts[i] >= end:
                yield start, end
                return
            if self._starts[i] > start:
                yield start, self._starts[i]
            start = max(start, self._starts[i] + len(self._pieces[i]))
            i += 1

    def _from_plan(self, start: int, end: int) -> list[tuple[int, int]]:
        """Of the ranges planned, ``BATCH_BYTES`` from the one holding ``start`` on (from ``start``
        when it is far into it), taken from the plan, when ``start:end`` is in it."""
        i = bisect.bisect_right(self._plan, (start, self.size + 1)) - 1
        i = i if i >= 0 and self._plan[i][1] > start else i + 1
        if i == len(self._plan) or self._plan[i][0] >= end:
            return []
        rest = self._plan[:i]
        first, last = self._plan[i]
        if start - first > self.gap:  # far into a long range (one read through in order): from here on
            rest.append((first, start))
            first = start
        taken, budget = [], BATCH_BYTES
        for s, e in [(first, last), *self._plan[i + 1 :]]:
            if budget <= 0:
                rest.append((s, e))
                continue
            taken.append((s, min(e, s + budget)))
            if s + budget < e:
                rest.append((s + budget, e))
            budget -= e - s
        self._plan = sorted(rest)
        return taken

    def _keep(self, ranges: list[tuple[int, int]]) -> None:
        """Fetch what of ``ranges`` is not kept, and keep it (the oldest pieces let go past ``CACHE_BYTES``)."""
        for start, data in self._get(ranges):
            i = bisect.bisect_left(self._starts, start)
            self._starts.insert(i, start)
            self._pieces.insert(i, data)
            self._order.append(start)
            self._kept += len(data)
        while self._kept > CACHE_BYTES and self._order:
            old = self._order.popleft()
            i = bisect.bisect_left(self._starts, old)
            if i < len(self._starts) and self._starts[i] == old:
                self._kept -= len(self._pieces[i])
                del self._starts[i], self._pieces[i]

    def _get(self, ranges: list[tuple[int, int]]) -> list[tuple[int, bytes]]:
        """The parts of ``ranges`` not kept, fetched: ``PIECE_BYTES`` a request, ``BATCH_BYTES`` a call."""
        missing = [gap for start, end in ranges for gap in self._missing(start, end)]
        pieces = [(s, min(s + PIECE_BYTES, end)) for start, end in missing for s in range(start, end, PIECE_BYTES)]
        got: list[tuple[int, bytes]] = []
        batch: list[tuple[int, int]] = []
        for piece in pieces:
            if batch and sum(e - s for s, e in batch) + piece[1] - piece[0] > BATCH_BYTES:
                got += self._fetch(batch)
                batch = []
            batch.append(piece)
        return got + self._fetch(batch) if batch else got

    def _fetch(self, pieces: list[tuple[int, int]]) -> list[tuple[int, bytes]]:
        """The pieces, each in one request (a reply shorter than asked padded with zeros). A server under
        load drops a request now and then (a reset, a timeout): what failed is asked once more."""
        try:
            replies = self._request(pieces)
        except Exception:
            replies = self._request(pieces, again=True)
        failed = [i for i, reply in enumerate(replies) if isinstance(reply, Exception)]
        if failed and not any(isinstance(replies[i], FileNotFoundError) for i in failed):
            for i, reply in zip(failed, self._request([pieces[i] for i in failed], again=True), strict=True):
                replies[i] = reply
        got = []
        for (start, end), reply in zip(pieces, replies, strict=True):
            if isinstance(reply, BaseException):
                with _remote(self.url, f"reading bytes {start}-{end}"):
                    raise reply
            if len(reply) > end - start:
                raise RemoteError(self.url, f"the server sent {len(reply)} bytes for {end - start} asked")
            self.fetched += len(reply)
            got.append((start, bytes(reply).ljust(end - start, b"\0")))
        return got

    def _request(self, pieces: list[tuple[int, int]], again: bool = False) -> list[bytes | Exception]:
        """One call for the pieces, within its deadline: each piece's bytes, or what its request met;
        a failure of the call itself raised (as a ``RemoteError`` when ``again``)."""
        self.requests += len(pieces)
        asked = sum(end - start for start, end in pieces)
        with _remote(self.url, "reading") if again else nullcontext():
            replies: list[bytes | Exception] = self.fs.cat_ranges(
                [self.path] * len(pieces),
                [s for s, _ in pieces],
                [e for _, e in pieces],
                on_error="return",
                **_deadline(self.fs, CONNECT_TIMEOUT * len(pieces) + asked / MIN_RATE),  # a request a piece
            )
        return replies

    def _assemble(self, start: int, end: int, fetched: list[tuple[int, bytes]]) -> bytes:
        """``start:end`` from the pieces kept and ``fetched``, which cover it."""
        i = max(0, bisect.bisect_right(self._starts, start) - 1)
        found = [*zip(self._starts[i:], self._pieces[i:], strict=True), *fetched]
        parts, pos = [], start
        for s, data in sorted(found, key=lambda piece: piece[0]):
            if s > pos or s >= end:
                break
            if s + len(data) > pos:
                parts.append(memoryview(data)[pos - s : min(end, s + len(data)) - s])
                pos = s + len(data)
        return b"".join(parts)


class _Buffer:
    """A remote file's bytes as record parsers read them (``source.FileBytes``): slices and searches
    read through its source."""

    WINDOW = 1 << 20  # searched at a time

    def __init__(self, source: RemoteSource) -> None:
        self.source = source

    def __len__(self) -> int:
        return self.source.size

    def __getitem__(self, key: slice, /) -> bytes:
        start, stop, _ = key.indices(self.source.size)
        return self.source.read(start, stop)

    def find(self, sub: bytes, start: int, end: int, /) -> int:
        end = min(end, self.source.size)
        while start < end:
            stop = min(end, start + self.WINDOW)
            hit = self.source.read(start, stop).find(sub)
            if hit >= 0:
                return start + hit
            if stop == end:
                break
            start = stop - len(sub) + 1
        return -1


class RemoteFiles(Files):
    """A remote recording (a file, or a ROS 2 bag directory: listed once, on opening), each file read
    through a ``RemoteSource``; a ``.db3`` file fetched whole into a private temporary directory, once,
    removed on closing."""

    def __init__(self, url: str) -> None:
        self.url = url.rstrip("/")
        self.fs, path = filesystem(self.url)
        self.root = Path(path)
        self._stack = ExitStack()
        self._folder: Path | None = None
        self._sources: list[RemoteSource] = []
        self._local: dict[Path, Path] = {}
        self._whole = 0  # bytes fetched whole into local files
        with _remote(url, "listing"):
            self._dir = bool(self.fs.isdir(path, **_deadline(self.fs, LISTING_DEADLINE)))
            if self._dir:
                found = self.fs.find(path, maxdepth=1, detail=True, **_deadline(self.fs, LISTING_DEADLINE))
                listed = {f: i for f, i in found.items() if PurePosixPath(f).suffix in BAG_DIRECTORY_SUFFIXES}
            else:
                listed = {path: self.fs.info(path, **_deadline(self.fs, LISTING_DEADLINE))}
        self._sizes = {Path(f): _usable_size(url, f, info.get("size")) for f, info in listed.items()}
        self._paths = {Path(f): f for f in listed}  # as the filesystem names them (an HTTP one: a URL)

    def is_dir(self, path: Path) -> bool:
        return self._dir and path == self.root

    def exists(self, path: Path) -> bool:
        return path in self._sizes or self.is_dir(path)

    def size(self, path: Path) -> int:
        return self._sizes.get(path, 0)

    def listing(self, directory: Path) -> list[Path]:
        return [path for path in self._sizes if path.parent == directory]

    def load_yaml(self, path: Path) -> Any:
        if self.size(path) > user_files.MAX_BYTES:
            raise user_files.UserFileError(f"larger than {user_files.MAX_BYTES >> 20} MiB")
        with self.open(path) as source:
            return user_files.load_text(source.read(0, source.size).decode("utf-8", "replace"))

    def open(self, path: Path) -> ByteSource:
        if path.suffix in _LOCAL_SUFFIXES:
            return FileSource(self.local(path))
        if path not in self._sizes:
            raise BagNotFoundError(self._url_of(path))
        source = RemoteSource(self.fs, self._url_of(path), self._paths[path], self._sizes[path])
        self._sources.append(source)
        return source

    def local(self, path: Path) -> Path:
        """The file fetched whole into a private temporary directory (once while this is open)."""
        if path not in self._local:
            if self._folder is None:
                self._folder = Path(self._stack.enter_context(tempfile.TemporaryDirectory(prefix="tftools-remote-")))
            target = self._folder / path.name
            self.download(path, target)
            self._local[path] = target
        return self._local[path]

    def download(self, path: Path, target: Path) -> None:
        """The file fetched whole into ``target`` (a new file), ``BATCH_BYTES`` at a time."""
        size = self.size(path)
        free = shutil.disk_usage(target.parent).free
        if size > free:
            raise RemoteError(self._url_of(path), f"needs {size >> 20} MiB on this machine, {free >> 20} MiB are free")
        source = RemoteSource(self.fs, self._url_of(path), self._paths[path], size)
        with target.open("xb") as out:
            for start in range(0, size, BATCH_BYTES):
                out.write(source.read(start, min(size, start + BATCH_BYTES)))
        self._whole += source.fetched

    def fetched(self) -> Fetched:
        received = sum(s.fetched for s in self._sources) + self._whole
        return Fetched(received, sum(self._sizes.values()), bool(self._local))

    def said(self, text: str) -> str:
        for remote, local in self._local.items():
            text = text.replace(str(local), self._url_of(remote))
        # The URL may be said already (a remote read's own error), and holds the path: left as it is.
        return self.url.join(part.replace(str(self.root), self.url) for part in text.split(self.url))

    def close(self) -> None:
        for source in self._sources:
            source.close()
        self._stack.close()

    def _url_of(self, path: Path) -> str:
        return self.url if path == self.root else f"{self.url}/{path.relative_to(self.root).as_posix()}"


def _usable_size(url: str, path: str, size: object) -> int:
    if not isinstance(size, int) or not 0 <= size <= MAX_FILE_BYTES:
        raise RemoteError(url, f"{PurePosixPath(path).name} has no usable size ({size!r})")
    return size


@contextmanager
def whole_copy(url: str) -> Iterator[Path]:
    """``url`` (a file or ROS 2 bag directory) fetched whole into a temporary directory, for as long
    as the context lasts: for what reads every byte of a recording (a bag copier)."""
    files = RemoteFiles(url)
    with files, tempfile.TemporaryDirectory(prefix="tftools-remote-") as folder:
        local = Path(folder) / (files.root.name or "recording")
        if files.is_dir(files.root):
            local.mkdir()
            for path in files.listing(files.root):
                files.download(path, local / path.name)
        else:
            files.download(files.root, local)
        yield local
