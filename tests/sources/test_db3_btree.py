"""The .db3 page reader against sqlite: the same rows (topic id, timestamp, payload, order), and
the same transforms through ``read_bag``; every file it does not read falls back to sqlite."""

from __future__ import annotations

import importlib.util
import os
import sqlite3
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest
from rosbags.rosbag2 import StoragePlugin, Writer

from tests.sources.ros1_helpers import covered
from tests.sources.ros2_helpers import (
    NS,
    T0,
    TF_TYPE,
    Msg,
    Other,
    Tf,
    batch_rows,
    expected_rows,
    string_cdr,
    tf_cdr,
    typestore,
    varied_messages,
    write_rosbag2,
)
from tftools.sources.bag import db3_btree, db3_file
from tftools.sources.bag.db3_btree import UnhandledFileError, read_messages
from tftools.sources.bag.reader import read_bag

Row = tuple[int, int, bytes]  # topic id, timestamp, payload
TOPICS = [
    (1, "/tf", TF_TYPE),
    (2, "/tf_static", TF_TYPE),
    (3, "/camera/image_raw", "sensor_msgs/msg/Image"),
    (4, "/chatter", "std_msgs/msg/String"),
]
LEAF_POINTERS = 8  # a leaf page's cell pointers follow its 8-byte header
MESSAGES_TABLE = (
    "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,"
    " data BLOB NOT NULL)"
)


# --- what sqlite and the page reader give --------------------------------------------------------


def sqlite_rows(path: Path, topic_ids: Sequence[int] | None = None) -> list[Row]:
    with sqlite3.connect(f"file:{path}?mode=ro&immutable=1", uri=True) as db:
        rows = db.execute("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id").fetchall()
    return [row for row in rows if topic_ids is None or row[0] in topic_ids]


