# ruff: noqa: N801 - the structs carry the names ROS 2 gives them on the wire
"""Stand-ins for ROS 2 nodes, for the live ROS 2 tests (run as scripts, never imported by pytest).

No ROS 2 exists on the test machines: these talk DDS through Cyclone DDS the way rmw_cyclonedds
does (ROS 2 topic and type names, keyless XCDR1 types, rclcpp's QoS, ros_discovery_info), with
their own type definitions (tftools' are not used, so a mistake there cannot hide here).

    ros2_nodes.py dynamic NAME PARENT CHILD [--gid 16|24|0] [--hz 50] [--sim START [--loop SECONDS]]
        A TransformBroadcaster node /NAME: translation (x, 0.5, 0), identity rotation, x going from 0 to
        100 m and back at 1 m/s of stamp time (continuous: a wrap would be a jump that `wtf` reports).
        --gid: the Gid size of its ros_discovery_info announcement (0: no announcement, a plain DDS
        writer). --sim START: also publishes /clock from START seconds, and stamps with it; --loop:
        back to START every SECONDS, as a replay that loops.
    ros2_nodes.py scan TOPIC FRAME [--hz 10]   a sensor_msgs/msg/LaserScan writer on TOPIC (rclcpp's SensorDataQoS:
                                        best effort, keep last 5), stamped now, in FRAME
    ros2_nodes.py wrong_type TOPIC      a std_msgs/msg/String writer on TOPIC
    ros2_nodes.py volatile_static       a /tf_static writer that is volatile (tf2 listeners cannot hear it)
    ros2_nodes.py discovery_listener SIZE   prints the nodes of each ros_discovery_info sample its reader of
                                        SIZE-byte Gids gets, as JSON (a typed DDS peer of the other size is
                                        not matched: the listener of a Humble or of a later system)
    ros2_nodes.py static_listener       listens to /tf_static with tf2_ros's StaticListenerQoS for 1.5 s and
                                        prints as JSON each sample and its writer's QoS as DDS discovered it
    ros2_nodes.py kilohertz [COUNT]     once tfx's reader is matched, COUNT (3000) /tf samples at 1 kHz of 100
                                        transforms (root -> c0 ... c99) stamped 1 s + k ms; prints "done"
    ros2_nodes.py hostile KIND          a misbehaving /tf writer announced as node /hostile: KIND "flood" (20,000
                                        new frame names a sample, 10 Hz), "longnames" (1,000 new names of 4 KiB and
                                        one of 1 MiB a sample, 10 Hz), "names" (escape codes, newlines, 10,000-
                                        character names), "values" (NaN, inf, 1e308, a zero quaternion), "graph"
                                        (ros_discovery_info naming 1,000 nodes of hostile names), "burst" (10,000
                                        samples as fast as it can), "huge" (samples of 60 MiB back to back: one
                                        name of 60 MiB, serialized once, written raw as fast as Cyclone takes
                                        them), "participants" (ros_discovery_info announcing a new participant
                                        of 1,000 nodes in every sample, serialized once, written raw as fast as
                                        Cyclone takes them); run several for the rate of several writers
Each prints "ready" once its writers exist, then runs until killed.
"""

import json
import os
import sys
import time
from dataclasses import dataclass, field

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, bounded_str, float32, float64, int32, sequence, uint8, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration


@dataclass
class Time_(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32 = 0
    nanosec: uint32 = 0


@dataclass
class Header_(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time_ = field(default_factory=Time_)
    frame_id: str = ""


@dataclass
class Vector3_(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@dataclass
class Quaternion_(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0
    w: float64 = 1.0


@dataclass
class Transform_(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    translation: Vector3_ = field(default_factory=Vector3_)
    rotation: Quaternion_ = field(default_factory=Quaternion_)


@dataclass
class TransformStamped_(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    header: Header_ = field(default_factory=Header_)
    child_frame_id: str = ""
    transform: Transform_ = field(default_factory=Transform_)


@dataclass
class TFMessage_(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    transforms: sequence[TransformStamped_] = field(default_factory=list)


@dataclass
class Clock_(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    clock: Time_ = field(default_factory=Time_)


@dataclass
class LaserScan_(IdlStruct, typename="sensor_msgs::msg::dds_::LaserScan_"):
    header: Header_ = field(default_factory=Header_)
    angle_min: float32 = 0.0
    angle_max: float32 = 0.0
    angle_increment: float32 = 0.0
    time_increment: float32 = 0.0
    scan_time: float32 = 0.0
    range_min: float32 = 0.0
    range_max: float32 = 0.0
    ranges: sequence[float32] = field(default_factory=list)
    intensities: sequence[float32] = field(default_factory=list)


@dataclass
class String_(IdlStruct, typename="std_msgs::msg::dds_::String_"):
    data: str = ""


def gid_types(size):
    @dataclass
    class Gid_(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
        data: array[uint8, size] = field(default_factory=lambda: [0] * size)

    @dataclass
    class NodeEntitiesInfo_(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
        node_namespace: bounded_str[256] = "/"
        node_name: bounded_str[256] = ""
        reader_gid_seq: sequence[Gid_, 1024] = field(default_factory=list)
        writer_gid_seq: sequence[Gid_, 1024] = field(default_factory=list)

    @dataclass
    class ParticipantEntitiesInfo_(IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"):
        gid: Gid_ = field(default_factory=Gid_)
        node_entities_info_seq: sequence[NodeEntitiesInfo_, 1024] = field(default_factory=list)

    return Gid_, NodeEntitiesInfo_, ParticipantEntitiesInfo_


def qos(depth, reliable=True, transient_local=False):
    """rclcpp's QoS as rmw_cyclonedds sets it."""
    history = Policy.History.KeepLast(depth) if depth else Policy.History.KeepAll
    policies = [
        history,
        Policy.Reliability.Reliable(duration(infinite=True)) if reliable else Policy.Reliability.BestEffort,
        Policy.Durability.TransientLocal if transient_local else Policy.Durability.Volatile,
        Policy.DataRepresentation(use_cdrv0_representation=True),
        Policy.WriterDataLifecycle(autodispose=False),
    ]
    if transient_local:
        policies.append(Policy.DurabilityService(0, history, -1, -1, -1))
    return Qos(*policies)


def announce(dp, name, writers, size):
    """ros_discovery_info as rmw_dds_common's GraphCache publishes it."""
    gid, node, info = gid_types(size)

    def of(guid):
        return gid(list(guid.bytes.ljust(size, b"\0")))

    topic = Topic(dp, "ros_discovery_info", info)
    writer = DataWriter(dp, topic, qos=qos(1, transient_local=True))
    writer.write(info(of(dp.guid), [node("/", name, [], [of(w.guid) for w in writers])]))
    return writer


def dynamic(dp, name, parent, child, gid="16", hz="50", sim=None, loop=None):
    tf = DataWriter(dp, Topic(dp, "rt/tf", TFMessage_), qos=qos(100))
    clock = None
    if sim is not None:
        clock = DataWriter(dp, Topic(dp, "rt/clock", Clock_), qos=qos(1, reliable=False))
    keep = announce(dp, name, [tf, *([clock] if clock else [])], int(gid)) if int(gid) else None
    print("ready", flush=True)
    started = time.time_ns()
    while True:
        now = time.time_ns()
        if sim is not None:
            elapsed = now - started
            now = int(float(sim) * 1e9) + (elapsed % int(float(loop) * 1e9) if loop else elapsed)
            clock.write(Clock_(Time_(*divmod(now, 1_000_000_000))))
        stamp = Time_(*divmod(now, 1_000_000_000))
        x = 100 - abs(now % 200_000_000_000 - 100_000_000_000) / 1e9
        message = TransformStamped_(Header_(stamp, parent), child, Transform_(Vector3_(x, 0.5, 0.0)))
        tf.write(TFMessage_([message]))
        time.sleep(1 / float(hz))
    del keep


def kilohertz(dp, count="3000"):
    """A robot's /tf at 1 kHz, 100 transforms (root -> c0 ... c99) a sample: serialized once with a marker
    stamp that each sample replaces (Python's serializer is too slow for 1 kHz)."""
    import struct

    tf = DataWriter(dp, Topic(dp, "rt/tf", TFMessage_), qos=qos(100))
    keep = announce(dp, "kilohertz", [tf], 16)
    marker = Time_(0x7E57AB1E, 0x1D1D1D1D)
    template = bytearray(
        TFMessage_([TransformStamped_(Header_(marker, "root"), f"c{i}", Transform_()) for i in range(100)]).serialize()
    )
    packed = struct.pack("<iI", marker.sec, marker.nanosec)
    offsets = [i for i in range(len(template)) if template.startswith(packed, i)]
    while tf.get_publication_matched_status().current_count == 0:
        time.sleep(0.01)
    print("ready", flush=True)
    time.sleep(1.0)  # tfx's reader is matched; let it settle on our node's name
    start = due = time.perf_counter()
    for k in range(int(count)):
        while time.perf_counter() < due:
            pass
        # as rclcpp's wall timer, a period missed (this process descheduled) is skipped, not caught up in a burst
        # of back-to-back samples that a reader keeping tf2's last 100 would lose on a busy machine
        due = max(due + 1 / 1000, time.perf_counter())
        stamp = struct.pack("<iI", *divmod(1_000_000_000 + k * 1_000_000, 1_000_000_000))
        for offset in offsets:
            template[offset : offset + 8] = stamp
        write_raw(tf, bytes(template))
    print(f"done {count} in {time.perf_counter() - start:.2f} s", flush=True)
    while True:
        time.sleep(1)
    del keep


def scan(dp, topic, frame, hz="10"):
    writer = DataWriter(dp, Topic(dp, "rt/" + topic.strip("/"), LaserScan_), qos=qos(5, reliable=False))
    print("ready", flush=True)
    while True:
        stamp = Time_(*divmod(time.time_ns(), 1_000_000_000))
        writer.write(LaserScan_(Header_(stamp, frame), -1.0, 1.0, 0.5, range_max=10.0, ranges=[1.0, 2.0, 3.0]))
        time.sleep(1 / float(hz))


def wrong_type(dp, topic):
    writer = DataWriter(dp, Topic(dp, "rt/" + topic.strip("/"), String_), qos=qos(100))
    print("ready", flush=True)
    while True:
        writer.write(String_("not a transform"))
        time.sleep(0.1)


def volatile_static(dp):
    writer = DataWriter(dp, Topic(dp, "rt/tf_static", TFMessage_), qos=qos(1))
    print("ready", flush=True)
    while True:
        writer.write(TFMessage_([TransformStamped_(Header_(Time_(1, 0), "a"), "b")]))
        time.sleep(0.1)


def static_listener(dp):
    topic = Topic(dp, "rt/tf_static", TFMessage_)
    reader = DataReader(dp, topic, qos=qos(100, transient_local=True))
    publications = BuiltinDataReader(dp, BuiltinTopicDcpsPublication)
    print("ready", flush=True)
    samples = []
    deadline = time.monotonic() + 1.5
    while time.monotonic() < deadline:
        for sample in reader.take(10):
            samples.append(sample)
        time.sleep(0.02)
    writers = {}
    for endpoint in publications.take(100):
        if getattr(endpoint, "topic_name", None) == "rt/tf_static":
            q = endpoint.qos
            writers[str(endpoint.key)] = {
                "type": endpoint.type_name,
                "reliability": str(q[Policy.Reliability]),
                "durability": str(q[Policy.Durability]),
                "history": str(q[Policy.History]),
                "durability_service": str(q[Policy.DurabilityService]),
            }
    out = {
        "samples": [
            [
                {
                    "frame_id": t.header.frame_id,
                    "child_frame_id": t.child_frame_id,
                    "stamp": [t.header.stamp.sec, t.header.stamp.nanosec],
                    "translation": [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z],
                    "rotation": [
                        t.transform.rotation.x,
                        t.transform.rotation.y,
                        t.transform.rotation.z,
                        t.transform.rotation.w,
                    ],
                }
                for t in sample.transforms
            ]
            for sample in samples
        ],
        "writers": writers,
    }
    print(json.dumps(out), flush=True)


def discovery_listener(dp, size):
    _gid, _node, info = gid_types(int(size))
    reader = DataReader(dp, Topic(dp, "ros_discovery_info", info), qos=qos(0, transient_local=True))
    print("ready", flush=True)
    while True:
        for sample in reader.take(10):
            names = [f"{n.node_namespace.rstrip('/')}/{n.node_name}" for n in sample.node_entities_info_seq]
            print(json.dumps({"nodes": names}), flush=True)
        time.sleep(0.05)


def write_raw(writer, data):
    """``data`` (CDR, encapsulation header first) written as is: a peer at the rate of its network, not of
    Python's serializer."""
    from cyclonedds._clayer import ddspy_write

    while ddspy_write(writer._ref, data) < 0:  # a full writer cache (timed out): again
        time.sleep(0.001)


def hostile(dp, kind):
    tf = DataWriter(dp, Topic(dp, "rt/tf", TFMessage_), qos=qos(100))
    keep = announce(dp, "hostile", [tf], 16)
    if kind == "graph":
        gid, node, info = gid_types(16)
        topic = Topic(dp, "ros_discovery_info", info)
        junk = DataWriter(dp, topic, qos=qos(1, transient_local=True))
        nodes = [node("/\x1b[31m", f"n{i}\n\x07" + "x" * 200, [], []) for i in range(1000)]
        junk.write(info(gid(list(dp.guid.bytes)), nodes))
    if kind == "participants":
        gid, node, info = gid_types(16)
        flood = DataWriter(dp, Topic(dp, "ros_discovery_info", info), qos=qos(1, transient_local=True))
        writers = [gid(list(range(16))) for _ in range(10)]
        nodes = [node("/", f"n{i}_" + "x" * 200, [], writers) for i in range(1000)]
        sample = bytearray(info(gid([0] * 16), nodes).serialize())  # serialized once; each copy a new Gid
        print("ready", flush=True)
        for k in range(10**9):
            sample[4:20] = (k + (os.getpid() << 64)).to_bytes(16, "little")  # after the encapsulation header
            write_raw(flood, bytes(sample))
    if kind == "huge":
        stamp = Time_(*divmod(time.time_ns(), 1_000_000_000))
        huge = TFMessage_([TransformStamped_(Header_(stamp, "root"), "h" * (60 << 20), Transform_())]).serialize()
        print("ready", flush=True)
        while True:  # serialized once, written as fast as Cyclone takes it
            write_raw(tf, huge)
    print("ready", flush=True)

    def transform(parent, child, x=0.0, rotation=None):
        stamp = Time_(*divmod(time.time_ns(), 1_000_000_000))
        value = Transform_(Vector3_(x, 0.0, 0.0), rotation or Quaternion_())
        return TransformStamped_(Header_(stamp, parent), child, value)

    round_ = 0
    while True:
        round_ += 1
        if kind == "flood":
            message = [transform("root", f"r{round_}_{i}") for i in range(20_000)]
        elif kind == "longnames":  # names of 4 KiB, as long as tfx keeps, and of 1 MiB
            message = [transform("root", f"{round_}_{i}_".ljust(4096, "n")) for i in range(1000)]
            message.append(transform("root", f"{round_}_".ljust(1 << 20, "m")))
        elif kind == "names":
            message = [
                transform("root", "\x1b]0;title\x07\x1b[2J"),
                transform("root", "a\nb"),
                transform("root", "x" * 10_000),
                transform("root", ""),
            ]
        elif kind == "values":
            message = [
                transform("root", "nan", float("nan")),
                transform("root", "inf", float("inf")),
                transform("root", "big", 1e308),
                transform("root", "zero", 0.0, Quaternion_(0, 0, 0, 0)),
                transform("root", "fine", 1.0),
            ]
        else:
            message = [transform("root", "base", 1.0)]
        if kind == "burst":
            for _ in range(10_000):
                tf.write(TFMessage_(message))
        else:
            tf.write(TFMessage_(message))
        time.sleep(0.1)
    del keep


def main():
    domain = int(os.environ.get("ROS_DOMAIN_ID", "0"))
    dp = DomainParticipant(domain, qos=Qos(Policy.Userdata(b"enclave=/;")))
    mode, *arguments = sys.argv[1:]
    options = {}
    positional = []
    while arguments:
        word = arguments.pop(0)
        if word.startswith("--"):
            options[word[2:]] = arguments.pop(0)
        else:
            positional.append(word)
    {
        "dynamic": dynamic,
        "scan": scan,
        "wrong_type": wrong_type,
        "volatile_static": volatile_static,
        "static_listener": static_listener,
        "discovery_listener": discovery_listener,
        "hostile": hostile,
        "kilohertz": kilohertz,
    }[mode](dp, *positional, **options)


if __name__ == "__main__":
    main()
