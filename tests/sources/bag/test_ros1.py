"""The ROS1 bag reader against rosbags' reader, on bags the real rosbag and rosbags wrote, whole and damaged."""

from __future__ import annotations

import itertools
import os
import re
import shutil
import struct
import subprocess
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag1 import Reader

from tests.sources.bag.formats import read_as
from tests.sources.bag.reading import read_contents
from tests.sources.ros1_helpers import (
    NS,
    T0,
    Msg,
    covered,
    reference_rows,
    rosbag_unavailable,
    rows_of,
    varied_messages,
    write_rosbag,
    write_rosbags,
)
from tftools.core.batch import TransformBatch
from tftools.sources.bag.contents import BagFileInfo
from tftools.sources.bag.ros1 import file as ros1_file
from tftools.sources.bag.ros1 import index as ros1_index
from tftools.sources.bag.ros1.records import read_bag_header
from tftools.sources.bag.unpack import Budget, Unpacked, unpack
from tftools.sources.codecs.ros1 import decode_tf
from tftools.sources.errors import CorruptBagError, OldRos1BagError, UnknownBagFormatError
from tftools.sources.live.received import Received, decode_received
from tftools.sources.storage.source import FileSource

TOPICS = ("/tf", "/tf_static")
SAMPLE = Path(__file__).resolve().parents[3] / "sample_bags" / "robot.bag"


@pytest.fixture(scope="session")
def rosbag_available() -> None:
    """Skip unless the real rosbag can write bags; in CI it must."""
    reason = rosbag_unavailable()
    if reason is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must test against the real rosbag, but {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Varied bags by the real rosbag, small chunks: name -> path (written once per module)."""
    if rosbag_unavailable() is not None:
        return {}
    folder = tmp_path_factory.mktemp("ros1")
    made: dict[str, Path] = {}
    for kind, messages in (("", varied_messages(1, 300)), ("ordered_", varied_messages(1, 300, ordered=True))):
        for c in ("none", "bz2", "lz4"):
            made[kind + c] = write_rosbag(folder / f"{kind}{c}.bag", messages, c, chunk_threshold=100_000)
    for c in ("none", "bz2"):
        made[f"open_{c}"] = write_rosbag(
            folder / f"open_{c}.bag", varied_messages(1, 300, ordered=True), c, 100_000, close=False
        )
    return made


def read(path: Path, topics: tuple[str, ...] = TOPICS) -> tuple[list[TransformBatch], BagFileInfo]:
    return read_as("ros1", path, topics)


def tf_messages(path: Path, topics: tuple[str, ...] = TOPICS) -> int:
    with Reader(path) as reader:
        return sum(1 for _ in reader.messages([c for c in reader.connections if c.topic in topics]))


def tf_counts(path: Path, topics: tuple[str, ...] = TOPICS) -> list[int]:
    """Transform messages per chunk, in file order, from rosbags' reading of the index."""
    with Reader(path) as reader:
        wanted = {c.id for c in reader.connections if c.topic in topics}
        infos = sorted(reader.chunk_infos, key=lambda info: info.pos)
        return [sum(n for conn, n in info.connection_counts.items() if conn in wanted) for info in infos]


# Whole bags: every row as rosbags reads it.


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_rosbag_bags_read_as_rosbags_reads_them(
    rosbag_available: None, bags: dict[str, Path], compression: str
) -> None:
    bag = bags[compression]
    topics = (*TOPICS, "/tf_old")  # tf/tfMessage
    batches, info = read(bag, topics)
    expected = reference_rows(bag, topics)
    assert len(expected) > 400 and "/legacy" in batches[0].authorities
    assert rows_of(batches) == expected
    with Reader(bag) as reader:
        assert (info.start, info.end, info.message_count) == (reader.start_time, reader.end_time - 1, 300)
        assert info.topics == {c.topic: c.msgtype.replace("/msg/", "/") for c in reader.connections}
    assert info.transform_count == len(expected)
    assert info.format == "ros1" and info.problems == []


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_several_publishers_on_one_topic_and_tf1_messages(tmp_path: Path, compression: str) -> None:
    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=2), compression, chunk_threshold=60_000)
    topics = ("/tf", "/tf_static", "/tf_old")
    batches, info = read(bag, topics)
    assert rows_of(batches) == reference_rows(bag, topics)
    (batch,) = batches
    # /tf has three connections: two callerids and one without (whose publisher is the topic)
    assert {"/amcl", "/ekf", "/tf", "/robot_state_publisher", "/legacy"} == set(batch.authorities)
    assert info.topics["/tf_old"] == "tf/tfMessage"
    assert batch.static.any() and not batch.static.all()


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_decoding_equals_rosbags_deserializer(tmp_path: Path, seed: int) -> None:
    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=seed, count=600), "none", chunk_threshold=30_000)
    topics = ("/tf", "/tf_static", "/tf_old")
    batches, info = read(bag, topics)
    assert rows_of(batches) == reference_rows(bag, topics) and info.problems == []


