"""Damaged copies of real recordings (made in tmp_path from the corpus, skipped where it is absent), each beside
a designed case of the same damage: what can still be read is read and the loss said; what cannot gets one
line that names the damage and what to do, in the recording's own format's words."""

from __future__ import annotations

import os
import re
import sqlite3
import struct
from contextlib import closing
from pathlib import Path
from typing import Any

import pytest
from mcap.writer import CompressionType

from tests.sources.bag.damaged import copied, cut, rows
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import Other, batch_rows, varied_messages, write_rosbag2
from tftools.analysis.wtf import Scene, findings_of
from tftools.sources import read_recording
from tftools.sources.bag.mcap.index import summary_of
from tftools.sources.bag.mcap.records import ChunkIndex
from tftools.sources.bag.ros1.records import (
    OP_CHUNK,
    OP_CONNECTION,
    OP_MESSAGE,
    read_bag_header,
    read_chunk,
    read_connection,
    read_record,
)
from tftools.sources.bag.rosbag2.db3 import cut_short
from tftools.sources.bag.rosbag2.db3_salvage import salvage, salvage_topics
from tftools.sources.errors import CorruptBagError, UnreadableFileError
from tftools.sources.storage.source import FileSource

# A .db3 that ends inside a page: sqlite reads the missing bytes as zeros and the message there as whole.


def test_cut_short_says_a_file_that_ends_inside_a_page_or_before_its_pages() -> None:
    header = bytearray(100)
    header[16:18] = (4096).to_bytes(2, "big")
    header[28:32] = (10).to_bytes(4, "big")
    header[24:28] = header[92:96] = (3).to_bytes(4, "big")
    assert cut_short(bytes(header), 40960) == ""
    assert cut_short(bytes(header), 40959) == "cut short: it ends 4095 bytes into a page of 4096"
    assert cut_short(bytes(header), 8192) == "cut short: 2 of its 10 pages"
    assert cut_short(bytes(header), 8192, check_count=False) == ""  # a -wal file beside it may hold the rest
    header[92:96] = (2).to_bytes(4, "big")  # the count is stale: sqlite does not trust it either
    assert cut_short(bytes(header), 8192) == ""
    header[16:18] = (1000).to_bytes(2, "big")  # not a page size
    assert cut_short(bytes(header), 40959) == ""


