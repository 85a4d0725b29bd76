"""The .db3 reader: sqlite reads the tf topics' rows fetch after fetch and writes nothing beside the
file; a file sqlite refuses is salvaged from its intact pages, within bounds."""

from __future__ import annotations

import hashlib
import sqlite3
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import NS, T0, Tf, string_cdr, tf_cdr
from tftools.sources.bag.contents import ProgressCallback
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.rosbag2 import db3 as db3_reader
from tftools.sources.bag.spans import Spans

TOPICS = [
    (1, "/tf", "tf2_msgs/msg/TFMessage"),
    (2, "/tf_static", "tf2_msgs/msg/TFMessage"),
    (3, "/camera/image_raw", "sensor_msgs/msg/Image"),
    (4, "/chatter", "std_msgs/msg/String"),
]
MESSAGES_TABLE = (
    "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,"
    " data BLOB NOT NULL)"
)
PAGE = 4096
DbRow = tuple[int, int, int, bytes]  # id, topic id, timestamp, data


def write_db3(path: Path, rows: Sequence[DbRow], *, table: str = MESSAGES_TABLE, pragmas: Sequence[str] = ()) -> Path:
    """A bare rosbag2 .db3 made with sqlite: rows inserted in the order given."""
    with sqlite3.connect(path) as db:
        db.execute(f"PRAGMA page_size = {PAGE}")
        for pragma in pragmas:
            db.execute(f"PRAGMA {pragma}")
        db.execute(
            "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
            " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)"
        )
        db.executemany("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", TOPICS)
        db.execute(table)
        db.execute("CREATE INDEX timestamp_idx ON messages (timestamp ASC)")
        db.executemany("INSERT INTO messages (id, topic_id, timestamp, data) VALUES (?, ?, ?, ?)", rows)
    db.close()
    return path


def tf_payload(i: int, transforms: int = 1) -> bytes:
    """A /tf message whose transforms are stamped ``i`` s after 1_700_000_000, children link_0.."""
    return tf_cdr(tuple(Tf("odom", f"link_{j}", 1_700_000_000 + i, j, (i, j, 0.5)) for j in range(transforms)))


