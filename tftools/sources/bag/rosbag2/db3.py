"""rosbag2 sqlite3 files (.db3): the transform messages of one file, read through its one sqlite connection
(``Database``; when damaged, from its pages)."""

from __future__ import annotations

import sqlite3
from collections.abc import Iterator
from contextlib import closing, suppress
from pathlib import Path

import numpy as np

from tftools.core.arrays import Int32Array
from tftools.sources.bag.contents import ProgressCallback
from tftools.sources.bag.formats import SQLITE3, ZSTD_MAGIC
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.rosbag2.database import Database, Fetched, PageError
from tftools.sources.bag.rosbag2.db3_salvage import Salvaged, salvage, salvage_topics
from tftools.sources.bag.scan import FileScan
from tftools.sources.bag.spans import Spans
from tftools.sources.bag.unpack import zstd_messages
from tftools.sources.codecs.select import HeaderCodec, Wanted, copied, select
from tftools.sources.codecs.wire import HEADER_BYTES
from tftools.sources.contents import Recorded
from tftools.sources.errors import CorruptBagError
from tftools.sources.storage.source import ByteSource, FileSource

_FETCH = 1 << 12  # rows per fetch at most: progress is reported between fetches
_FETCH_BYTES = 4 << 20  # and payload bytes (a fetch ends with the row that reaches them)
_MAX_TOPIC_ID = 1 << 24  # topic ids index a lookup array: rosbag2 numbers them from 1


class Db3File:
    """A rosbag2 sqlite3 file open for reading through one connection, its topics and statistics read
    once: read whole, or window after window."""

    def __init__(self, path: Path, source: ByteSource) -> None:
        self.path = path
        self.source = source
        wal = path.with_name(path.name + "-wal")
        self.unmerged = wal.name if wal.exists() and wal.stat().st_size > 0 else ""
        if source.read(0, len(SQLITE3.magic)) != SQLITE3.magic:
            raise CorruptBagError(str(path), "not an SQLite database")
        #: What says the file was cut short ("" where nothing does): sqlite reads the missing bytes of its last
        #: page as zeros, and a message there as if whole.
        self.cut = cut_short(source.read(0, _HEADER_BYTES), source.size, check_count=not self.unmerged)
        self.database = Database(path)
        try:
            self.topics = _topics(self.database)
            self.definitions = _definitions(self.database)
            self.statistics = _statistics(self.database)
        except BaseException:
            self.database.close()
            raise

    def scan(self, wanted: Wanted, progress: ProgressCallback, messages: MessageSet) -> FileScan:
        """The file's messages (into ``messages``, zstd-compressed ones decompressed) and description;
        ``CorruptBagError`` when nothing could be read."""
        result = FileScan(messages)
        channels, headers = _channels(self.topics, wanted, result, self.definitions)
        if self.statistics is not None:
            result.message_count, result.start, result.end = self.statistics
        every = len(channels) == sum(isinstance(row, tuple) for row in self.topics)
        _messages(self.database, channels, headers, result, progress, every_topic=every, cut=self.cut)
        if self.unmerged:
            result.note_problem(
                f"{self.unmerged} holds writes never merged into the database; they were not read"
                " (they are merged when a copy of the .db3 and its -wal file is opened once with sqlite3;"
                " opening the original would change it)"
            )
        return result

    def close(self) -> None:
        self.database.close()
        self.source.close()


#: A topic as the topics table holds it: id, name, type, serialization format, offered QoS profiles
#: and type hash ("" where the table has no such column).
TopicRow = tuple[int, str, str, str, str, str]
#: Columns of the topics table that rosbag2 added over time (Foxy, Iron).
_LATER_COLUMNS = ("offered_qos_profiles", "type_description_hash")


def _topics(db: Database) -> list[TopicRow | str]:
    """The topics table's rows (a line for each that is not a topic)."""
    try:
        present = {str(row[1]) for row in db.rows("PRAGMA table_info(topics)")}
        later = ", ".join(c if c in present else "''" for c in _LATER_COLUMNS)
        rows = db.rows(f"SELECT id, name, type, serialization_format, {later} FROM topics")
    except sqlite3.Error as e:
        with closing(FileSource(db.path)) as source:
            found = salvage_topics(source.mapped(), source.release)
        if not found:
            raise CorruptBagError(str(db.path), f"its topics table cannot be read: {e}") from None
        damage = f"its topics table is damaged (sqlite: {e}): {len(found)} topics read from its intact pages"
        return [damage, *found]
    topics: list[TopicRow | str] = []
    for topic_id, *texts in rows:
        if not isinstance(topic_id, int) or not 0 <= topic_id <= _MAX_TOPIC_ID:
            topics.append(f"a topic with id {_text(topic_id)!r} is skipped: not a topic id")
            continue
        name, type_name, encoding, qos, digest = (_text(t) for t in texts)
        topics.append((topic_id, name, type_name, encoding, qos, digest))
    return topics


