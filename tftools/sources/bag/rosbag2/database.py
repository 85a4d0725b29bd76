"""``Database``: a .db3 file's one read-only connection, which serves its small tables (topics, type
definitions, statistics) and its messages, fetch after fetch, as arrays and one byte buffer.

It goes through sqlite's C API (``_sqlite``, built from native/sqlite_module.cpp when sqlite's headers
are there at build time), else through Python's own sqlite3 module, which builds a tuple and a bytes
object a row: the same rows, about 2.5 times slower (a build without sqlite's headers still reads .db3
files). Measured (issue 31): the 84,001 rows of the 600 s robot's tf in 75-107 ms through the extension,
255-306 ms through sqlite3 (the whole read 0.15-0.17 s against 0.27-0.33 s), which the .db3 ingest goal
cannot spare; the corpus's largest .db3 (8,542 rows) 13-16 ms against 24-28 ms.

Without a window, the extension reads rosbag2's messages table from the file's pages itself (``pages``):
sqlite spends ~1,500 instructions a row where a leaf cell is a few varints and a blob. Wherever that
reader meets what it does not read as sqlite does, it raises ``PageError`` and the rows are read again
through sqlite.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Protocol
from urllib.parse import quote

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.errors import CorruptBagError

#: The rows of one fetch: each row's topic id, record time and row id, where its payload starts in the
#: bytes and its length, and the bytes.
Fetched = tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]

_FIRST_ROWS = 64  # asked for first, before the payloads' size is known
#: The conditions that leave out rows whose topic or time is not an integer or whose blob is not a blob
#: (sqlite stores any value in any column): they are not messages. The extension skips them itself.
_TYPED = " AND typeof(topic_id) = 'integer' AND typeof(timestamp) = 'integer' AND typeof(data) = 'blob'"


class _Rows(Protocol):
    def fetch(self, rows: int, bytes: int) -> Fetched: ...


class _Connection(Protocol):
    def rows(self, query: str) -> list[tuple[object, ...]]: ...

    def messages(self, query: str, topics: list[int]) -> _Rows: ...

    def close(self) -> None: ...


#: rosbag2's messages table, as its every release creates it (whitespace aside): the table the page
#: reader reads (its ``id`` the rowid).
_MESSAGES_TABLE = (
    "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL,"
    "data BLOB NOT NULL)"
)
#: Files beside a database that may hold pages newer than its own: sqlite reads it then.
_BESIDE = ("-wal", "-journal")

try:
    from tftools.sources.bag.rosbag2._sqlite import Database as _Native
    from tftools.sources.bag.rosbag2._sqlite import PageError as PageError
    from tftools.sources.bag.rosbag2._sqlite import TablePages as _TablePages
except ImportError:  # built without sqlite's headers

    class PageError(Exception):  # type: ignore[no-redef]
        """Never raised: there is no page reader."""

    _Native = None  # type: ignore[assignment,misc]
    _TablePages = None  # type: ignore[assignment,misc]


class Database:
    """The .db3 file at ``path`` opened read-only and immutable (sqlite neither writes nor creates -wal/-shm
    files next to it), until ``close``; through Python's sqlite3 where the extension is not built, or
    ``native`` is False. ``CorruptBagError`` when sqlite cannot open it."""

    def __init__(self, path: Path, *, native: bool = True) -> None:
        self.path = path
        self.native = native and _Native is not None
        #: Added to a message query's conditions (``messages``): the typed rows only, where the reader
        #: does not skip the others itself.
        self.typed = "" if self.native else _TYPED
        #: Whether ``messages`` leaves out the rows of topics not listed itself (sqlite's ``topic_id IN``
        #: costs ~270 instructions a row more); else the query's conditions must.
        self.skips_topics = self.native
        uri = f"file:{quote(str(path.resolve()))}?mode=ro&immutable=1"
        try:
            self._db: _Connection = _Native(uri) if self.native else _Python(uri)
        except (OSError, sqlite3.Error) as e:
            raise CorruptBagError(str(path), str(e)) from None

    def rows(self, query: str) -> list[tuple[object, ...]]:
        """The rows of a query of a few rows (text not in UTF-8 decoded with replacement characters);
        raises ``sqlite3.Error``."""
        return self._db.rows(query)

    def messages(self, query: str, rows: int, nbytes: int, topics: Sequence[int] = ()) -> Iterator[Fetched]:
        """The rows of ``query``, ``SELECT topic, time, id, blob ...`` (its conditions ending in
        ``typed``), fetch after fetch of up to ``rows`` rows and about ``nbytes`` of blobs; where
        ``skips_topics``, only those of ``topics`` (none: every topic); raises ``sqlite3.Error``."""
        return _fetches(self._db.messages(query, list(topics)), rows, nbytes)

    def pages(
        self, rows: int, nbytes: int, topics: Sequence[int], headed: Sequence[int], header_bytes: int
    ) -> Iterator[Fetched] | None:
        """The messages table's rows, as ``messages`` gives those of ``SELECT topic_id, timestamp, id, data
        FROM messages NOT INDEXED`` of ``topics`` (the blobs of ``headed`` ones cut to ``header_bytes``
        but where compressed), read from the file's pages; None where there is no page reader or the
        table is not rosbag2's or pages may lie beside the file; raises ``PageError`` (the caller reads
        them through sqlite then) and ``sqlite3.Error``."""
        if (
            _TablePages is None
            or not self.native
            or any(self.path.with_name(self.path.name + s).exists() for s in _BESIDE)
        ):
            return None
        found = self.rows("SELECT rootpage, sql FROM sqlite_master WHERE type = 'table' AND name = 'messages'")
        if len(found) != 1 or not isinstance(root := found[0][0], int) or not isinstance(sql := found[0][1], str):
            return None
        if "".join(sql.split()) != "".join(_MESSAGES_TABLE.split()) or not 1 < root < 1 << 32:
            return None
        try:
            reader = _TablePages(str(self.path), root, list(topics), list(headed), header_bytes)
        except PageError:  # its header or root page is not what the reader reads
            return None
        return _fetches(reader, rows, nbytes)

    def close(self) -> None:
        self._db.close()


def _fetches(reader: _Rows, rows: int, nbytes: int) -> Iterator[Fetched]:
    """``reader``'s rows, fetch after fetch."""
    while len((fetched := reader.fetch(rows, nbytes))[0]):
        yield fetched
        del fetched  # let go: the next fetch fills the same bytes again


