"""ROS1 test bags written by the real rosbag (Debian's Python) or by rosbags, and rosbags' reading of them."""

from __future__ import annotations

import json
import math
import subprocess
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from tftools.core.batch import TransformBatch
from tftools.sources.contents import is_static_topic

ROS_PYTHON = "/usr/bin/python3"
WRITER = Path(__file__).with_name("ros1_rosbag_writer.py")
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TF_TYPES = {"tf2": "tf2_msgs/msg/TFMessage", "tf1": "tf/msg/tfMessage"}

#: (parent, child, stamp, values as bytes, record time, authority, static): compared exactly, NaN included.
Row = tuple[str, str, int, bytes, int, str, bool]


@dataclass(frozen=True)
class Msg:
    """One message to record: ``body`` is [(parent, child, stamp, 7 values)] for "tf2"/"tf1",
    a byte count for "image", text for "string"."""

    topic: str
    kind: str
    record_time: int
    callerid: str
    body: Any


@cache
def rosbag_unavailable() -> str | None:
    """Why the real rosbag cannot write bags here, or None."""
    try:
        probe = subprocess.run(
            [ROS_PYTHON, "-c", "import rosbag, tf.msg, tf2_msgs.msg, sensor_msgs.msg, rosgraph_msgs.msg"],
            capture_output=True,
            timeout=60,
        )
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"{ROS_PYTHON} cannot run: {e}"
    return (
        None
        if probe.returncode == 0
        else "the real rosbag is not installed (apt-get install python3-rosbag python3-tf)"
    )