def _definitions(db: Database) -> dict[str, str]:
    """Each type's message definition, as rosbag2 (Iron on) stores them; none in an older file."""
    try:
        rows = db.rows("SELECT topic_type, encoded_message_definition FROM message_definitions")
    except sqlite3.Error:
        return {}
    return {_text(type_name): _text(definition) for type_name, definition in rows}


def _channels(
    topics: list[TopicRow | str], wanted: Wanted, result: FileScan, definitions: dict[str, str]
) -> tuple[dict[int, int], set[int]]:
    """Topic ids to read -> MessageSet channels, and those of them read for their headers only;
    fills the description's topics."""
    channels: dict[int, int] = {}
    headers: set[int] = set()
    for row in topics:
        if isinstance(row, str):
            result.note_problem(row)
            continue
        topic_id, name, type_name, encoding, qos, digest = row
        result.topics[name] = type_name
        if qos:
            result.offered_qos[name] = qos
        codec, unread = (
            select(name, type_name, encoding, wanted, definitions.get(type_name, ""))
            if wanted.copy is None
            else (
                copied(
                    Recorded(name, type_name, encoding, definitions.get(type_name, ""), digest, qos=qos), wanted.copy
                ),
                None,
            )
        )
        result.note_skipped(unread)
        if codec is not None:
            channels[topic_id] = result.messages.channel(name, codec)
            if isinstance(codec, HeaderCodec):
                headers.add(topic_id)
    return channels, headers


def _statistics(db: Database) -> tuple[int, int, int] | None:
    """Messages, and the first and last record time; None for a damaged database (the messages read say)."""
    try:
        # One aggregate a query: min and max then search the timestamp index, count(*) counts its cells.
        ((count, start, end),) = db.rows(
            "SELECT (SELECT count(*) FROM messages), (SELECT min(timestamp) FROM messages),"
            " (SELECT max(timestamp) FROM messages)"
        )
    except sqlite3.Error:
        return None
    count, start, end = (v if isinstance(v, int) else 0 for v in (count, start, end))
    return count, start, end


def _messages(
    db: Database,
    channels: dict[int, int],
    headers: set[int],
    result: FileScan,
    progress: ProgressCallback,
    *,
    every_topic: bool = False,
    cut: str = "",
) -> None:
    """Add the wanted topics' messages, fetch after fetch in the table's order (decoded as they
    come, so they are never all held at once; ``MessageSet`` puts them in (record time, id) order);
    from the intact pages of a damaged file. Of the topics in ``headers``, sqlite hands over only
    the bytes that can hold a header of each message (a compressed one whole), not the images or
    points after it. Rows of other types (sqlite stores any value in any column) are not messages:
    left out. Where ``every_topic`` of the topics table is wanted, the reader leaves out rows of
    other topic ids itself where it can (``Database.skips_topics``). Without a window the rows are
    read from the table's pages where the extension can (``Database.pages``), else through sqlite. A file
    ``cut`` short is read from its whole pages only."""
    if not channels:
        return
    path = db.path
    size = path.stat().st_size
    lookup = lookup_of(channels)
    if cut:
        _add_salvaged(path, channels, headers, lookup, result, cut, size)
        return
    ids = ",".join(str(int(i)) for i in channels)
    headed = ",".join(str(int(i)) for i in headers)
    data = (
        f"CASE WHEN topic_id NOT IN ({headed}) OR substr(data, 1, {len(ZSTD_MAGIC)}) = x'{ZSTD_MAGIC.hex()}'"
        f" THEN data ELSE substr(data, 1, {HEADER_BYTES}) END"
        if headers
        else "data"
    )
    # NOT INDEXED: the table read in its own order, page after page, not through the timestamp index;
    # but a window's rows are found through it.
    # The topics' condition only where it spares sqlite other topics' rows (their blobs copied) or the
    # reader does not skip them itself: it costs more than the reader's own test.
    conditions = [] if every_topic and db.skips_topics else [f"topic_id IN ({ids})"]
    window = result.messages.window
    table = "messages NOT INDEXED"
    if window is not None:
        table = "messages"
        below = "<=" if window.closed else "<"
        conditions += [f"timestamp >= {int(window.first)}", f"timestamp {below} {int(window.last)}"]
    where = " AND ".join(c for c in (*conditions, db.typed.removeprefix(" AND ")) if c)
    query = f"SELECT topic_id, timestamp, id, {data} FROM {table}" + (f" WHERE {where}" if where else "")
    unpack = result.messages.unpack
    try:
        pages = (
            None if window is not None else db.pages(_FETCH, _FETCH_BYTES, list(channels), list(headers), HEADER_BYTES)
        )
        if pages is not None:
            try:
                _add(pages, lookup, result, size, progress)
                return
            except PageError:  # read them again through sqlite, forgetting what the pages gave
                pages = None  # and the page reader, its buffer and map
                result.messages = result.messages.emptied()
                result.messages.unpack = unpack
        _add(db.messages(query, _FETCH, _FETCH_BYTES, list(channels)), lookup, result, size, progress)
        return
    except sqlite3.Error as e:
        damage = f"sqlite: {e}"
    # Start again from the pages, forgetting what the query gave: out of the except block, whose error's
    # traceback holds the query's last fetch while the pages are read; sqlite's page cache let go too.
    result.messages = result.messages.emptied()
    with suppress(sqlite3.Error):
        db.rows("PRAGMA shrink_memory")
    _add_salvaged(path, channels, headers, lookup, result, damage, size)