class _Python:
    """``Database``'s connection through Python's sqlite3 module."""

    def __init__(self, uri: str) -> None:
        # check_same_thread: a replay reads its windows in a thread of its own, one read at a time.
        self._db = sqlite3.connect(uri, uri=True, check_same_thread=False)
        self._db.text_factory = lambda raw: raw.decode("utf-8", "replace")
        # A file cut short says it has more pages than it holds; sqlite then refuses it whole
        # unless the schema is "writable" (a flag of this read-only connection, nothing written).
        self._db.execute("PRAGMA writable_schema=ON")

    def rows(self, query: str) -> list[tuple[object, ...]]:
        return self._db.execute(query).fetchall()

    def messages(self, query: str, topics: list[int]) -> _Rows:
        return _PythonRows(self._db.execute(query))

    def close(self) -> None:
        self._db.close()


class _PythonRows:
    """A message query's rows through Python's sqlite3: as many rows a fetch as make about the bytes asked
    for, at the payload sizes met so far."""

    def __init__(self, cursor: sqlite3.Cursor) -> None:
        self._cursor = cursor
        self._ask = _FIRST_ROWS

    def fetch(self, rows: int, bytes: int) -> Fetched:
        got = self._cursor.fetchmany(min(rows, self._ask))
        if not got:
            empty = np.zeros(0, np.int64)
            return empty, empty, empty, empty, empty, np.zeros(0, np.uint8)
        topic, time, row_id, payloads = zip(*got, strict=True)
        length = np.fromiter(map(len, payloads), np.int64, len(payloads))
        self._ask = max(1, min(rows, bytes * len(got) // max(int(length.sum()), 1)))
        return (
            np.array(topic, np.int64),
            np.array(time, np.int64),
            np.array(row_id, np.int64),
            np.cumsum(length) - length,
            length,
            np.frombuffer(b"".join(payloads), np.uint8),
        )