def messages_root(path: Path) -> int:
    with sqlite3.connect(f"file:{path}?mode=ro&immutable=1", uri=True) as db:
        return int(db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'messages'").fetchone()[0])


def page_rows(path: Path, topic_ids: Sequence[int] | None = None) -> list[Row]:
    """The page reader's rows (of every topic unless ``topic_ids``) in (timestamp, id) order; its ids
    come in key order, and it counts every message with its time range as sqlite does."""
    if topic_ids is None:
        with sqlite3.connect(f"file:{path}?mode=ro&immutable=1", uri=True) as db:
            topic_ids = [row[0] for row in db.execute("SELECT id FROM topics")]
    found: list[tuple[int, int, int, bytes]] = []  # timestamp, id, topic id, payload
    count, first, last = 0, [], []
    with path.open("rb") as f:
        for cells in read_messages(f.fileno(), messages_root(path), np.array(topic_ids, np.int64)):
            count += cells.count
            if cells.count:
                first.append(cells.first_time)
                last.append(cells.last_time)
            for topic, time, rowid, start, length in zip(
                cells.topic_ids, cells.times, cells.ids, cells.starts, cells.lengths, strict=True
            ):
                found.append((int(time), int(rowid), int(topic), cells.data[start : start + length].tobytes()))
    ids = [rowid for _, rowid, _, _ in found]
    assert ids == sorted(ids) and len(set(ids)) == len(ids)
    with sqlite3.connect(f"file:{path}?mode=ro&immutable=1", uri=True) as db:
        stats = db.execute("SELECT count(*), min(timestamp), max(timestamp) FROM messages").fetchone()
    assert (count, min(first, default=None), max(last, default=None)) == tuple(stats)
    return [(topic, time, payload) for time, _, topic, payload in sorted(found)]


@pytest.fixture
def paths_taken(monkeypatch: pytest.MonkeyPatch) -> list[bool]:
    """Whether each .db3 file read since was read by the page reader (True) or by sqlite."""
    taken: list[bool] = []
    read_pages = db3_file._read_pages

    def spy(*args: Any) -> bool:
        taken.append(read_pages(*args))
        return taken[-1]

    monkeypatch.setattr(db3_file, "_read_pages", spy)
    return taken


def without_page_reader(path: Path, monkeypatch: pytest.MonkeyPatch) -> Any:
    with monkeypatch.context() as patch:
        patch.setattr(db3_file, "_read_pages", lambda *_: False)
        return read_bag([path])


def assert_reads_like_sqlite(path: Path, monkeypatch: pytest.MonkeyPatch, taken: list[bool], *, pages: bool) -> Any:
    """``read_bag`` gives what it gives without the page reader; ``pages``: the page reader read it."""
    contents = read_bag([path])
    assert taken == [pages]
    reference = without_page_reader(path, monkeypatch)
    assert batch_rows(contents.transforms) == batch_rows(reference.transforms)
    assert contents.files[0].message_count == reference.files[0].message_count
    assert (contents.start, contents.end, contents.problems) == (reference.start, reference.end, reference.problems)
    return contents


# --- bags -------------------------------------------------------------------------------------


def write_db3(
    path: Path,
    rows: Sequence[tuple[int, int, int, bytes | str]],
    *,
    page_size: int = 4096,
    table: str = MESSAGES_TABLE,
    pragmas: Sequence[str] = (),
) -> Path:
    """A bare rosbag2 .db3 made with sqlite: rows (id, topic id, timestamp, data) in the order given."""
    with sqlite3.connect(path) as db:
        db.execute(f"PRAGMA page_size = {page_size}")
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
    return tf_cdr(tuple(Tf("odom", f"link_{j}", 1_700_000_000 + i, j, (i, j, 0.5)) for j in range(transforms)))


def mixed_rows(count: int, first_id: int = 1, id_step: int = 1) -> list[tuple[int, int, int, bytes]]:
    """/tf (some large enough to spill), /chatter and image-sized blobs; ids from ``first_id``."""
    payloads = [tf_payload(i, 1 + i % 7) for i in range(40)]
    rows: list[tuple[int, int, int, bytes]] = []
    for i in range(count):
        topic, data = 1, payloads[i % 40]
        if i % 11 == 0:
            topic, data = 4, string_cdr("chat " * (i % 90))
        if i % 97 == 0:
            topic, data = 3, bytes([i % 256]) * (20_000 + 50 * i)
        if i % 53 == 0:
            topic, data = 1, tf_payload(i, 200)  # spills into overflow pages
        rows.append((first_id + i * id_step, topic, T0 + (i // 3) * NS // 100, data))  # ties of three
    rows.append((first_id + count * id_step, 2, T0, tf_payload(0, 3)))
    return rows


def load_robot() -> ModuleType:
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "robot.py"
    spec = importlib.util.spec_from_file_location("bench_robot", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def robot_bag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The benchmark's robot, 6 s with camera images, written by rosbags."""
    robot = load_robot()
    path = tmp_path_factory.mktemp("robot") / "bag"
    writer = Writer(path, version=Writer.VERSION_LATEST, storage_plugin=StoragePlugin.SQLITE3)
    with writer:
        connections: dict[str, Any] = {}
        for record_time, topic, _, content in robot.messages(6, images=True):
            if topic not in connections:
                kind = "sensor_msgs/msg/Image" if topic == robot.IMAGE_TOPIC else TF_TYPE
                connections[topic] = writer.add_connection(topic, kind, typestore=typestore())
            writer.write(connections[topic], record_time, robot.cdr_payload(topic, content))
    return path / "bag.db3"


def many_topics_bag(path: Path) -> Path:
    """rosbags' writer: five topics, out of record-time order, ties, 60-transform messages that spill."""
    messages: list[Msg | Other] = list(varied_messages(5, 600))
    for i in range(0, 600, 40):
        many = tuple(Tf("arm_base", f"arm_link_{j}", 1_700_000_000 + i, j) for j in range(60))
        messages.append(Msg("/tf", T0 + i * NS // 100, many))
    return write_rosbag2(path, messages) / "bag.db3"


# --- the same rows as sqlite ------------------------------------------------------------------


def test_robot_bag_rows(robot_bag: Path) -> None:
    assert page_rows(robot_bag) == sqlite_rows(robot_bag)
    assert page_rows(robot_bag, (1, 2)) == sqlite_rows(robot_bag, (1, 2))


def test_bag_of_several_topics_written_by_rosbags(tmp_path: Path) -> None:
    bag = many_topics_bag(tmp_path / "bag")
    assert page_rows(bag) == sqlite_rows(bag)
    with sqlite3.connect(bag) as db:
        assert db.execute("SELECT count(*) FROM topics").fetchone()[0] == 5
        (tf_id,) = db.execute("SELECT id FROM topics WHERE name = '/tf'").fetchone()
    assert page_rows(bag, (tf_id,)) == sqlite_rows(bag, (tf_id,))


@pytest.mark.parametrize("page_size", [512, 1024, 4096, 65536])
def test_overflow_ties_and_page_sizes(tmp_path: Path, page_size: int) -> None:
    """Blobs larger than a page (images, 200-transform tf messages), read or skipped; timestamp ties
    in id order."""
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(1500), page_size=page_size)
    rows = sqlite_rows(db3)
    assert any(len(payload) > page_size for _, _, payload in rows)
    assert page_rows(db3) == rows
    assert page_rows(db3, (1, 2)) == sqlite_rows(db3, (1, 2))


def test_several_interior_levels(tmp_path: Path) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(12_000), page_size=512)
    data = db3.read_bytes()
    root = (messages_root(db3) - 1) * 512
    first_cell = root + int.from_bytes(data[root + 12 : root + 14], "big")  # after the interior page header
    child = (int.from_bytes(data[first_cell : first_cell + 4], "big") - 1) * 512  # the cell's left child
    assert data[root] == data[child] == 0x05  # two interior levels at least
    assert page_rows(db3) == sqlite_rows(db3)


@pytest.mark.parametrize(
    ("first_id", "step"),
    [(1, 1), (200, 131), (2**31, 2**20 + 7), (2**56 + 3, 2**40), (-(2**62), 2**50), (-(2**63), 2**53)],
)
def test_rowids_of_every_varint_length(tmp_path: Path, first_id: int, step: int) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(400, first_id, step))
    assert page_rows(db3) == sqlite_rows(db3)


def test_integers_of_every_width_and_ties_in_id_order(tmp_path: Path) -> None:
    """Timestamps and topic ids stored in 0 to 8 bytes; rows inserted out of id and time order."""
    times = [0, 1, 5, -5, 300, -40_000, 2**23 - 1, 2**31, -(2**40), 2**47 - 1, T0, -(2**63), 2**63 - 1]
    rows = [(1000 - 7 * i, 1 + i % 2, time, tf_payload(i)) for i, time in enumerate(times * 3)]
    rows += [(5000 + i, 4, 7, string_cdr("tie")) for i in range(5)]
    db3 = write_db3(tmp_path / "a.db3", rows[::-1])
    assert page_rows(db3) == sqlite_rows(db3)


def test_empty_table(tmp_path: Path) -> None:
    db3 = write_db3(tmp_path / "a.db3", [])
    assert page_rows(db3) == sqlite_rows(db3) == []


# --- read_bag: the same transforms with and without the page reader -----------------------------


def test_read_bag_robot(robot_bag: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]) -> None:
    contents = assert_reads_like_sqlite(robot_bag.parent, monkeypatch, paths_taken, pages=True)
    assert len(contents.transforms) > 6 * 850


def test_read_bag_robot_without_preadv(
    robot_bag: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]
) -> None:
    """A system without ``os.preadv`` (an older macOS): the pages are read with ``os.pread`` all the same."""
    monkeypatch.delattr(os, "preadv")
    contents = assert_reads_like_sqlite(robot_bag.parent, monkeypatch, paths_taken, pages=True)
    assert len(contents.transforms) > 6 * 850


def test_read_bag_several_topics(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]) -> None:
    bag = many_topics_bag(tmp_path / "bag")
    assert_reads_like_sqlite(bag.parent, monkeypatch, paths_taken, pages=True)


@pytest.mark.parametrize("page_size", [512, 4096])
def test_read_bag_mixed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool], page_size: int
) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(3000, 2**33, 3), page_size=page_size)
    contents = assert_reads_like_sqlite(db3, monkeypatch, paths_taken, pages=True)
    assert np.unique(contents.transforms.record_time, return_counts=True)[1].max() >= 200  # the spilled ones


