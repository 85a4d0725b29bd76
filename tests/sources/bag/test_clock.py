"""The recorded clock (rosgraph_msgs/Clock) read from ROS1 bags, rosbag2 bags and MCAP files, merged
in record order, alongside the transforms, damaged messages lost with a problem line."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from mcap.writer import CompressionType
from mcap.writer import Writer as McapWriter

from tests.sources import ros1_helpers as ros1h
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import (
    NS,
    T0,
    FoxgloveChannel,
    McapOptions,
    Msg,
    Other,
    Tf,
    batch_rows,
    expected_rows,
    typestore,
    varied_messages,
    write_foxglove_mcap,
    write_rosbag2,
    write_split_rosbag2,
)
from tftools.sources.bag import BagContents
from tftools.sources.storage.source import FileSource

CLOCK = "rosgraph_msgs/msg/Clock"
ROS1_CLOCK = "rosgraph_msgs/Clock"
SAMPLES = Path(__file__).resolve().parents[3] / "sample_bags"

#: (record time, clock) of each clock message as written.
Clocks = list[tuple[int, int]]


def clocks(seed: int, count: int = 150) -> Clocks:
    """Record times mostly rising, some repeated and some out of order; sim time that jumps back once."""
    rng = np.random.default_rng(seed)
    out: Clocks = []
    for i in range(count):
        record = T0 + i * NS // 50 + (int(rng.integers(-3, 3)) * NS // 10 if i % 11 == 0 else 0)
        if i % 17 == 0 and out:
            record = out[-1][0]  # a tie: kept in the order written
        sim = 40 * NS + i * NS // 100 - (5 * NS if i > count // 2 else 0) + int(rng.integers(0, 1000))
        out.append((record, sim))
    return out


def in_record_order(written: Clocks) -> tuple[list[int], list[int]]:
    ordered = sorted(written, key=lambda c: c[0])  # stable: ties as written
    return [r for r, _ in ordered], [c for _, c in ordered]


def read_clock(contents: BagContents) -> tuple[str, list[int], list[int]]:
    clock = contents.clock
    assert clock.record_time.dtype == np.int64 and clock.clock.dtype == np.int64
    return clock.topic, clock.record_time.tolist(), clock.clock.tolist()


def clock_cdr(ns: int, *, little_endian: bool = True) -> bytes:
    store = typestore()
    t = store.types
    message = t[CLOCK](clock=t["builtin_interfaces/msg/Time"](sec=ns // NS, nanosec=ns % NS))
    return bytes(store.serialize_cdr(message, CLOCK, little_endian=little_endian))


def clock_messages(written: Clocks, topic: str = "/clock") -> list[Other]:
    return [Other(topic, r, clock_cdr(c, little_endian=i % 3 != 0), CLOCK) for i, (r, c) in enumerate(written)]


# --- rosbag2 (sqlite3 and mcap) and MCAP files of ROS2 ----------------------------------------


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_rosbag2_clock_beside_transforms(tmp_path: Path, storage: str) -> None:
    tf = varied_messages(3, 200)
    written = clocks(1)
    bag = write_rosbag2(tmp_path / "bag", [*clock_messages(written), *tf], storage=storage)
    contents = read_contents([bag])
    assert read_clock(contents) == ("/clock", *in_record_order(written))
    assert batch_rows(contents.parts) == expected_rows(tf) and contents.problems == []
    assert contents.files[0].topics["/clock"] == CLOCK


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_rosbag2_split_clock_merged(tmp_path: Path, storage: str) -> None:
    written = clocks(2, 300)
    halves = [written[:140], written[140:]]
    parts = [[*clock_messages(half), *varied_messages(4 + i, 50)] for i, half in enumerate(halves)]
    bag = write_split_rosbag2(tmp_path / "split", parts, storage=storage)
    assert read_clock(read_contents([bag])) == ("/clock", *in_record_order(written))


def test_split_files_given_one_by_one_merged(tmp_path: Path) -> None:
    """Two bags named on the command line are one recording: their clocks merge by record time."""
    written = clocks(5, 200)
    first = write_rosbag2(tmp_path / "a", clock_messages(written[1::2]))
    second = write_rosbag2(tmp_path / "b", clock_messages(written[::2]), storage="mcap")
    contents = read_contents([first, second])
    assert read_clock(contents) == ("/clock", *in_record_order([*written[1::2], *written[::2]]))
    assert [f.message_count for f in contents.files] == [100, 100]


def test_clock_read_whatever_the_topics(tmp_path: Path) -> None:
    written = clocks(6, 40)
    bag = write_rosbag2(tmp_path / "bag", [*clock_messages(written, "/sim/clock"), *varied_messages(7, 30)])
    contents = read_contents([bag], ["/robot/tf"])
    assert read_clock(contents) == ("/sim/clock", *in_record_order(written))


def test_clock_topic_preferred(tmp_path: Path) -> None:
    """/clock over any other clock topic; else the one with the most messages."""
    many, few = clocks(8, 60), clocks(9, 20)
    both = write_rosbag2(tmp_path / "both", [*clock_messages(many, "/sim/clock"), *clock_messages(few, "/clock")])
    assert read_clock(read_contents([both])) == ("/clock", *in_record_order(few))
    others = write_rosbag2(tmp_path / "others", [*clock_messages(few, "/a/clock"), *clock_messages(many, "/b/clock")])
    assert read_clock(read_contents([others])) == ("/b/clock", *in_record_order(many))


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_damaged_clock_messages_lost_with_a_problem(tmp_path: Path, storage: str) -> None:
    written = clocks(10, 30)
    messages = clock_messages(written)
    messages[4] = Other("/clock", written[4][0], clock_cdr(written[4][1])[:9], CLOCK)  # cut short
    messages[7] = Other("/clock", written[7][0], b"\x07\x01\x00\x00" + clock_cdr(written[7][1])[4:], CLOCK)
    contents = read_contents([write_rosbag2(tmp_path / "bag", messages, storage=storage)])
    kept = [c for i, c in enumerate(written) if i not in (4, 7)]
    assert read_clock(contents) == ("/clock", *in_record_order(kept))
    (line,) = contents.files[0].problems
    assert line.startswith(f"/clock: 2 of 30 messages could not be decoded as {CLOCK} (cdr), skipped (first: ")


def test_no_clock(tmp_path: Path) -> None:
    for path in (SAMPLES / "robot.bag", SAMPLES / "robot_db3", SAMPLES / "robot_mcap"):
        clock = read_contents([path]).clock
        assert (clock.topic, len(clock), clock.record_time.dtype == np.int64) == ("", 0, True)


# --- MCAP files: ROS1, CDR and JSON encodings --------------------------------------------------


def write_clock_mcap(path: Path, encoding: str, written: Clocks) -> Path:
    """An MCAP of a clock channel in ``encoding`` ("ros1", "cdr" or "json") among foxglove transforms."""
    type_name, schema_encoding, definition = {
        "ros1": (ROS1_CLOCK, "ros1msg", b"time clock\n"),
        "cdr": (CLOCK, "ros2msg", b"builtin_interfaces/Time clock\n"),
        "json": (CLOCK, "jsonschema", b""),
    }[encoding]
    with path.open("wb") as f:
        writer = McapWriter(f, chunk_size=2000)
        writer.start(profile="", library="tftools-tests")
        channel = writer.register_channel(
            "/clock", encoding, writer.register_schema(type_name, schema_encoding, definition)
        )
        for record, value in written:
            writer.add_message(channel, record, _clock_payload(encoding, value), record)
        writer.finish()
    return path


def _clock_payload(encoding: str, ns: int) -> bytes:
    sec, nsec = divmod(ns, NS)
    if encoding == "ros1":
        return int(sec).to_bytes(4, "little") + int(nsec).to_bytes(4, "little")
    if encoding == "json":
        return json.dumps({"clock": {"sec": sec, "nanosec" if ns % 2 else "nsec": nsec}}).encode()
    return clock_cdr(ns)


@pytest.mark.parametrize("encoding", ["ros1", "cdr", "json"])
def test_mcap_clock_encodings(tmp_path: Path, encoding: str) -> None:
    written = sorted(clocks(11, 120))  # MCAP files are written in record order
    contents = read_contents([write_clock_mcap(tmp_path / "clock.mcap", encoding, written)])
    assert read_clock(contents) == ("/clock", *in_record_order(written))
    assert contents.problems == []


def test_mcap_clock_read_in_ranges(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The clock messages of uncompressed chunks whose bulk is images are read in byte ranges
    through the chunks' indexes, with the transforms (chunks mostly wanted are read whole)."""
    in_ranges: list[int] = []
    read_into = FileSource.read_into

    def counted(source: FileSource, view: memoryview, offset: int) -> bool:
        in_ranges.append(len(view))
        return read_into(source, view, offset)

    monkeypatch.setattr(FileSource, "read_into", counted)
    written = sorted(clocks(12, 200))
    tf = [Msg("/tf", T0 + i * NS // 30, (Tf("odom", "base", 1_700_000_000 + i),)) for i in range(300)]
    images = [Other("/camera", T0 + i * NS // 7, bytes(20_000), "sensor_msgs/msg/Image") for i in range(60)]
    options = McapOptions(
        chunk_size=100_000, compression=CompressionType.NONE, extra=[*clock_messages(written), *images]
    )
    contents = read_contents(
        [write_foxglove_mcap(tmp_path / "f.mcap", [FoxgloveChannel("/tf", "protobuf")], tf, options)]
    )
    assert read_clock(contents) == ("/clock", *in_record_order(written))
    assert len(contents.transforms) == 300 and contents.problems == [] and in_ranges


# --- ROS1 bags written by the real rosbag ------------------------------------------------------


@pytest.fixture(scope="module")
def rosbag_available() -> None:
    reason = ros1h.rosbag_unavailable()
    if reason is not None:
        pytest.skip(reason)


def ros1_messages(seed: int, written: Clocks) -> list[ros1h.Msg]:
    tf = ros1h.varied_messages(seed, 150, image_bytes=20_000)
    clock = [ros1h.Msg("/clock", "clock", r, "/gazebo", c) for r, c in written]
    mixed = [m for pair in zip(tf, clock, strict=False) for m in pair]
    return [*mixed, *clock[len(mixed) // 2 :]]


@pytest.mark.usefixtures("rosbag_available")
@pytest.mark.parametrize(("compression", "close"), [("none", True), ("bz2", True), ("lz4", True), ("none", False)])
def test_ros1_clock(tmp_path: Path, compression: str, close: bool) -> None:
    """Read through the index (uncompressed chunks in ranges, compressed whole) or, in a bag never
    closed, by scanning its chunks; the transforms read as before."""
    written = clocks(13, 200)
    path = ros1h.write_rosbag(tmp_path / "c.bag", ros1_messages(13, written), compression, 30_000, close=close)
    contents = read_contents([path])
    assert read_clock(contents) == ("/clock", *in_record_order(written))
    assert contents.files[0].topics["/clock"] == ROS1_CLOCK
    if close:
        assert contents.problems == [] and ros1h.rows_of(contents.parts) == ros1h.reference_rows(path)
    assert "/clock" not in contents.parts[0].authorities


@pytest.mark.usefixtures("rosbag_available")
def test_ros1_split_clock_merged(tmp_path: Path) -> None:
    written = clocks(14, 160)
    first = ros1h.write_rosbag(tmp_path / "a.bag", ros1_messages(14, written[:90]), "none", 30_000)
    second = ros1h.write_rosbag(tmp_path / "b.bag", ros1_messages(15, written[90:]), "lz4", 30_000)
    assert read_clock(read_contents([first, second])) == ("/clock", *in_record_order(written))