def test_a_db3_one_byte_short_reads_its_whole_pages_only(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", varied_messages(400))
    whole, _ = rows(bag)
    (db3,) = bag.glob("*.db3")
    cut(db3, db3.stat().st_size - 1)
    got, problems = rows(bag)
    assert set(got) <= set(whole) and got
    assert any("cut short: it ends 4095 bytes into a page of 4096" in p for p in problems)


def test_a_real_db3_one_byte_short_is_said_damaged_not_read_into_false_findings(tmp_path: Path) -> None:
    """tfbag's Franka Panda .db3 one byte short: sqlite read its last page's missing byte as 0, one rotation of
    panda_link6 -> panda_link7 came out 0.21 off unit length, and tfx wtf warned of invalid_values and a jump,
    with no word of damage; now the warning says the file is cut short and that page's messages are left out."""
    bag = copied("tfbag-franka-panda-ros2", tmp_path)
    whole, _ = rows(bag)
    (db3,) = bag.glob("*.db3")
    cut(db3, db3.stat().st_size - 1)
    got, problems = rows(bag)
    assert set(got) <= set(whole) and len(got) > 0.9 * len(whole)
    assert any("cut short" in p for p in problems)


# What cannot be read at all: one line, in the words of the problem and of the recording's format.


def test_an_empty_file_is_said_empty(tmp_path: Path) -> None:
    (tmp_path / "a.bag").write_bytes(b"")
    with pytest.raises(CorruptBagError, match=r"a\.bag: corrupt or unreadable \(an empty file: 0 bytes\)"):
        read_contents([tmp_path / "a.bag"])
    bag = write_rosbag2(tmp_path / "bag", varied_messages(3))
    (db3,) = bag.glob("*.db3")
    cut(db3, 0)
    with pytest.raises(CorruptBagError, match=r"\(bag\.db3: an empty file: 0 bytes; nothing read from it\)"):
        read_contents([bag])
    mcap = write_rosbag2(tmp_path / "mcap", varied_messages(3), storage="mcap")
    (part,) = mcap.glob("*.mcap")
    cut(part, 0)  # was: 'no MCAP magic at the start'
    with pytest.raises(CorruptBagError, match=r"\(mcap\.mcap: an empty file: 0 bytes; nothing read from it\)"):
        read_contents([mcap])


def test_a_db3_bag_that_cannot_be_read_is_said_so_once_in_ros_2_words(tmp_path: Path) -> None:
    """Was: 'corrupt or unreadable (x.db3: corrupt or unreadable (not an SQLite database); nothing read from it);
    for a ROS1 bag try `rosbag reindex`'."""
    bag = copied("tfbag-franka-panda-ros2", tmp_path)
    (db3,) = bag.glob("*.db3")
    cut(db3, 1000)
    with pytest.raises(CorruptBagError) as raised:
        read_contents([bag])
    message = str(raised.value)
    assert message.count("corrupt or unreadable") == 1 and "nothing read from it" in message
    assert "rosbag reindex" not in raised.value.hint and ".recover" in raised.value.hint


def _refused(monkeypatch: pytest.MonkeyPatch, refused: Path) -> None:
    """``refused`` cannot be opened, as a file of mode 000 cannot (root reads any file: the test runs as
    whoever runs it)."""
    real_open = os.open

    def guarded(path: Any, *args: Any, **kwargs: Any) -> int:
        if Path(path) == refused:
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(os, "open", guarded)  # as FileSource calls it


def test_a_file_tfx_may_not_read_is_said_so_not_said_not_a_bag(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Was: 'not a ROS1 bag, ROS2 bag (sqlite3 or mcap) or MCAP file (Permission denied); tftools reads .bag, ...'
    (the evo tf example bag, chmod 000, read by a user who is not root)."""
    bag = copied("ros1_evo_tf_example.bag", tmp_path)
    _refused(monkeypatch, bag)
    with pytest.raises(UnreadableFileError) as raised:
        read_contents([bag])
    assert str(raised.value) == f"{bag}: cannot be opened (Permission denied)"
    assert "chmod" in raised.value.hint


def test_a_bag_directory_whose_files_tfx_may_not_read_is_said_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bag = write_rosbag2(tmp_path / "bag", varied_messages(3))
    (db3,) = bag.glob("*.db3")
    _refused(monkeypatch, db3)
    with pytest.raises(UnreadableFileError, match=r"cannot be opened \(bag\.db3: Permission denied; nothing read"):
        read_contents([bag])


def test_a_metadata_yaml_without_its_files_says_to_copy_them(tmp_path: Path) -> None:
    """Was: '... is listed in metadata.yaml but missing; ...; for a ROS1 bag try `rosbag reindex`' (the Franka
    Panda bag directory's metadata.yaml copied alone)."""
    bag = copied("tfbag-franka-panda-ros2", tmp_path)
    (db3,) = bag.glob("*.db3")
    db3.unlink()
    with pytest.raises(
        CorruptBagError, match=r"rosbagFrankaPandaRos2\.bag\.db3 is listed in metadata\.yaml but missing"
    ) as raised:
        read_contents([bag])
    assert raised.value.hint.startswith("copy the files metadata.yaml lists into the directory")


def test_an_mcap_cut_in_its_first_chunk_says_nothing_was_read_not_a_time_of_0(tmp_path: Path) -> None:
    """Was: 'cut short at byte 1000, inside the record at byte 90: read the 0 messages before it, up to record
    time 0.000 s; the rest is lost' (the CougUV AUV's .mcap cut at 1,000 bytes)."""
    bag = copied("ros2_mcap_coug_auv_replayed", tmp_path)
    (part,) = bag.glob("*.mcap")
    cut(part, 1000)
    assert read_contents([bag]).problems == [
        "cut short at byte 1000, inside a chunk that runs from byte 90 to 584742: no message before it could be read; "
        "the rest is lost"
    ]


def test_an_mcap_bag_cut_short_says_how_much_of_what_its_metadata_lists_was_read(tmp_path: Path) -> None:
    """A scout's cut copy of a CompRobo Neato's bag as MCAP (2026-12-02): 'cut short at byte 100000, inside the
    record at byte 43', PASSED, hinted to 'repair the bag as the problem says' (it names no repair); a directory of
    one .mcap cut to nothing was told sqlite3's .recover. The chunk is said as one, with how much of what
    metadata.yaml lists was read, and the MCAP's own repair."""
    bag = copied("ros2_mcap_coug_auv_replayed", tmp_path)
    (part,) = bag.glob("*.mcap")
    cut(part, 300_000)
    (problem,) = [f for f in findings_of(Scene(read_recording([bag]))) if f.code == "bag_problem"]
    assert re.search(r" \(metadata\.yaml lists \d+ messages: \d+ read, \d+%\)$", problem.message), problem.message
    assert problem.hint.endswith("`mcap recover` (the mcap CLI) rescues what it can read"), problem.hint
    cut(part, 40)
    with pytest.raises(CorruptBagError) as raised:
        read_contents([bag])
    assert "`mcap recover`" in raised.value.hint and "sqlite3" not in raised.value.hint


def _topics_table(db3: Path) -> tuple[list[tuple[object, ...]], int, int]:
    """The topics table's rows, its root page and the page size (the file opened immutable: not changed)."""
    with closing(sqlite3.connect(f"file:{db3}?mode=ro&immutable=1", uri=True)) as db:
        rows = db.execute("SELECT id, name, type, serialization_format, offered_qos_profiles FROM topics").fetchall()
        (root,) = db.execute("SELECT rootpage FROM sqlite_master WHERE name = 'topics'").fetchone()
        (page_size,) = db.execute("PRAGMA page_size").fetchone()
    return rows, root, page_size


def test_a_db3_whose_topics_table_sqlite_cannot_read_has_its_topics_read_from_their_pages(tmp_path: Path) -> None:
    """A topics table of many topics is a b-tree: its root page damaged, sqlite refuses the whole table (and so
    tfx the whole file) where its leaf pages still hold every topic."""
    topics = [f"/sensor_{i:03d}/{'x' * 60}" for i in range(150)]
    written = [*varied_messages(5), *(Other(t, 10_000 + i, b"\0\1\0\0\0\0\0\0") for i, t in enumerate(topics))]
    bag = write_rosbag2(tmp_path / "bag", written)
    (db3,) = bag.glob("*.db3")
    table, root, page_size = _topics_table(db3)
    with db3.open("r+b") as f:  # the root, an interior page: its cells' pointers zeroed
        f.seek((root - 1) * page_size + 8)
        f.write(bytes(64))
    assert [row[:5] for row in salvage_topics(db3.read_bytes())] == table
    got, problems = rows(bag)
    assert got and problems[0].startswith("its topics table is damaged (sqlite: ")
    assert problems[0].endswith(f"{len(table)} topics read from its intact pages")


def test_a_real_db3_cut_where_its_topics_pages_are_reads_the_messages_before_the_cut(tmp_path: Path) -> None:
    """The Husky UR MoveIt 2 .db3 (29 topics, 5.3 MB) cut at half: 'corrupt or unreadable (le_bag2_0.db3: its
    topics table cannot be read: database disk image is malformed; nothing read from it)', exit 2 on every
    command; now 28 topics from their pages and the transforms of the whole pages before the cut."""
    bag = copied("ros2_db3_husky_ur_moveit2_gazebo_long_2025", tmp_path)
    whole, _ = rows(bag)
    (db3,) = bag.glob("*.db3")
    cut(db3, db3.stat().st_size // 2)
    got, problems = rows(bag)
    assert set(got) <= set(whole) and len(got) > len(whole) // 3
    assert any(p.startswith("its topics table is damaged") for p in problems)


def test_a_real_db3_whose_header_claims_2_to_the_31_pages_gives_every_message_from_its_pages(tmp_path: Path) -> None:
    """The TurtleBot3 walker's .db3 (886 pages) with its header's page count set to 2**31, its change counter
    still valid: taken for a file cut short, it is read from its pages. Compared with the intact file: all of its
    1,743 transforms in its 1,242 tf messages come back, and its 255 clock messages (1,497 messages of the topics
    read); every one of the 8,542 messages sqlite counts is in the pages. Said so: before, the line said
    'those in missing or damaged pages are lost' while none was."""
    intact = copied("ros2_db3_tb3_gazebo_walker", tmp_path / "intact")
    bag = copied("ros2_db3_tb3_gazebo_walker", tmp_path)
    (db3,) = bag.glob("*.db3")
    data = bytearray(db3.read_bytes())
    data[28:32] = (2**31).to_bytes(4, "big")
    db3.write_bytes(bytes(data))
    was, read = read_contents([intact]), read_contents([bag])
    assert not was.problems
    (problem,) = read.problems
    assert problem.startswith("the database is damaged (cut short: 886 of its 2147483648 pages): read the 1497 ")
    assert problem.endswith("all 8,542 messages its statistics count are there, none lost")
    assert sorted(batch_rows(read.transforms)) == sorted(batch_rows(was.transforms)) and len(was.transforms) == 1743
    assert read.files[0].tf_messages == was.files[0].tf_messages == {"/tf": (1241, 0), "/tf_static": (1, 0)}
    assert len(read.clock.record_time) == len(was.clock.record_time) == 255


def test_the_pages_of_a_damaged_db3_give_a_header_topics_messages_cut_to_their_header(tmp_path: Path) -> None:
    """Read from its pages (a .db3 that sqlite refuses), a camera's images are kept as far as their header
    reaches, as sqlite hands them over: not every image whole in memory at once."""
    images = [Other("/camera", 1_000 + i, bytes([i]) * 50_000, "sensor_msgs/msg/Image") for i in range(20)]
    bag = write_rosbag2(tmp_path / "bag", [*varied_messages(3), *images])
    (db3,) = bag.glob("*.db3")
    with closing(sqlite3.connect(f"file:{db3}?mode=ro&immutable=1", uri=True)) as db:
        ((camera,),) = db.execute("SELECT id FROM topics WHERE name = '/camera'").fetchall()
    data = db3.read_bytes()
    whole = salvage(data, [camera]).rows
    cut_rows = salvage(data, [camera], [camera], 64).rows
    assert [len(payload) for _, _, payload in whole] == [50_000] * 20
    assert [payload for _, _, payload in cut_rows] == [payload[:64] for _, _, payload in whole]


# A damaged MCAP chunk (hostile43): the messages whose records still parse are read, and how many said.

NAV2_TB4 = "ros2_mcap_nav2_turtlebot4.mcap"  # one zstd chunk of 8,197 messages


def _flipped(path: Path, at: int) -> None:
    with path.open("r+b") as f:
        f.seek(at)
        (byte,) = f.read(1)
        f.seek(at)
        f.write(bytes([byte ^ 0xFF]))


def test_a_real_zstd_chunk_failing_its_checksum_gives_every_message(tmp_path: Path) -> None:
    """The Nav2 TurtleBot 4's .mcap, one byte flipped inside its one zstd chunk: zstd decodes it all but its
    checksum fails. Was: 'no transforms could be read: 1 of 1 chunks could not be read (...)', exit 2 on every
    command; now all 8197 messages, the damage said."""
    bag = copied(NAV2_TB4, tmp_path)
    whole, _ = rows(bag)
    _flipped(bag, 58 + 180_000)
    got, problems = rows(bag)
    assert len(got) == len(whole) and len(set(got) - set(whole)) <= 1
    assert problems == [
        "1 of 1 chunks is damaged (zstd chunk cannot be decompressed whole (zstd data damaged (zstd decompress error: "
        "Restored data doesn't match checksum))): all 8197 of its messages still parse and are read, but a value "
        "among them may be wrong"
    ]


def test_a_real_zstd_chunk_damaged_mid_way_gives_the_messages_before_the_damage(tmp_path: Path) -> None:
    bag = copied(NAV2_TB4, tmp_path)
    whole, _ = rows(bag)
    _flipped(bag, 352_254)
    got, problems = rows(bag)
    assert set(got) <= set(whole) and 0.8 * len(whole) < len(got) < len(whole)
    assert problems == [
        "1 of 1 chunks is damaged (zstd chunk cannot be decompressed whole (zstd data damaged (zstd decompress error: "
        "Data corruption detected))): 7615 of its 8197 messages read from the records that still parse (a value "
        "among them may be wrong), 582 lost"
    ]


def test_a_real_lz4_chunk_damaged_mid_way_gives_the_messages_before_the_damage(tmp_path: Path) -> None:
    """The same recording written again with lz4 chunks (3), a byte of the first flipped: lz4 gives nothing of a
    damaged block, and the chunk's 2889 messages were all lost; now those before the damage are read."""
    from tests.corpus.variants import rewrite_mcap

    original = copied(NAV2_TB4, tmp_path)
    bag = rewrite_mcap(original, tmp_path / "lz4.mcap", compression=CompressionType.LZ4)
    whole, _ = rows(bag)
    first = _chunks(bag)[0]
    _flipped(bag, 75_113)
    got, problems = rows(bag)
    outside = [row for row in whole if not first.message_start <= row[6] <= first.message_end]
    assert set(outside) <= set(got) and len(got) > len(outside) + 1000
    assert len(set(got) - set(whole)) <= 2  # decoded past the damage: the line says a value may be wrong
    assert problems[0].startswith("1 of 3 chunks is damaged (lz4 chunk cannot be decompressed whole (lz4 data damaged")
    assert problems[0].endswith(
        "1326 of its 2889 messages read from the records that still parse (a value among them may be wrong), 1563 lost"
    )


def test_a_real_uncompressed_chunk_with_a_damaged_record_loses_that_record_only(tmp_path: Path) -> None:
    """The CougUV AUV's .mcap (one uncompressed chunk of 2671 messages), the opcode of one /tf message record
    overwritten: read in ranges, then whole (rosbag2 writes no CRC), its message index does not match it; every
    other message is read (before: none)."""
    bag = copied("ros2_mcap_coug_auv_replayed", tmp_path)
    whole, _ = rows(bag)
    (part,) = bag.glob("*.mcap")
    (chunk,) = _chunks(part)
    data = part.read_bytes()
    tf = _channel_ids(part, "/tf")
    at, records_end = chunk.records_start, chunk.records_start + chunk.records_length
    while not (data[at] == 0x05 and int.from_bytes(data[at + 9 : at + 11], "little") == tf):
        at += 9 + int.from_bytes(data[at + 1 : at + 9], "little")
        assert at < records_end
    (log_time,) = struct.unpack_from("<q", data, at + 9 + 2 + 4)
    with part.open("r+b") as f:
        f.seek(at)
        f.write(b"\x50")
    got, problems = rows(bag)
    assert got == [row for row in whole if (row[6], row[7]) != (log_time, "/tf")] and len(got) < len(whole)
    assert problems == [
        "1 of 1 chunks is damaged (message index does not match its chunk): 2670 of its 2671 messages read from the "
        "records that still parse (a value among them may be wrong), 1 lost"
    ]


def test_a_real_uncompressed_chunk_failing_its_crc_says_so_where_read_in_ranges(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The CougUV AUV's .mcap written again with a CRC on its one uncompressed chunk (as mcap's writers do by
    default; rosbag2 writes none), one byte of a /tf message's last rotation value flipped: read in ranges, the
    wrong value passed silently (a different /tf row, no word of damage); the chunk that states a CRC is now read
    whole, fails it, and says a value may be wrong. The file as rosbag2 wrote it (no CRC) is still read in ranges."""
    from tests.corpus.variants import rewrite_mcap

    original = copied("ros2_mcap_coug_auv_replayed", tmp_path)
    (part,) = original.glob("*.mcap")
    crc = rewrite_mcap(part, tmp_path / "crc.mcap", compression=CompressionType.NONE)
    whole, _ = rows(original)
    assert rows(crc) == (whole, [])
    (chunk,) = _chunks(crc)
    data = crc.read_bytes()
    assert struct.unpack_from("<I", data, chunk.offset + 9 + 24) != (0,)  # it states a CRC
    tf = _channel_ids(crc, "/tf")
    at = chunk.records_start
    while not (data[at] == 0x05 and int.from_bytes(data[at + 9 : at + 11], "little") == tf):
        at += 9 + int.from_bytes(data[at + 1 : at + 9], "little")
    _flipped(crc, at + 9 + int.from_bytes(data[at + 1 : at + 9], "little") - 3)
    got, problems = rows(crc)
    assert len(got) == len(whole) and len(set(got) - set(whole)) == 1
    assert problems == [
        "1 of 1 chunks is damaged (chunk fails its CRC check): all 2671 of its messages still parse and are read, but "
        "a value among them may be wrong"
    ]
    from tftools.sources.bag.mcap import index

    read_whole: list[Any] = []
    read_chunk = index._read_chunk

    def noted(*args: Any) -> None:
        read_whole.append(args)
        read_chunk(*args)

    monkeypatch.setattr(index, "_read_chunk", noted)
    assert rows(original) == (whole, []) and not read_whole  # in ranges: no CRC to check


def _chunks(path: Path) -> list[ChunkIndex]:
    with FileSource(path) as source:
        summary = summary_of(source)
    assert summary is not None
    return sorted(summary.chunks, key=lambda c: c.offset)


def _channel_ids(path: Path, topic: str) -> int:
    from mcap.reader import make_reader

    with path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    (channel,) = [c.id for c in summary.channels.values() if c.topic == topic]
    return int(channel)


# A ROS 1 bag cut inside its last chunk: every whole record before the cut is read.


def _tf_records(data: bytes) -> tuple[list[int], int, int]:
    """The data end of every /tf and /tf_static message record of a ROS 1 bag of uncompressed chunks, in file
    order, and its last chunk's data start and end: walked over its records here, not by tftools' reader."""
    header = read_bag_header(data)
    records, pos = [], header.data_start
    connections = {}
    at = header.index_pos
    while at < len(data):  # the connection records after the chunks
        record = read_record(data, at)
        if record.op == OP_CONNECTION:
            connection = read_connection(data, record)
            connections[connection.id] = connection.topic
        at = record.data_end
    last = (0, 0)
    while pos < header.index_pos:
        record = read_record(data, pos)
        if record.op == OP_CHUNK:
            chunk = read_chunk(record)
            assert chunk.compression == "none"
            last = (chunk.data_start, chunk.data_end)
            inner = chunk.data_start
            while inner < chunk.data_end:
                message = read_record(data, inner)
                if message.op == OP_MESSAGE and connections[message.uint("conn")] in ("/tf", "/tf_static"):
                    records.append(message.data_end)
                inner = message.data_end
        pos = record.data_end
    return records, *last


@pytest.mark.parametrize("fraction", [0.3, 0.6, 0.9])
def test_a_real_plain_bag_cut_inside_a_record_reads_every_whole_record_before_it(
    tmp_path: Path, fraction: float
) -> None:
    """The self-driving car's bag (4 uncompressed chunks) cut inside its last chunk: every /tf message whose
    record ends before the cut is read, as many as counted here over the bag's records."""
    bag = copied("ros1_car_path_follower.bag", tmp_path)
    whole, _ = rows(bag)
    records, start, end = _tf_records(bag.read_bytes())
    at = start + int((end - start) * fraction)
    expected = sum(1 for record_end in records if record_end <= at)
    cut(bag, at)
    got, problems = rows(bag)
    assert set(got) <= set(whole) and len(got) < len(whole)
    (line,) = problems
    assert line.startswith(f"{bag.name}: truncated after {at} of more than ")
    assert f"; read {expected} of ~" in line


def test_a_real_bz2_bag_cut_inside_its_last_chunk_says_why_that_chunk_is_lost(tmp_path: Path) -> None:
    """bz2 decompresses whole blocks only (a chunk is one): the Zed EKF bag cut inside its last chunk loses it,
    which the line now says."""
    bag = copied("ros1_sail_zed_revalued_stamps_2022.bag", tmp_path)
    data = bag.read_bytes()
    header, pos, last = read_bag_header(data), read_bag_header(data).data_start, (0, 0)
    while pos < header.index_pos:  # to the last chunk
        record = read_record(data, pos)
        if record.op == OP_CHUNK:
            last = (read_chunk(record).data_start, record.data_end)
        pos = record.data_end
    cut(bag, (last[0] + last[1]) // 2)
    _, problems = rows(bag)
    (line,) = problems
    assert (
        "; its last chunk (bz2) is cut short, and bz2 gives nothing of a block cut short: its messages are lost" in line
    )


def test_a_real_db3_read_from_its_pages_lets_the_pages_read_go_as_it_goes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A real TurtleBot3 lap's .db3 (28 MB) cut at 60%, read from its pages: its map's pages were all resident at
    the end (the read took 27.6 MiB beyond the imports, the intact file's 11.6 MiB); each 4 MiB of pages read is
    let go now (16.2 MiB), the file's pages left in the page cache."""
    bag = copied("ros2_db3_tb3_real_lap_2025", tmp_path)
    (db3,) = bag.glob("*.db3")
    cut(db3, db3.stat().st_size * 6 // 10)
    released: list[tuple[int, int]] = []
    release = FileSource.release

    def noted(source: FileSource, start: int, end: int) -> None:
        released.append((start, end))
        release(source, start, end)

    monkeypatch.setattr(FileSource, "release", noted)
    got, problems = rows(bag)
    assert got and any("cut short" in p for p in problems)
    size = db3.stat().st_size
    assert len(released) >= size // (4 << 20) and set(released) == {(0, size)}


def test_a_real_chunk_whose_message_index_lies_about_its_length_is_read_by_walking_it(tmp_path: Path) -> None:
    """The Nav2 TurtleBot 4's .mcap, the byte length of one of its message indexes set to 2^31 - 1 (beyond the
    file): its one chunk, intact, was lost ('no transforms could be read: 1 of 1 chunks could not be read (bad
    message index)', exit 2 on every command); now its records are walked, every message read, the index said."""
    bag = copied(NAV2_TB4, tmp_path)
    whole, _ = rows(bag)
    (chunk,) = _chunks(bag)
    at = min(chunk.index_offsets.values())
    with bag.open("r+b") as f:  # opcode (1), record length (8), channel id (2), then the entries' byte length
        f.seek(at + 11)
        f.write(struct.pack("<I", 0x7FFFFFFF))
    got, problems = rows(bag)
    assert got == whole
    assert problems == [
        "1 of 1 chunks is damaged (bad message index): all 8197 of its messages still parse and are read, but a "
        "value among them may be wrong"
    ]


@pytest.mark.parametrize("name", [NAV2_TB4, "ros2_mcap_coug_auv_replayed"], ids=["zstd", "uncompressed, in ranges"])
def test_a_real_chunk_with_a_message_index_beyond_the_file_is_walked_alike_read_from_object_storage(
    name: str, tmp_path: Path
) -> None:
    """One walk for a local file and one read in ranges through fsspec (its memory filesystem, as object storage
    is read): the chunk with a message index's length set beyond the file is walked, every message read, alike
    (the CougUV AUV's one uncompressed chunk is read in ranges, /tf and /tf_static out of its 2,671 messages)."""
    import fsspec

    bag = copied(name, tmp_path)
    (part,) = [bag] if bag.is_file() else bag.glob("*.mcap")
    whole, _ = rows(bag)
    (chunk,) = _chunks(part)
    with part.open("r+b") as f:
        f.seek(min(chunk.index_offsets.values()) + 11)
        f.write(struct.pack("<I", 0x7FFFFFFF))
    fs = fsspec.filesystem("memory")
    url = f"/hostile48/{tmp_path.name}/{part.name}"
    fs.put(str(part), url)
    try:
        here, there = (
            read_contents([part], ["/tf", "/tf_static"]),
            read_contents([f"memory://{url}"], ["/tf", "/tf_static"]),
        )
    finally:
        fs.rm(url)
    assert batch_rows(there.transforms) == batch_rows(here.transforms) and sorted(
        batch_rows(here.transforms)
    ) == sorted(whole)
    assert there.problems == here.problems and len(here.problems) == 1
    assert here.problems[0].startswith("1 of 1 chunks is damaged (bad message index): all ")
    assert there.files[0].fetched is not None and here.files[0].fetched is None  # read remotely, and here


def test_a_real_db3_sqlite_gives_up_on_lets_go_of_what_sqlite_held_before_its_pages_are_read(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The TurtleBot3 lap's .db3 with 64 KiB of its pages zeroed at 45%: its page reader and sqlite both give up
    part way, and its pages are then read. The read took 15.7 MiB beyond the imports (the intact file's 9.2): the
    page reader's buffer and map and sqlite's page cache were still held while the pages were read. Both are let
    go first now (14.0 MiB; the rest is the salvage's, which holds the messages found in one buffer)."""
    from tests.sources.bag.damaged import zeroed_pages
    from tftools.sources.bag.rosbag2 import db3 as db3_module
    from tftools.sources.bag.rosbag2.database import Database

    bag = copied("ros2_db3_tb3_real_lap_2025", tmp_path)
    (db3,) = bag.glob("*.db3")
    zeroed_pages(db3, 0.45)
    said: list[str] = []
    from tftools.sources.bag.rosbag2.db3_salvage import salvage as salvaged

    asked = Database.rows

    def rows_of(db: Database, query: str) -> list[tuple[object, ...]]:
        said.append(query)
        return asked(db, query)

    def salvage(*args: Any, **kwargs: Any) -> Any:
        said.append("salvage")
        return salvaged(*args, **kwargs)

    monkeypatch.setattr(Database, "rows", rows_of)
    monkeypatch.setattr(db3_module, "salvage", salvage)
    got, problems = rows(bag)
    assert got and any("the database is damaged" in p for p in problems)
    assert said[-2:] == ["PRAGMA shrink_memory", "salvage"]
