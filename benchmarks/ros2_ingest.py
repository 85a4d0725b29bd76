"""Transforms per second of ``BagReader`` on ROS2 bags (sqlite3, mcap, zstd-compressed) and Foxglove
MCAP files (CDR, protobuf) of a 17-frame robot recorded 600 s (252k transforms).

Run: ``python3 benchmarks/ros2_ingest.py``; bags are written once under /tmp/tftools-bench.
Prints figures, asserts nothing.
"""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np
from mcap.writer import Writer as McapWriter
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore
from timing import read_whole, rosbags_transforms, timed

NS = 1_000_000_000
START = 1_700_000_000 * NS
SECONDS = 600
OUT = Path("/tmp/tftools-bench")
ARM = [f"arm_link{i}" for i in range(1, 7)]
PUBLISHERS = [  # Hz, (parent, child) pairs
    (10, [("map", "odom")]),
    (50, [("odom", "base_footprint")]),
    (30, [("base_link", "left_wheel"), ("base_link", "right_wheel")]),
    (50, list(zip(["arm_base", *ARM[:-1]], ARM, strict=True))),
]
STATIC = [("base_footprint", "base_link"), ("base_link", "laser"), ("base_link", "imu_link"),
          ("base_link", "camera_link"), ("camera_link", "camera_optical_frame"), ("base_link", "arm_base"),
          ("arm_link6", "gripper")]  # fmt: skip


def tf_cdr(stamp: int, pairs: list[tuple[str, str]], phase: float) -> bytes:
    """A little-endian CDR ``tf2_msgs/msg/TFMessage`` (as rosbags would serialize it)."""
    sec, nsec = divmod(stamp, NS)
    out = bytearray(b"\x00\x01\x00\x00") + struct.pack("<I", len(pairs))
    for i, (parent, child) in enumerate(pairs):
        angle = 0.3 * math.sin(stamp / NS + phase + i)
        out += b"\x00" * (-(len(out) - 4) % 4) + struct.pack("<iI", sec, nsec)
        for name in (parent, child):
            out += b"\x00" * (-(len(out) - 4) % 4) + struct.pack("<I", len(name) + 1) + name.encode() + b"\x00"
        out += b"\x00" * (-(len(out) - 4) % 8)
        out += struct.pack("<7d", 0.1 * i, 0.0, 0.05, 0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))
    return bytes(out)


def messages() -> list[tuple[int, str, bytes]]:
    """(record time, topic, payload) in record order."""
    out = [(START + 1_000_000, "/tf_static", tf_cdr(START, STATIC, 0.0))]
    for hz, pairs in PUBLISHERS:
        period = NS // hz
        for k, stamp in enumerate(range(START + period // 3, START + SECONDS * NS, period)):
            out.append((stamp + 1_000_000 + (k * 7919) % 3_000_000, "/tf", tf_cdr(stamp, pairs, hz)))
    return sorted(out, key=lambda m: m[0])


def write_rosbag2(path: Path, storage: str, compression: str = "") -> Path:
    if path.exists():
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    store = get_typestore(Stores.ROS2_HUMBLE)
    writer = Writer(path, version=Writer.VERSION_LATEST, storage_plugin=StoragePlugin[storage.upper()])
    if compression:
        writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
    with writer:
        connections = {}
        for record_time, topic, payload in messages():
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, "tf2_msgs/msg/TFMessage", typestore=store)
            writer.write(connections[topic], record_time, payload)
    return path


def write_foxglove(path: Path, encoding: str) -> Path:
    """FrameTransforms in ros2msg (CDR) encoding (the same bytes as a TFMessage), or in protobuf."""
    if path.exists():
        return path
    with path.open("wb") as f:
        writer = McapWriter(f)
        writer.start(profile="", library="tftools-bench")
        if encoding == "protobuf":
            schema = writer.register_schema("foxglove.FrameTransforms", "protobuf", b"")
        else:
            schema = writer.register_schema("foxglove_msgs/msg/FrameTransforms", "ros2msg", b"")
        channels = {}
        for record_time, topic, payload in messages():
            if topic not in channels:
                message_encoding = "protobuf" if encoding == "protobuf" else "cdr"
                channels[topic] = writer.register_channel(topic, message_encoding, schema)
            data = to_protobuf(payload) if encoding == "protobuf" else payload
            writer.add_message(channels[topic], record_time, data, record_time)
        writer.finish()
    return path


def to_protobuf(cdr: bytes) -> bytes:
    """A CDR TFMessage as foxglove.FrameTransforms on the protobuf wire."""
    from tftools.sources.codecs import cdr as codec
    from tftools.sources.live.received import Received, decode_received

    batch = decode_received(codec.decode_tf, [Received("/tf", cdr, "", 0)]).batch
    parents, children = ([batch.frame_names[i] for i in ids] for ids in (batch.parent, batch.child))
    rows = np.hstack([batch.translation, batch.rotation]).tolist()
    out = b""
    for parent, child, stamp, values in zip(parents, children, batch.stamp.tolist(), rows, strict=True):
        sec, nsec = divmod(stamp, NS)
        timestamp = _field(1, 0, _varint(sec)) + _field(2, 0, _varint(nsec))
        vector = b"".join(_field(i, 1, struct.pack("<d", v)) for i, v in enumerate(values[:3], 1))
        quaternion = b"".join(_field(i, 1, struct.pack("<d", v)) for i, v in enumerate(values[3:], 1))
        transform = (_field(1, 2, timestamp) + _field(2, 2, parent.encode()) + _field(3, 2, child.encode())
                     + _field(4, 2, vector) + _field(5, 2, quaternion))  # fmt: skip
        out += _field(1, 2, transform)
    return out


def _field(number: int, wire: int, value: bytes) -> bytes:
    return _varint(number << 3 | wire) + (_varint(len(value)) if wire == 2 else b"") + value


def _varint(value: int) -> bytes:
    out = bytearray()
    while True:
        out.append(value & 0x7F | (0x80 if value > 0x7F else 0))
        value >>= 7
        if not value:
            return bytes(out)


def main() -> None:
    bags = {
        "sqlite3": write_rosbag2(OUT / "robot_600s_db3", "sqlite3"),
        "mcap": write_rosbag2(OUT / "robot_600s_mcap", "mcap"),
        "sqlite3, zstd by message": write_rosbag2(OUT / "robot_600s_db3_zstd_message", "sqlite3", "message"),
        "sqlite3, zstd file": write_rosbag2(OUT / "robot_600s_db3_zstd_file", "sqlite3", "file"),
        "foxglove mcap, CDR": write_foxglove(OUT / "robot_600s_foxglove.mcap", "cdr"),
        "foxglove mcap, protobuf": write_foxglove(OUT / "robot_600s_foxglove_pb.mcap", "protobuf"),
    }
    first = None
    for name, bag in bags.items():
        size = sum(p.stat().st_size for p in bag.iterdir()) if bag.is_dir() else bag.stat().st_size
        timed(f"BagReader, {name} ({size / 1e6:.0f} MB)", lambda bag=bag: len(read_whole([bag]).transforms))
        batch = read_whole([bag]).transforms
        values = np.hstack([batch.stamp[:, None].astype(float), batch.translation, batch.rotation])
        first = values if first is None else first
        if not np.array_equal(values, first):
            print(f"  {name}: NOT the same transforms as {next(iter(bags))}")
    bag = bags["sqlite3"]
    timed("rosbags' reader and deserializer, sqlite3", lambda: rosbags_transforms(bag), repeat=1)


if __name__ == "__main__":
    main()
