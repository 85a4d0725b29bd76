"""Writing ROS2 bags and MCAP files for the source tests, and what they must read back as."""

from __future__ import annotations

import json
import math
import shutil
import sqlite3
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cache
from io import StringIO
from pathlib import Path
from typing import Any

import numpy as np
from mcap.reader import make_reader
from mcap.writer import CompressionType, IndexType
from mcap.writer import Writer as McapWriter
from rosbags.highlevel import AnyReader
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from ruamel.yaml import YAML

from tftools.core.batch import TransformBatch
from tftools.sources.contents import is_static_topic

NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TF_TYPE = "tf2_msgs/msg/TFMessage"
FRAME_TRANSFORM_MSG = """\
builtin_interfaces/Time timestamp
string parent_frame_id
string child_frame_id
geometry_msgs/Vector3 translation
geometry_msgs/Quaternion rotation
"""
FRAME_TRANSFORMS_MSG = "foxglove_msgs/FrameTransform[] transforms\n"


@dataclass(frozen=True)
class Tf:
    parent: str
    child: str
    sec: int
    nsec: int = 0
    translation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)

    @property
    def stamp(self) -> int:
        return self.sec * 1_000_000_000 + self.nsec


@dataclass(frozen=True)
class Msg:
    """One recorded message of transforms."""

    topic: str
    record_time: int
    transforms: tuple[Tf, ...]


@dataclass(frozen=True)
class Other:
    """One recorded message of another type, as raw CDR bytes."""

    topic: str
    record_time: int
    data: bytes
    type_name: str = "std_msgs/msg/String"


@cache
def typestore() -> Any:
    store = get_typestore(Stores.ROS2_HUMBLE)
    store.register(get_types_from_msg(FRAME_TRANSFORM_MSG, "foxglove_msgs/msg/FrameTransform"))
    store.register(get_types_from_msg(FRAME_TRANSFORMS_MSG, "foxglove_msgs/msg/FrameTransforms"))
    return store


def _ros(tf: Tf) -> Any:
    t = typestore().types
    return t["geometry_msgs/msg/TransformStamped"](
        header=t["std_msgs/msg/Header"](
            stamp=t["builtin_interfaces/msg/Time"](sec=tf.sec, nanosec=tf.nsec), frame_id=tf.parent
        ),
        child_frame_id=tf.child,
        transform=t["geometry_msgs/msg/Transform"](
            translation=t["geometry_msgs/msg/Vector3"](*tf.translation),
            rotation=t["geometry_msgs/msg/Quaternion"](*tf.rotation),
        ),
    )


ROS1_TF2, ROS1_TF1 = "tf2_msgs/TFMessage", "tf/tfMessage"
ROS1_TF_DEFINITION = "geometry_msgs/TransformStamped[] transforms\n"  # the dependencies left out


@cache
def ros1_typestore() -> Any:
    store = get_typestore(Stores.ROS1_NOETIC)  # without tf2_msgs
    store.register(get_types_from_msg(ROS1_TF_DEFINITION, TF_TYPE))
    return store


def tf_ros1(transforms: Sequence[Tf], seq: int = 7) -> bytes:
    """A ROS1-serialized TFMessage: seconds are unsigned there (rosbags takes them as int32)."""
    t = ros1_typestore().types
    stamped = [
        t["geometry_msgs/msg/TransformStamped"](
            header=t["std_msgs/msg/Header"](
                seq=seq + i,
                stamp=t["builtin_interfaces/msg/Time"](sec=tf.sec - (tf.sec >= 2**31) * 2**32, nanosec=tf.nsec),
                frame_id=tf.parent,
            ),
            child_frame_id=tf.child,
            transform=t["geometry_msgs/msg/Transform"](
                translation=t["geometry_msgs/msg/Vector3"](*tf.translation),
                rotation=t["geometry_msgs/msg/Quaternion"](*tf.rotation),
            ),
        )
        for i, tf in enumerate(transforms)
    ]
    message = t[TF_TYPE](transforms=stamped)
    return bytes(ros1_typestore().serialize_ros1(message, TF_TYPE))


