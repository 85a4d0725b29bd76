"""What a recording holds, read without tftools (rosbags' reader; sqlite3 for a .db3 left without
metadata.yaml; rosbags' ROS 1 reader for a bag whose types AnyReader refuses), and lookups composed with numpy.

The corpus tests compare tftools against these: tf samples per edge (stamps, values, record
times), whether /clock was recorded, and a lookup computed as ROS 2's tf2 does it (statics
timeless; each dynamic edge interpolated between the samples around the time, translation
linearly, rotation by shortest-path slerp; the chain composed through the tree).
"""

from __future__ import annotations

import dataclasses
import json
import math
import sqlite3
from collections import Counter
from collections.abc import Iterator
from contextlib import closing, contextmanager
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any, cast

import numpy as np
import numpy.typing as npt
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.rosbag1 import Reader as Ros1Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

# "tf" and "tf_static" (no slash) are what a writer that did not resolve the names stored: in ROS 2's root
# namespace they are /tf and /tf_static.
TF_TOPICS = ("/tf", "/tf_static", "tf", "tf_static")
Edge = tuple[str, str]  # (parent, child)


@dataclass
class EdgeSamples:
    """One edge's samples in record order."""

    static: bool
    stamps: list[int] = field(default_factory=list)  # ns
    record_times: list[int] = field(default_factory=list)  # ns
    values: list[list[float]] = field(default_factory=list)  # tx ty tz qx qy qz qw
    publishers: set[str] = field(default_factory=set)
    on_tf: list[bool] = field(default_factory=list)  # each sample: whether it came on /tf (not /tf_static)


@dataclass
class Contents:
    """What the recording holds, as its own reader gives it."""

    topics: set[str]
    first_record: int  # ns, over every message
    last_record: int
    edges: dict[Edge, EdgeSamples]
    clock: list[tuple[int, int]]  # (clock value, record time) ns
    #: Messages holding a transform, per (topic, publisher): the callerid where a ROS 1 bag names it
    messages: Counter[tuple[str, str]] = field(default_factory=Counter)

    @property
    def frames(self) -> set[str]:
        return {frame for edge in self.edges for frame in edge}

    @property
    def dynamic(self) -> dict[Edge, EdgeSamples]:
        return {e: s for e, s in self.edges.items() if not s.static}


def _is_tf_message(msgtype: str) -> bool:
    """Whether tf2 reads the type: a topic named tf of another type (a TransformStamped) is no tf."""
    return msgtype.rsplit("/", 1)[-1].lower() == "tfmessage"


def _ns(stamp: Any) -> int:  # a rosbags message (untyped)
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def _strip(frame: str) -> str:
    return frame[1:] if frame.startswith("/") else frame


@cache
def read_contents(path: Path) -> Contents:
    """Every /tf and /tf_static sample and /clock value of a recording (ROS1, ROS2, or an MCAP of JSON
    messages). A record time of 0 is unset (a writer that left an MCAP log time empty): not the span's."""
    if path.suffix == ".mcap" and _plain_mcap(path):
        return _read_plain_mcap(path)
    if _db3_without_metadata(path):
        return _read_db3(path)
    edges: dict[Edge, EdgeSamples] = {}
    clock: list[tuple[int, int]] = []
    times: list[int] = []
    sent: Counter[tuple[str, str]] = Counter()
    ros2 = path.suffix != ".bag"
    with _reader(path) as reader:
        topics = {c.topic for c in reader.connections}
        for connection, record_time, raw in reader.messages():
            times.append(record_time)
            if connection.topic in TF_TOPICS and _is_tf_message(connection.msgtype):
                publisher = getattr(connection.ext, "callerid", None) or connection.topic
                message: Any = reader.deserialize(raw, connection.msgtype)
                sent[connection.topic, publisher] += bool(message.transforms)
                for t in message.transforms:
                    tr, q = t.transform.translation, t.transform.rotation
                    _add(
                        edges,
                        connection.topic,
                        publisher,
                        record_time,
                        _strip(t.header.frame_id),
                        _strip(t.child_frame_id),
                        _ns(t.header.stamp),
                        [tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w],
                        ros2=ros2,
                    )
            elif connection.topic == "/clock":
                clock.append((_ns(cast(Any, reader.deserialize(raw, connection.msgtype)).clock), record_time))
    return dataclasses.replace(_contents(topics, times, edges, clock), messages=sent)