def lookup_of(channels: dict[int, int]) -> Int32Array:
    """Topic id -> MessageSet channel, as an array to index."""
    lookup = np.zeros(max(channels) + 1, np.int32)
    lookup[list(channels)] = list(channels.values())
    return lookup


def _add_salvaged(
    path: Path,
    channels: dict[int, int],
    headers: set[int],
    lookup: Int32Array,
    result: FileScan,
    damage: str,
    size: int,
) -> None:
    """The messages of the file's whole pages into ``result`` (of ``headers`` topics, their headers' bytes),
    ``damage`` said as why they were read so; the stretches whose messages were lost with their pages noted."""
    found = _salvage(path, channels, headers, result, damage)
    spans, data = found.spans, memoryview(found.data)
    _unpack_if_compressed(bytes(data[spans.start[0] : spans.start[0] + len(ZSTD_MAGIC)]), result, size)
    result.messages.add_spans(lookup[spans.channel], spans, data)
    result.damaged += found.missing


#: The bytes of an SQLite file's header that say its page size and count.
_HEADER_BYTES = 100


def cut_short(header: bytes, size: int, *, check_count: bool = True) -> str:
    """What says an SQLite file of ``size`` bytes beginning with ``header`` was cut short: it ends inside a
    page, or (``check_count``: no -wal file beside it may hold the rest) before the pages its header counts
    (https://www.sqlite.org/fileformat2.html: the page size a big-endian u16 at 16, 1 meaning 65536; the
    page count a u32 at 28, valid while the u32 at 92 equals the change counter at 24); "" where nothing does."""
    if len(header) < _HEADER_BYTES:
        return ""
    page_size = int.from_bytes(header[16:18], "big")
    page_size = 65536 if page_size == 1 else page_size
    if page_size < 512 or page_size & (page_size - 1):  # not a page size: the header says nothing
        return ""
    pages = int.from_bytes(header[28:32], "big")
    counted = check_count and pages and header[92:96] == header[24:28]
    if size % page_size:
        return f"cut short: it ends {size % page_size} bytes into a page of {page_size}"
    if counted and size < pages * page_size:
        return f"cut short: {size // page_size} of its {pages} pages"
    return ""


def _add(
    fetches: Iterator[Fetched], lookup: Int32Array, result: FileScan, size: int, progress: ProgressCallback
) -> None:
    """The messages of ``fetches`` into ``result`` (its topic ids to channels through ``lookup``), the
    progress reported by record time after each fetch."""
    latest = result.start  # the latest record time met: rows may come a little out of order
    for fetched in fetches:
        topic, timestamp, row_id, start, length, payloads = fetched
        _unpack_if_compressed(payloads[start[0] : start[0] + length[0]][:4].tobytes(), result, size)
        spans = Spans(np.zeros_like(row_id), row_id, topic, timestamp, start, start + length)
        result.messages.add_spans(lookup[topic], spans, payloads.data)
        latest = max(latest, int(timestamp.max()))
        span = result.end - result.start  # progress estimated by record time
        progress(int(size * (latest - result.start) / span) if span > 0 else 0, size)
        del fetched, payloads  # let go: the next fetch fills the same bytes again
        if result.messages.full:  # the first headers of each topic alone were asked for, and are there
            return


def _salvage(path: Path, channels: dict[int, int], headers: set[int], result: FileScan, damage: str) -> Salvaged:
    with closing(FileSource(path)) as source:
        found = salvage(source.mapped(), channels, headers, HEADER_BYTES, source.release)
    read = len(found.spans)
    result.windowed = False
    if not read:
        raise CorruptBagError(str(path), f"no message could be read ({damage})")
    counted = result.message_count  # by sqlite, 0 where it could not count them
    if not counted:
        result.message_count, result.start, result.end = found.count, found.start, found.end
    lost = f", {found.lost} more lost their data" if found.lost else ""
    # every message sqlite counted is in the pages: the header's count of pages is what is damaged
    whole = counted and not found.lost and not found.missing and found.count == counted
    result.note_problem(
        f"the database is damaged ({damage}): read the {read} messages its intact pages hold of the topics read"
        + (f"; all {found.count:,} messages its statistics count are there, none lost" if whole else
           f"{lost}; those in missing or damaged pages are lost")
    )  # fmt: skip
    return found


def _text(value: object) -> str:
    """A text column's value, whatever sqlite holds there (NULL, bytes, a number)."""
    if isinstance(value, str):
        return value
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return "" if value is None else str(value)


def _unpack_if_compressed(payload: bytes, result: FileScan, size: int) -> None:
    """Have the payloads decompressed if the first is compressed: a bare .db3 of a bag compressed
    message by message."""
    if result.messages.unpack is None and payload[:4] == ZSTD_MAGIC:
        result.messages.unpack = zstd_messages(size)
