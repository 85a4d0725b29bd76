"""A small wheeled robot as robot_state_publisher, joint_state_publisher and odometry would record it, in
every bag format, with its URDF; and the same robot with one thing wrong (a joint never published,
robot_state_publisher not running, a sensor moved or flipped since the URDF was written)."""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from tests.bags import BagFormat, _typestore, rosbags_tf_message
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sinks.static_bag import static_qos
from tftools.sources.urdf import Joint, parse_urdf

START = 1_700_000_000 * NS_PER_S
SECONDS = 5.0
HZ = 20.0
DELAY = 2_000_000  # ns between a message's stamp and its recording
WHEEL_SPEED = 2.0  # rad/s

URDF = """<?xml version="1.0"?>
<robot name="rover">
  <link name="base_footprint"/>
  <link name="base_link"/>
  <link name="laser"/>
  <link name="camera_link"/>
  <link name="wheel_left_link"/>
  <link name="wheel_right_link"/>
  <joint name="base_joint" type="fixed">
    <parent link="base_footprint"/><child link="base_link"/><origin xyz="0 0 0.1" rpy="0 0 0"/>
  </joint>
  <joint name="laser_joint" type="fixed">
    <parent link="base_link"/><child link="laser"/><origin xyz="0.2 0 0.15" rpy="0 0 0"/>
  </joint>
  <joint name="camera_joint" type="fixed">
    <parent link="base_link"/><child link="camera_link"/><origin xyz="0.1 0 0.3" rpy="0 0.2 0"/>
  </joint>
  <joint name="wheel_left_joint" type="continuous">
    <parent link="base_link"/><child link="wheel_left_link"/>
    <origin xyz="0 0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="wheel_right_joint" type="continuous">
    <parent link="base_link"/><child link="wheel_right_link"/>
    <origin xyz="0 -0.15 0" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"""

ROBOT = parse_urdf(URDF, "rover.urdf")
JOINTS = {j.name: j for j in ROBOT.joints}
MOVING = [j for j in ROBOT.joints if j.moving]
FIXED = [j for j in ROBOT.joints if j.type == "fixed"]


@dataclass(frozen=True)
class Setup:
    """What ran on the robot: which joint states were published, whether robot_state_publisher ran, and
    fixed joints whose real origin (xyz, rpy) differs from the URDF's (a moved or flipped sensor)."""

    joint_states: Sequence[str] = ("wheel_left_joint", "wheel_right_joint")
    extra_states: Sequence[str] = ()  # joints published that the URDF lacks
    state_publisher: bool = True
    fixed_published: bool = True
    real_origins: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = field(default_factory=dict)
    description: bool = False  # /robot_description recorded
    description_text: str = URDF
    wheel_speed: float = WHEEL_SPEED  # rad/s
    tf_every: int = 1  # robot_state_publisher publishes the moving joints of every n-th joint state
    prefix: str = ""  # robot_state_publisher's frame_prefix (a namespaced robot)
    statics_stamped_before: int = 0  # ns: robot_state_publisher started (and stamped its statics) this long before


def position(joint: str, seconds: float, speed: float = WHEEL_SPEED) -> float:
    return speed * seconds * (1.0 if joint.endswith("left_joint") else -1.0)


def _transform(joint: Joint, q: float, stamp: int, prefix: str = "") -> Transform:
    xyz, quat = joint.transform_at(q)
    return Transform(xyz, quat, stamp, prefix + joint.parent, prefix + joint.child)


@dataclass(frozen=True)
class Recorded:
    """One message: topic, record time, publisher (ROS 1), and its value (transforms, a joint state as
    (stamp, names, positions), or a string)."""

    topic: str
    record_time: int
    value: Any
    publisher: str = ""


