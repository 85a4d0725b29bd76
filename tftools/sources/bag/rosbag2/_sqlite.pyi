"""One read-only sqlite connection: small queries as tuples, messages into arrays fetch after fetch
(native/sqlite_module.cpp); the messages table read from its pages (native/db3_pages.hpp)."""

import sqlite3

from tftools.core.arrays import Int64Array, UInt8Array

class SqliteError(sqlite3.DatabaseError):
    """sqlite's error while it read (a damaged database, say)."""

class PageError(Exception):
    """Pages the page reader does not read as sqlite does: sqlite is to read them."""

class TablePages:
    """The rows of rosbag2's messages table whose root page is ``root``, in the table's order, read from
    the file's pages: those of the topic ids ``wanted``, the blobs of those of ``headed`` cut to
    ``header_bytes`` but where compressed. A row whose topic or time is not an integer or whose blob is
    not a blob is skipped. ``PageError`` (here or from ``fetch``) at pages it does not read."""

    def __init__(self, path: str, root: int, wanted: list[int], headed: list[int], header_bytes: int) -> None: ...
    def fetch(
        self, rows: int, bytes: int
    ) -> tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]:
        """As ``Messages.fetch``."""

class Messages:
    """The rows of a query ``SELECT topic, time, id, blob ...`` (``Database.messages``). A row whose
    topic or time is not an integer or whose blob is not a blob is skipped, as is one whose topic is
    not among those listed (where some are)."""

    def fetch(
        self, rows: int, bytes: int
    ) -> tuple[Int64Array, Int64Array, Int64Array, Int64Array, Int64Array, UInt8Array]:
        """The next rows, up to ``rows`` of them or until their blobs reach ``bytes``: each row's
        topic, time and id, where its blob starts in the bytes and its length, and the bytes; none
        at the end."""

class Database:
    """The database at the URI ``uri`` opened read-only (its schema writable: a flag of the
    connection, nothing written), until ``close``."""

    def __init__(self, uri: str) -> None: ...
    def rows(self, query: str) -> list[tuple[object, ...]]:
        """Every row of ``query``, each column as Python's sqlite3 gives it (text not in UTF-8
        decoded with replacement characters)."""
    def messages(self, query: str, topics: list[int] = ...) -> Messages:
        """The message rows of ``query`` on this connection, those of ``topics`` only where any are listed."""
    def close(self) -> None:
        """Let the connection go (once the message queries on it are let go too)."""
