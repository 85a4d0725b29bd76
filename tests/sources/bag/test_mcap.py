"""The MCAP reader against the mcap library (with protobuf's, json's and rosbags' decoders):
Foxglove FrameTransform(s) in protobuf, JSON and CDR, tf2 channels, every layout the mcap
writer makes, and files cut short or damaged."""

from __future__ import annotations

import re
import struct
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mcap.writer import CompressionType, IndexType

from tests.sources.bag.formats import read_as
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import (
    NS,
    T0,
    TF_TYPE,
    FoxgloveChannel,
    McapOptions,
    Msg,
    Other,
    Tf,
    batch_rows,
    expected_rows,
    mcap_reference_rows,
    reference_rows,
    string_cdr,
    tf_cdr,
    varied_messages,
    varied_transform,
    write_foxglove_mcap,
    write_rosbag2,
)
from tftools.sources.bag.mcap import index as mcap_index
from tftools.sources.bag.mcap.records import CHUNK_HEAD, Body, ChunkIndex, chunk_records
from tftools.sources.bag.messages import MessageSet
from tftools.sources.bag.spans import Spans
from tftools.sources.errors import BagError, CorruptBagError
from tftools.sources.storage.source import FileSource

DEFAULT = ("/tf", "/tf_static")
CHANNELS = [
    FoxgloveChannel("/fox/pb", "protobuf"),
    FoxgloveChannel("/fox/pb_one", "protobuf", single=True),
    FoxgloveChannel("/fox/json", "json"),
    FoxgloveChannel("/fox/json_one", "json", single=True),
    FoxgloveChannel("/fox/cdr", "ros2msg"),
    FoxgloveChannel("/fox/tf_static", "ros2msg", single=True),
]
SINGLE = {c.topic for c in CHANNELS if c.single}
FOXGLOVE = tuple(c.topic for c in CHANNELS)
READ_BY_DEFAULT = (*DEFAULT, *FOXGLOVE)


@cache
def scene(seed: int, count: int = 400) -> tuple[list[Msg], list[Other], list[Msg]]:
    """(foxglove messages, other messages, every transform message in the order written): the
    foxglove channels, tf2 TFMessages on /tf, /tf_static and /robot/tf, and String on /chatter."""
    rng = np.random.default_rng(seed)
    foxglove: list[Msg] = []
    others: list[Other] = []
    tf2: dict[int, Msg] = {}  # id of the Other written -> its transforms
    topics = [*FOXGLOVE, "/tf", "/tf_static", "/robot/tf", "/chatter"]
    for i in range(count):
        record_time = T0 + int(rng.integers(0, 10 * NS)) if i % 11 else T0 + 3 * NS
        topic = topics[int(rng.integers(0, len(topics)))]
        if topic == "/chatter":
            others.append(Other(topic, record_time, string_cdr(f"hello {i}")))
            continue
        k = 1 if topic in SINGLE else int(rng.choice([0, 1, 2, 5, 30], p=[0.05, 0.5, 0.25, 0.15, 0.05]))
        message = Msg(topic, record_time, tuple(varied_transform(rng) for _ in range(k)))
        if topic.startswith("/fox"):
            foxglove.append(message)
        else:
            others.append(Other(topic, record_time, tf_cdr(message.transforms), TF_TYPE))
            tf2[id(others[-1])] = message
    stream: list[Msg | Other] = sorted([*foxglove, *others], key=lambda m: m.record_time)  # as write_foxglove_mcap does
    written = [m if isinstance(m, Msg) else tf2[id(m)] for m in stream if isinstance(m, Msg) or id(m) in tf2]
    return foxglove, others, written


FOXGLOVE_MESSAGES, OTHERS, WRITTEN = scene(1)

LAYOUTS = {
    "chunked_zstd": McapOptions(),
    "chunked_lz4": McapOptions(compression=CompressionType.LZ4),
    "chunked_plain": McapOptions(compression=CompressionType.NONE),
    "small_chunks": McapOptions(chunk_size=3000),
    "chunk_index_only": McapOptions(chunk_size=3000, index_types=IndexType.CHUNK),
    "no_index": McapOptions(chunk_size=3000, index_types=IndexType.NONE),
    "no_statistics": McapOptions(chunk_size=3000, use_statistics=False),
    "unchunked": McapOptions(use_chunking=False),
}