def recorded(setup: Setup) -> list[Recorded]:
    """What ``rosbag record -a`` would hold of the robot under ``setup``, in record order."""
    messages: list[Recorded] = []
    if setup.description:
        messages.append(Recorded("/robot_description", START, setup.description_text, "/robot_state_publisher"))
    if setup.state_publisher and setup.fixed_published:
        statics = []
        for j in FIXED:
            xyz, rpy = setup.real_origins.get(j.name, (j.xyz, j.rpy))
            real = Joint(j.name, j.type, j.parent, j.child, xyz, rpy)
            statics.append(_transform(real, 0.0, START - setup.statics_stamped_before, setup.prefix))
        messages.append(Recorded("/tf_static", START + DELAY, statics, "/robot_state_publisher"))
    for i in range(round(SECONDS * HZ)):
        seconds = i / HZ
        stamp = START + round(seconds * NS_PER_S)
        odom = Transform.from_rpy(
            (0.3 * seconds, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, f"{setup.prefix}odom", f"{setup.prefix}base_footprint"
        )
        messages.append(Recorded("/tf", stamp + DELAY, [odom], "/odometry"))
        names = list(setup.joint_states) + list(setup.extra_states)
        if names:
            states = (stamp, names, [position(n, seconds, setup.wheel_speed) for n in names])
            messages.append(Recorded("/joint_states", stamp + DELAY // 2, states, "/joint_state_publisher"))
        if setup.state_publisher and i % setup.tf_every == 0:
            moving = [
                _transform(j, position(j.name, seconds, setup.wheel_speed), stamp, setup.prefix)
                for j in MOVING
                if j.name in setup.joint_states
            ]
            if moving:
                messages.append(Recorded("/tf", stamp + DELAY + 1000, moving, "/robot_state_publisher"))
    return sorted(messages, key=lambda m: m.record_time)


TYPES = {
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/joint_states": "sensor_msgs/msg/JointState",
    "/robot_description": "std_msgs/msg/String",
}


def _message(store: Any, m: Recorded) -> Any:
    types = store.types
    if m.topic in ("/tf", "/tf_static"):
        return rosbags_tf_message(store, m.value)
    if m.topic == "/robot_description":
        return types["std_msgs/msg/String"](data=m.value)
    stamp, names, positions = m.value
    sec, nanosec = divmod(stamp, NS_PER_S)
    header_fields: dict[str, Any] = {
        "stamp": types["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
        "frame_id": "",
    }
    if any(name == "seq" for name, _ in store.fielddefs["std_msgs/msg/Header"][1]):
        header_fields["seq"] = 0
    return types["sensor_msgs/msg/JointState"](
        header=types["std_msgs/msg/Header"](**header_fields),
        name=list(names),
        position=np.array(positions, np.float64),
        velocity=np.zeros(0),
        effort=np.zeros(0),
    )


def write_robot_bag(path: Path, messages: Iterable[Recorded], fmt: BagFormat = BagFormat.ros1) -> Path:
    """The messages as a new bag of ``fmt`` at ``path`` (a directory for ROS 2)."""
    ordered = list(heapq.merge(messages, key=lambda m: m.record_time))
    if fmt is BagFormat.ros1:
        from rosbags.rosbag1 import Writer as Ros1Writer

        store = _typestore("ros1")
        with Ros1Writer(path) as writer:
            connections: dict[tuple[str, str], Any] = {}
            for m in ordered:
                key = (m.topic, m.publisher)
                if key not in connections:
                    latched = 1 if m.topic in ("/tf_static", "/robot_description") else None
                    connections[key] = writer.add_connection(
                        m.topic, TYPES[m.topic], typestore=store, callerid=m.publisher or None, latching=latched
                    )
                writer.write(
                    connections[key], m.record_time, bytes(store.serialize_ros1(_message(store, m), TYPES[m.topic]))
                )
        return path
    from rosbags.rosbag2 import StoragePlugin, Writer

    store = _typestore("ros2")
    storage = StoragePlugin.MCAP if fmt is BagFormat.rosbag2_mcap else StoragePlugin.SQLITE3
    with Writer(path, version=Writer.VERSION_LATEST, storage_plugin=storage) as writer2:
        topics: dict[str, Any] = {}
        for m in ordered:
            if m.topic not in topics:
                offered = [static_qos()] if m.topic in ("/tf_static", "/robot_description") else []
                topics[m.topic] = writer2.add_connection(
                    m.topic, TYPES[m.topic], typestore=store, offered_qos_profiles=offered
                )
            writer2.write(
                topics[m.topic], m.record_time, bytes(store.serialize_cdr(_message(store, m), TYPES[m.topic]))
            )
    return path


def robot_bag(directory: Path, name: str, setup: Setup, fmt: BagFormat = BagFormat.ros1) -> Path:
    """The robot under ``setup`` recorded as a bag of ``fmt`` in ``directory``."""
    path = directory / (f"{name}.bag" if fmt is BagFormat.ros1 else f"{name}_{fmt.value}")
    return write_robot_bag(path, recorded(setup), fmt)


def urdf_file(directory: Path, name: str = "rover.urdf", text: str = URDF) -> Path:
    path = directory / name
    path.write_text(text)
    return path


FLIPPED = ((0.2, 0.0, 0.15), (math.pi, 0.0, 0.0))  # the laser mounted upside down
MOVED = ((0.22, 0.0, 0.15), (0.0, 0.0, 0.0))  # the laser 2 cm further forward