@contextmanager
def _reader(path: Path) -> Iterator[Any]:
    """rosbags' AnyReader; for a ROS 1 bag it refuses, rosbags' ROS 1 reader with the types of tf and /clock
    taken from their own connections (``_Ros1Tf``)."""
    if path.suffix == ".bag" and _ros1_type_hash_mismatch(path):
        with Ros1Reader(path) as ros1:
            yield _Ros1Tf(ros1)
        return
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        yield reader


def _ros1_type_hash_mismatch(path: Path) -> bool:
    """A ROS 1 bag a connection of which declares an md5sum its own definition does not hash to (fishberg's
    microstrain.bag: /ekf/status): AnyReader refuses the whole bag, rosbag and tf2 read it (the md5 is only
    compared between live peers)."""
    try:
        with AnyReader([path]):
            return False
    except AnyReaderError as error:
        return "hash mismatch" in str(error)


class _Ros1Tf:
    """A ROS 1 bag's connections and messages, decoding only tf's and /clock's (their types registered from
    the definitions their connections carry)."""

    def __init__(self, reader: Ros1Reader) -> None:
        self._reader = reader
        self.connections = reader.connections
        self._store = get_typestore(Stores.EMPTY)
        for c in reader.connections:
            if (c.topic in TF_TOPICS and _is_tf_message(c.msgtype)) or c.topic == "/clock":
                self._store.register(get_types_from_msg(c.msgdef.data, c.msgtype))

    def messages(self) -> Iterator[tuple[Any, int, bytes]]:
        return cast(Iterator[tuple[Any, int, bytes]], self._reader.messages())

    def deserialize(self, raw: bytes, msgtype: str) -> Any:
        return self._store.deserialize_ros1(raw, msgtype)


def _add(
    edges: dict[Edge, EdgeSamples],
    topic: str,
    publisher: str,
    record_time: int,
    parent: str,
    child: str,
    stamp: int,
    value: list[float],
    *,
    ros2: bool,
) -> None:
    """Adds a sample as the recording's tf2 keeps it: ROS 1's keeps a frame in the kind of cache its first
    sample made; ROS 2's replaces the frame's cache when it switches between /tf_static and /tf, dropping
    its samples (``core/semantics.py``)."""
    if not parent or not child:  # tf2 refuses it (TF_NO_FRAME_ID, TF_NO_CHILD_FRAME_ID): nothing is stored
        return
    static = topic.lstrip("/") == "tf_static"
    if ros2:
        for key in [key for key, held in edges.items() if key[1] == child and held.static != static]:
            del edges[key]
    else:  # the frame's cache, whichever parent its first sample named
        static = next((held.static for key, held in edges.items() if key[1] == child), static)
    samples = edges.setdefault((parent, child), EdgeSamples(static=static))
    samples.stamps.append(stamp)
    samples.record_times.append(record_time)
    samples.values.append(value)
    samples.publishers.add(publisher)
    samples.on_tf.append(topic.lstrip("/") != "tf_static")


def _contents(
    topics: set[str], times: list[int], edges: dict[Edge, EdgeSamples], clock: list[tuple[int, int]]
) -> Contents:
    known = [t for t in times if t > 0]
    return Contents(topics, min(known, default=0), max(known, default=0), edges, clock)


def _db3_without_metadata(path: Path) -> bool:
    """A rosbag2 sqlite3 bag whose recorder stopped before writing metadata.yaml (rosbags refuses it)."""
    folder = path if path.is_dir() else path.parent
    return not (folder / "metadata.yaml").exists() and any(folder.glob("*.db3"))