def write(path: Path, layout: str, messages: list[Msg] = FOXGLOVE_MESSAGES, others: list[Other] = OTHERS) -> Path:
    options = LAYOUTS[layout]
    options.extra = others
    return write_foxglove_mcap(path, CHANNELS, messages, options)


def by_time(rows: list[tuple[Any, ...]]) -> list[tuple[Any, ...]]:
    return sorted(rows, key=lambda row: (row[6], repr(row)))


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_layouts(tmp_path: Path, layout: str) -> None:
    path = write(tmp_path / "x.mcap", layout)
    contents = read_contents([path])
    rows = batch_rows(contents.transforms)
    assert rows == expected_rows(WRITTEN, READ_BY_DEFAULT)
    reference = [row for row in mcap_reference_rows(path) if row[7] in READ_BY_DEFAULT]
    assert by_time(rows) == by_time(reference)
    (info,) = contents.files
    every: list[Msg | Other] = [*FOXGLOVE_MESSAGES, *OTHERS]
    times = [m.record_time for m in every]
    assert info.problems == [] and info.format == "mcap"
    assert (info.message_count, info.start, info.end) == (len(times), min(times), max(times))
    assert info.topics["/fox/pb"] == "foxglove.FrameTransforms"
    assert info.topics["/fox/json_one"] == "foxglove.FrameTransform"
    assert info.topics["/fox/cdr"] == "foxglove_msgs/msg/FrameTransforms"
    assert info.topics["/chatter"] == "std_msgs/msg/String"


def test_static_flag_and_publishers(tmp_path: Path) -> None:
    """Rows published by their topic; static on a tf_static topic, whatever the message type."""
    batch = read_contents([write(tmp_path / "x.mcap", "chunked_zstd")]).transforms
    topics = [batch.authorities[a] for a in batch.authority]
    assert set(topics) == set(READ_BY_DEFAULT)
    assert batch.static.tolist() == [t.endswith("tf_static") for t in topics]


def test_chosen_topics(tmp_path: Path) -> None:
    """Asked for topics, only they are read (foxglove channels elsewhere too)."""
    path = write(tmp_path / "x.mcap", "small_chunks")
    topics = ("/robot/tf", "/fox/json", "/chatter")
    contents = read_contents([path], topics)
    assert batch_rows(contents.transforms) == expected_rows(WRITTEN, topics[:2])
    assert contents.problems == [
        "/chatter: std_msgs/msg/String (cdr) is not a transform message tftools reads, skipped"
    ]


@pytest.mark.parametrize("encoding", ["protobuf", "json", "ros2msg"])
def test_zero_and_absent_fields(tmp_path: Path, encoding: str) -> None:
    """proto3 leaves zeros off the wire: messages with and without them, of equal lengths too."""
    zeros = [Tf("", "", 0), Tf("a", "b", 0, 5), Tf("a", "b", 7, 0, (0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0)),
             Tf("a", "b", -3, 0, (-0.0, 0.0, 2.0), (1.0, 0.0, 0.0, 0.0)),
             Tf("ab", "b", 1, 1, (1.0, 0.0, 0.0))]  # fmt: skip
    messages = [Msg("/z", T0 + i, (tf,)) for i, tf in enumerate(zeros * 3)]
    messages += [Msg("/zs", T0 + 100 + i, tuple(zeros[i:])) for i in range(len(zeros))]
    channels = [FoxgloveChannel("/z", encoding, single=True), FoxgloveChannel("/zs", encoding)]
    path = write_foxglove_mcap(tmp_path / "z.mcap", channels, messages)
    rows = batch_rows(read_contents([path]).transforms)
    assert rows == expected_rows(messages, ("/z", "/zs")) == mcap_reference_rows(path)


