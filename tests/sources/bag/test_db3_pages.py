"""The .db3 messages table read from its pages (native/db3_pages.hpp): sqlite's rows, bit for bit, or
``PageError`` and the rows read through sqlite; on hostile pages no crash, no hang, bounded memory."""

from __future__ import annotations

import random
import sqlite3
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest

from tests.sources.bag.reading import read_contents
from tests.sources.bag.test_db3 import MESSAGES_TABLE, DbRow, mixed_rows, tf_payload, write_db3
from tests.sources.ros2_helpers import T0, string_cdr
from tftools.core.batch import TransformBatch
from tftools.sources.bag.rosbag2 import database
from tftools.sources.bag.rosbag2.database import Database, Fetched, PageError
from tftools.sources.codecs.wire import HEADER_BYTES

_sqlite = pytest.importorskip("tftools.sources.bag.rosbag2._sqlite", reason="built without sqlite's headers")

Row = tuple[int, int, int, bytes]  # topic id, record time, id, bytes handed over
TOPIC_IDS = [1, 2, 3, 4]


def same_transforms(a: TransformBatch, b: TransformBatch) -> bool:
    """Every column alike, bit for bit."""
    arrays = ("parent", "child", "stamp", "translation", "rotation", "static", "record_time", "authority")
    names = list(a.frame_names) == list(b.frame_names) and list(a.authorities) == list(b.authorities)
    return names and all(getattr(a, f).tobytes() == getattr(b, f).tobytes() for f in arrays)


def rows_of(fetches: Iterator[Fetched]) -> list[Row]:
    found: list[Row] = []
    for topic, time, ids, start, length, data in fetches:
        raw = data.tobytes()
        columns = (c.tolist() for c in (topic, time, ids, start, length))
        found += [(t, s, i, raw[a : a + n]) for t, s, i, a, n in zip(*columns, strict=True)]
    return found


def through_sqlite(db: Database, topics: Sequence[int], headed: Sequence[int]) -> list[Row]:
    """The rows of db3.py's query without a window, through sqlite."""
    listed = ",".join(map(str, headed))
    data = (
        f"CASE WHEN topic_id NOT IN ({listed}) OR substr(data, 1, 4) = x'28b52ffd' THEN data"
        f" ELSE substr(data, 1, {HEADER_BYTES}) END"
        if headed
        else "data"
    )
    query = f"SELECT topic_id, timestamp, id, {data} FROM messages NOT INDEXED"
    return rows_of(db.messages(query, 50, 1 << 16, topics))


def from_pages(db: Database, topics: Sequence[int], headed: Sequence[int], rows: int = 50) -> list[Row]:
    fetches = db.pages(rows, 1 << 16, topics, headed, HEADER_BYTES)
    assert fetches is not None, "the page reader takes this file"
    return rows_of(fetches)


def assert_alike(path: Path, topics: Sequence[int] = TOPIC_IDS, headed: Sequence[int] = ()) -> list[Row]:
    """The page reader's rows are sqlite's (where it reads the pages at all)."""
    db = Database(path)
    try:
        expected = through_sqlite(db, topics, headed)
        assert from_pages(db, topics, headed) == expected
    finally:
        db.close()
    return expected


@pytest.mark.parametrize("page", [512, 4096, 65536])
@pytest.mark.parametrize("journal", ["DELETE", "WAL"])
def test_sqlites_rows_at_every_page_size(tmp_path: Path, page: int, journal: str) -> None:
    """Blobs spilling into overflow pages (images of 20 kB and more, /tf of 200 transforms), a tree
    several levels deep at 512-byte pages; every topic, some topics, some cut to a header's bytes."""
    rows = mixed_rows(1500)
    path = write_db3(
        tmp_path / "a.db3", rows, pragmas=[f"page_size = {page}", f"journal_mode = {journal}", "synchronous = OFF"]
    )
    (path.with_name("a.db3-wal")).unlink(missing_ok=True)  # merged on close
    assert len(assert_alike(path)) == len(rows)
    assert_alike(path, topics=[1, 3])
    headed = assert_alike(path, headed=[3, 4])
    assert max(len(r[3]) for r in headed if r[0] == 3) == HEADER_BYTES


