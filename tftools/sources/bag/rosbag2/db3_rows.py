"""``Rows``: a .db3 query's message rows read through Python's own sqlite3, fetch after fetch, as arrays
and one byte buffer (no sqlite headers needed to build tftools)."""

from __future__ import annotations

import sqlite3

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array

#: The rows of one fetch: each row's topic id, record time and row id, where its payload starts in the
#: bytes and its length, and the bytes.
Fetched = tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]

_FIRST_ROWS = 64  # asked for first, before the payloads' size is known


class Rows:
    """The rows of ``SELECT topic, time, id, blob ...`` (a query that leaves out rows whose topic or
    time is not an integer or whose blob is not a blob) on a database opened read-only."""

    def __init__(self, uri: str, query: str) -> None:
        self._db = sqlite3.connect(uri, uri=True, check_same_thread=False)
        try:
            # A file cut short says it has more pages than it holds; sqlite then refuses it whole
            # unless the schema is "writable" (a flag of this read-only connection, nothing written).
            self._db.execute("PRAGMA writable_schema=ON")
            self._cursor = self._db.execute(query)
        except sqlite3.Error:
            self._db.close()
            raise
        self._ask = _FIRST_ROWS

    def fetch(self, rows: int, nbytes: int) -> Fetched:
        """The next rows, up to ``rows`` of them and about ``nbytes`` of payloads; none at the end."""
        got = self._cursor.fetchmany(min(rows, self._ask))
        if not got:
            self.close()
            none = np.zeros(0, np.int64)
            return none, none, none, none, none, np.zeros(0, np.uint8)
        topic, time, row_id, payloads = zip(*got, strict=True)
        length = np.fromiter(map(len, payloads), np.int64, len(payloads))
        total = int(length.sum())
        # As many rows next time as make about ``nbytes``, at the sizes met so far.
        self._ask = max(1, min(rows, nbytes * len(got) // max(total, 1)))
        data = np.frombuffer(b"".join(payloads), np.uint8)
        return (
            np.array(topic, np.int64),
            np.array(time, np.int64),
            np.array(row_id, np.int64),
            np.cumsum(length) - length,
            length,
            data,
        )

    def close(self) -> None:
        self._db.close()