def test_malformed_messages_are_skipped_with_a_reason(tmp_path: Path) -> None:
    good = _tf_payload([("map", "odom", T0, 1.0)])
    size = len(good)
    malformed = {
        good + b"\x00": "1 byte after the last transform",
        good[:-1]: f"message ends at byte {size - 1}, a field needs {size}",
        struct.pack("<I", 2) + good[4:]: f"2 transforms cannot fit in {size} bytes",
        _tf_payload([("map", "od\xff", T0, 1.0)]): "a frame id is not UTF-8",
        b"": "message ends at byte 0, a field needs 4",
        struct.pack("<I", 0) + b"\x01": "1 byte after the last transform",
    }
    bag = _raw_bag(tmp_path / "m.bag", [good, *malformed, struct.pack("<I", 0), good])
    batches, info = read(bag)
    assert [(row[:3], row[4]) for row in rows_of(batches)] == [(("map", "odom", T0), T0), (("map", "odom", T0), T0 + 8)]
    (line,) = info.problems
    assert line == (
        "/tf: 6 of 9 messages could not be decoded as tf2_msgs/TFMessage (ros1),"
        " skipped (first: 1 byte after the last transform)"
    )
    for payload, reason in malformed.items():  # as live sources decode them
        ((_, said),) = decode_received(decode_tf, [Received("/tf", payload, "", 0)]).unreadable
        assert re.search(reason, said)


def test_frame_ids_that_differ_in_one_byte_stay_apart(tmp_path: Path) -> None:
    """Frame ids of one length are told apart by all their bytes: robot_1/base_link and robot_2/base_link."""
    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=9), "none")
    expected = reference_rows(bag)
    (batch,), _ = read(bag)
    assert {"robot_1/base_link", "robot_2/base_link"} <= set(batch.frame_names)
    assert rows_of(batch) == expected


@pytest.mark.parametrize("threshold", [10_000_000, 500])
def test_one_big_chunk_or_hundreds_of_small_ones(tmp_path: Path, threshold: int) -> None:
    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=6, image_bytes=1_000), "lz4", threshold)
    chunks = len(tf_counts(bag))
    assert chunks == 1 if threshold > 1_000_000 else chunks > 100
    assert rows_of(read(bag)[0]) == reference_rows(bag)


