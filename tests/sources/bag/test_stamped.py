"""Sensor data's headers per topic: the streams of a split recording's files merged into one."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.sources.ros2_helpers import Other, typestore, write_rosbag2
from tftools.sources import read_recording
from tftools.sources.contents import StampedMessages
from tftools.sources.headers import merged

IMAGE = "sensor_msgs/msg/Image"


def _stream(topic: str, times: list[int], frames: list[int], names: list[str]) -> StampedMessages:
    record_time = np.array(times, np.int64)
    return StampedMessages(
        topic, "sensor_msgs/msg/Imu", record_time, record_time - 5, np.array(frames, np.int32), names
    )


def test_a_topic_of_two_files_is_one_stream_in_record_order_naming_only_its_frames() -> None:
    first = _stream("/imu", [10, 30], [2, 2], ["map", "odom", "imu_left"])
    second = _stream("/imu", [20, 40], [0, 1], ["imu_right", "imu_left"])
    other = _stream("/scan", [15], [0], ["laser"])
    scan, imu = merged([first, other, second])[::-1]
    assert imu.record_time.tolist() == [10, 20, 30, 40] and imu.stamp.tolist() == [5, 15, 25, 35]
    assert list(imu.frame_ids) == ["imu_left", "imu_right"]
    assert [imu.frame_ids[f] for f in imu.frame.tolist()] == ["imu_left", "imu_right", "imu_left", "imu_left"]
    assert (scan.topic, list(scan.frame_ids), scan.frame.tolist()) == ("/scan", ["laser"], [0])


def _image(store: Any, sec: int, frame: str, size: int) -> bytes:
    header = store.types["std_msgs/msg/Header"](store.types["builtin_interfaces/msg/Time"](sec, 250), frame)
    pixels = np.random.default_rng(sec).integers(0, 256, size, np.uint8)  # incompressible
    image = store.types[IMAGE](header, 1, size, "mono8", 0, size, pixels)
    return bytes(store.serialize_cdr(image, "sensor_msgs/msg/Image"))


@pytest.mark.parametrize("compression", ["", "message", "file"])
def test_a_db3_gives_each_images_header_whole_or_compressed(tmp_path: Path, compression: str) -> None:
    """sqlite hands over only a header's bytes of an uncompressed image (and a compressed one whole):
    the stamps and frames are those written, long frame names included."""
    store = typestore()
    frames = ["camera", "c" * 3000]
    images = [Other("/camera", 1_000 + i, _image(store, 100 + i, frames[i % 2], 50_000), IMAGE) for i in range(6)]
    bag = write_rosbag2(tmp_path / "images", images, compression=compression)
    (stream,) = read_recording([bag], headers=(), allow_empty=True).stamped.streams
    assert stream.record_time.tolist() == [1_000 + i for i in range(6)]
    assert stream.stamp.tolist() == [(100 + i) * 1_000_000_000 + 250 for i in range(6)]
    assert [stream.frame_ids[f] for f in stream.frame.tolist()] == [frames[i % 2] for i in range(6)]


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_a_read_of_a_few_headers_per_topic_decodes_no_more(tmp_path: Path, storage: str) -> None:
    """``header_limit`` (what names a recording's data frames where it has no tf): each topic's first headers,
    in record order, and no more; a topic of fewer gives them all, a tf topic every transform."""
    from tests.sources.ros2_helpers import Msg, Tf

    store = typestore()
    written: list[Msg | Other] = []
    for i in range(6):
        written.append(Other("/camera", 1_000 + 10 * i, _image(store, 100 + i, f"camera{i}", 100), IMAGE))
        written.append(Msg("/tf", 1_001 + 10 * i, (Tf("map", "odom", i),)))
    written.append(Other("/side", 2_000, _image(store, 200, "side", 100), IMAGE))
    bag = write_rosbag2(tmp_path / "images", written, storage=storage)
    recording = read_recording([bag], headers=(), header_limit=2)
    camera, side = recording.stamped.streams
    assert (camera.topic, camera.record_time.tolist(), list(camera.frame_ids)) == (
        "/camera", [1_000, 1_010], ["camera0", "camera1"],
    )  # fmt: skip
    assert (side.topic, len(side), list(side.frame_ids)) == ("/side", 1, ["side"])
    assert recording.transform_count == 6
    every = read_recording([bag], headers=()).stamped.streams[0]
    assert [every.frame_ids[f] for f in every.frame.tolist()] == [f"camera{i}" for i in range(6)]


def test_a_db3_read_for_a_few_headers_per_topic_stops_once_each_has_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The second read of a recording without tf (``no_transforms.DATA_HEADERS`` of each topic) stops after the
    fetch that gives every topic its headers, not at the file's end; a topic short of them reads it all."""
    from tftools.sources.bag.rosbag2 import db3
    from tftools.sources.bag.spans import Spans

    store = typestore()
    images = [Other("/camera", 1_000 + i, _image(store, 100 + i, f"camera{i}", 100), IMAGE) for i in range(400)]
    bag = write_rosbag2(tmp_path / "images", images)
    fetched: list[int] = []

    def counted(*columns: Any) -> Any:
        fetched.append(len(columns[1]))
        return Spans(*columns)

    monkeypatch.setattr(db3, "_FETCH", 10)
    monkeypatch.setattr("tftools.sources.bag.rosbag2.db3.Spans", counted)
    (stream,) = read_recording([bag], headers=(), header_limit=25, allow_empty=True).stamped.streams
    assert [stream.frame_ids[f] for f in stream.frame.tolist()] == [f"camera{i}" for i in range(25)]
    assert sum(fetched) == 30  # three fetches of 10: the last that was needed
    fetched.clear()
    (stream,) = read_recording([bag], headers=(), header_limit=500, allow_empty=True).stamped.streams
    assert len(stream) == 400 and sum(fetched) == 400


def test_a_ros1_bag_gives_each_images_header_reading_little_more(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Of an uncompressed ROS 1 bag's images only the bytes that may hold their header are read (the
    stamps and frames are those written, long frame names included), not the 300 KB after each."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from tftools.sources.bag.reader import BagReader

    store = get_typestore(Stores.ROS1_NOETIC)
    frames = ["camera", "c" * 3000]
    bag = tmp_path / "images.bag"
    with Writer(bag) as writer:
        connection = writer.add_connection("/camera", IMAGE, typestore=store)
        for i in range(12):
            header = store.types["std_msgs/msg/Header"](i, store.types["builtin_interfaces/msg/Time"](100 + i, 250),
                                                        frames[i % 2])  # fmt: skip
            pixels = np.random.default_rng(i).integers(0, 256, 300_000, np.uint8)
            image = store.types[IMAGE](header, 1, 300_000, "mono8", 0, 300_000, pixels)
            writer.write(connection, 1_000 + i, bytes(store.serialize_ros1(image, IMAGE)))
    read = _bytes_read(monkeypatch)
    with BagReader([bag], headers=()) as reader:
        (stream,) = reader.read().stamped.streams
    assert stream.stamp.tolist() == [(100 + i) * 1_000_000_000 + 250 for i in range(12)]
    assert [stream.frame_ids[f] for f in stream.frame.tolist()] == [frames[i % 2] for i in range(12)]
    assert 0 < sum(read) < 0.05 * bag.stat().st_size


def test_an_mcap_gives_each_images_header_reading_little_more(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Of an MCAP file's uncompressed chunks only the bytes that may hold each image's header are read,
    alongside the transforms, not the 300 KB after each."""
    from tests.sources.ros2_helpers import Msg, Tf
    from tftools.sources.bag.reader import BagReader

    store = typestore()
    frames = ["camera", "c" * 3000]
    written: list[Any] = []
    for i in range(12):
        written.append(Other("/camera", 1_000 + 10 * i, _image(store, 100 + i, frames[i % 2], 300_000), IMAGE))
        written.append(Msg("/tf", 1_005 + 10 * i, (Tf("map", "odom", i),)))
    bag = write_rosbag2(tmp_path / "images", written, storage="mcap")
    read = _bytes_read(monkeypatch)
    with BagReader([bag], headers=()) as reader:
        contents = reader.read()
    (stream,) = contents.stamped.streams
    assert stream.stamp.tolist() == [(100 + i) * 1_000_000_000 + 250 for i in range(12)]
    assert [stream.frame_ids[f] for f in stream.frame.tolist()] == [frames[i % 2] for i in range(12)]
    assert len(contents.transforms) == 12 and contents.problems == []
    size = sum(p.stat().st_size for p in bag.iterdir())
    assert 0 < sum(read) < 0.05 * size


def _bytes_read(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The bytes of each ranged read of a recording from now on (``ByteSource.read_ranges``), as a list that fills."""
    from tftools.sources.storage.source import ByteSource

    read: list[int] = []
    ranges = ByteSource.read_ranges

    def counted(source: ByteSource, starts: Any, ends: Any) -> Any:
        read.append(int((ends - starts).sum()))
        return ranges(source, starts, ends)

    monkeypatch.setattr(ByteSource, "read_ranges", counted)
    return read


def test_each_message_is_placed_among_the_transforms_of_every_file_read(tmp_path: Path) -> None:
    """``tf_before``: the transforms read before each message, a tie of record time in file order (the tf
    written after the image at its instant comes after it), counted over a split recording's files."""
    from tests.sources.ros2_helpers import Msg, Tf
    from tftools.sources.recording import read_recording

    store = typestore()
    parts = []
    for part in range(2):
        written: list[Any] = []
        for i in range(6 * part, 6 * part + 6):
            written.append(Other("/camera", 1_000 + 10 * i, _image(store, 100 + i, "camera", 100), IMAGE))
            written.append(Msg("/tf", 1_000 + 10 * i, (Tf("map", "odom", i),)))  # the same instant, after it
        parts.append(write_rosbag2(tmp_path / f"part{part}", written, storage="mcap"))
    recording = read_recording(parts, headers=())
    (stream,) = recording.stamped.streams
    assert stream.ordered and stream.tf_before.tolist() == list(range(12))
    history = recording.buffer.history("odom")
    assert history is not None
    sequence = history.sequence
    assert sequence.tolist() == list(range(12))  # the buffer numbers the same transforms alike


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_each_message_is_placed_among_the_transforms_of_every_file_of_a_split_bag(tmp_path: Path, storage: str) -> None:
    """As above, for one bag directory of three files (``ros2 bag record --max-bag-duration``): a message of the
    third file comes after the transforms of the first two. Each was counted among its own file's only, and the
    corpus's ros2_db3_create3_real_two_urdfs split in three said "16 /scan messages arrived before odom ->
    base_link's first transform, its newest stamp 18.286 s behind" where the whole bag says 3 and 0.088 s."""
    from tests.sources.ros2_helpers import Msg, Tf, write_split_rosbag2
    from tftools.sources.recording import read_recording

    store = typestore()
    parts: list[list[Msg | Other]] = []
    for part in range(3):
        written: list[Msg | Other] = []
        for i in range(4 * part, 4 * part + 4):
            written.append(Other("/camera", 1_000 + 10 * i, _image(store, 100 + i, "camera", 100), IMAGE))
            written.append(Msg("/tf", 1_000 + 10 * i, (Tf("map", "odom", i),)))  # the same instant, after it
        parts.append(written)
    recording = read_recording([write_split_rosbag2(tmp_path / "bag", parts, storage=storage)], headers=())
    (stream,) = recording.stamped.streams
    assert stream.ordered and stream.tf_before.tolist() == list(range(12))


def test_a_gamepads_joy_is_no_sensor_data_unless_asked_for(tmp_path: Path) -> None:
    """CyberShip Voyager's /voyager/joy (corpus ros2-cybership-voyager-mocap-basin-2025-db3): sensor_msgs/Joy in
    'joy', which places nothing in space, so no tree names it and no tf2 filter waits for it; a point in
    imu_link beside it is read. Named by topic (``tfx filter --topic``), it is read like any header."""
    store = typestore()

    def joy(sec: int) -> bytes:
        header = store.types["std_msgs/msg/Header"](store.types["builtin_interfaces/msg/Time"](sec, 0), "joy")
        pad = store.types["sensor_msgs/msg/Joy"](header, np.zeros(2, np.float32), np.zeros(4, np.int32))
        return bytes(store.serialize_cdr(pad, "sensor_msgs/msg/Joy"))

    def point(sec: int) -> bytes:
        header = store.types["std_msgs/msg/Header"](store.types["builtin_interfaces/msg/Time"](sec, 0), "imu_link")
        point = store.types["geometry_msgs/msg/PointStamped"](header, store.types["geometry_msgs/msg/Point"](0, 0, 0))
        return bytes(store.serialize_cdr(point, "geometry_msgs/msg/PointStamped"))

    messages = [Other("/joy", 1_000 + i, joy(100 + i), "sensor_msgs/msg/Joy") for i in range(3)]
    messages += [Other("/imu", 1_500 + i, point(100 + i), "geometry_msgs/msg/PointStamped") for i in range(3)]
    bag = write_rosbag2(tmp_path / "pad", messages)
    read = read_recording([bag], headers=(), allow_empty=True).stamped.streams
    assert [s.topic for s in read] == ["/imu"]
    (asked,) = read_recording([bag], headers=("/joy",), allow_empty=True).stamped.streams
    assert (asked.topic, list(asked.frame_ids), len(asked)) == ("/joy", ["joy"], 3)


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_a_type_only_the_recording_defines_is_read_for_its_header_from_both_storages(
    tmp_path: Path, storage: str
) -> None:
    """A driver's own message type (dvl_msgs/msg/DVL) that begins with a Header: its definition is in the recording
    (an MCAP's schema; a .db3's message_definitions table, rosbag2 Iron on), and its headers are read from either.
    The .db3's definitions went unused: the corpus's ros2_mcap_coug_auv_replayed written as a .db3 lost its DVL
    and GPSFix topics from wtf's sensor checks (sensor_frame named 3 topics fewer)."""
    import struct

    from rosbags.rosbag2 import StoragePlugin, Writer

    from tests.sources.ros2_helpers import TF_TYPE, Tf, tf_cdr

    def dvl(sec: int) -> bytes:
        frame = b"dvl_link\x00"
        head = struct.pack("<iiI", sec, 0, len(frame)) + frame
        return b"\x00\x01\x00\x00" + head + b"\x00" * (-len(head) % 8) + struct.pack("<d", 1.5)

    bag = tmp_path / "bag"
    writer = Writer(bag, version=9, storage_plugin=StoragePlugin[storage.upper()])
    writer.open()
    sensor = writer.add_connection(
        "/dvl", "dvl_msgs/msg/DVL", msgdef="std_msgs/Header header\nfloat64 time\n", rihs01="RIHS01_" + "0" * 64
    )
    tf = writer.add_connection("/tf", TF_TYPE, typestore=typestore())
    for i in range(3):
        writer.write(tf, 1_000 + 10 * i, tf_cdr((Tf("map", "dvl_link", i),)))
        writer.write(sensor, 1_001 + 10 * i, dvl(100 + i))
    writer.close()
    (stream,) = read_recording([bag], headers=()).stamped.streams
    assert stream.topic == "/dvl" and stream.frame_ids == ["dvl_link"]
    assert stream.stamp.tolist() == [(100 + i) * 1_000_000_000 for i in range(3)]