def tf_cdr(transforms: Sequence[Tf], *, little_endian: bool = True) -> bytes:
    message = typestore().types[TF_TYPE](transforms=[_ros(tf) for tf in transforms])
    return bytes(typestore().serialize_cdr(message, TF_TYPE, little_endian=little_endian))


def string_cdr(text: str) -> bytes:
    message = typestore().types["std_msgs/msg/String"](data=text)
    return bytes(typestore().serialize_cdr(message, "std_msgs/msg/String"))


def _foxglove_ros(tf: Tf) -> Any:
    t = typestore().types
    return t["foxglove_msgs/msg/FrameTransform"](
        timestamp=t["builtin_interfaces/msg/Time"](sec=tf.sec, nanosec=tf.nsec),
        parent_frame_id=tf.parent,
        child_frame_id=tf.child,
        translation=t["geometry_msgs/msg/Vector3"](*tf.translation),
        rotation=t["geometry_msgs/msg/Quaternion"](*tf.rotation),
    )


def foxglove_cdr(transforms: Sequence[Tf], *, single: bool) -> bytes:
    store = typestore()
    if single:
        (tf,) = transforms
        return bytes(store.serialize_cdr(_foxglove_ros(tf), "foxglove_msgs/msg/FrameTransform"))
    message = store.types["foxglove_msgs/msg/FrameTransforms"](transforms=[_foxglove_ros(t) for t in transforms])
    return bytes(store.serialize_cdr(message, "foxglove_msgs/msg/FrameTransforms"))


# --- ROS2 bags ------------------------------------------------------------------------------


def write_rosbag2(
    path: Path,
    messages: Iterable[Msg | Other],
    *,
    storage: str = "sqlite3",
    version: int = Writer.VERSION_LATEST,
    compression: str = "",
    big_endian: bool = False,
) -> Path:
    """A ROS2 bag directory written by rosbags, messages in the given order."""
    writer = Writer(path, version=version, storage_plugin=StoragePlugin[storage.upper()])  # type: ignore[arg-type]  # rosbags: a Literal of versions
    if compression:
        writer.set_compression(CompressionMode[compression.upper()], CompressionFormat.ZSTD)
    writer.open()
    connections: dict[tuple[str, str], Any] = {}
    for message in messages:
        type_name = TF_TYPE if isinstance(message, Msg) else message.type_name
        key = (message.topic, type_name)
        if key not in connections:
            connections[key] = writer.add_connection(message.topic, type_name, typestore=typestore())
        data = tf_cdr(message.transforms, little_endian=not big_endian) if isinstance(message, Msg) else message.data
        writer.write(connections[key], message.record_time, data)
    writer.close()
    return path