def test_only_chunks_holding_transforms_are_decompressed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A bag whose bulk is images: its image-only chunks are never read."""
    early = [
        Msg("/tf", "tf2", T0 + i * NS // 10, "/amcl", [("map", "odom", T0 + i, [0.0] * 6 + [1.0])]) for i in range(50)
    ]
    images = [Msg("/camera/image", "string", T0 + 6 * NS + i * NS // 10, "/camera", "x" * 200_000) for i in range(40)]
    bag = write_rosbags(tmp_path / "b.bag", early + images, "bz2", chunk_threshold=100_000)
    decompressed: list[int] = []

    def counting(compression: str, raw: bytes | memoryview, size: int, budget: Budget | None = None) -> Unpacked:
        decompressed.append(size)
        return unpack(compression, raw, size, budget)

    monkeypatch.setattr(ros1_file, "unpack", counting)
    batches, info = read(bag)
    counts = tf_counts(bag)
    assert len(counts) > 20
    assert len(decompressed) == sum(1 for n in counts if n) < 5
    assert len(rows_of(batches)) == 50 and info.message_count == 90


# Uncompressed chunks: only the wanted records are read, by the chunks' indexes.


def interleaved(images: int, image_bytes: int) -> list[Msg]:
    """Three /tf messages between consecutive camera images, as a robot with a camera records."""
    messages = []
    for i in range(images):
        t = T0 + i * NS // 10
        messages.append(Msg("/camera/image", "image", t, "/camera", image_bytes))
        for k in range(1, 4):
            transform = ("odom", "base_link", t + k, [0.1 * i, 0.2 * k, 0.0, 0.0, 0.0, 0.0, 1.0])
            messages.append(Msg("/tf", "tf2", t + k, "/ekf", [transform]))
    return messages


def test_the_images_of_an_uncompressed_bag_are_not_read(
    rosbag_available: None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bag = write_rosbag(tmp_path / "b.bag", interleaved(60, 300_000), "none", chunk_threshold=768 * 1024)
    read_bytes: list[int] = []
    pread, read_into = os.pread, FileSource.read_into

    def counted_pread(fd: int, length: int, offset: int) -> bytes:  # a chunk read whole
        read_bytes.append(length)
        return pread(fd, length, offset)

    def counted_range(source: FileSource, view: memoryview, offset: int) -> bool:
        read_bytes.append(len(view))
        return read_into(source, view, offset)

    monkeypatch.setattr(os, "pread", counted_pread)
    monkeypatch.setattr(FileSource, "read_into", counted_range)
    batches, info = read(bag)
    assert rows_of(batches) == reference_rows(bag) and len(rows_of(batches)) == 180 and info.problems == []
    assert len(tf_counts(bag)) > 20 and bag.stat().st_size > 18_000_000
    assert 0 < sum(read_bytes) < 100_000  # the transforms' records, not the 18 MB of images


def test_chunk_headers_and_indexes_are_prefetched(
    rosbag_available: None, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each chunk's header and index records are asked for all at once first: from a file not in
    the page cache, reading them one chunk after another would wait for the disk at each."""
    bag = write_rosbag(tmp_path / "b.bag", interleaved(60, 300_000), "none", chunk_threshold=768 * 1024)
    prefetched: list[tuple[int, int]] = []

    def noted(_source: FileSource, starts: np.ndarray, ends: np.ndarray) -> None:
        prefetched.extend(zip(starts.tolist(), ends.tolist(), strict=True))

    monkeypatch.setattr(FileSource, "ahead", noted)
    assert rows_of(read(bag)[0]) == reference_rows(bag)
    with Reader(bag) as reader:
        infos = sorted(reader.chunk_infos, key=lambda info: info.pos)
        ends = [*(info.pos for info in infos[1:]), read_bag_header(bag.read_bytes()).index_pos]
        for info, end in zip(infos, ends, strict=True):
            chunk = reader.chunks[info.pos]
            assert covered(prefetched, info.pos, chunk.datapos)  # the chunk's header
            assert covered(prefetched, chunk.datapos + chunk.datasize, end)  # its index records
    assert len(infos) > 20 and sum(b - a for a, b in prefetched) < 0.01 * bag.stat().st_size


@pytest.mark.parametrize(("records", "nbytes"), [(1, 1 << 30), (1 << 30, 1), (40, 1 << 30), (1 << 30, 1 << 30)])
def test_records_read_in_batches_of_any_size_read_alike(
    rosbag_available: None, bags: dict[str, Path], monkeypatch: pytest.MonkeyPatch, records: int, nbytes: int
) -> None:
    """Chunk after chunk, a few chunks at a time, or the whole bag at once: the same rows."""
    monkeypatch.setattr(ros1_index, "_SPAN_RECORDS", records)
    monkeypatch.setattr(ros1_index, "_SPAN_BYTES", nbytes)
    for name in ("none", "ordered_none"):
        batches, info = read(bags[name], (*TOPICS, "/tf_old"))
        assert rows_of(batches) == reference_rows(bags[name], (*TOPICS, "/tf_old")) and info.problems == []