def test_ros1_channels(tmp_path: Path) -> None:
    """MCAP files recorded from ROS1: tf2_msgs/TFMessage and tf/tfMessage in ROS1 serialization."""
    rng = np.random.default_rng(12)
    messages = []
    for i in range(300):
        topic = ["/tf", "/tf_static", "/tf_old"][i % 3]
        tfs = [varied_transform(rng) for _ in range(int(rng.integers(0, 4)))]
        tfs = [Tf(t.parent, t.child, t.sec % 2**32, t.nsec, t.translation, t.rotation) for t in tfs]
        messages.append(Msg(topic, T0 + int(rng.integers(0, 5 * NS)), tuple(tfs)))
    channels = [FoxgloveChannel("/tf", "ros1"), FoxgloveChannel("/tf_static", "ros1"),
                FoxgloveChannel("/tf_old", "ros1", single=True)]  # fmt: skip
    path = write_foxglove_mcap(tmp_path / "ros1.mcap", channels, messages, McapOptions(chunk_size=5000))
    topics = ("/tf", "/tf_static", "/tf_old")
    contents = read_contents([path], topics)
    rows = batch_rows(contents.transforms)
    assert rows == expected_rows(messages, topics)
    assert by_time(rows) == by_time(mcap_reference_rows(path))
    assert contents.problems == [] and contents.files[0].topics["/tf_old"] == "tf/tfMessage"


def test_ros2_bag_storage_file_alone(tmp_path: Path) -> None:
    """The .mcap of a rosbag2 directory is an MCAP file like any other."""
    from tests.sources.ros2_helpers import varied_messages, write_rosbag2

    messages = varied_messages(4)
    bag = write_rosbag2(tmp_path / "bag", messages, storage="mcap")
    rows = batch_rows(read_contents([bag / "bag.mcap"]).transforms)
    assert rows == expected_rows(messages)


# --- damaged files ---------------------------------------------------------------------------


def assert_partial(rows: list[tuple[Any, ...]], expected: list[tuple[Any, ...]], problems: list[str]) -> None:
    it = iter(expected)
    assert all(row in it for row in rows), "rows read are not a subsequence of the file's rows"
    assert all(line and "\n" not in line for line in problems)


@pytest.mark.parametrize("layout", ["small_chunks", "chunked_lz4", "unchunked", "no_index"])
def test_cut_short(tmp_path: Path, layout: str) -> None:
    """Cut anywhere: what comes before the cut is read, with one line on what was lost; a file
    cut before its first message is a corrupt bag."""
    data = write(tmp_path / "whole.mcap", layout).read_bytes()
    expected = expected_rows(WRITTEN, READ_BY_DEFAULT)
    counts = []
    for fraction in np.linspace(0.0, 1.0, 31)[:-1]:
        cut = tmp_path / "cut.mcap"
        cut.write_bytes(data[: int(len(data) * fraction)])
        try:
            contents = read_contents([cut])
        except BagError as e:  # too short to be recognised, or nothing readable
            assert fraction < 0.1 and "\n" not in str(e), e
            counts.append(0)
            continue
        rows = batch_rows(contents.transforms)
        assert_partial(rows, expected, contents.problems)
        if rows != expected:  # else cut in the summary: nothing lost
            (line,) = contents.problems
            assert line.startswith(f"cut short at byte {int(len(data) * fraction)}") and "the rest is lost" in line
        counts.append(len(rows))
    assert counts == sorted(counts) and counts[-1] > 0.8 * len(expected)


