"""``fetches``: a .db3 query's message rows, fetch after fetch, as arrays and one byte buffer.

They are read through sqlite's C API (``_sqlite``, built from native/sqlite_module.cpp when sqlite's
headers are there at build time), else through Python's own sqlite3 module, which builds a tuple and
a bytes object a row: the same rows, about 2.5 times slower (a build without sqlite's headers still
reads .db3 files). Measured (issue 31): the 84,001 rows of the 600 s robot's tf in 75-107 ms through the
extension, 255-306 ms through sqlite3 (the whole read 0.15-0.17 s against 0.27-0.33 s), which the .db3
ingest goal cannot spare; the corpus's largest .db3 (8,542 rows) 13-16 ms against 24-28 ms.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from typing import Protocol

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array

#: The rows of one fetch: each row's topic id, record time and row id, where its payload starts in the
#: bytes and its length, and the bytes.
Fetched = tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]

_FIRST_ROWS = 64  # asked for first, before the payloads' size is known


class _Rows(Protocol):
    def fetch(self, rows: int, bytes: int) -> Fetched: ...


try:
    from tftools.sources.bag.rosbag2._sqlite import Messages as _Native
except ImportError:  # built without sqlite's headers
    _Native = None  # type: ignore[assignment,misc]

#: Added to a query's conditions: rows whose topic or time is not an integer or whose blob is not a
#: blob (sqlite stores any value in any column) are not messages. The extension skips them itself.
TYPED = (
    ""
    if _Native is not None
    else " AND typeof(topic_id) = 'integer' AND typeof(timestamp) = 'integer' AND typeof(data) = 'blob'"
)


def fetches(uri: str, query: str, rows: int, nbytes: int, *, native: bool = True) -> Iterator[Fetched]:
    """The rows of ``query``, ``SELECT topic, time, id, blob ...`` (its conditions ending in ``TYPED``,
    or of the typed rows only when ``native`` is False), on the database at ``uri`` opened read-only:
    fetch after fetch of up to ``rows`` rows and about ``nbytes`` of blobs. ``native`` False: through
    Python's sqlite3 even where the extension is built."""
    if native and _Native is not None:
        reader: _Rows = _Native(uri, query)
        while len((fetched := reader.fetch(rows, nbytes))[0]):
            yield fetched
            del fetched  # let go: the next fetch fills the same bytes again
        return
    db = sqlite3.connect(uri, uri=True, check_same_thread=False)
    try:
        # A file cut short says it has more pages than it holds; sqlite then refuses it whole
        # unless the schema is "writable" (a flag of this read-only connection, nothing written).
        db.execute("PRAGMA writable_schema=ON")
        cursor = db.execute(query)
        ask = _FIRST_ROWS
        while got := cursor.fetchmany(min(rows, ask)):
            topic, time, row_id, payloads = zip(*got, strict=True)
            length = np.fromiter(map(len, payloads), np.int64, len(payloads))
            # As many rows next time as make about ``nbytes``, at the sizes met so far.
            ask = max(1, min(rows, nbytes * len(got) // max(int(length.sum()), 1)))
            yield (
                np.array(topic, np.int64),
                np.array(time, np.int64),
                np.array(row_id, np.int64),
                np.cumsum(length) - length,
                length,
                np.frombuffer(b"".join(payloads), np.uint8),
            )
    finally:
        db.close()