def test_an_index_entry_pointing_at_another_topics_record_loses_that_message(
    rosbag_available: None, tmp_path: Path
) -> None:
    bag = write_rosbag(tmp_path / "b.bag", interleaved(10, 5_000), "none", chunk_threshold=1 << 20)
    data = bytearray(bag.read_bytes())
    with Reader(bag) as reader:
        tf, image = (next(c for c in reader.connections if c.topic == t) for t in ("/tf", "/camera/image"))
        entry, target = reader.indexes[tf.id][4], reader.indexes[image.id][2]
    # The index data record of /tf lists (sec, nsec, offset) entries; point the fifth at an image.
    needle = struct.pack("<III", entry.time // NS, entry.time % NS, entry.offset)
    assert data.count(needle) == 1
    at = data.index(needle)
    data[at + 8 : at + 12] = struct.pack("<I", target.offset)
    line = read_losing_one(bag, data, entry.time, tmp_path)
    assert line.startswith("damaged.bag: a damaged part could not be read (first at byte ")
    assert line.endswith("its index points at no message); 1 transform messages lost")


def test_a_record_longer_than_its_index_allows_loses_that_message(rosbag_available: None, tmp_path: Path) -> None:
    """Its length would reach into the next record read: it is refused, not decoded from foreign bytes."""
    bag = write_rosbag(tmp_path / "b.bag", interleaved(10, 5_000), "none", chunk_threshold=1 << 20)
    data = bytearray(bag.read_bytes())
    with Reader(bag) as reader:
        tf = next(c for c in reader.connections if c.topic == "/tf")
        entry = reader.indexes[tf.id][4]
        record = reader.chunks[entry.chunk_pos].datapos + entry.offset
    (header_len,) = struct.unpack_from("<I", data, record)
    (data_len,) = struct.unpack_from("<I", data, record + 4 + header_len)
    struct.pack_into("<I", data, record + 4 + header_len, data_len + 64)
    assert read_losing_one(bag, data, entry.time, tmp_path).endswith("; 1 transform messages lost")


def read_losing_one(bag: Path, data: bytearray, record_time: int, tmp_path: Path) -> str:
    """``bag`` damaged into ``data``, read: all its rows but the message recorded at ``record_time``'s;
    its one problem line."""
    damaged = tmp_path / "damaged.bag"
    damaged.write_bytes(bytes(data))
    batches, info = read(damaged)
    assert rows_of(batches) == [row for row in reference_rows(bag) if row[4] != record_time]
    (line,) = info.problems
    return line


def test_the_sample_bag(rosbag_available: None) -> None:
    batches, info = read(SAMPLE)
    assert rows_of(batches) == reference_rows(SAMPLE)
    assert info.transform_count == 6307


def test_read_bag_reports_progress_and_other_types(tmp_path: Path) -> None:
    messages = [
        Msg("/tf", "string", T0, "/confused", "not a transform"),
        Msg("/tf_static", "tf2", T0 + 1, "/rsp", [("base", "laser", T0, [0.0] * 6 + [1.0])]),
    ]
    bag = write_rosbags(tmp_path / "b.bag", messages)
    seen: list[tuple[int, int]] = []
    contents = read_contents([bag], progress=lambda done, total: seen.append((done, total)))
    assert contents.problems == ["/tf: std_msgs/String (ros1) is not a transform message tftools reads, skipped"]
    assert rows_of(contents.transforms) == [
        ("base", "laser", T0, np.array([0.0] * 6 + [1.0]).tobytes(), T0 + 1, "/rsp", True)
    ]
    assert seen[-1] == (bag.stat().st_size,) * 2
    assert all(a[0] <= b[0] for a, b in itertools.pairwise(seen))


# Damaged bags: what can be read is read, each problem is one line.


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_truncated_bags_read_what_is_left(
    rosbag_available: None, bags: dict[str, Path], tmp_path: Path, compression: str
) -> None:
    bag = bags[f"ordered_{compression}"]
    data = bag.read_bytes()
    full = reference_rows(bag)
    with Reader(bag) as reader:
        first_chunk = min(c.pos for c in reader.chunk_infos)
    read_before = -1
    for cut in [first_chunk + 50, len(data) // 3, len(data) // 2, 2 * len(data) // 3]:
        cut_bag = tmp_path / "cut.bag"
        cut_bag.write_bytes(data[:cut])
        batches, info = read(cut_bag)
        rows = rows_of(batches)
        assert rows == full[: len(rows)]  # what was recorded before the cut
        assert len(rows) >= read_before
        read_before = len(rows)
        (line,) = info.problems
        assert line.startswith(f"cut.bag: truncated after {cut} of more than ")
        assert f"; read {_messages(batches)} of " in line
        assert line.endswith("(run `rosbag reindex` on a copy to repair it)")
    assert read_before > 0


@pytest.mark.parametrize("compression", ["none", "bz2"])
def test_a_bag_cut_in_its_index_is_read_whole(
    rosbag_available: None, bags: dict[str, Path], tmp_path: Path, compression: str
) -> None:
    data = bags[compression].read_bytes()
    for cut in (len(data) - 1, len(data) - 150):
        cut_bag = tmp_path / "cut.bag"
        cut_bag.write_bytes(data[:cut])
        batches, info = read(cut_bag)
        assert rows_of(batches) == reference_rows(bags[compression])
        (line,) = info.problems
        assert line.startswith("cut.bag: has a damaged index (") and "by scanning its chunks" in line


@pytest.mark.parametrize("cut", [0, 5, 13, 20])
def test_a_bag_cut_in_its_header_is_corrupt(bags: dict[str, Path], tmp_path: Path, cut: int) -> None:
    bag = tmp_path / "cut.bag"
    bag.write_bytes(SAMPLE.read_bytes()[:cut])
    with pytest.raises((CorruptBagError, UnknownBagFormatError)):
        read_contents([bag])


def test_not_a_bag(tmp_path: Path) -> None:
    bag = tmp_path / "x.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n" + b"\xff" * 5000)
    with pytest.raises(CorruptBagError, match=r"x\.bag: corrupt or unreadable"):
        read(bag)
    bag.write_bytes(b"no bag at all" * 100)
    with pytest.raises(UnknownBagFormatError):
        read_contents([bag])


@pytest.mark.parametrize(("version", "hint"), [("1.2", "rosbag fix OLD.bag NEW.bag"), ("1.1", "1.2 and 2.0 only")])
def test_a_bag_of_the_old_format_is_said_to_be_one(tmp_path: Path, version: str, hint: str) -> None:
    """A ROS 1 bag of format 1.x (scan_tools' 2010 demo bags are 1.2) is a ROS 1 bag tfx does not read, not
    "not a ROS1 bag"; the hint says what converts it (Noetic's rosbag fails on a 1.2 bag's messages)."""
    bag = tmp_path / "demo.bag"
    # a 1.2 bag's first record: its header's length, then op=0x03 (FILE_HEADER) as "op=" field
    bag.write_bytes(
        f"#ROSRECORD V{version}\n".encode() + struct.pack("<I", 8) + b"\x04\x00\x00\x00op=\x03" + b"\x00" * 64
    )
    with pytest.raises(OldRos1BagError) as raised:
        read_contents([bag])
    assert isinstance(raised.value, UnknownBagFormatError)
    assert (
        raised.value.problem == f"a ROS 1 bag of the old format {version}, which tftools does not read (it reads 2.0)"
    )
    assert hint in raised.value.hint


@pytest.mark.parametrize("compression", ["none", "bz2"])
def test_an_unclosed_bag_reads_as_rosbag_reindex_repairs_it(
    rosbag_available: None, bags: dict[str, Path], tmp_path: Path, compression: str
) -> None:
    bag = bags[f"open_{compression}"]
    copy = shutil.copy(bag, tmp_path / "copy.bag")
    (tmp_path / "re").mkdir()
    done = subprocess.run(["rosbag", "reindex", "--output-dir", str(tmp_path / "re"), copy], capture_output=True)
    assert done.returncode == 0, done.stderr
    batches, info = read(bag)
    repaired = reference_rows(tmp_path / "re" / "copy.bag")
    if compression == "none":  # rosbag reindex drops the open chunk's messages; all are on disk
        assert rows_of(batches) == reference_rows(bags["ordered_none"])
        assert not Counter(repaired) - Counter(rows_of(batches))
    else:  # the open chunk is still in the compressor: lost for both
        assert rows_of(batches) == repaired
    (line,) = info.problems
    assert line.startswith(f"{bag.name}: has no index (its recording was not closed); read {_messages(batches)} ")


@pytest.mark.parametrize("compression", ["bz2", "lz4"])
def test_a_damaged_chunk_loses_its_messages_only(
    rosbag_available: None, bags: dict[str, Path], tmp_path: Path, compression: str
) -> None:
    bag = bags[f"ordered_{compression}"]
    data = bytearray(bag.read_bytes())
    with Reader(bag) as reader:
        info = sorted(reader.chunk_infos, key=lambda i: i.pos)[2]
        chunk = reader.chunks[info.pos]
    middle = chunk.datapos + chunk.datasize // 2
    data[middle : middle + 40] = b"\xa5" * 40
    damaged = tmp_path / "damaged.bag"
    damaged.write_bytes(bytes(data))
    batches, problems = read(damaged)[0], read(damaged)[1].problems
    in_chunk = [row for row in reference_rows(bag) if info.start_time <= row[4] < info.end_time]
    assert in_chunk
    read_in_chunk = [row for row in rows_of(batches) if row in in_chunk]
    wrong = [row for row in rows_of(batches) if row not in reference_rows(bag)]  # where the bytes were overwritten
    assert [row for row in rows_of(batches) if row not in wrong] == [
        row for row in reference_rows(bag) if row not in in_chunk or row in read_in_chunk
    ]
    assert len(wrong) <= 2
    (line,) = problems
    if compression == "bz2":  # a bz2 block gives nothing unless whole
        assert line.startswith(f"damaged.bag: a damaged part could not be read (first at byte {info.pos}: bz2")
        assert not read_in_chunk and line.endswith(f"; {tf_counts(bag)[2]} transform messages lost")
    else:  # lz4: the sequences before the damage are exact (before, the chunk's messages were all lost)
        assert len(read_in_chunk) > len(in_chunk) // 2
        assert line.startswith(f"damaged.bag: a damaged part found (first at byte {info.pos}: lz4 data damaged")
        assert line.endswith("; of a damaged chunk, the transform messages read may hold a wrong value")


def test_a_damaged_message_header_loses_that_message(
    rosbag_available: None, bags: dict[str, Path], tmp_path: Path
) -> None:
    bag, data = bags["ordered_none"], bytearray(bags["ordered_none"].read_bytes())
    with Reader(bag) as reader:
        tf = next(c for c in reader.connections if c.topic == "/tf")
        entry = reader.indexes[tf.id][10]
        record = reader.chunks[entry.chunk_pos].datapos + entry.offset
    data[record + 4 : record + 12] = b"\x00" * 8
    damaged = tmp_path / "damaged.bag"
    damaged.write_bytes(bytes(data))
    batches, info = read(damaged)
    assert rows_of(batches) == [row for row in reference_rows(bag) if row[4] != entry.time]
    (line,) = info.problems
    assert line.endswith("; 1 transform messages lost")


def test_without_lz4_its_chunks_are_one_problem_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=7), "lz4", chunk_threshold=50_000)
    monkeypatch.setitem(sys.modules, "lz4.frame", None)  # import fails
    batches, info = read(bag)
    assert batches == []
    (line,) = info.problems
    assert "the lz4 package is not installed (pip install lz4)" in line
    assert line.endswith(f"; {sum(tf_counts(bag))} transform messages lost")