def mixed_rows(count: int) -> list[DbRow]:
    """/tf (some large enough to spill into overflow pages), /chatter and image-sized blobs, ties of
    three record times, and one /tf_static."""
    rows = []
    for i in range(count):
        topic, data = 1, tf_payload(i, 1 + i % 7)
        if i % 11 == 0:
            topic, data = 4, string_cdr("chat " * (i % 90))
        if i % 97 == 0:
            topic, data = 3, bytes([i % 256]) * (20_000 + 50 * i)
        if i % 53 == 0:
            topic, data = 1, tf_payload(i, 200)
        rows.append((1 + i, topic, T0 + (i // 3) * NS // 100, data))
    rows.append((1 + count, 2, T0, tf_payload(count, 3)))
    return rows


def expected(rows: Sequence[DbRow]) -> list[tuple[int, int, str]]:
    """(record time, stamp's seconds, child) of each transform of the tf rows, in (time, id) order."""
    out = []
    for _, topic, time, data in sorted(rows, key=lambda row: (row[2], row[0])):
        if topic in (1, 2):
            count = int.from_bytes(data[4:8], "little")
            seconds = int.from_bytes(data[8:12], "little")
            out += [(time, seconds, f"link_{j}") for j in range(count)]
    return out


def read(path: Path, progress: ProgressCallback | None = None) -> tuple[list[tuple[int, int, str]], Any]:
    contents = read_contents([path], progress=progress)
    batch = contents.transforms
    got = [
        (int(batch.record_time[i]), int(batch.stamp[i] // NS), batch.frame_names[batch.child[i]])
        for i in range(len(batch))
    ]
    return got, contents


# --- sqlite reads ----------------------------------------------------------------------------


def test_ties_and_integers_of_every_width_in_record_order(tmp_path: Path) -> None:
    """Timestamps and topic ids stored in 0 to 8 bytes, rows inserted out of id and time order:
    transforms in (record time, id) order. (Within a year of each other: times decades apart are not one
    recording's, ``test_strays``.)"""
    times = [0, 1, 5, 300, 40_000, 2**23 - 1, 2**31, 2**47 - 1, 2**54, 2**54 + 2**40]
    rows = [(1000 - 7 * i, 1 + i % 2, time, tf_payload(i, 1 + i % 3)) for i, time in enumerate(times * 3)]
    rows += [(5000 + i, 4, 7, string_cdr("tie")) for i in range(5)]
    db3 = write_db3(tmp_path / "a.db3", rows[::-1])
    got, contents = read(db3)
    assert got == expected(rows) and contents.problems == []
    assert (contents.files[0].message_count, contents.start, contents.end) == (len(rows), 0, 2**54 + 2**40)


def test_rows_fetched_a_batch_at_a_time_and_only_the_tf_topics(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Memory stays bounded: the decoder is handed each fetch on its own, never an image's blob."""
    rows = mixed_rows(3000)
    db3 = write_db3(tmp_path / "a.db3", rows)
    handed: list[list[int]] = []  # the payload lengths of each call
    add_spans = MessageSet.add_spans

    def spy(self: MessageSet, channel: Any, spans: Spans, data: Any) -> None:
        handed.append((spans.end - spans.start).tolist())
        add_spans(self, channel, spans, data)

    monkeypatch.setattr(MessageSet, "add_spans", spy)
    monkeypatch.setattr(db3_reader, "_FETCH", 100)
    got, _ = read(db3)
    assert got == expected(rows)
    tf_rows = [row for row in rows if row[1] in (1, 2)]
    assert max(map(len, handed)) == 100 and sum(map(len, handed)) == len(tf_rows)
    assert max(max(lengths) for lengths in handed) == max(len(row[3]) for row in tf_rows) < 20_000


@pytest.mark.parametrize("native", [True, False], ids=["extension", "sqlite3"])
def test_rows_of_a_topic_id_the_topics_table_does_not_list_are_left_out(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, native: bool
) -> None:
    """Where every topic the topics table lists is read, the extension leaves the other topic ids' rows out
    itself (the query has no ``topic_id IN``): rows of an id the table does not list, /tf payloads or not,
    are not read, through the extension or Python's sqlite3."""
    from tftools.sources.bag.rosbag2 import database

    rows = [(1 + i, 1 + i % 2, T0 + i * NS, tf_payload(i, 1 + i % 3)) for i in range(40)]
    rows += [(100 + i, topic, T0 + i * NS, tf_payload(50 + i, 2)) for i, topic in enumerate((3, 4, 0, -1, 2**40))]
    db3 = write_db3(tmp_path / "a.db3", rows)
    with sqlite3.connect(db3) as writer:
        writer.execute("DELETE FROM topics WHERE id > 2")
    writer.close()
    if not native:
        monkeypatch.setattr(database, "_Native", None)
    got, contents = read(db3)
    assert got == expected(rows) and contents.problems == []
    assert len(got) == sum(1 + i % 3 for i in range(40))


def test_rows_stored_out_of_time_order(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The table is read in its own order, fetch after fetch: transforms still come in (record time,
    id) order, and progress only moves forward."""
    rows = [(1 + i, 1, T0 + (299 - i) // 2 * NS, tf_payload(i, 1 + i % 3)) for i in range(300)]
    db3 = write_db3(tmp_path / "a.db3", rows)
    monkeypatch.setattr(db3_reader, "_FETCH", 16)
    calls: list[int] = []
    got, _ = read(db3, lambda done, _total: calls.append(done))
    assert got == expected(rows)
    assert len(calls) > 10 and calls == sorted(calls)


def fingerprint(folder: Path) -> dict[str, tuple[str, int]]:
    return {p.name: (hashlib.sha256(p.read_bytes()).hexdigest(), p.stat().st_mtime_ns) for p in folder.iterdir()}


@pytest.mark.parametrize("journal", ["DELETE", "WAL"])
@pytest.mark.parametrize("damaged", [False, True])
def test_nothing_written_beside_the_file(tmp_path: Path, journal: str, damaged: bool) -> None:
    """No -journal, -wal or -shm file made, the file's bytes and time unchanged, in WAL mode too, and
    when the file is damaged (salvaged)."""
    rows = mixed_rows(500)
    db3 = write_db3(tmp_path / "a.db3", rows, pragmas=[f"journal_mode = {journal}"])
    if damaged:
        db3.write_bytes(db3.read_bytes()[: db3.stat().st_size // 2])
    before = fingerprint(tmp_path)
    assert list(before) == ["a.db3"]
    got, contents = read(db3)
    assert got and ("damaged" in contents.problems[0] if damaged else got == expected(rows))
    assert fingerprint(tmp_path) == before


@pytest.mark.parametrize(
    "table",
    [
        MESSAGES_TABLE.replace("data BLOB NOT NULL", "data BLOB NOT NULL, extra INTEGER"),
        MESSAGES_TABLE.replace("topic_id INTEGER NOT NULL, timestamp", "timestamp INTEGER NOT NULL, topic_id"),
        MESSAGES_TABLE.replace("id INTEGER PRIMARY KEY", "id INT PRIMARY KEY"),  # not the rowid
        MESSAGES_TABLE + " WITHOUT ROWID",
    ],
    ids=["extra_column", "columns_swapped", "id_not_rowid", "without_rowid"],
)
def test_other_table_shapes(tmp_path: Path, table: str) -> None:
    rows = mixed_rows(300)
    got, contents = read(write_db3(tmp_path / "a.db3", rows, table=table))
    assert got == expected(rows) and contents.problems == []


# --- damaged files: salvaged -------------------------------------------------------------------


def one_spilling_tf_message(path: Path) -> tuple[list[DbRow], list[int]]:
    """A .db3 whose only record larger than a page is a 200-transform /tf message (id 151); its
    overflow pages in chain order. In a file of fewer than 2**24 pages, an overflow page's first byte
    (that of the next page's number) is 0, never a b-tree page type."""
    rows = [(i + 1, 1, T0 + i, tf_payload(i, 200 if i == 150 else 2)) for i in range(300)]
    data = write_db3(path, rows).read_bytes()
    overflow = [p for p in range(2, len(data) // PAGE + 1) if data[(p - 1) * PAGE] == 0]
    following = {p: int.from_bytes(data[(p - 1) * PAGE : (p - 1) * PAGE + 4], "big") for p in overflow}
    (page,) = set(overflow) - set(following.values())
    chain = [page]
    while following[chain[-1]]:
        chain.append(following[chain[-1]])
    assert len(chain) == len(overflow) > 2
    return rows, chain


def damaged_copy(db3: Path, page: int, offset: int, data: bytes) -> Path:
    damaged = bytearray(db3.read_bytes())
    damaged[(page - 1) * PAGE + offset : (page - 1) * PAGE + offset + len(data)] = data
    path = db3.with_name("damaged.db3")
    path.write_bytes(bytes(damaged))
    return path


@pytest.mark.parametrize("damage", ["chain_past_the_end", "chain_cut", "leaf_type"])
def test_damaged_file_salvaged(tmp_path: Path, damage: str) -> None:
    """sqlite refuses the file: every message of the intact pages is read, with one line on the loss."""
    db3 = tmp_path / "a.db3"
    rows, chain = one_spilling_tf_message(db3)
    pages = db3.stat().st_size // PAGE
    leaves = [p for p in range(2, pages + 1) if db3.read_bytes()[(p - 1) * PAGE] == 0x0D]
    page, offset, data = {
        "chain_past_the_end": (chain[0], 0, (pages + 1).to_bytes(4, "big")),
        "chain_cut": (chain[1], 0, bytes(4)),
        "leaf_type": (leaves[-1], 0, b"\x07"),
    }[damage]
    got, contents = read(damaged_copy(db3, page, offset, data))
    (problem,) = contents.problems
    assert problem.startswith("the database is damaged (sqlite: database disk image is malformed)")
    if damage == "leaf_type":  # the messages of that page are lost
        assert 0 < len(got) < len(expected(rows)) and all(row in expected(rows) for row in got)
    else:  # the spilling message is lost
        assert got == expected([row for row in rows if row[0] != 151]) and "1 more lost their data" in problem


def test_both_row_readers_give_the_same_rows(tmp_path: Path) -> None:
    """sqlite's C API (the _sqlite extension) and Python's sqlite3 module, which reads .db3 files in a
    build without sqlite's headers, give the same rows, wrong-typed ones left out alike."""
    from tests.sources.bag import hostile
    from tftools.sources.bag.rosbag2 import database

    bag = hostile.db3(tmp_path / "odd.db3", [tf_cdr([Tf("map", "odom", 7)]), tf_cdr([Tf("map", "base", 8)]) * 40])
    db = sqlite3.connect(bag)
    db.execute("INSERT INTO messages VALUES (5, 'x', 9, X'00')")
    db.execute("INSERT INTO messages VALUES (6, 1, 9, 'text, not a blob')")
    db.commit()
    db.close()

    def rows(native: bool) -> list[tuple[int, int, int, bytes]]:
        db = database.Database(bag, native=native)
        assert db.native == native, "the extension is built here"
        query = f"SELECT topic_id, timestamp, id, data FROM messages WHERE 1{db.typed}"
        found = []
        for topic, time, row, start, length, data in db.messages(query, 1, 100):
            raw = data.tobytes()
            found += [
                (t, s, r, raw[a : a + n])
                for t, s, r, a, n in zip(*(c.tolist() for c in (topic, time, row, start, length)), strict=True)
            ]
        db.close()
        return found

    python = rows(native=False)
    assert python == rows(native=True) and len(python) == 2 and python[1][3] == tf_cdr([Tf("map", "base", 8)]) * 40


def test_a_build_without_the_extension_reads_db3_files_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    """Without sqlite's headers at build time there is no _sqlite: .db3 rows come through Python's
    sqlite3, wrong-typed rows left out by the query; the sample bag reads the same."""
    from tests.cli.conftest import SAMPLE_BAGS
    from tftools.sources.bag.rosbag2 import database

    native = read_contents([SAMPLE_BAGS["db3"]])
    monkeypatch.setattr(database, "_Native", None)
    python = read_contents([SAMPLE_BAGS["db3"]])
    assert python.problems == native.problems == []
    assert len(python.transforms) == len(native.transforms) > 1000
    assert np.array_equal(python.transforms.translation, native.transforms.translation)


@pytest.mark.parametrize("native", [True, False], ids=["extension", "sqlite3"])
def test_one_connection_serves_the_tables_and_the_messages(tmp_path: Path, native: bool) -> None:
    """A .db3's one connection answers the small tables' queries (text not in UTF-8 with replacement
    characters, alike through the extension and Python's sqlite3) and its messages, until closed."""
    from tftools.sources.bag.rosbag2.database import Database

    rows = mixed_rows(300)
    bag = write_db3(tmp_path / "a.db3", rows)
    with sqlite3.connect(bag) as writer:
        writer.execute("INSERT INTO topics VALUES (9, CAST(X'2F6361FF' AS TEXT), 'x/msg/Y', 'cdr', '')")
    writer.close()
    db = Database(bag, native=native)
    assert db.native == native
    assert db.rows("SELECT count(*), min(timestamp) FROM messages") == [(len(rows), T0)]
    assert db.rows("SELECT name FROM topics WHERE id = 9") == [("/ca\ufffd",)]
    query = f"SELECT topic_id, timestamp, id, data FROM messages WHERE topic_id = 4{db.typed}"
    fetched = [(row, data[start : start + length].tobytes())
               for topic, _time, ids, starts, lengths, data in db.messages(query, 7, 1 << 20)
               for row, start, length in zip(ids.tolist(), starts.tolist(), lengths.tolist(), strict=True)]  # fmt: skip
    assert fetched == [(row_id, data) for row_id, topic, _t, data in rows if topic == 4]
    db.close()
    with pytest.raises(sqlite3.Error):
        db.rows("SELECT count(*) FROM messages")
