"""The ROS2 bag reader against rosbags' reader and deserializer: sqlite3 and mcap storage, bare
files, split and compressed bags, older layouts, bags converted from ROS1, and damaged bags."""

from __future__ import annotations

import hashlib
import os
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from tests.bags import BagFormat, TfMessage, write_bag
from tests.sources.bag.formats import read_as
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import (
    NS,
    T0,
    Msg,
    Other,
    Tf,
    batch_rows,
    expected_rows,
    reference_rows,
    string_cdr,
    tf_cdr,
    typestore,
    varied_messages,
    write_legacy_rosbag2,
    write_rosbag2,
    write_split_rosbag2,
)
from tftools.core.transform import Transform
from tftools.sources import user_files
from tftools.sources.errors import BagError, CorruptBagError
from tftools.sources.recording import read_recording

TOPICS = ("/tf", "/tf_static")
MESSAGES = varied_messages(7)


def by_time(rows: list[tuple[Any, ...]]) -> list[tuple[Any, ...]]:
    """Rows in record-time order, ties in a fixed order (readers may order ties differently)."""
    return sorted(rows, key=lambda row: (row[6], repr(row)))


def read_rows(*paths: Path, topics: tuple[str, ...] = TOPICS) -> tuple[list[tuple[Any, ...]], Any]:
    contents = read_contents(list(paths), topics)
    return batch_rows(contents.transforms), contents


def assert_like_rosbags(path: Path, messages: list[Msg | Other], topics: tuple[str, ...] = TOPICS) -> Any:
    """The bag reads as written (ties in write order) and as rosbags reads it; returns the contents."""
    rows, contents = read_rows(path, topics=topics)
    assert rows == expected_rows(messages, topics)
    assert by_time(rows) == by_time(reference_rows(path, topics))
    assert contents.problems == []
    return contents


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("big_endian", [False, True], ids=["little", "big"])
def test_bag_directory(tmp_path: Path, storage: str, big_endian: bool) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage=storage, big_endian=big_endian)
    contents = assert_like_rosbags(bag, MESSAGES)
    (info,) = contents.files
    times = [m.record_time for m in MESSAGES]
    assert (info.path, info.format) == (str(bag), f"rosbag2-{storage}")
    assert (info.start, info.end, info.message_count) == (min(times), max(times), len(MESSAGES))
    assert info.topics == {m.topic: "tf2_msgs/msg/TFMessage" if isinstance(m, Msg) else m.type_name for m in MESSAGES}
    assert info.transform_count == len(contents.transforms)