def test_rows_deleted_and_pages_freed_and_a_vacuum_map(tmp_path: Path) -> None:
    """Rows deleted (free pages, freed overflow chains) in an auto-vacuumed file (pointer-map pages
    among the table's)."""
    rows = mixed_rows(2000)
    path = write_db3(
        tmp_path / "a.db3", rows, pragmas=["page_size = 1024", "auto_vacuum = INCREMENTAL", "synchronous = OFF"]
    )
    with sqlite3.connect(path) as db:
        db.execute("DELETE FROM messages WHERE id % 5 = 0 OR topic_id = 3")
        db.execute("PRAGMA incremental_vacuum(3)")
        db.execute("INSERT INTO messages VALUES (99999, 3, 5, ?)", (b"\x28\xb5\x2f\xfd" + bytes(9000),))
    db.close()
    assert int.from_bytes(path.read_bytes()[36:40], "big") > 0, "free pages left"
    got = assert_alike(path, headed=[3])
    assert got[-1] == (3, 5, 99999, b"\x28\xb5\x2f\xfd" + bytes(9000)), "a compressed blob handed over whole"


def test_values_of_other_types_left_out_alike(tmp_path: Path) -> None:
    """Integers of every width; rows whose topic or time is not an integer or whose data is not a blob
    (sqlite stores any value in any column) are left out, as the sqlite reader leaves them out."""
    times = [0, 1, -1, 300, 40_000, -(2**23), 2**31, 2**47 - 1, -(2**63), 2**63 - 1]
    rows: list[DbRow] = [(i + 1, 1 + i % 2, t, tf_payload(i)) for i, t in enumerate(times)]
    path = write_db3(tmp_path / "a.db3", rows)
    with sqlite3.connect(path) as db:
        odd = [(1.5, T0, b"x"), (1, 2.5, b"x"), ("x", T0, b"x"), (1, "y", b"x"), (1, T0, "text"), (1, T0, 7)]
        for i, (topic, time, data) in enumerate(odd):
            db.execute("INSERT INTO messages VALUES (?, ?, ?, ?)", (100 + i, topic, time, data))
        db.execute("INSERT INTO messages VALUES (200, 4, 7, ?)", (string_cdr("an empty blob next"),))
        db.execute("INSERT INTO messages VALUES (201, 4, 8, x'')")
    db.close()
    got = assert_alike(path)
    assert [r[2] for r in got] == [*range(1, len(times) + 1), 200, 201]