def _read_db3(path: Path) -> Contents:
    """Its .db3 files read with sqlite3 directly, immutable (a -wal file beside one is neither read nor
    merged: nothing given is modified), each message decoded from its topic's CDR type by rosbags."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    edges: dict[Edge, EdgeSamples] = {}
    clock: list[tuple[int, int]] = []
    times: list[int] = []
    topics: set[str] = set()
    sent: Counter[tuple[str, str]] = Counter()
    for db3 in sorted(path.glob("*.db3")) if path.is_dir() else [path]:
        with closing(sqlite3.connect(f"{db3.resolve().as_uri()}?immutable=1", uri=True)) as db:
            types = {i: (name, kind) for i, name, kind in db.execute("SELECT id, name, type FROM topics")}
            topics |= {name for name, _ in types.values()}
            query = "SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id"
            for topic_id, record_time, raw in db.execute(query):
                times.append(record_time)
                topic, kind = types[topic_id]
                if topic in TF_TOPICS and _is_tf_message(kind):
                    transforms = cast(Any, store.deserialize_cdr(raw, kind)).transforms
                    sent[topic, topic] += bool(transforms)
                    for t in transforms:
                        tr, q = t.transform.translation, t.transform.rotation
                        value = [tr.x, tr.y, tr.z, q.x, q.y, q.z, q.w]
                        parent, child = _strip(t.header.frame_id), _strip(t.child_frame_id)
                        _add(edges, topic, topic, record_time, parent, child, _ns(t.header.stamp), value, ros2=True)
                elif topic == "/clock":
                    clock.append((_ns(cast(Any, store.deserialize_cdr(raw, kind)).clock), record_time))
    return dataclasses.replace(_contents(topics, times, edges, clock), messages=sent)


def _plain_mcap(path: Path) -> bool:
    """An MCAP rosbags does not read: JSON messages (Foxglove style), or CDR without the ros2 profile (a file
    rewritten by another writer, foxglove-wizard's drone.mcap)."""
    with path.open("rb") as f:
        reader = make_reader(f)
        profile, summary = reader.get_header().profile, reader.get_summary()
    json_messages = summary is not None and any(c.message_encoding == "json" for c in summary.channels.values())
    return json_messages or profile != "ros2"


def _mcap_transforms(encoding: str, schema: str, data: bytes) -> list[tuple[str, str, int, list[float]]]:
    """A tf2_msgs/TFMessage's transforms, as JSON objects or CDR: (frame_id, child_frame_id, stamp, value)."""
    if encoding == "json":
        found = []
        for t in json.loads(data)["transforms"]:
            header, tr, q = t["header"], t["transform"]["translation"], t["transform"]["rotation"]
            stamp = int(header["stamp"]["sec"]) * 1_000_000_000 + int(header["stamp"]["nanosec"])
            value = [tr["x"], tr["y"], tr["z"], q["x"], q["y"], q["z"], q["w"]]
            found.append((header["frame_id"], t["child_frame_id"], stamp, value))
        return found
    message = cast(Any, get_typestore(Stores.ROS2_HUMBLE).deserialize_cdr(data, schema))
    return [
        (t.header.frame_id, t.child_frame_id, _ns(t.header.stamp), [*_xyz(t.transform.translation), *_xyzw(t)])
        for t in message.transforms
    ]


def _xyz(v: Any) -> list[float]:
    return [v.x, v.y, v.z]


def _xyzw(t: Any) -> list[float]:
    q = t.transform.rotation
    return [q.x, q.y, q.z, q.w]


def _read_plain_mcap(path: Path) -> Contents:
    """An MCAP read with the mcap library: tf2_msgs/TFMessage in JSON or CDR."""
    edges: dict[Edge, EdgeSamples] = {}
    times: list[int] = []
    sent: Counter[tuple[str, str]] = Counter()
    with path.open("rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None, f"{path} has no summary"
        topics = {c.topic for c in summary.channels.values()}
        for schema, channel, message in reader.iter_messages(log_time_order=True):
            times.append(message.log_time)
            if channel.topic not in TF_TOPICS:
                continue
            name = schema.name if schema is not None else ""
            transforms = _mcap_transforms(channel.message_encoding, name, message.data)
            sent[channel.topic, channel.topic] += bool(transforms)
            for parent, child, stamp, value in transforms:
                _add(
                    edges,
                    channel.topic,
                    channel.topic,
                    message.log_time,
                    _strip(parent),
                    _strip(child),
                    stamp,
                    value,
                    ros2=True,
                )
    return dataclasses.replace(_contents(topics, times, edges, []), messages=sent)


#: Stamps below this (2001-09-09) count from boot or a simulation's start, not from the epoch.
EPOCH_SECONDS = 1_000_000_000


def _clock_cuts(stamps: npt.NDArray[np.int64], records: npt.NDArray[np.int64]) -> tuple[npt.NDArray[np.bool_], bool]:
    """Which intervals between consecutive ``stamps`` (sorted; ``records`` their record times, in that order)
    join two clocks: either side of the epoch floor, or longer than the samples took to arrive (their record
    span, where every record time is known), unless half of them are (record times that are no clock); and
    whether the record times are a clock."""
    cuts = (stamps[:-1] < EPOCH_SECONDS * 10**9) & (stamps[1:] >= EPOCH_SECONDS * 10**9)
    if not len(records) or records.min() <= 0:
        return cuts, False
    between = np.diff(stamps) > records.max() - records.min()
    if 2 * between.sum() >= len(between):
        return cuts, False
    return cuts | between, True


def _sorted(samples: EdgeSamples) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]:
    stamps = np.asarray(samples.stamps, np.int64)
    order = np.argsort(stamps, kind="stable")
    return stamps[order], np.asarray(samples.record_times, np.int64)[order]


def one_clock_intervals(samples: EdgeSamples) -> npt.NDArray[np.int64]:
    """The intervals between consecutive sorted stamps on one clock (ns), none across two (``_clock_cuts``: a
    replay's stamps a week behind a live node's)."""
    stamps, records = _sorted(samples)
    cuts, _ = _clock_cuts(stamps, records)
    kept: npt.NDArray[np.int64] = np.diff(stamps)[~cuts]
    return kept


def stamp_rate(samples: EdgeSamples) -> float:
    """Samples per second of an edge. On one clock: over the time its stamps cover. On several
    (``_clock_cuts``), side by side: where the record times are a clock, every clock's stamps moved onto it by
    their median delay, the samples over the time those cover together; else each clock's rate, added."""
    stamps, records = _sorted(samples)
    cuts, placed = _clock_cuts(stamps, records)
    pieces = np.split(np.arange(len(stamps)), np.flatnonzero(cuts) + 1)
    if len(pieces) == 1:
        span = float(stamps[-1] - stamps[0]) if len(stamps) else 0.0
        return (len(stamps) - 1) * 1e9 / span if span > 0 else 0.0
    if not placed:
        spans = [float(stamps[p[-1]] - stamps[p[0]]) for p in pieces]
        return sum((len(p) - 1) * 1e9 / span for p, span in zip(pieces, spans, strict=True) if span > 0)
    windows = sorted(
        (float(stamps[p[0]]) + delay, float(stamps[p[-1]]) + delay)
        for p in pieces
        for delay in [float(np.median(records[p] - stamps[p]))]
    )
    covered, reach = 0.0, -math.inf
    for low, high in windows:
        covered += max(high - max(low, reach), 0.0)
        reach = max(reach, high)
    return sum(len(p) - 1 for p in pieces) * 1e9 / covered if covered > 0 else 0.0


def largest_stamp_gap(samples: EdgeSamples) -> float:
    """The longest time between consecutive stamps on one clock (``one_clock_intervals``), in seconds."""
    intervals = one_clock_intervals(samples)
    return float(intervals.max()) / 1e9 if len(intervals) else 0.0


# --- lookups as ROS 2's tf2 computes them ------------------------------------------------------


def q_mul(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    )


def q_rotate(q: npt.NDArray[np.float64], v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    conj = q * np.array([-1.0, -1.0, -1.0, 1.0])
    return q_mul(q_mul(q, np.array([*v, 0.0])), conj)[:3]


def slerp(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64], ratio: float) -> npt.NDArray[np.float64]:
    """Shortest-path spherical interpolation, as tf2's Quaternion::slerp: the angle is measured between the
    quaternions as given, divided by their lengths (a recorded rotation may be a little off unit length)."""
    dot = float(np.dot(a, b))
    if dot < 0:
        b, dot = -b, -dot
    theta = np.arccos(min(dot / np.sqrt(float(np.dot(a, a)) * float(np.dot(b, b))), 1.0))
    if theta < 1e-12:
        return a
    mixed: npt.NDArray[np.float64] = (np.sin((1 - ratio) * theta) * a + np.sin(ratio * theta) * b) / np.sin(theta)
    return mixed


Pose = tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]  # translation, rotation (x y z w)