def write_rosbag(
    path: Path, messages: list[Msg], compression: str = "none", chunk_threshold: int = 768 * 1024, close: bool = True
) -> Path:
    """A bag written by the real rosbag (one connection per topic: its first message's callerid)."""
    spec = {
        "path": str(path),
        "compression": compression,
        "chunk_threshold": chunk_threshold,
        "close": close,
        "messages": [[m.topic, m.kind, m.record_time, m.callerid, m.body] for m in messages],
    }
    done = subprocess.run(
        [ROS_PYTHON, str(WRITER)], input=json.dumps(spec), capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return path


def write_rosbags(path: Path, messages: list[Msg], compression: str = "none", chunk_threshold: int = 1 << 20) -> Path:
    """A bag written by rosbags: one connection per (topic, callerid), so one topic may have several."""
    from rosbags.rosbag1 import Writer

    store = typestore()
    writer = Writer(path)
    writer.chunk_threshold = chunk_threshold
    if compression != "none":
        writer.set_compression(Writer.CompressionFormat[compression.upper()])
    with writer:
        connections: dict[tuple[str, str], Any] = {}
        for m in messages:
            type_name = TF_TYPES.get(m.kind, "std_msgs/msg/String")
            key = (m.topic, m.callerid)
            if key not in connections:
                connections[key] = writer.add_connection(
                    m.topic, type_name, typestore=store, callerid=m.callerid or None
                )
            writer.write(connections[key], m.record_time, bytes(store.serialize_ros1(_message(store, m), type_name)))
    return path


@cache
def typestore() -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    for name in TF_TYPES.values():
        if name not in store.types:
            store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", name))
    return store


def _message(store: Any, m: Msg) -> Any:
    types = store.types
    if m.kind not in TF_TYPES:
        return types["std_msgs/msg/String"](data=str(m.body))
    stamped = []
    for parent, child, stamp, v in m.body:
        sec = stamp // NS - (stamp // NS >= 2**31) * 2**32  # rosbags' ROS1 seconds are an int32
        time = types["builtin_interfaces/msg/Time"](sec=sec, nanosec=stamp % NS)
        header = types["std_msgs/msg/Header"](seq=0, stamp=time, frame_id=parent)
        transform = types["geometry_msgs/msg/Transform"](
            translation=types["geometry_msgs/msg/Vector3"](x=v[0], y=v[1], z=v[2]),
            rotation=types["geometry_msgs/msg/Quaternion"](x=v[3], y=v[4], z=v[5], w=v[6]),
        )
        stamped.append(
            types["geometry_msgs/msg/TransformStamped"](header=header, child_frame_id=child, transform=transform)
        )
    return types[TF_TYPES[m.kind]](transforms=stamped)


def reference_rows(path: Path, topics: tuple[str, ...] = ("/tf", "/tf_static")) -> list[Row]:
    """The transforms as rosbags reads and deserializes them, in its (record time) order."""
    from rosbags.interfaces import ConnectionExtRosbag1
    from rosbags.rosbag1 import Reader

    store = typestore()
    rows: list[Row] = []
    with Reader(path) as reader:
        wanted = [c for c in reader.connections if c.topic in topics and c.msgtype in TF_TYPES.values()]
        for connection, record_time, data in reader.messages(connections=wanted):
            message = store.deserialize_ros1(data, connection.msgtype)
            assert isinstance(connection.ext, ConnectionExtRosbag1)
            authority = connection.ext.callerid or connection.topic
            for t in message.transforms:
                stamp = (t.header.stamp.sec & 0xFFFFFFFF) * NS + t.header.stamp.nanosec  # ROS1 time is unsigned
                a, r = t.transform.translation, t.transform.rotation
                values = np.array([a.x, a.y, a.z, r.x, r.y, r.z, r.w], np.float64).tobytes()
                rows.append((t.header.frame_id, t.child_frame_id, stamp, values, record_time, authority,
                             is_static_topic(connection.topic)))  # fmt: skip
    return rows


def rows_of(batches: list[TransformBatch] | TransformBatch) -> list[Row]:
    """The rows of ``batches`` as comparable tuples."""
    if isinstance(batches, TransformBatch):
        batches = [batches]
    rows: list[Row] = []
    for b in batches:
        values = np.hstack([b.translation, b.rotation])
        for i in range(len(b)):
            rows.append((b.frame_names[b.parent[i]], b.frame_names[b.child[i]], int(b.stamp[i]), values[i].tobytes(),
                         int(b.record_time[i]), b.authorities[b.authority[i]], bool(b.static[i])))  # fmt: skip
    return rows


NAMES = ["map", "odom", "base_link", "/base_footprint", "", "a", "laser mount", "kamera_ö_光", "x" * 70,
         "arm/link_1", "arm/link_2", "arm/link_10", "robot_1/base_link", "robot_2/base_link"]  # fmt: skip
SPECIAL = [math.nan, math.inf, -math.inf, -0.0, 1e-300, 1e300]


def varied_messages(seed: int, count: int = 400, image_bytes: int = 50_000, ordered: bool = False) -> list[Msg]:
    """/tf (several publishers), /tf_static, tf/tfMessage on /tf_old, a big image topic and a
    string topic: frame ids of every length, 0 to 40 transforms a message, odd values, record
    times out of order and repeated.

    ``ordered``: record times 10 ms apart in order, and no message without transforms (then the
    messages behind rows can be counted, and a chunk holds a span of time of its own)."""
    rng = np.random.default_rng(seed)
    messages: list[Msg] = []
    for i in range(count):
        record_time = T0 + int(rng.integers(0, 20 * NS)) if i % 17 else T0 + 5 * NS  # some share one time
        if ordered:
            record_time = T0 + i * NS // 100
        roll = rng.random()
        if roll < 0.08:
            messages.append(Msg("/camera/image", "image", record_time, "/camera", image_bytes))
        elif roll < 0.12:
            messages.append(Msg("/chatter", "string", record_time, "/talker", f"hello {i}"))
        else:
            topic, kind, callerid = _tf_channel(rng)
            k = int(rng.choice([0, 1, 1, 2, 3, 6, 40], p=[0.03, 0.4, 0.2, 0.15, 0.1, 0.1, 0.02])) or int(ordered)
            messages.append(Msg(topic, kind, record_time, callerid, [_transform(rng) for _ in range(k)]))
    return messages


def _tf_channel(rng: np.random.Generator) -> tuple[str, str, str]:
    return [
        ("/tf", "tf2", "/amcl"),
        ("/tf", "tf2", "/ekf"),
        ("/tf", "tf2", ""),
        ("/tf_static", "tf2", "/robot_state_publisher"),
        ("/tf_old", "tf1", "/legacy"),
    ][int(rng.integers(0, 5))]


def _transform(rng: np.random.Generator) -> tuple[str, str, int, list[float]]:
    parent, child = (NAMES[int(i)] for i in rng.integers(0, len(NAMES), 2))
    stamp = int(rng.choice([0, T0 + int(rng.integers(0, 30 * NS)), (2**32 - 1) * NS + 999_999_999]))
    values = [float(v) for v in rng.normal(size=7)]
    if rng.random() < 0.1:
        values[int(rng.integers(0, 7))] = float(rng.choice(SPECIAL))
    return parent, child, stamp, values


def covered(ranges: list[tuple[int, int]], start: int, end: int) -> bool:
    """Whether the byte ranges ``[a, b)`` of ``ranges`` together cover ``[start, end)``."""
    reach = start
    for a, b in sorted(ranges):
        if a > reach:
            break
        reach = max(reach, b)
    return reach >= end
