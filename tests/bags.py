"""``write_bag``: transforms into a ROS1 bag or a ROS2 bag (sqlite3 or MCAP storage)."""

from __future__ import annotations

import enum
import heapq
import os
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sinks.static_bag import static_qos
from tftools.sources.errors import BagError

TF_TYPE = "tf2_msgs/msg/TFMessage"
CLOCK_TYPE = "rosgraph_msgs/msg/Clock"


class BagFormat(str, enum.Enum):
    """The formats ``write_bag`` writes; ROS2 bags are directories."""

    ros1 = "ros1"
    rosbag2_sqlite3 = "rosbag2-sqlite3"
    rosbag2_mcap = "rosbag2-mcap"


@dataclass(frozen=True)
class TfMessage:
    """One recorded tf2_msgs/TFMessage: where, when, what, and who sent it (ROS1 callerid)."""

    topic: str
    record_time: int
    transforms: Sequence[Transform]
    publisher: str = ""


@dataclass(frozen=True)
class ClockMessage:
    """One recorded rosgraph_msgs/Clock on /clock: when it was recorded and the time it carried."""

    record_time: int
    clock: int
    topic: str = "/clock"
    publisher: str = ""


Message = TfMessage | ClockMessage


def write_bag(
    path: str | os.PathLike[str],
    messages: Iterable[TfMessage],
    fmt: BagFormat = BagFormat.ros1,
    clock: Iterable[ClockMessage] = (),
) -> Path:
    """Write ``messages`` and ``clock`` (each in record order) as a new bag at ``path``; refuses to overwrite."""
    target = Path(path)
    if target.exists():
        raise BagError(str(target), "already exists", "choose another output path or remove it first")
    merged: Iterator[Message] = heapq.merge(messages, clock, key=lambda m: m.record_time)
    if fmt is BagFormat.ros1:
        _write_ros1(target, merged)
    else:
        _write_rosbag2(target, merged, "mcap" if fmt is BagFormat.rosbag2_mcap else "sqlite3")
    return target


def detections_bag(path: str | os.PathLike[str]) -> Path:
    """A camera's marker detections (DIGIT_works' camera -> marker_367 shape): marker_0 seen 50 times at 25 Hz from
    1 s, marker_367 once at 1.5 s, each recorded 1 ms after its stamp."""

    def seen(stamp: int, child: str) -> TfMessage:
        return TfMessage(
            "/tf", stamp + 1_000_000, [Transform((1.0, 0, 0), (0, 0, 0, 1.0), stamp, "camera", child)], "/aruco"
        )

    messages = [seen(1_000_000_000 + i * 40_000_000, "marker_0") for i in range(50)]
    messages.append(seen(1_500_000_000, "marker_367"))
    return write_bag(path, sorted(messages, key=lambda m: m.record_time))


def device_beside_simulation_bag(path: str | os.PathLike[str]) -> Path:
    """One /tf of a robot simulated from 100 s without /clock (odom -> base_link) beside a device stamped on the
    wall clock (imu_link -> range, recorded 3 ms after its stamps), 50 of each every 0.1 s: the IAS0220 course's
    Gazebo robot beside its IMU, a ROS 2 bag (no publishers named)."""
    wall, ms = 1_700_000_000_000_000_000, 1_000_000
    messages = []
    for k in range(50):
        record = wall + k * 100 * ms
        sim = Transform((0.01 * k, 0, 0), (0, 0, 0, 1.0), 100_000_000_000 + k * 100 * ms, "odom", "base_link")
        device = Transform((0, 0, 0), (0, 0, 0, 1.0), record - 2 * ms, "imu_link", "range")
        messages += [TfMessage("/tf", record, [sim]), TfMessage("/tf", record + ms, [device])]
    return write_bag(path, messages, BagFormat.rosbag2_sqlite3)


def _write_ros1(path: Path, messages: Iterable[Message]) -> None:
    from rosbags.rosbag1 import Writer

    store = _typestore("ros1")
    with Writer(path) as writer:
        connections: dict[tuple[str, str], Any] = {}
        for message in messages:
            key = (message.topic, message.publisher)
            kind = _type(message)
            if key not in connections:
                latching = 1 if message.topic.endswith("tf_static") else None
                connections[key] = writer.add_connection(
                    message.topic, kind, typestore=store, callerid=message.publisher or None, latching=latching
                )
            data = store.serialize_ros1(_message(store, message), kind)
            writer.write(connections[key], message.record_time, bytes(data))


def _write_rosbag2(path: Path, messages: Iterable[Message], storage: str) -> None:
    from rosbags.rosbag2 import StoragePlugin, Writer

    store = _typestore("ros2")
    writer = Writer(path, version=Writer.VERSION_LATEST, storage_plugin=StoragePlugin[storage.upper()])
    with writer:
        connections: dict[str, Any] = {}
        for message in messages:
            kind = _type(message)
            if message.topic not in connections:
                # as ros2 bag record does: the QoS the publishers offered (tf2_ros': transient local on /tf_static)
                offered = [static_qos()] if message.topic.endswith("tf_static") else []
                connections[message.topic] = writer.add_connection(
                    message.topic, kind, typestore=store, offered_qos_profiles=offered
                )
            data = store.serialize_cdr(_message(store, message), kind)
            writer.write(connections[message.topic], message.record_time, bytes(data))


def _type(message: Message) -> str:
    return TF_TYPE if isinstance(message, TfMessage) else CLOCK_TYPE


def _message(store: Any, message: Message) -> Any:
    if isinstance(message, TfMessage):
        return rosbags_tf_message(store, message.transforms)
    sec, nanosec = divmod(message.clock, NS_PER_S)
    return store.types[CLOCK_TYPE](clock=store.types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec))


@cache
def _typestore(ros: str) -> Any:
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if ros == "ros1" else Stores.ROS2_HUMBLE)
    if TF_TYPE not in store.types:  # rosbags' ROS1 store lacks tf2_msgs
        store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", TF_TYPE))
    return store


def rosbags_tf_message(store: Any, transforms: Sequence[Transform]) -> Any:
    """``transforms`` as rosbags' TFMessage of ``store`` (ROS 1's or ROS 2's types), to serialize."""
    types = store.types
    time_type = types["builtin_interfaces/msg/Time"]
    stamped = []
    for t in transforms:
        sec, nanosec = divmod(t.stamp, NS_PER_S)
        header = types["std_msgs/msg/Header"](**_header_fields(store, time_type(sec=sec, nanosec=nanosec), t.frame_id))
        x, y, z = (float(v) for v in t.translation)
        qx, qy, qz, qw = (float(v) for v in t.rotation)
        geometry = types["geometry_msgs/msg/Transform"](
            translation=types["geometry_msgs/msg/Vector3"](x=x, y=y, z=z),
            rotation=types["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
        )
        stamped_type = types["geometry_msgs/msg/TransformStamped"]
        stamped.append(stamped_type(header=header, child_frame_id=t.child_frame_id, transform=geometry))
    return types[TF_TYPE](transforms=stamped)


def _header_fields(store: Any, stamp: Any, frame_id: str) -> dict[str, Any]:
    fields: dict[str, Any] = {"stamp": stamp, "frame_id": frame_id}
    if any(name == "seq" for name, _ in store.fielddefs["std_msgs/msg/Header"][1]):  # ROS1 only
        fields["seq"] = 0
    return fields