def compose(a: Pose, b: Pose) -> Pose:
    return a[0] + q_rotate(a[1], b[0]), q_mul(a[1], b[1])


def invert(a: Pose) -> Pose:
    conj = a[1] * np.array([-1.0, -1.0, -1.0, 1.0])
    return -q_rotate(conj, a[0]), conj


def edge_at(samples: EdgeSamples, time: int) -> Pose:
    """The edge's transform at ``time`` (ns); ValueError outside its samples. ROS 2's tf2 holds each
    rotation as a unit quaternion (through ``tf2::Transform``'s matrix), so these are normalized first."""
    values = np.asarray(samples.values, np.float64).copy()
    values[:, 3:] /= np.linalg.norm(values[:, 3:], axis=1, keepdims=True)
    if samples.static:
        return values[-1, :3], values[-1, 3:]
    stamps = np.asarray(samples.stamps, np.int64)
    order = np.argsort(stamps, kind="stable")
    stamps, values = stamps[order], values[order]
    if not stamps[0] <= time <= stamps[-1]:
        raise ValueError(f"{time} outside {stamps[0]}..{stamps[-1]}")
    i = int(np.searchsorted(stamps, time, side="left"))
    if stamps[i] == time:
        # several samples at one stamp (ROS 2's tf2 stores each value sent): the last one counts, but at the
        # oldest stamp the first (ROS 1's tf2 stores one sample a stamp: the two are one)
        i = i if i == 0 else int(np.searchsorted(stamps, time, side="right")) - 1
        return values[i, :3], values[i, 3:]
    ratio = (time - stamps[i - 1]) / (stamps[i] - stamps[i - 1])
    before, after = values[i - 1], values[i]
    return before[:3] + ratio * (after[:3] - before[:3]), slerp(before[3:], after[3:], ratio)


