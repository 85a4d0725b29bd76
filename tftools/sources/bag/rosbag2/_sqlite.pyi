"""A query's rows read through sqlite's C API into arrays, fetch after fetch (native/sqlite_module.cpp)."""

import sqlite3

from tftools.core.arrays import Int64Array, UInt8Array

class SqliteError(sqlite3.DatabaseError):
    """sqlite's error while it read the rows (a damaged database, say)."""

class Messages:
    """The rows of ``query``, ``SELECT topic, time, id, blob ...``, on the database at the URI
    ``uri`` opened read-only (its schema writable: a flag of the connection, nothing written).
    A row whose topic or time is not an integer or whose blob is not a blob is skipped."""

    def __init__(self, uri: str, query: str) -> None: ...
    def fetch(
        self, rows: int, bytes: int
    ) -> tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]:
        """The next rows, up to ``rows`` of them or until their blobs reach ``bytes``: each row's
        topic, time and id, where its blob starts in the bytes and its length, and the bytes; none
        at the end."""