def write_split_rosbag2(path: Path, parts: Sequence[Sequence[Msg | Other]], *, storage: str = "sqlite3") -> Path:
    """One bag directory made of several files, as ``ros2 bag record --max-bag-size`` leaves it."""
    path.mkdir()
    yaml = YAML(typ="safe")
    infos = []
    for index, part in enumerate(parts):
        single = write_rosbag2(path.parent / f"{path.name}-part{index}", part, storage=storage)
        info = yaml.load((single / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
        (name,) = info["relative_file_paths"]
        target = f"{path.name}_{index}{Path(name).suffix}"
        shutil.move(single / name, path / target)
        info["relative_file_paths"] = [target]
        info["files"][0]["path"] = target
        infos.append(info)
        shutil.rmtree(single)
    merged = infos[0]
    merged["relative_file_paths"] = [i["relative_file_paths"][0] for i in infos]
    merged["files"] = [i["files"][0] for i in infos]
    merged["message_count"] = sum(i["message_count"] for i in infos)
    out = StringIO()
    yaml.dump({"rosbag2_bagfile_information": merged}, out)
    (path / "metadata.yaml").write_text(out.getvalue())
    return path


# --- Foxglove MCAP files --------------------------------------------------------------------


@dataclass
class FoxgloveChannel:
    """A channel of foxglove FrameTransform(s), or with ``encoding`` "ros1" of a ROS1 TFMessage
    (``single``: of the older tf/tfMessage)."""

    topic: str
    encoding: str  # "protobuf", "json", "ros2msg" or "ros1"
    single: bool = False  # FrameTransform rather than FrameTransforms


@dataclass
class McapOptions:
    chunk_size: int = 1 << 20
    compression: CompressionType = CompressionType.ZSTD
    use_chunking: bool = True
    index_types: IndexType = IndexType.ALL
    use_statistics: bool = True
    extra: list[Other] = field(default_factory=list)
    messages_per_chunk: int = 0  # when set, a chunk ends after so many messages,
    chunk_compressions: tuple[CompressionType, ...] = ()  # and the next is compressed with the next of these
    enable_crcs: bool = True  # the mcap library's default; rosbag2's mcap storage writes none


def write_foxglove_mcap(
    path: Path, channels: Sequence[FoxgloveChannel], messages: Sequence[Msg], options: McapOptions | None = None
) -> Path:
    """An MCAP of foxglove FrameTransform(s) channels (and tf2 / other ROS2 channels by topic)."""
    options = options or McapOptions()
    with path.open("wb") as f:
        writer = McapWriter(
            f,
            chunk_size=options.chunk_size,
            compression=options.compression,
            use_chunking=options.use_chunking,
            index_types=options.index_types,
            use_statistics=options.use_statistics,
            enable_crcs=options.enable_crcs,
        )
        writer.start(profile="", library="tftools-tests")
        ids = {c.topic: _register(writer, c) for c in channels}
        kinds = {c.topic: c for c in channels}
        others: dict[str, int] = {}
        stream: list[Msg | Other] = sorted([*messages, *options.extra], key=lambda m: m.record_time)
        for i, message in enumerate(stream):
            if options.messages_per_chunk and i and i % options.messages_per_chunk == 0:
                _next_chunk(writer, options, i // options.messages_per_chunk)
            if isinstance(message, Other):
                if message.topic not in others:
                    others[message.topic] = _register_ros2(writer, message.topic, message.type_name)
                writer.add_message(others[message.topic], message.record_time, message.data, message.record_time)
            else:
                data = _foxglove_payload(kinds[message.topic], message.transforms)
                writer.add_message(ids[message.topic], message.record_time, data, message.record_time)
        writer.finish()
    return path


def _next_chunk(writer: McapWriter, options: McapOptions, chunk: int) -> None:
    writer.flush()
    if options.chunk_compressions:  # the writer has no public way to change it between chunks
        compression = options.chunk_compressions[chunk % len(options.chunk_compressions)]
        writer._Writer__compression = compression  # type: ignore[attr-defined]  # private: see above


def _register_ros2(writer: McapWriter, topic: str, type_name: str) -> int:
    msgdef, _ = typestore().generate_msgdef(type_name, ros_version=2)
    schema = writer.register_schema(type_name, "ros2msg", msgdef.encode())
    return writer.register_channel(topic, "cdr", schema)


def _register(writer: McapWriter, channel: FoxgloveChannel) -> int:
    name = "FrameTransform" if channel.single else "FrameTransforms"
    if channel.encoding == "ros1":
        type_name = ROS1_TF1 if channel.single else ROS1_TF2
        schema = writer.register_schema(type_name, "ros1msg", ROS1_TF_DEFINITION.encode())
        return writer.register_channel(channel.topic, "ros1", schema)
    if channel.encoding == "ros2msg":
        nested = "=" * 80 + "\nMSG: foxglove_msgs/FrameTransform\n" + FRAME_TRANSFORM_MSG
        text = FRAME_TRANSFORM_MSG if channel.single else FRAME_TRANSFORMS_MSG + nested
        schema = writer.register_schema(f"foxglove_msgs/msg/{name}", "ros2msg", text.encode())
        return writer.register_channel(channel.topic, "cdr", schema)
    if channel.encoding == "json":
        title = json.dumps({"title": f"foxglove.{name}"}).encode()
        schema = writer.register_schema(f"foxglove.{name}", "jsonschema", title)
        return writer.register_channel(channel.topic, "json", schema)
    descriptor_set = proto_classes()[name].DESCRIPTOR_SET
    schema = writer.register_schema(f"foxglove.{name}", "protobuf", descriptor_set)
    return writer.register_channel(channel.topic, "protobuf", schema)


def _foxglove_payload(channel: FoxgloveChannel, transforms: Sequence[Tf]) -> bytes:
    if channel.encoding == "ros1":
        return tf_ros1(transforms)
    if channel.encoding == "ros2msg":
        return foxglove_cdr(transforms, single=channel.single)
    if channel.encoding == "json":
        items = [_json_transform(tf) for tf in transforms]
        return json.dumps(items[0] if channel.single else {"transforms": items}).encode()
    payload: bytes = proto_message(transforms, single=channel.single).SerializeToString()
    return payload


def _json_transform(tf: Tf) -> dict[str, Any]:
    return {
        "timestamp": {"sec": tf.sec, "nsec": tf.nsec},
        "parent_frame_id": tf.parent,
        "child_frame_id": tf.child,
        "translation": dict(zip("xyz", tf.translation, strict=True)),
        "rotation": dict(zip("xyzw", tf.rotation, strict=True)),
    }


# --- foxglove protobuf classes, built from the schema's field numbers ------------------------


@cache
def proto_classes() -> dict[str, Any]:
    """Message classes of foxglove.FrameTransform(s), from a FileDescriptorSet built here."""
    from google.protobuf import descriptor_pb2, descriptor_pool, message_factory, timestamp_pb2

    pool = descriptor_pool.DescriptorPool()
    timestamp_file = descriptor_pb2.FileDescriptorProto()
    timestamp_pb2.DESCRIPTOR.CopyToProto(timestamp_file)
    pool.Add(timestamp_file)
    files = [timestamp_file]
    for proto in _foxglove_files():
        pool.Add(proto)
        files.append(proto)
    classes: dict[str, Any] = {}
    for name in ("FrameTransform", "FrameTransforms"):
        cls = message_factory.GetMessageClass(pool.FindMessageTypeByName(f"foxglove.{name}"))
        wanted = {
            "google/protobuf/timestamp.proto",
            "foxglove/Vector3.proto",
            "foxglove/Quaternion.proto",
            "foxglove/FrameTransform.proto",
            f"foxglove/{name}.proto",
        }
        needed = descriptor_pb2.FileDescriptorSet(file=[f for f in files if f.name in wanted])
        cls.DESCRIPTOR_SET = needed.SerializeToString()
        classes[name] = cls
    return classes


def _foxglove_files() -> list[Any]:
    from google.protobuf import descriptor_pb2

    field = descriptor_pb2.FieldDescriptorProto
    double, message, string = field.TYPE_DOUBLE, field.TYPE_MESSAGE, field.TYPE_STRING
    optional, repeated = field.LABEL_OPTIONAL, field.LABEL_REPEATED

    def file(name: str, message_name: str, fields: list[tuple[str, int, int, str, int]], deps: list[str]) -> Any:
        proto = descriptor_pb2.FileDescriptorProto(name=name, package="foxglove", syntax="proto3", dependency=deps)
        msg = proto.message_type.add(name=message_name)
        for field_name, number, kind, type_name, label in fields:
            added = msg.field.add(name=field_name, number=number, type=kind, label=label)
            if type_name:
                added.type_name = type_name
        return proto

    def doubles(names: str) -> list[tuple[str, int, int, str, int]]:
        return [(name, number, double, "", optional) for number, name in enumerate(names, 1)]

    return [
        file("foxglove/Vector3.proto", "Vector3", doubles("xyz"), []),
        file("foxglove/Quaternion.proto", "Quaternion", doubles("xyzw"), []),
        file(
            "foxglove/FrameTransform.proto",
            "FrameTransform",
            [
                ("timestamp", 1, message, ".google.protobuf.Timestamp", optional),
                ("parent_frame_id", 2, string, "", optional),
                ("child_frame_id", 3, string, "", optional),
                ("translation", 4, message, ".foxglove.Vector3", optional),
                ("rotation", 5, message, ".foxglove.Quaternion", optional),
            ],
            ["google/protobuf/timestamp.proto", "foxglove/Vector3.proto", "foxglove/Quaternion.proto"],
        ),
        file(
            "foxglove/FrameTransforms.proto",
            "FrameTransforms",
            [("transforms", 1, message, ".foxglove.FrameTransform", repeated)],
            ["foxglove/FrameTransform.proto"],
        ),
    ]


def proto_transform(tf: Tf) -> Any:
    cls = proto_classes()["FrameTransform"]
    message = cls(parent_frame_id=tf.parent, child_frame_id=tf.child)
    message.timestamp.seconds, message.timestamp.nanos = tf.sec, tf.nsec
    message.translation.x, message.translation.y, message.translation.z = tf.translation
    message.rotation.x, message.rotation.y, message.rotation.z, message.rotation.w = tf.rotation
    return message


def proto_message(transforms: Sequence[Tf], *, single: bool) -> Any:
    if single:
        (tf,) = transforms
        return proto_transform(tf)
    return proto_classes()["FrameTransforms"](transforms=[proto_transform(tf) for tf in transforms])


# --- what a batch must hold ------------------------------------------------------------------


def _bits(values: Iterable[float]) -> tuple[str, ...]:
    return tuple(float(v).hex() for v in values)


def expected_rows(
    messages: Iterable[Msg | Other], topics: Sequence[str] = ("/tf", "/tf_static")
) -> list[tuple[Any, ...]]:
    """The rows a reader must produce: record-time order (stable), one per transform."""
    tf_messages = [m for m in messages if isinstance(m, Msg) and m.topic in topics]
    rows = []
    for m in sorted(tf_messages, key=lambda m: m.record_time):
        for tf in m.transforms:
            rows.append(
                (
                    tf.parent,
                    tf.child,
                    tf.stamp,
                    _bits(tf.translation),
                    _bits(tf.rotation),
                    is_static_topic(m.topic),
                    m.record_time,
                    m.topic,
                )
            )
    return rows


def batch_rows(batches: TransformBatch | Sequence[TransformBatch]) -> list[tuple[Any, ...]]:
    """The rows of batches as comparable tuples (floats by their bits, NaN included)."""
    if isinstance(batches, TransformBatch):
        batches = [batches]
    rows = []
    for b in batches:
        for i in range(len(b)):
            rows.append(
                (
                    b.frame_names[b.parent[i]],
                    b.frame_names[b.child[i]],
                    int(b.stamp[i]),
                    _bits(b.translation[i]),
                    _bits(b.rotation[i]),
                    bool(b.static[i]),
                    int(b.record_time[i]),
                    b.authorities[b.authority[i]],
                )
            )
    return rows


def reference_rows(path: Path, topics: Sequence[str] = ("/tf", "/tf_static")) -> list[tuple[Any, ...]]:
    """The rows of a ROS2 bag as rosbags reads and deserializes it, in its (record time) order."""
    store = typestore()
    rows = []
    with AnyReader([path], default_typestore=store) as reader:
        wanted = [c for c in reader.connections if c.topic in topics and c.msgtype == TF_TYPE]
        for connection, record_time, data in reader.messages(connections=wanted):
            for t in store.deserialize_cdr(data, TF_TYPE).transforms:
                v, stamp = t.transform, t.header.stamp
                rows.append(
                    (t.header.frame_id, t.child_frame_id, stamp.sec * NS + stamp.nanosec,
                     _bits((v.translation.x, v.translation.y, v.translation.z)),
                     _bits((v.rotation.x, v.rotation.y, v.rotation.z, v.rotation.w)),
                     is_static_topic(connection.topic), record_time, connection.topic)
                )  # fmt: skip
    return rows


def mcap_reference_rows(path: Path) -> list[tuple[Any, ...]]:
    """The transforms of an MCAP file's foxglove and tf2 channels as the mcap library reads them
    (protobuf by its decoder, JSON by ``json``, CDR by rosbags), in the file's order."""
    from mcap_protobuf.decoder import DecoderFactory

    rows = []
    with path.open("rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            if schema is None or not _is_transform_schema(schema.name):
                continue
            for tf in _mcap_transforms(schema.name, channel.message_encoding, message.data):
                rows.append((tf.parent, tf.child, tf.stamp, _bits(tf.translation), _bits(tf.rotation),
                             is_static_topic(channel.topic), message.log_time, channel.topic))  # fmt: skip
    return sorted(rows, key=lambda row: row[6])


def _is_transform_schema(name: str) -> bool:
    return name in (TF_TYPE, ROS1_TF1, ROS1_TF2, "foxglove.FrameTransform", "foxglove.FrameTransforms",
                    "foxglove_msgs/msg/FrameTransform", "foxglove_msgs/msg/FrameTransforms")  # fmt: skip


def _mcap_transforms(schema: str, encoding: str, data: bytes) -> list[Tf]:
    single = not schema.endswith("s")
    if encoding == "ros1":
        message = ros1_typestore().deserialize_ros1(data, TF_TYPE)
        return [_tf_of_ros(t) for t in message.transforms]
    if encoding == "cdr":
        message = typestore().deserialize_cdr(data, schema)
        if schema == TF_TYPE:
            return [_tf_of_ros(t) for t in message.transforms]
        items = [message] if single else message.transforms
        return [Tf(t.parent_frame_id, t.child_frame_id, t.timestamp.sec, t.timestamp.nanosec,
                   _xyz(t.translation), _xyzw(t.rotation)) for t in items]  # fmt: skip
    if encoding == "json":
        document = json.loads(data)
        items = [document] if single else document["transforms"]
        return [Tf(t["parent_frame_id"], t["child_frame_id"], t["timestamp"]["sec"], t["timestamp"]["nsec"],
                   _xyz_dict(t["translation"]), _xyzw_dict(t["rotation"])) for t in items]  # fmt: skip
    cls = proto_classes()["FrameTransform" if single else "FrameTransforms"]
    message = cls.FromString(data)
    items = [message] if single else list(message.transforms)
    return [Tf(t.parent_frame_id, t.child_frame_id, t.timestamp.seconds, t.timestamp.nanos,
               _xyz(t.translation), _xyzw(t.rotation)) for t in items]  # fmt: skip


def _tf_of_ros(t: Any) -> Tf:
    v = t.transform
    sec = t.header.stamp.sec if "seq" not in t.header.__dataclass_fields__ else t.header.stamp.sec & 0xFFFFFFFF
    return Tf(t.header.frame_id, t.child_frame_id, sec, t.header.stamp.nanosec,
              _xyz(v.translation), _xyzw(v.rotation))  # fmt: skip


def _xyz(v: Any) -> tuple[float, float, float]:
    return (v.x, v.y, v.z)


def _xyzw(q: Any) -> tuple[float, float, float, float]:
    return (q.x, q.y, q.z, q.w)


def _xyz_dict(v: dict[str, float]) -> tuple[float, float, float]:
    return (v["x"], v["y"], v["z"])


def _xyzw_dict(q: dict[str, float]) -> tuple[float, float, float, float]:
    return (q["x"], q["y"], q["z"], q["w"])


# --- varied test data ------------------------------------------------------------------------

#: Frame ids of every length modulo 8 (so every CDR alignment), empty, slashes, spaces, non-ASCII.
NAMES = ["map", "odom", "base_link", "/base_footprint", "", "a", "ab", "abcd", "laser mount", "kamera_ö_光",
         "x" * 70, "arm/link_1", "arm/link_10", "robot_1/base_link"]  # fmt: skip
SPECIAL = [math.nan, math.inf, -math.inf, -0.0, 1e-300, 1e300, 5e-324]


def varied_transform(rng: np.random.Generator) -> Tf:
    parent, child = (NAMES[int(i)] for i in rng.integers(0, len(NAMES), 2))
    sec = int(rng.choice([0, 1_700_000_000 + int(rng.integers(0, 30)), -1, 2**31 - 1, -(2**31)]))
    nsec = int(rng.choice([0, int(rng.integers(0, NS)), NS - 1]))
    values = [float(v) for v in rng.normal(size=7)]
    if rng.random() < 0.1:
        values[int(rng.integers(0, 7))] = float(rng.choice(SPECIAL))
    return Tf(parent, child, sec, nsec, (values[0], values[1], values[2]), (values[3], values[4], values[5], values[6]))


def varied_messages(seed: int, count: int = 300, *, ties: bool = True) -> list[Msg | Other]:
    """/tf, /tf_static, /robot/tf_static and /robot/tf (TFMessage), /chatter (String): 0 to 40
    transforms a message, odd frame ids and values; written out of record-time order, some
    messages sharing one record time (when ``ties``)."""
    rng = np.random.default_rng(seed)
    messages: list[Msg | Other] = []
    for i in range(count):
        record_time = T0 + int(rng.integers(0, 20 * NS))
        if ties and i % 13 == 0:
            record_time = T0 + 5 * NS
        roll = rng.random()
        if roll < 0.08:
            messages.append(Other("/chatter", record_time, string_cdr(f"hello {i}" * int(rng.integers(1, 30)))))
            continue
        topic = ["/tf", "/tf", "/tf", "/tf_static", "/robot/tf", "/robot/tf_static"][int(rng.integers(0, 6))]
        k = int(rng.choice([0, 1, 2, 3, 6, 40], p=[0.03, 0.45, 0.2, 0.15, 0.15, 0.02]))
        messages.append(Msg(topic, record_time, tuple(varied_transform(rng) for _ in range(k))))
    return messages


# --- rosbag2 of older ROS distributions ------------------------------------------------------

_TOPICS_TABLES = {
    "dashing": "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
    " serialization_format TEXT NOT NULL, created_at INTEGER NOT NULL)",
    "foxy": "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
    " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)",
}


def write_legacy_rosbag2(path: Path, messages: Sequence[Msg | Other], distro: str, *, prefixed: bool = False) -> Path:
    """A sqlite3 bag as Dashing (metadata version 1) or Foxy (version 4) wrote it; ``prefixed``:
    the file listed with the bag directory in front, as some early versions did."""
    path.mkdir()
    name = f"{path.name}_0.db3"
    db = sqlite3.connect(path / name)
    db.execute(_TOPICS_TABLES[distro])
    db.execute("CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
               " timestamp INTEGER NOT NULL, data BLOB NOT NULL)")  # fmt: skip
    if distro != "dashing":
        db.execute("CREATE INDEX timestamp_idx ON messages (timestamp ASC)")
    topic_ids: dict[str, int] = {}
    types: dict[str, str] = {}
    for m in messages:
        type_name = TF_TYPE if isinstance(m, Msg) else m.type_name
        if m.topic not in topic_ids:
            topic_ids[m.topic] = len(topic_ids) + 1
            types[m.topic] = type_name
            extra = 0 if distro == "dashing" else ""
            db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', ?)", (topic_ids[m.topic], m.topic, type_name, extra))
        data = tf_cdr(m.transforms) if isinstance(m, Msg) else m.data
        db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                   (topic_ids[m.topic], m.record_time, data))  # fmt: skip
    db.commit()
    db.close()
    times = [m.record_time for m in messages]
    info: dict[str, Any] = {
        "version": 1 if distro == "dashing" else 4,
        "storage_identifier": "sqlite3",
        "relative_file_paths": [f"{path.name}/{name}" if prefixed else name],
        "duration": {"nanoseconds": max(times) - min(times)},
        "starting_time": {"nanoseconds_since_epoch": min(times)},
        "message_count": len(messages),
        "topics_with_message_count": [
            {"topic_metadata": {"name": topic, "type": types[topic], "serialization_format": "cdr"}, "message_count": 1}
            for topic in topic_ids
        ],
    }
    if distro == "foxy":
        info.update(compression_format="", compression_mode="")
        info["files"] = [{"path": name, "starting_time": info["starting_time"], "duration": info["duration"],
                          "message_count": len(messages)}]  # fmt: skip
    out = StringIO()
    YAML(typ="safe").dump({"rosbag2_bagfile_information": info}, out)
    (path / "metadata.yaml").write_text(out.getvalue())
    return path