def _parents(contents: Contents) -> dict[str, Edge]:
    parents: dict[str, Edge] = {}
    for edge in contents.edges:
        parents[edge[1]] = edge
    return parents


def _to_root(contents: Contents, frame: str, time: int) -> tuple[str, Pose]:
    """The root of ``frame``'s tree and T(root <- frame) at ``time``."""
    parents = _parents(contents)
    pose: Pose = (np.zeros(3), np.array([0.0, 0.0, 0.0, 1.0]))
    while frame in parents:
        edge = parents[frame]
        pose = compose(edge_at(contents.edges[edge], time), pose)
        frame = edge[0]
    return frame, pose


def lookup(contents: Contents, target: str, source: str, time: int) -> Pose:
    """T(target <- source) at ``time``: a point in ``source`` expressed in ``target``."""
    root_t, target_pose = _to_root(contents, target, time)
    root_s, source_pose = _to_root(contents, source, time)
    if root_t != root_s:
        raise ValueError(f"{target} and {source} are in different trees")
    return compose(invert(target_pose), source_pose)


def chain_edges(contents: Contents, frame: str) -> list[Edge]:
    """The edges from ``frame`` up to its root."""
    parents = _parents(contents)
    out = []
    while frame in parents:
        out.append(parents[frame])
        frame = parents[frame][0]
    return out


def covered_sample_times(contents: Contents, target: str, source: str, limit: int) -> list[int]:
    """Up to ``limit`` sample stamps of the chain's dynamic edges where every one of them has data."""
    dynamic = [contents.edges[e] for e in {*chain_edges(contents, target), *chain_edges(contents, source)}]
    dynamic = [s for s in dynamic if not s.static]
    if not dynamic:
        return []
    low = max(min(s.stamps) for s in dynamic)
    high = min(max(s.stamps) for s in dynamic)
    times = sorted({t for s in dynamic for t in s.stamps if low <= t <= high})
    step = max(1, len(times) // limit)
    return times[::step][:limit]


#: Types whose header's frame_id places nothing in space (a gamepad's joy_node stamps 'joy'; joint positions
#: name no frame): no MessageFilter's data, whatever their frame_id.
PLACING_NOTHING = ("sensor_msgs/msg/Joy", "sensor_msgs/msg/JointState")


def framed_topics(path: Path) -> set[str]:
    """The topics with a message whose header (its first field, a std_msgs/Header) names a frame: the sensor
    data a tf2 MessageFilter could be given, read with rosbags (every message of a topic until one names a
    frame). A ROS 2 bag's types are those rosbags knows (Humble's): a type it does not know is not read."""
    if path.suffix == ".mcap" and _plain_mcap(path):
        return _framed_in_plain_mcap(path)
    found: set[str] = set()
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        fields = reader.typestore.fielddefs
        stamped = [
            c
            for c in reader.connections
            if c.msgtype in fields
            and c.msgtype not in PLACING_NOTHING
            and fields[c.msgtype][1][:1]
            and fields[c.msgtype][1][0][0] == "header"
        ]
        for connection, _, raw in reader.messages(connections=stamped) if stamped else ():  # [] would be all
            message: Any = reader.deserialize(raw, connection.msgtype)
            if connection.topic not in found and message.header.frame_id:
                found.add(connection.topic)
    return found


def _framed_in_plain_mcap(path: Path) -> set[str]:
    """``framed_topics`` of an MCAP rosbags does not read: JSON messages, or CDR of a type Humble has."""
    store, found = get_typestore(Stores.ROS2_HUMBLE), set()
    with path.open("rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            name = schema.name if schema is not None else ""
            if channel.topic in found or name in PLACING_NOTHING or channel.topic in TF_TOPICS:
                continue
            if channel.message_encoding == "json":
                header = json.loads(message.data).get("header")
                frame = header.get("frame_id") if isinstance(header, dict) else None
            elif (
                name in store.fielddefs and store.fielddefs[name][1][:1] and store.fielddefs[name][1][0][0] == "header"
            ):
                frame = cast(Any, store.deserialize_cdr(message.data, name)).header.frame_id
            else:
                frame = None
            if frame:
                found.add(channel.topic)
    return found