def test_read_bag_compressed_message_by_message(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]
) -> None:
    messages = varied_messages(3, 200)
    bag = write_rosbag2(tmp_path / "bag", messages, compression="message")
    contents = assert_reads_like_sqlite(bag / "bag.db3", monkeypatch, paths_taken, pages=True)
    assert batch_rows(contents.transforms) == expected_rows(messages)


@pytest.mark.parametrize("pragma", ["encoding = 'UTF-16le'", "journal_mode = WAL", "auto_vacuum = FULL"])
def test_read_bag_other_database_settings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool], pragma: str
) -> None:
    """Text encodings (records of integers and a blob do not depend on them), WAL mode (a merged
    -wal), pointer-map pages."""
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(2000), pragmas=[pragma])
    assert page_rows(db3) == sqlite_rows(db3)
    assert_reads_like_sqlite(db3, monkeypatch, paths_taken, pages=True)


def test_the_pages_of_blobs_not_read_are_not_touched(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Only the table's b-tree pages are read, not the overflow pages of the images."""
    rows = [(i, 1 if i % 4 else 3, T0 + i, tf_payload(i) if i % 4 else bytes(300_000)) for i in range(400)]
    db3 = write_db3(tmp_path / "a.db3", rows)
    read = 0
    preadv, pread = os.preadv, os.pread

    def counted_preadv(fd: int, buffers: list[Any], offset: int) -> int:
        nonlocal read
        read += sum(len(b) for b in buffers)
        return preadv(fd, buffers, offset)

    def counted_pread(fd: int, length: int, offset: int) -> bytes:
        nonlocal read
        read += length
        return pread(fd, length, offset)

    monkeypatch.setattr(os, "preadv", counted_preadv)
    monkeypatch.setattr(os, "pread", counted_pread)
    assert page_rows(db3, (1,)) == sqlite_rows(db3, (1,))
    assert 0 < read < 0.02 * db3.stat().st_size


def test_the_leaf_pages_are_prefetched_before_they_are_read(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Scattered among the images' overflow pages, the leaf pages are asked for all at once first
    (from a file not in the page cache, each read would otherwise wait for the disk), and only they."""
    rows = [(i, 1 if i % 4 else 3, T0 + i, tf_payload(i) if i % 4 else bytes(300_000)) for i in range(400)]
    db3 = write_db3(tmp_path / "a.db3", rows)
    prefetched: list[tuple[int, int]] = []
    read_after: list[tuple[int, int]] = []
    preadv = os.preadv

    def noted_prefetch(fd: int, starts: np.ndarray, ends: np.ndarray) -> None:
        prefetched.extend(zip(starts.tolist(), ends.tolist(), strict=True))

    def noted_preadv(fd: int, buffers: list[Any], offset: int) -> int:
        if prefetched:
            read_after.append((offset, offset + sum(len(b) for b in buffers)))
        return preadv(fd, buffers, offset)

    monkeypatch.setattr(db3_btree, "prefetch", noted_prefetch)
    monkeypatch.setattr(os, "preadv", noted_preadv)
    assert page_rows(db3, (1,)) == sqlite_rows(db3, (1,))
    assert read_after and all(covered(prefetched, start, end) for start, end in read_after)
    assert sum(end - start for start, end in prefetched) < 0.02 * db3.stat().st_size


# --- falling back to sqlite -------------------------------------------------------------------


def test_unmerged_wal_falls_back(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(300))
    (tmp_path / "a.db3-wal").write_bytes(b"\x37\x7f\x06\x82" + b"\x00" * 100)
    contents = read_bag([db3])
    assert paths_taken == []  # not even tried
    (line,) = contents.problems
    assert line.startswith("a.db3-wal holds writes never merged")
    assert batch_rows(contents.transforms) == batch_rows(without_page_reader(db3, monkeypatch).transforms)


@pytest.mark.parametrize(
    "table",
    [
        MESSAGES_TABLE.replace("data BLOB NOT NULL", "data BLOB NOT NULL, extra INTEGER"),
        MESSAGES_TABLE.replace("topic_id INTEGER NOT NULL, timestamp", "timestamp INTEGER NOT NULL, topic_id"),
        MESSAGES_TABLE.replace("id INTEGER PRIMARY KEY", "id INT PRIMARY KEY"),  # not the rowid
        MESSAGES_TABLE + " WITHOUT ROWID",  # an index b-tree
    ],
    ids=["extra_column", "columns_swapped", "id_not_rowid", "without_rowid"],
)
def test_other_table_shapes_fall_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool], table: str
) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(300), table=table)
    contents = assert_reads_like_sqlite(db3, monkeypatch, paths_taken, pages=False)
    assert len(contents.transforms) > 300 and contents.problems == []


def test_record_of_another_shape_falls_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]
) -> None:
    """A /chatter row whose data is text, not a blob: sqlite never hands it over, the page reader gives up."""
    rows: list[tuple[int, int, int, bytes | str]] = list(mixed_rows(500))
    rows.append((10_000, 4, T0, "some text"))
    db3 = write_db3(tmp_path / "a.db3", rows)
    with pytest.raises(UnhandledFileError), db3.open("rb") as f:
        list(read_messages(f.fileno(), messages_root(db3), np.array([1, 2])))
    assert_reads_like_sqlite(db3, monkeypatch, paths_taken, pages=False)


def test_table_not_where_the_schema_says_falls_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]
) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(2000))
    with sqlite3.connect(db3) as db:
        (index_root,) = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'timestamp_idx'").fetchone()
        (topics_root,) = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'topics'").fetchone()
    db.close()
    pages = db3.stat().st_size // 4096
    for wrong in (index_root, topics_root, 1, pages + 1, 2**31):
        monkeypatch.setattr(db3_file, "_messages_root", lambda _db, page=wrong: page)
        assert_reads_like_sqlite(db3, monkeypatch, paths_taken, pages=False)
        paths_taken.clear()


def one_spilling_tf_message(path: Path) -> tuple[Path, list[int]]:
    """A .db3 whose only record larger than a page is a 200-transform /tf message; its overflow pages
    in chain order. In a file of fewer than 2**24 pages, an overflow page's first byte (that of the
    next page's number) is 0, never a b-tree page type."""
    rows = [(i, 1, T0 + i, tf_payload(i, 200 if i == 150 else 2)) for i in range(300)]
    data = write_db3(path, rows).read_bytes()
    overflow = [p for p in range(2, len(data) // 4096 + 1) if data[(p - 1) * 4096] == 0]
    following = {p: int.from_bytes(data[(p - 1) * 4096 : (p - 1) * 4096 + 4], "big") for p in overflow}
    (page,) = set(overflow) - set(following.values())
    chain = [page]
    while following[chain[-1]]:
        chain.append(following[chain[-1]])
    assert len(chain) == len(overflow) > 2
    return path, chain


def damaged_copy(db3: Path, page: int, offset: int, data: bytes) -> Path:
    damaged = bytearray(db3.read_bytes())
    damaged[(page - 1) * 4096 + offset : (page - 1) * 4096 + offset + len(data)] = data
    path = db3.with_name("damaged.db3")
    path.write_bytes(bytes(damaged))
    return path


@pytest.mark.parametrize(
    "damage", ["chain_past_the_end", "chain_longer_than_the_payload", "chain_of_a_leaf", "leaf_type", "cell_pointer"]
)
def test_damaged_files_fall_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool], damage: str
) -> None:
    """The page reader gives up on them: what sqlite makes of them (read, or salvaged) is read."""
    db3, chain = one_spilling_tf_message(tmp_path / "a.db3")
    pages = db3.stat().st_size // 4096
    leaf = next(p for p in range(messages_root(db3) + 1, pages) if db3.read_bytes()[(p - 1) * 4096] == 0x0D)
    page, offset, data = {
        "chain_past_the_end": (chain[0], 0, (pages + 1).to_bytes(4, "big")),
        "chain_longer_than_the_payload": (chain[-1], 0, (chain[0]).to_bytes(4, "big")),
        "chain_of_a_leaf": (chain[0], 0, leaf.to_bytes(4, "big")),
        "leaf_type": (leaf, 0, b"\x07"),
        "cell_pointer": (leaf, LEAF_POINTERS, b"\x00\x02"),  # a cell inside the page header
    }[damage]
    damaged = damaged_copy(db3, page, offset, data)
    with pytest.raises(UnhandledFileError), damaged.open("rb") as f:
        list(read_messages(f.fileno(), messages_root(db3), np.array([1, 2])))
    assert_reads_like_sqlite(damaged, monkeypatch, paths_taken, pages=False)


def test_file_cut_short_falls_back(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, paths_taken: list[bool]) -> None:
    db3 = write_db3(tmp_path / "a.db3", mixed_rows(3000))
    cut = tmp_path / "cut.db3"
    cut.write_bytes(db3.read_bytes()[: db3.stat().st_size * 3 // 4])
    contents = assert_reads_like_sqlite(cut, monkeypatch, paths_taken, pages=False)
    assert "damaged" in contents.problems[0]