def test_publishers_are_topics_and_tf_static_is_static(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    topics = ("/tf", "/tf_static", "/robot/tf", "/robot/tf_static")
    contents = assert_like_rosbags(bag, MESSAGES, topics)
    batch = contents.transforms
    assert set(batch.authorities) == set(topics)
    for row in range(len(batch)):
        topic = batch.authorities[batch.authority[row]]
        assert batch.static[row] == topic.endswith("/tf_static")


def test_chosen_topics_only_and_other_types_named(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    rows, contents = read_rows(bag, topics=("/robot/tf", "/chatter"))
    assert rows == expected_rows(MESSAGES, ("/robot/tf",))
    assert contents.problems == [
        "/chatter: std_msgs/msg/String (cdr) is not a transform message tftools reads, skipped"
    ]


def test_a_topic_named_tf_of_one_transform_is_said_to_be_no_tf_to_tf2_either(tmp_path: Path) -> None:
    """The e-Yantra eBot's recording (corpus ros2-ebot-nav2-tf-as-transformstamped-2024-db3): topic `tf`
    of geometry_msgs/msg/TransformStamped, which no tf2 listener reads; not a limitation of tftools alone."""
    lone = typestore().serialize_cdr(
        typestore().types["geometry_msgs/msg/TransformStamped"](
            typestore().types["std_msgs/msg/Header"](typestore().types["builtin_interfaces/msg/Time"](43, 0), "odom"),
            "ebot_base_link",
            typestore().types["geometry_msgs/msg/Transform"](
                typestore().types["geometry_msgs/msg/Vector3"](1.0, 2.0, 0.0),
                typestore().types["geometry_msgs/msg/Quaternion"](0.0, 0.0, 0.0, 1.0),
            ),
        ),
        "geometry_msgs/msg/TransformStamped",
    )
    bag = write_rosbag2(tmp_path / "bag", [Other("tf", T0, lone, "geometry_msgs/msg/TransformStamped")])
    _, contents = read_rows(bag)
    (line,) = contents.unread
    assert line.startswith("tf: geometry_msgs/msg/TransformStamped (cdr) is one transform, not a tf2_msgs TFMessage")
    assert "no tf2 listener reads it" in line


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_bare_file(tmp_path: Path, storage: str) -> None:
    """A .db3 or .mcap file of a bag directory, given alone."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage=storage)
    (file,) = [p for p in bag.iterdir() if p.suffix != ".yaml"]
    rows, contents = read_rows(file)
    assert rows == expected_rows(MESSAGES)
    assert contents.files[0].format == ("rosbag2-sqlite3" if storage == "sqlite3" else "mcap")
    assert contents.files[0].message_count == len(MESSAGES) and contents.problems == []


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("mode", ["file", "message"])
def test_zstd_compressed(tmp_path: Path, storage: str, mode: str) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage=storage, compression=mode)
    files = sorted(bag.iterdir())
    assert any(p.suffix == ".zstd" for p in files) == (mode == "file")
    assert_like_rosbags(bag, MESSAGES)
    assert sorted(bag.iterdir()) == files  # decompressed elsewhere, nothing left beside the bag


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_bare_file_compressed_whole(tmp_path: Path, storage: str) -> None:
    """A file of ``--compression-mode file`` given alone, away from its metadata.yaml (a user copied the one
    file): read as its directory is, decompressed elsewhere (it was refused as an unknown format)."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage=storage, compression="file")
    (compressed,) = [p for p in bag.iterdir() if p.suffix == ".zstd"]
    alone = tmp_path / "alone" / compressed.name
    alone.parent.mkdir()
    compressed.rename(alone)
    rows, contents = read_rows(alone)
    assert rows == expected_rows(MESSAGES) and contents.problems == []
    assert contents.files[0].format == f"rosbag2-{storage}"
    assert list(alone.parent.iterdir()) == [alone]


def test_bare_db3_compressed_message_by_message(tmp_path: Path) -> None:
    """Without metadata.yaml to say so, zstd-compressed payloads are recognised as such."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, compression="message")
    rows, contents = read_rows(bag / "bag.db3")
    assert rows == expected_rows(MESSAGES) and contents.problems == []


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("metadata", [True, False], ids=["metadata", "no_metadata"])
def test_split_bag(tmp_path: Path, storage: str, metadata: bool) -> None:
    """Eleven files (bag_2 comes before bag_10); equal record times across files keep file order."""
    parts = [varied_messages(seed, 30) for seed in range(11)]
    for index, part in enumerate(parts):  # one message each at the same time: file order decides
        part.append(Msg("/tf", T0 + 5 * NS, (Tf("map", f"tie_{index}", index),)))
    bag = write_split_rosbag2(tmp_path / "bag", parts, storage=storage)
    assert {p.name for p in bag.iterdir()} >= {f"bag_{i}.{'db3' if storage == 'sqlite3' else 'mcap'}" for i in (2, 10)}
    reference = reference_rows(bag)
    if not metadata:
        (bag / "metadata.yaml").unlink()
    everything = [m for part in parts for m in part]
    rows, contents = read_rows(bag)
    assert rows == expected_rows(everything)
    assert by_time(rows) == by_time(reference)
    assert contents.problems == []
    assert contents.files[0].message_count == len(everything)
    ties = [row[1] for row in rows if row[1].startswith("tie_")]
    assert ties == [f"tie_{i}" for i in range(11)]


@pytest.mark.parametrize("version", [8, 9])
def test_metadata_versions_written_by_rosbags(tmp_path: Path, version: int) -> None:
    assert_like_rosbags(write_rosbag2(tmp_path / "bag", MESSAGES, version=version), MESSAGES)


@pytest.mark.parametrize("distro", ["dashing", "foxy"])
@pytest.mark.parametrize("prefixed", [False, True], ids=["plain", "prefixed"])
def test_older_bags(tmp_path: Path, distro: str, prefixed: bool) -> None:
    """Metadata versions 1 and 4, sqlite schemas without QoS or without a timestamp index, files
    listed with the bag directory in front."""
    bag = write_legacy_rosbag2(tmp_path / "bag", MESSAGES, distro, prefixed=prefixed)
    assert_like_rosbags(bag, MESSAGES)


def test_messages_out_of_order_in_the_file(tmp_path: Path) -> None:
    """Rows come in record-time order whatever order the messages were written in."""
    messages = varied_messages(3, ties=False)
    bag = write_rosbag2(tmp_path / "bag", messages)
    assert [m.record_time for m in messages] != sorted(m.record_time for m in messages)
    rows, _ = read_rows(bag)
    assert [row[6] for row in rows] == sorted(row[6] for row in rows)
    assert rows == expected_rows(messages)


def test_input_is_not_modified(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    before = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in bag.iterdir()}
    read_contents([bag])
    read_contents([bag / "bag.db3"])
    assert {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in bag.iterdir()} == before


@pytest.mark.parametrize("compression", ["", "file"])
def test_progress_reaches_the_end(tmp_path: Path, compression: str) -> None:
    bag = write_rosbag2(tmp_path / "bag", big_messages(1000), compression=compression)
    calls: list[tuple[int, int]] = []
    read_contents([bag], progress=lambda done, total: calls.append((done, total)))
    total = sum(p.stat().st_size for p in bag.iterdir())
    assert calls[-1] == (total, total) and len(calls) > 2
    assert [done for done, _ in calls] == sorted(done for done, _ in calls)
    assert all(0 <= done <= total for done, _ in calls)


# --- bags converted from ROS1 by rosbags-convert ---------------------------------------------

SAMPLE = Path(__file__).resolve().parents[3] / "sample_bags" / "robot.bag"


def ros1_rows(path: Path) -> list[tuple[Any, ...]]:
    """A ROS1 bag's transforms as rosbags reads them: the same tuples as ``batch_rows``, the
    topic as publisher (a ROS2 bag has no caller ids)."""
    from tests.sources.ros1_helpers import reference_rows as ros1_reference_rows

    rows = []
    for parent, child, stamp, values, record_time, _, static in ros1_reference_rows(path):
        floats = [float(v).hex() for v in memoryview(values).cast("d")]
        rows.append((parent, child, stamp, tuple(floats[:3]), tuple(floats[3:]), static, record_time,
                     "/tf_static" if static else "/tf"))  # fmt: skip
    return rows


def convert(source: Path, target: Path, storage: str) -> Path:
    # rosbags' own command, from the interpreter running the tests (its scripts need not be on PATH)
    command = [
        sys.executable,
        "-m",
        "rosbags.convert",
        "--src",
        str(source),
        "--dst",
        str(target),
        "--dst-typestore",
        "ros2_humble",
    ]
    if storage == "mcap":
        command += ["--dst-storage", "mcap"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return target


def real_ros1_bag(path: Path) -> Path:
    """A bag by the real rosbag: odd frame ids and values, stamps within ROS2's int32 seconds."""
    from tests.sources.ros1_helpers import Msg as Ros1Msg
    from tests.sources.ros1_helpers import rosbag_unavailable, write_rosbag

    reason = rosbag_unavailable()
    if reason is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must test against the real rosbag, but {reason}")
        pytest.skip(reason)
    messages = []
    for i, m in enumerate(varied_messages(11, 200)):
        callerid = "/node" if i % 2 else ""
        if isinstance(m, Other):
            messages.append(Ros1Msg(m.topic, "string", m.record_time, "/talker", f"hello {i}"))
            continue
        body = [[t.parent, t.child, (t.sec % 2**31) * NS + t.nsec, [*t.translation, *t.rotation]] for t in m.transforms]
        messages.append(Ros1Msg(m.topic, "tf2", m.record_time, callerid, body))
    return write_rosbag(path, messages, "lz4", chunk_threshold=20_000)


@pytest.fixture(scope="module")
def real_rosbag(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return real_ros1_bag(tmp_path_factory.mktemp("ros1") / "real.bag")


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("source", ["sample", "real_rosbag"])
def test_converted_from_ros1(request: pytest.FixtureRequest, tmp_path: Path, storage: str, source: str) -> None:
    """A ROS1 bag converted to ROS2: the same transforms, stamps, frame names and record times."""
    ros1 = SAMPLE if source == "sample" else request.getfixturevalue("real_rosbag")
    bag = convert(ros1, tmp_path / "ros2", storage)
    rows, contents = read_rows(bag)
    assert len(rows) > 100 and contents.problems == []
    assert by_time(rows) == by_time(ros1_rows(ros1))


# --- damaged input ---------------------------------------------------------------------------


def assert_partial(rows: list[tuple[Any, ...]], expected: list[tuple[Any, ...]], problems: list[str]) -> None:
    """What was read is part of the bag, in order; each problem is one line."""
    it = iter(expected)
    assert all(row in it for row in rows), "rows read are not a subsequence of the bag's rows"
    assert all(line and "\n" not in line and "Traceback" not in line for line in problems)


def big_messages(count: int = 3000) -> list[Msg | Other]:
    """Enough messages to fill many sqlite pages, mixed with another topic; some larger than a
    page (their ends in overflow pages)."""
    out: list[Msg | Other] = []
    for i in range(count):
        tfs = (Tf("odom", "base_link", 1_700_000_000 + i, i, (i, 0.5, 0.0)), Tf("map", "odom", 1_700_000_000, i))
        out.append(Msg("/tf", T0 + i * NS // 100, tfs))
        if i % 5 == 0:
            out.append(Other("/chatter", T0 + i * NS // 100 + 1, string_cdr("x" * (i % 300))))
        if i % 50 == 0:
            many = tuple(Tf("arm_base", f"arm_link_{j}", 1_700_000_000 + i, j) for j in range(60))
            out.append(Msg("/tf", T0 + i * NS // 100 + 2, many))
    return out


@pytest.fixture(scope="module")
def big_db3(tmp_path_factory: pytest.TempPathFactory) -> Path:
    bag = write_rosbag2(tmp_path_factory.mktemp("big") / "bag", big_messages())
    return bag / "bag.db3"


@pytest.mark.parametrize("fraction", [0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99])
def test_truncated_db3(tmp_path: Path, big_db3: Path, fraction: float) -> None:
    """A .db3 cut short: the messages in what is left are read, with one problem line, or it is a
    corrupt bag (when not even the topics survive)."""
    cut = tmp_path / "cut.db3"
    data = big_db3.read_bytes()
    cut.write_bytes(data[: int(len(data) * fraction)])
    expected = expected_rows(big_messages())
    try:
        rows, contents = read_rows(cut)
    except CorruptBagError as e:
        assert fraction < 0.1 and "\n" not in str(e)
        return
    assert_partial(rows, expected, contents.problems)
    assert len(contents.problems) == 1
    assert "damaged" in contents.problems[0]
    assert len(rows) > 0.5 * fraction * len(expected)


def test_damaged_pages_in_the_middle(tmp_path: Path, big_db3: Path) -> None:
    damaged = tmp_path / "damaged.db3"
    data = bytearray(big_db3.read_bytes())
    page = sqlite3.connect(big_db3).execute("PRAGMA page_size").fetchone()[0]
    middle = len(data) // 2 // page * page
    data[middle : middle + 3 * page] = b"\xff" * (3 * page)
    damaged.write_bytes(bytes(data))
    rows, contents = read_rows(damaged)
    expected = expected_rows(big_messages())
    assert_partial(rows, expected, contents.problems)
    damage, *undecodable = contents.problems  # messages whose overflow pages were overwritten
    assert "damaged" in damage and all("could not be decoded" in line for line in undecodable)
    assert 0.5 * len(expected) < len(rows) < len(expected)


def test_damaged_file_in_a_split_bag(tmp_path: Path) -> None:
    parts = [varied_messages(seed, 40) for seed in range(3)]
    bag = write_split_rosbag2(tmp_path / "bag", parts)
    (bag / "bag_1.db3").write_bytes(b"SQLite format 3\x00" + b"\x00" * 50)
    rows, contents = read_rows(bag)
    assert rows == expected_rows(parts[0] + parts[2])
    (line,) = contents.problems
    assert line.startswith("bag_1.db3: ") and line.endswith("nothing read from it")


def test_missing_file_listed_in_metadata(tmp_path: Path) -> None:
    parts = [varied_messages(seed, 40) for seed in range(3)]
    bag = write_split_rosbag2(tmp_path / "bag", parts, storage="mcap")
    (bag / "bag_0.mcap").unlink()
    rows, contents = read_rows(bag)
    assert rows == expected_rows(parts[1] + parts[2])
    assert contents.problems == ["bag_0.mcap is listed in metadata.yaml but missing; its messages are lost"]


def test_every_file_missing(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    (bag / "bag.db3").unlink()
    with pytest.raises(CorruptBagError, match=r"bag\.db3 is listed in metadata\.yaml but missing"):
        read_contents([bag])


def test_every_file_missing_but_another_there_says_which_to_give(tmp_path: Path) -> None:
    """A CompRobo student's bag directory (mtong1/CompRoboWarmup2023 person_follower_demo) lists
    person_follower_0.db3 in metadata.yaml but holds person_follower_demo_0.db3 (renamed after recording):
    the error names the file there and how to read it, not ``rosbag reindex`` (a ROS 1 tool)."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    (bag / "bag.db3").rename(bag / "bag_demo_0.db3")
    with pytest.raises(CorruptBagError, match=r"bag\.db3 is listed in metadata\.yaml but missing") as raised:
        read_contents([bag])
    assert "bag_demo_0.db3, which metadata.yaml does not list" in raised.value.hint
    assert str(bag / "bag_demo_0.db3") in raised.value.hint and "reindex" not in raised.value.hint
    assert read_contents([bag / "bag_demo_0.db3"])  # what the hint says to give reads


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("rosbag2_bagfile_information: [unclosed\n  - : :", "metadata.yaml is unreadable"),
        ("just a string\n", "metadata.yaml has no rosbag2_bagfile_information"),
        ("rosbag2_bagfile_information:\n  version: 9\n", "metadata.yaml lists no files"),
        ("\x00\xff\xfe binary", "metadata.yaml is unreadable"),
    ],
)
def test_corrupt_metadata(tmp_path: Path, text: str, problem: str) -> None:
    """The bag files in the directory are read anyway."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    (bag / "metadata.yaml").write_text(text, "utf-8", "surrogateescape")
    rows, contents = read_rows(bag)
    assert rows == expected_rows(MESSAGES)
    (line,) = contents.problems
    assert line.startswith(problem) and line.endswith("read the bag files found instead")


def test_metadata_naming_other_storage(tmp_path: Path) -> None:
    """The files' own format counts, whatever storage_identifier says."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage="mcap")
    meta = bag / "metadata.yaml"
    meta.write_text(meta.read_text().replace("storage_identifier: mcap", "storage_identifier: sqlite3"))
    assert read_rows(bag)[0] == expected_rows(MESSAGES)


def test_undecodable_messages(tmp_path: Path) -> None:
    """Messages on /tf that are not TFMessages are skipped, one line for them all."""
    good = varied_messages(5, 100, ties=False)
    bad = [Other("/tf", T0 + 30 * NS + i, b"\x00\x01\x00\x00" + bytes([i]) * 3, "tf2_msgs/msg/TFMessage")
           for i in range(1, 4)]  # fmt: skip
    bag = write_rosbag2(tmp_path / "bag", [*good, *bad])
    rows, contents = read_rows(bag)
    assert rows == expected_rows(good)
    (line,) = contents.problems
    total = sum(1 for m in good if m.topic == "/tf") + 3
    assert line.startswith(f"/tf: 3 of {total} messages could not be decoded as tf2_msgs/msg/TFMessage (cdr)")


def test_message_that_cannot_be_decompressed(tmp_path: Path) -> None:
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, compression="message")
    db = sqlite3.connect(bag / "bag.db3")
    (tf,) = db.execute("SELECT id FROM topics WHERE name = '/tf'").fetchone()
    (first,) = db.execute("SELECT min(id) FROM messages WHERE topic_id = ?", (tf,)).fetchone()
    db.execute("UPDATE messages SET data = ? WHERE id = ?", (b"\x28\xb5\x2f\xfd broken", first))
    db.commit()
    db.close()
    rows, contents = read_rows(bag)
    broken = next(m for m in MESSAGES if m.topic == "/tf")
    assert rows == expected_rows([m for m in MESSAGES if m is not broken])
    (line,) = contents.problems
    total = sum(1 for m in MESSAGES if m.topic == "/tf")
    first = "zstd data damaged"
    assert line.startswith(f"/tf: 1 of {total} messages could not be decompressed, skipped (first: {first}")


@pytest.mark.parametrize("content", [b"", b"hello, not a bag\n", b"SQLite format 3\x00" + b"\x07" * 4000])
def test_not_a_bag(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "x.db3"
    path.write_bytes(content)
    with pytest.raises(BagError):
        read_contents([path])
    with pytest.raises(CorruptBagError):
        read_as("rosbag2", path, TOPICS)


def test_directory_of_garbage(tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "a.db3").write_bytes(b"not sqlite")
    (bag / "b.mcap").write_bytes(b"not mcap")
    with pytest.raises(CorruptBagError) as caught:
        read_contents([bag])
    assert "a.db3" in str(caught.value) and "b.mcap" in str(caught.value) and "\n" not in str(caught.value)


def test_unmerged_wal(tmp_path: Path) -> None:
    """Writes left in a -wal file (a recorder killed) are not read, and that is said."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES)
    shutil.copy(bag / "bag.db3", tmp_path / "copy.db3")
    (bag / "bag.db3-wal").write_bytes(b"\x37\x7f\x06\x82" + b"\x00" * 100)
    rows, contents = read_rows(bag)
    assert rows == expected_rows(MESSAGES)
    (line,) = contents.problems
    assert line.startswith("bag.db3-wal holds writes never merged")
    assert "a copy of the .db3" in line and "opening the original would change it" in line  # never advise that


def test_mcap_scan_is_the_bare_reader(tmp_path: Path) -> None:
    """A bag's .mcap file read by the MCAP reader and by the bag reader gives the same rows."""
    bag = write_rosbag2(tmp_path / "bag", MESSAGES, storage="mcap")
    alone = read_as("mcap", bag / "bag.mcap", TOPICS)
    in_bag = read_as("rosbag2", bag, TOPICS)
    assert batch_rows(alone[0]) == batch_rows(in_bag[0])


def test_tf_cdr_round_trip_sanity() -> None:
    """The helpers write what rosbags reads (guards the tests themselves)."""
    from tests.sources.ros2_helpers import typestore

    tf = Tf("a", "b", 3, 4, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.0))
    message = typestore().deserialize_cdr(tf_cdr([tf], little_endian=False), "tf2_msgs/msg/TFMessage")
    assert message.transforms[0].child_frame_id == "b" and message.transforms[0].header.stamp.nanosec == 4


def _listing(tmp_path: Path, missing: int) -> tuple[Path, list[list[Msg | Other]]]:
    """A split bag whose metadata.yaml lists ``missing`` files nobody wrote before its own two."""
    parts = [varied_messages(seed, 40) for seed in range(2)]
    bag = write_split_rosbag2(tmp_path / "bag", parts, storage="mcap")
    metadata = bag / "metadata.yaml"
    text = metadata.read_text()
    listed = ", ".join(f"g{n}.mcap" for n in range(missing))
    assert "relative_file_paths: [bag_0.mcap, bag_1.mcap]" in text
    metadata.write_text(text.replace("[bag_0.mcap, bag_1.mcap]", f"[{listed}, bag_0.mcap, bag_1.mcap]", 1))
    return bag, parts


@pytest.mark.slow  # ruamel parses the metadata.yaml of 40,000 files in ~3 s of CPU
def test_a_metadata_listing_many_missing_files_is_said_in_one_line(tmp_path: Path) -> None:
    """A damaged metadata.yaml that lists 40,000 files nobody wrote: one line counting them, not a line each."""
    bag, parts = _listing(tmp_path, 40_000)
    rows, contents = read_rows(bag)
    assert rows == expected_rows(parts[0] + parts[1])
    (line,) = contents.problems
    assert line == (
        "40000 files listed in metadata.yaml are missing (g0.mcap, g1.mcap, g2.mcap and 39997 more);"
        " their messages are lost"
    )


def test_a_metadata_listing_200000_files_is_not_parsed_and_the_files_found_are_read(tmp_path: Path) -> None:
    """Beyond what tfx parses (20 s of ruamel for 200,000 names): said once, and the bag's files read."""
    bag, parts = _listing(tmp_path, 200_000)
    rows, contents = read_rows(bag)
    assert rows == expected_rows(parts[0] + parts[1])
    assert contents.problems == [
        f"metadata.yaml is unreadable (more than {user_files.MAX_ITEMS:,} lines and items, more than tfx parses),"
        " read the bag files found instead"
    ]


@pytest.mark.parametrize("fmt", [BagFormat.rosbag2_sqlite3, BagFormat.rosbag2_mcap, BagFormat.ros1])
def test_tf_topics_stored_without_their_slash_are_read_as_tf(tmp_path: Path, fmt: BagFormat) -> None:
    """A writer that stored the topics as ``tf`` and ``tf_static`` (relative names, published as /tf and
    /tf_static by a bag player in the root namespace): read as the tf topics they are, statics static."""
    second = 1_000_000_000
    moving = [
        TfMessage("tf", 1000 * second + k, [Transform((k, 0, 0), (0, 0, 0, 1), 1000 * second + k, "odom", "base")])
        for k in range(5)
    ]
    fixed = TfMessage("tf_static", 1000 * second, [Transform((0.1, 0, 0), (0, 0, 0, 1), 0, "base", "laser")])
    recording = read_recording([write_bag(tmp_path / "relative", [fixed, *moving], fmt)])
    assert recording.buffer.lookup("odom", "laser").translation == pytest.approx((4.1, 0, 0))
    laser, base = recording.buffer.history("laser"), recording.buffer.history("base")
    assert laser is not None and base is not None
    assert laser.static and not base.static