def test_any_damage_reads_or_raises_corrupt_bag(tmp_path: Path) -> None:
    """Cut, overwritten or deleted bytes anywhere: what is read or one CorruptBagError, never another exception."""
    rng = np.random.default_rng(11)
    for compression in ("none", "bz2"):
        bag = write_rosbags(
            tmp_path / f"{compression}.bag", varied_messages(8, 120, 5_000, ordered=True), compression, 20_000
        )
        data, full = bag.read_bytes(), reference_rows(bag)
        for k in range(40):
            damaged = bytearray(data)
            at = int(rng.integers(13, len(data)))
            if k % 3 == 0:
                del damaged[at:]
            elif k % 3 == 1:
                damaged[at : at + 300] = rng.integers(0, 256, 300, dtype=np.uint8).tobytes()
            else:
                del damaged[at : at + int(rng.integers(1, 3000))]
            fuzzed = tmp_path / "fuzz.bag"
            fuzzed.write_bytes(bytes(damaged))
            try:
                batches, info = read(fuzzed)
            except CorruptBagError as e:
                assert str(e).startswith(f"{fuzzed}: corrupt or unreadable (")
                continue
            assert all("\n" not in line for line in info.problems)
            if k % 3 == 0:  # cut: what was recorded before the cut
                rows = rows_of(batches)
                assert rows == full[: len(rows)] and info.problems