def test_read_from_pages_as_through_sqlite(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A whole read (transforms, problems, description) is the same with the page reader as without it,
    and the page reader is what read it."""
    path = write_db3(tmp_path / "a.db3", mixed_rows(3000))
    opened: list[str] = []
    pages = _sqlite.TablePages

    def spy(path: str, root: int, wanted: list[int], headed: list[int], header_bytes: int) -> object:
        opened.append(path)
        return pages(path, root, wanted, headed, header_bytes)

    monkeypatch.setattr(database, "_TablePages", spy)
    fast = read_contents([path])
    assert opened == [str(path)]
    monkeypatch.setattr(Database, "pages", lambda *_args: None)
    slow = read_contents([path])
    assert fast.problems == slow.problems == []
    assert same_transforms(fast.transforms, slow.transforms) and len(fast.transforms) > 3000


@pytest.mark.parametrize("beside", ["-wal", "-journal"])
def test_not_read_from_pages_with_pages_beside_it(tmp_path: Path, beside: str) -> None:
    path = write_db3(tmp_path / "a.db3", mixed_rows(100))
    path.with_name("a.db3" + beside).write_bytes(b"")
    db = Database(path)
    assert db.pages(50, 1 << 16, TOPIC_IDS, (), HEADER_BYTES) is None
    db.close()


@pytest.mark.parametrize(
    "table",
    [
        MESSAGES_TABLE.replace("data BLOB NOT NULL", "data BLOB NOT NULL, extra INTEGER"),
        MESSAGES_TABLE.replace("id INTEGER PRIMARY KEY", "id INT PRIMARY KEY"),
        MESSAGES_TABLE + " WITHOUT ROWID",
    ],
    ids=["extra_column", "id_not_rowid", "without_rowid"],
)
def test_not_read_from_pages_in_another_table_shape(tmp_path: Path, table: str) -> None:
    db = Database(write_db3(tmp_path / "a.db3", mixed_rows(100), table=table))
    assert db.pages(50, 1 << 16, TOPIC_IDS, (), HEADER_BYTES) is None
    db.close()


# --- hostile pages -------------------------------------------------------------------------------

PAGE = 512


def small_file(tmp_path: Path) -> tuple[Path, bytes]:
    rows = [(i + 1, 1 + i % 4, T0 + i, tf_payload(i, 1 + i % 3)) for i in range(120)]
    rows += [(200, 3, T0, bytes(range(256)) * 8), (201, 1, T0 + 1, tf_payload(0, 40))]  # overflow chains
    path = write_db3(tmp_path / "a.db3", rows, pragmas=[f"page_size = {PAGE}", "synchronous = OFF"])
    return path, path.read_bytes()


def pages_or_error(path: Path, headed: Sequence[int] = ()) -> list[Row] | None:
    """The page reader's rows, or None where it refused the pages (sqlite's rows are then what any read
    gives) or sqlite could not read the schema."""
    db = Database(path)
    try:
        fetches = db.pages(7, 1 << 16, TOPIC_IDS, headed, HEADER_BYTES)
        return None if fetches is None else rows_of(fetches)
    except (PageError, sqlite3.Error):
        return None
    finally:
        db.close()


def sqlite_rows(path: Path, headed: Sequence[int] = ()) -> list[Row] | None:
    db = Database(path)
    try:
        return through_sqlite(db, TOPIC_IDS, headed)
    except sqlite3.Error:
        return None
    finally:
        db.close()


def kinds(path: Path, data: bytes, kind: int) -> list[int]:
    """The messages table's interior (0x05) or leaf (0x0D) pages, in the tree's order."""
    with sqlite3.connect(path) as db:
        (root,) = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'messages'").fetchone()
    db.close()
    found: list[int] = []
    todo = [root]
    while todo:
        page = todo.pop()
        at = (page - 1) * PAGE
        if data[at] == kind:
            found.append(page)
        if data[at] == 0x05:
            cells = int.from_bytes(data[at + 3 : at + 5], "big")
            offsets = [int.from_bytes(data[at + 12 + 2 * i : at + 14 + 2 * i], "big") for i in range(cells)]
            children = [int.from_bytes(data[at + o : at + o + 4], "big") for o in offsets]
            todo += [int.from_bytes(data[at + 8 : at + 12], "big"), *children[::-1]]
    return found


def patched(path: Path, data: bytes, at: int, new: bytes) -> Path:
    changed = bytearray(data)
    changed[at : at + len(new)] = new
    out = path.with_name("changed.db3")
    out.write_bytes(bytes(changed))
    return out


def test_loops_in_page_pointers_refused(tmp_path: Path) -> None:
    """An interior page whose child is itself or the root, an overflow chain round a loop, the next
    page of a chain beyond the file: refused, or (a loop) sqlite's rows, in no more reads than twice
    the file's pages."""
    path, data = small_file(tmp_path)
    interior = kinds(path, data, 0x05)
    assert interior, "a tree of more than one level"
    root = interior[0]
    right_most = (root - 1) * PAGE + 8
    assert pages_or_error(patched(path, data, right_most, root.to_bytes(4, "big"))) is None
    first_cell = int.from_bytes(data[(root - 1) * PAGE + 12 : (root - 1) * PAGE + 14], "big")
    left = (root - 1) * PAGE + first_cell
    assert pages_or_error(patched(path, data, left, root.to_bytes(4, "big"))) is None
    overflow = [n for n in range(2, len(data) // PAGE + 1) if data[(n - 1) * PAGE] == 0]
    for page in overflow:  # each points at itself: a loop as long as the record says it is
        looped = patched(path, data, (page - 1) * PAGE, page.to_bytes(4, "big"))
        got = pages_or_error(looped)
        assert got is None or got == sqlite_rows(looped)
        if data[(page - 1) * PAGE : (page - 1) * PAGE + 4] != bytes(4):  # not a chain's last page
            beyond = patched(path, data, (page - 1) * PAGE, (len(data) // PAGE + 1).to_bytes(4, "big"))
            assert pages_or_error(beyond) is None


def test_huge_cell_sizes_refused(tmp_path: Path) -> None:
    """A leaf cell claiming a payload of 2**56 bytes, or more bytes than its page holds: refused, nothing
    allocated for it."""
    path, data = small_file(tmp_path)
    leaf = kinds(path, data, 0x0D)[0]
    cell = int.from_bytes(data[(leaf - 1) * PAGE + 8 : (leaf - 1) * PAGE + 10], "big")
    assert pages_or_error(patched(path, data, (leaf - 1) * PAGE + cell, b"\xff" * 8)) is None
    assert pages_or_error(patched(path, data, (leaf - 1) * PAGE + cell, b"\x83\x60")) is None


def test_cut_at_every_page(tmp_path: Path) -> None:
    """A file cut short after any page: refused (sqlite then reads what it can)."""
    path, data = small_file(tmp_path)
    for pages in range(1, len(data) // PAGE):
        cut = path.with_name("cut.db3")
        cut.write_bytes(data[: pages * PAGE + (pages % 3) * 100])
        assert pages_or_error(cut) is None


def test_corrupted_bytes_sqlites_rows_or_refused(tmp_path: Path) -> None:
    """Bytes of the table's pages changed at random (a seeded fuzz of 600 files): wherever the page
    reader hands rows over, sqlite gives the same rows; elsewhere it refuses, and nothing crashes or hangs."""
    path, data = small_file(tmp_path)
    overflow = [n for n in range(2, len(data) // PAGE + 1) if data[(n - 1) * PAGE] == 0]
    table_pages = kinds(path, data, 0x05) + kinds(path, data, 0x0D) + overflow
    chance = random.Random(41)
    read = refused = 0
    for _ in range(600):
        changed = bytearray(data)
        for _ in range(chance.choice((1, 1, 2, 4))):
            page = chance.choice(table_pages)
            at = (page - 1) * PAGE + chance.randrange(PAGE)
            changed[at] = chance.choice((0, 0xFF, changed[at] ^ (1 << chance.randrange(8)), chance.randrange(256)))
        mutant = path.with_name("mutant.db3")
        mutant.write_bytes(bytes(changed))
        headed = chance.choice(((), (3,)))
        got = pages_or_error(mutant, headed)
        if got is None:
            refused += 1
        else:
            read += 1
            assert got == sqlite_rows(mutant, headed)
    assert read > 100 and refused > 30  # both ways exercised


def test_a_refused_file_reads_as_through_sqlite(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Pages refused midway (a leaf's cell out of its page, found after rows were handed over): the whole
    read is that of sqlite, the rows handed over before forgotten."""
    path, data = small_file(tmp_path)
    leaf = kinds(path, data, 0x0D)[-1]
    bad = patched(path, data, (leaf - 1) * PAGE + 8, b"\x00\x01")  # the first cell at the page's start
    assert pages_or_error(bad) is None and sqlite_rows(bad) is not None
    fast = read_contents([bad])
    monkeypatch.setattr(Database, "pages", lambda *_args: None)
    slow = read_contents([bad])
    assert fast.problems == slow.problems == []
    assert same_transforms(fast.transforms, slow.transforms) and len(fast.transforms) > 100