@pytest.mark.parametrize("compression", [CompressionType.ZSTD, CompressionType.LZ4, CompressionType.NONE])
def test_damaged_chunk(tmp_path: Path, compression: CompressionType) -> None:
    """Bytes overwritten inside one chunk: the other chunks' messages are read, and those of that chunk whose
    records still parse (before, all of its messages were lost); one line says so, with how many."""
    messages, others, _ = scene(2, 1500)
    options = McapOptions(chunk_size=10_000, compression=compression, extra=others)
    path = write_foxglove_mcap(tmp_path / "x.mcap", CHANNELS, messages, options)
    expected = batch_rows(read_contents([path]).transforms)
    data = bytearray(path.read_bytes())
    chunks = chunk_offsets(bytes(data))
    assert len(chunks) > 3
    start, length = chunks[len(chunks) // 2]
    middle = start + length // 2
    data[middle : middle + 64] = bytes(range(64))
    path.write_bytes(bytes(data))
    contents = read_contents([path])
    rows = batch_rows(contents.transforms)
    damaged_span = struct.unpack_from("<QQ", data, start + 9)
    outside = [row for row in expected if not damaged_span[0] <= row[6] <= damaged_span[1]]
    inside = [row for row in rows if damaged_span[0] <= row[6] <= damaged_span[1]]
    assert [row for row in rows if row not in inside] == outside
    assert len([row for row in inside if row in expected]) > 0.3 * (len(expected) - len(outside))
    assert len([row for row in inside if row not in expected]) <= 4  # the messages the overwritten bytes fall in
    assert re.fullmatch(
        r"1 of \d+ chunks is damaged \(.*\): (all )?\d+ of its (\d+ )?messages .*", contents.problems[0]
    )


def chunk_offsets(data: bytes) -> list[tuple[int, int]]:
    """(record start, record length) of the top-level chunk records."""
    pos, out = 8, []
    while pos + 9 <= len(data):
        opcode, length = struct.unpack_from("<BQ", data, pos)
        if opcode == 0x06:
            out.append((pos, 9 + length))
        if opcode == 0x02:
            break
        pos += 9 + length
    return out


def test_damaged_footer_reads_everything(tmp_path: Path) -> None:
    """Without a usable summary the records are read one by one, all of them."""
    path = write(tmp_path / "x.mcap", "small_chunks")
    data = bytearray(path.read_bytes())
    data[-8 - 20 : -8 - 12] = struct.pack("<Q", len(data) * 3)  # summary start beyond the end
    path.write_bytes(bytes(data))
    contents = read_contents([path])
    assert batch_rows(contents.transforms) == expected_rows(WRITTEN, READ_BY_DEFAULT)
    assert contents.problems == []


def test_damaged_record_without_summary(tmp_path: Path) -> None:
    """Read record by record, a file is read up to a damaged record."""
    path = write(tmp_path / "x.mcap", "unchunked")
    data = bytearray(path.read_bytes())
    pos = 8
    while pos < len(data) // 2:  # to a record half way
        pos += 9 + struct.unpack_from("<Q", data, pos + 1)[0]
    data[pos] = 0x50
    path.write_bytes(bytes(data[: len(data) * 3 // 4]))  # and no summary
    contents = read_contents([path])
    rows = batch_rows(contents.transforms)
    expected = expected_rows(WRITTEN, READ_BY_DEFAULT)
    assert_partial(rows, expected, contents.problems)
    assert 0.3 * len(expected) < len(rows) < 0.7 * len(expected)
    (line,) = contents.problems
    assert line.startswith(f"damaged at byte {pos} (unknown record type 0x50): read the ")


def test_damaged_message_index(tmp_path: Path) -> None:
    path = write(tmp_path / "x.mcap", "small_chunks")
    expected = batch_rows(read_contents([path]).transforms)
    data = bytearray(path.read_bytes())
    start, length = chunk_offsets(bytes(data))[2]
    index = start + length  # the chunk's message index records follow it
    assert data[index] == 0x07
    data[index + 9 + 2 + 4 + 8 : index + 9 + 2 + 4 + 16] = struct.pack("<Q", 10**9)  # an offset out of the chunk
    path.write_bytes(bytes(data))
    contents = read_contents([path])
    rows = batch_rows(contents.transforms)
    assert_partial(rows, expected, contents.problems)
    assert len(rows) < len(expected)
    (line,) = contents.problems
    assert line.startswith("1 of ") and "message index" in line


def test_undecodable_messages(tmp_path: Path) -> None:
    bad = [Other("/tf", T0 + 20 * NS + i, b"\x00\x01\x00\x00\xff\xff\xff\x7f", TF_TYPE) for i in range(4)]
    path = write(tmp_path / "x.mcap", "small_chunks", others=[*OTHERS, *bad])
    contents = read_contents([path])
    assert batch_rows(contents.transforms) == expected_rows(WRITTEN, READ_BY_DEFAULT)
    (line,) = contents.problems
    assert line.startswith("/tf: 4 of ") and "could not be decoded as tf2_msgs/msg/TFMessage (cdr)" in line


@pytest.mark.parametrize("content", [b"\x89MCAP0\r\n", b"\x89MCAP0\r\n" + b"\x01" * 40, b"\x89MCAP", b"plain text"])
def test_not_mcap(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "x.mcap"
    path.write_bytes(content)
    with pytest.raises(CorruptBagError) as caught:
        read_as("mcap", path, DEFAULT)
    assert "\n" not in str(caught.value)


# --- uncompressed chunks, read in ranges -----------------------------------------------------

IMAGE_TYPE = "sensor_msgs/msg/Image"
RANGE_TOPICS = ("/tf", "/tf_static", "/robot/tf", "/robot/tf_static")
LOST = " their messages are lost"


def with_images(messages: list[Msg | Other], every: int = 10, size: int = 40_000) -> list[Msg | Other]:
    """The messages with a camera image (``size`` random bytes, never decoded) after every ``every``-th."""
    rng = np.random.default_rng(size)
    out: list[Msg | Other] = []
    for i, message in enumerate(messages):
        out.append(message)
        if i % every == every - 1:
            out.append(Other("/camera/image", message.record_time, rng.bytes(size), IMAGE_TYPE))
    return out


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, int]]:
    """What the MCAP reader reads of its chunks, as it reads it: ("range", bytes) of the ranges
    read from uncompressed chunks, (compression, bytes) of a chunk read whole."""
    seen: list[tuple[str, int]] = []
    read_into = FileSource.read_into

    def counted_range(source: FileSource, view: memoryview, offset: int) -> bool:
        seen.append(("range", len(view)))
        return read_into(source, view, offset)

    def counted_chunk(content: memoryview, *args: Any) -> tuple[bytes | memoryview, str]:
        body = Body(content)
        body.take(CHUNK_HEAD)
        seen.append((body.string() or "none", len(content)))
        return chunk_records(content, *args)

    monkeypatch.setattr(FileSource, "read_into", counted_range)
    monkeypatch.setattr(mcap_index, "chunk_records", counted_chunk)
    return seen


@pytest.fixture
def handed_on(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The positions (file order) of the messages handed to the message set, in the order handed on."""
    seen: list[int] = []
    add_spans = MessageSet.add_spans

    def noted(self: MessageSet, channel: Any, spans: Spans, data: Any) -> None:
        seen.extend(spans.position.tolist())
        add_spans(self, channel, spans, data)

    monkeypatch.setattr(MessageSet, "add_spans", noted)
    return seen


def rosbags_mcap(tmp_path: Path, messages: list[Msg | Other], compression: str = "") -> Path:
    """An MCAP file as the rosbags library writes it (uncompressed chunks of about 1 MB, CRC 0)."""
    return write_rosbag2(tmp_path / "bag", messages, storage="mcap", compression=compression) / "bag.mcap"


@pytest.mark.parametrize("compression", ["", "message"])
def test_images_between_transforms_read_in_ranges(
    tmp_path: Path, reads: list[tuple[str, int]], compression: str
) -> None:
    """A bag whose bulk is images: its transforms read by index, as rosbags and the record by record
    reader read them (ties in record time kept in file order), and little more than them read; with
    every message zstd-compressed on its own too (the bag directory says so)."""
    messages = with_images(varied_messages(21, 1200))
    path = rosbags_mcap(tmp_path, messages, compression)
    contents = read_contents([path.parent if compression else path], RANGE_TOPICS)
    rows = batch_rows(contents.transforms)
    assert rows == expected_rows(messages, RANGE_TOPICS)
    assert by_time(rows) == by_time(reference_rows(path.parent, RANGE_TOPICS))
    assert contents.problems == [] and contents.files[0].topics["/camera/image"] == IMAGE_TYPE
    assert {kind for kind, _ in reads} == {"range"} and sum(n for _, n in reads) < 0.1 * path.stat().st_size
    with FileSource(path) as source:
        summary = mcap_index.summary_of(source)
        assert summary is not None and len(summary.chunks) > 3
    data = bytearray(path.read_bytes())
    data[-8 - 20 : -8 - 12] = struct.pack("<Q", len(data) * 3)  # no summary: read record by record
    path.write_bytes(bytes(data))
    assert batch_rows(read_contents([path.parent if compression else path], RANGE_TOPICS).transforms) == rows


def test_foxglove_channels_between_images(tmp_path: Path, reads: list[tuple[str, int]]) -> None:
    """The mcap library's uncompressed chunks, with every kind of transform channel among images (without CRCs, as
    rosbag2 writes them: a chunk that states one is read whole, to be checked)."""
    path = foxglove_among_images(tmp_path, chunk_size=150_000, compression=CompressionType.NONE, enable_crcs=False)
    assert {kind for kind, _ in reads} == {"range"} and sum(n for _, n in reads) < 0.2 * path.stat().st_size


def test_compressed_and_uncompressed_chunks(tmp_path: Path, reads: list[tuple[str, int]], handed_on: list[int]) -> None:
    """Chunks compressed and not in one file: the compressed read whole, the others in ranges, their
    messages handed on in file order all the same."""
    kinds = (CompressionType.NONE, CompressionType.ZSTD, CompressionType.NONE, CompressionType.LZ4)
    foxglove_among_images(
        tmp_path, compression=kinds[0], messages_per_chunk=40, chunk_compressions=kinds, enable_crcs=False
    )
    assert {kind for kind, _ in reads} == {"range", "zstd", "lz4"}
    assert handed_on == sorted(handed_on) and len(handed_on) == len(set(handed_on)) > 100


def foxglove_among_images(tmp_path: Path, **options: Any) -> Path:
    """An MCAP file by the mcap library with every kind of transform channel among camera images,
    read: the transforms written, in order, as the mcap library reads them, and no problem."""
    images = [
        m
        for m in with_images(list(OTHERS), every=3, size=20_000)
        if isinstance(m, Other) and m.topic == "/camera/image"
    ]
    written = McapOptions(extra=[*OTHERS, *images], **options)
    path = write_foxglove_mcap(tmp_path / "x.mcap", CHANNELS, FOXGLOVE_MESSAGES, written)
    contents = read_contents([path])
    rows = batch_rows(contents.transforms)
    assert rows == expected_rows(WRITTEN, READ_BY_DEFAULT)
    assert by_time(rows) == by_time([row for row in mcap_reference_rows(path) if row[7] in READ_BY_DEFAULT])
    assert contents.problems == []
    return path


def chunks_of(path: Path) -> list[ChunkIndex]:
    with FileSource(path) as source:
        summary = mcap_index.summary_of(source)
    assert summary is not None
    return sorted(summary.chunks, key=lambda c: c.offset)


def rows_outside(rows: list[tuple[Any, ...]], data: bytes, chunk: ChunkIndex) -> list[tuple[Any, ...]]:
    """The rows not recorded in the time span of ``chunk`` (messages written in record-time order)."""
    start, end = struct.unpack_from("<QQ", data, chunk.offset + 9)
    return [row for row in rows if not start <= row[6] <= end]


def damaged_rosbags_mcap(tmp_path: Path, seed: int) -> tuple[Path, list[Msg | Other], bytearray, ChunkIndex, int]:
    """A rosbags MCAP of images and transforms in record-time order: its path, messages, bytes,
    the chunk in the middle (to damage) and the number of chunks."""
    messages = with_images(sorted(varied_messages(seed, 1200, ties=False), key=lambda m: m.record_time))
    path = rosbags_mcap(tmp_path, messages)
    chunks = chunks_of(path)
    return path, messages, bytearray(path.read_bytes()), chunks[len(chunks) // 2], len(chunks)


@pytest.mark.parametrize("where", ["past_the_chunk", "inside_a_record", "swapped_with_an_image"])
def test_index_entry_pointing_elsewhere(tmp_path: Path, where: str) -> None:
    """A /tf index entry of an uncompressed chunk read in ranges that does not point at a /tf
    message: that chunk is read whole, and every message of it whose entry does point at it is read
    (before, the chunk's messages were all lost); one line says how many were lost."""
    path, messages, data, chunk, count = damaged_rosbags_mcap(tmp_path, 22)
    tf, image = [chunk.index_offsets[c] for c in _channel_ids(path, "/tf", "/camera/image")]
    tf_entry, image_entry = tf + 9 + 2 + 4 + 16 * 3 + 8, image + 9 + 2 + 4 + 8  # offsets of a /tf message, an image
    (offset,), (image_offset,) = struct.unpack_from("<Q", data, tf_entry), struct.unpack_from("<Q", data, image_entry)
    (moved_time,) = struct.unpack_from("<Q", data, tf_entry - 8)
    moved = {"past_the_chunk": 10**9, "inside_a_record": offset + 3, "swapped_with_an_image": image_offset}[where]
    struct.pack_into("<Q", data, tf_entry, moved)
    if where.startswith("swapped"):
        struct.pack_into("<Q", data, image_entry, offset)
    path.write_bytes(bytes(data))
    contents = read_contents([path], RANGE_TOPICS)
    expected = expected_rows(messages, RANGE_TOPICS)
    assert batch_rows(contents.transforms) == [row for row in expected if (row[6], row[7]) != (moved_time, "/tf")]
    (line,) = contents.problems
    lost = 2 if where.startswith("swapped") else 1
    assert line.startswith(f"1 of {count} chunks is damaged (message index does not match its chunk): ")
    assert line.endswith(
        f"messages read from the records that still parse (a value among them may be wrong), {lost} lost"
    )


@pytest.mark.parametrize("field", ["opcode", "records_length"])
def test_chunk_head_damaged(tmp_path: Path, field: str) -> None:
    """The head of a chunk read in ranges is not what the summary says: no chunk there, its messages are lost;
    a records length one past the chunk's end, its records are read all the same and the damage said."""
    path, messages, data, chunk, count = damaged_rosbags_mcap(tmp_path, 24)
    if field == "opcode":
        data[chunk.offset] = 0x50
    else:
        struct.pack_into("<Q", data, chunk.records_start - 8, chunk.records_length + 1)
    path.write_bytes(bytes(data))
    contents = read_contents([path], RANGE_TOPICS)
    expected = expected_rows(messages, RANGE_TOPICS)
    (line,) = contents.problems
    if field == "opcode":
        assert batch_rows(contents.transforms) == rows_outside(expected, bytes(data), chunk)
        assert line.startswith(f"1 of {count} chunks could not be read (") and line.endswith(LOST)
    else:
        assert batch_rows(contents.transforms) == expected
        assert line.startswith(f"1 of {count} chunks is damaged (chunk shorter than it says): all ")


@pytest.mark.parametrize("fraction", [0.02, 0.5, 0.98])
def test_cut_inside_a_chunk_summary_kept(tmp_path: Path, fraction: float) -> None:
    """A file cut inside its last chunk, its summary and footer put back after the cut: the ranges
    of that chunk run past the end or into the summary. Its message indexes are then unreadable, and its
    records are walked as a chunk's without indexes: those before the cut are read (the whole chunk was lost)."""
    messages = with_images(sorted(varied_messages(23, 1200, ties=False), key=lambda m: m.record_time))
    path = rosbags_mcap(tmp_path, messages)
    data = path.read_bytes()
    chunks = chunks_of(path)
    last = chunks[-1]
    cut = last.offset + int(last.length * fraction)
    summary_start, summary_offsets = struct.unpack_from("<QQ", data, len(data) - 8 - 20)
    moved = summary_start - cut
    footer = struct.pack("<BQQQI", 0x02, 20, summary_start - moved, summary_offsets - moved, 0) + data[-8:]
    path.write_bytes(data[:cut] + data[summary_start : len(data) - 8 - 29] + footer)
    contents = read_contents([path], RANGE_TOPICS)
    expected = expected_rows(messages, RANGE_TOPICS)
    got = batch_rows(contents.transforms)
    kept = set(got)
    assert got == [row for row in expected if row in kept] and set(rows_outside(expected, data, last)) < kept
    (line,) = contents.problems
    assert line.startswith(f"1 of {len(chunks)} chunks is damaged (chunk shorter than it says): ") and "\n" not in line


def _channel_ids(path: Path, *topics: str) -> list[int]:
    from mcap.reader import make_reader

    with path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    ids = {channel.topic: channel.id for channel in summary.channels.values()}
    return [ids[topic] for topic in topics]


def test_a_summary_that_lies_is_read_past_by_scanning(tmp_path: Path) -> None:
    """A record inserted before the chunks moves every one of them: not one chunk is where the summary
    says, so the file is read record by record instead, every transform found (issue 32 U4)."""
    path = write(tmp_path / "x.mcap", "small_chunks")
    expected = batch_rows(read_contents([path]).transforms)
    data = path.read_bytes()
    header_end = 8 + 9 + struct.unpack_from("<Q", data, 9)[0]  # the magic, then the header record
    assert data[8] == 0x01
    moved = bytearray(data[:header_end] + data[8:header_end] + data[header_end:])  # the header again
    footer = len(moved) - 8 - 29  # the footer record: opcode, length, summary start, its offsets' start, crc
    assert moved[footer] == 0x02
    for at in (footer + 9, footer + 17):  # the summary is found where it now is; the chunks it lists are not
        (offset,) = struct.unpack_from("<Q", moved, at)
        struct.pack_into("<Q", moved, at, offset + header_end - 8 if offset else 0)
    path.write_bytes(bytes(moved))
    contents = read_contents([path])
    assert batch_rows(contents.transforms) == expected and len(expected) > 100
    assert not contents.files[0].windowed  # read whole, record by record