def _messages(batches: list[TransformBatch]) -> int:
    """Messages that the rows came from (each message's rows share a record time and publisher)."""
    rows = rows_of(batches)
    return len({(r[4], r[5]) for r in rows}) if rows else 0


def _tf_payload(transforms: list[tuple[str, str, int, float]]) -> bytes:
    parts = [struct.pack("<I", len(transforms))]
    for parent, child, stamp, x in transforms:
        parts.append(struct.pack("<III", 0, stamp // NS, stamp % NS))
        for name in (parent, child):
            raw = name.encode("latin-1")
            parts.append(struct.pack("<I", len(raw)) + raw)
        parts.append(struct.pack("<7d", x, 0, 0, 0, 0, 0, 1))
    return b"".join(parts)


def _raw_bag(path: Path, payloads: list[bytes]) -> Path:
    from rosbags.rosbag1 import Writer

    with Writer(path) as writer:
        connection = writer.add_connection(
            "/tf", "tf2_msgs/msg/TFMessage", msgdef="geometry_msgs/TransformStamped[] transforms", md5sum="0" * 32
        )
        for i, payload in enumerate(payloads):
            writer.write(connection, T0 + i, payload)
    return path


def test_a_message_of_thousands_of_transforms_among_small_ones(tmp_path: Path) -> None:
    """Read on its own past the few messages still going (not in a million numpy rounds), and alike."""
    rng = np.random.default_rng(9)
    big = [(f"p{i % 7}", f"frame_{i}" * (1 + i % 3), T0 + i, tuple(rng.normal(size=7))) for i in range(3000)]
    messages = [*varied_messages(seed=6, count=60), Msg("/tf", "tf2", T0 + 3 * NS, "/big", big)]
    bag = write_rosbags(tmp_path / "b.bag", messages, "none", chunk_threshold=30_000)
    topics = ("/tf", "/tf_static", "/tf_old")
    batches, _ = read(bag, topics)
    assert rows_of(batches) == reference_rows(bag, topics)
    assert len(rows_of(batches)) > 3000


def test_when_damage_takes_every_transform_the_error_says_so(tmp_path: Path) -> None:
    from tftools.sources.errors import NoTransformsError
    from tftools.sources.recording import read_recording

    bag = write_rosbags(tmp_path / "b.bag", varied_messages(seed=7, count=80, image_bytes=10), "bz2")
    data = bytearray(bag.read_bytes())
    at = data.find(b"BZh")
    while at != -1:  # every compressed chunk's stream spoilt just after its header
        data[at + 10 : at + 60] = bytes(50)
        at = data.find(b"BZh", at + 60)
    bag.write_bytes(bytes(data))
    with pytest.raises(NoTransformsError, match=r"no transforms could be read: .*bz2") as caught:
        read_recording([bag])
    assert "encoding tfx does not read" not in str(caught.value) and "re-copy" in caught.value.hint
