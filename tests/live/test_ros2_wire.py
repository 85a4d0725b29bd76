"""ROS 2's wire conventions as tftools speaks them, against ROS 2's own definitions: rosbags'
typestores (generated from each distribution's interface files) for type layouts and CDR bytes;
tf2_ros's qos.hpp and rmw_cyclonedds's rmw_node.cpp (quoted) for QoS and discovery settings.
No ROS 2 is installed: these are the authorities available offline."""

from __future__ import annotations

import dataclasses
import math
import random
import re
import threading
from types import ModuleType
from typing import Any, cast
from xml.etree import ElementTree

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_typestore
from rosbags.typesys.store import Typestore

from tests.live.ros2_processes import require_cyclonedds
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.codecs import cdr
from tftools.sources.codecs.decoded import message_clock
from tftools.sources.live.errors import DomainIdError
from tftools.sources.live.received import Received, decode_received
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.conventions import QosProfile
from tftools.sources.live.ros2.entities import decode_participant_entities

#: Distributions and their rmw_dds_common Gid size (24 through Humble, 16 since Iron).
STORES = {"humble": (Stores.ROS2_HUMBLE, 24), "jazzy": (Stores.ROS2_JAZZY, 16)}
TF = "tf2_msgs/msg/TFMessage"
CLOCK = "rosgraph_msgs/msg/Clock"
PARTICIPANT_INFO = "rmw_dds_common/msg/ParticipantEntitiesInfo"


def store(distro: str) -> Typestore:
    return get_typestore(STORES[distro][0])


def nested(typestore: Typestore, name: str) -> list[str]:
    """``name`` and every message type inside it, depth first."""
    found = [name]
    for _field, (kind, detail) in typestore.fielddefs[name][1]:
        inner = detail[0] if kind in (Nodetype.ARRAY, Nodetype.SEQUENCE) else (kind, detail)
        if inner[0] == Nodetype.NAME:
            found += [n for n in nested(typestore, cast(str, inner[1])) if n not in found]  # a NAME's detail: the name
    return found


# --- names --------------------------------------------------------------------------------------


def test_topic_names_have_ros2s_rt_prefix() -> None:
    assert [ros2.dds_topic(t) for t in ("/tf", "/tf_static", "/clock")] == ["rt/tf", "rt/tf_static", "rt/clock"]
    assert ros2.dds_topic("/robot1/tf") == "rt/robot1/tf"
    assert ros2.DISCOVERY_TOPIC == "ros_discovery_info"  # rmw_node.cpp: avoid_ros_namespace_conventions


@pytest.mark.parametrize("distro", STORES)
def test_type_names_are_those_of_every_type_inside_tfmessage_and_clock(distro: str) -> None:
    typestore = store(distro)
    assert [ros2.dds_type(n) for n in nested(typestore, TF)] == [
        ros2.TF_MESSAGE,
        "geometry_msgs::msg::dds_::TransformStamped_",
        "std_msgs::msg::dds_::Header_",
        "builtin_interfaces::msg::dds_::Time_",
        "geometry_msgs::msg::dds_::Transform_",
        "geometry_msgs::msg::dds_::Vector3_",
        "geometry_msgs::msg::dds_::Quaternion_",
    ]
    assert [ros2.dds_type(n) for n in nested(typestore, CLOCK)] == [ros2.CLOCK, "builtin_interfaces::msg::dds_::Time_"]
    assert [ros2.dds_type(n) for n in nested(typestore, PARTICIPANT_INFO)] == [
        ros2.PARTICIPANT_ENTITIES_INFO,
        ros2.GID,
        ros2.NODE_ENTITIES_INFO,
    ]
    assert ros2.TF_MESSAGE == "tf2_msgs::msg::dds_::TFMessage_"  # as the issue spells them
    assert ros2.CLOCK == "rosgraph_msgs::msg::dds_::Clock_"
    assert all(ros2.ros_type(ros2.dds_type(n)) == n for n in nested(typestore, TF))


@pytest.mark.parametrize("distro", STORES)
def test_gid_sizes_are_those_of_rmw_dds_common(distro: str) -> None:
    gid: Any = store(distro).fielddefs["rmw_dds_common/msg/Gid"][1][0][1]  # an ARRAY: (kind, ((element, _), size))
    (_kind, ((_element, _), size)) = gid
    assert size == STORES[distro][1] and size in ros2.GID_SIZES


# --- CDR as ROS 2 serializes it -----------------------------------------------------------------

frame = st.text(st.characters(codec="utf-8", exclude_characters="\0"), max_size=9)
number = st.floats(allow_nan=False, allow_infinity=False, width=64)
transform = st.builds(
    Transform,
    st.tuples(number, number, number),
    st.tuples(number, number, number, number),
    st.integers(-(2**31) * NS_PER_S, (2**31 - 1) * NS_PER_S + NS_PER_S - 1),
    frame,
    frame,
)


def rosbags_tf_message(typestore: Typestore, transforms: list[Transform]) -> Any:
    types = typestore.types
    return types[TF](
        transforms=[
            types["geometry_msgs/msg/TransformStamped"](
                header=types["std_msgs/msg/Header"](
                    stamp=types["builtin_interfaces/msg/Time"](*divmod(t.stamp, NS_PER_S)), frame_id=t.frame_id
                ),
                child_frame_id=t.child_frame_id,
                transform=types["geometry_msgs/msg/Transform"](
                    translation=types["geometry_msgs/msg/Vector3"](*t.translation),
                    rotation=types["geometry_msgs/msg/Quaternion"](*t.rotation),
                ),
            )
            for t in transforms
        ]
    )


@settings(max_examples=60, deadline=None)
@given(st.lists(transform, max_size=6), st.booleans(), st.sampled_from(sorted(STORES)))
def test_tfmessages_serialized_by_ros2_decode_exactly(transforms: list[Transform], little: bool, distro: str) -> None:
    typestore = store(distro)
    data = bytes(typestore.serialize_cdr(rosbags_tf_message(typestore, transforms), TF, little_endian=little))
    batch = decode_received(cdr.decode_tf, [Received("/tf_static", data, "/node", 7)]).batch
    assert len(batch) == len(transforms)
    names = list(batch.frame_names)
    assert [(names[p], names[c]) for p, c in zip(batch.parent, batch.child, strict=True)] == [
        (t.frame_id, t.child_frame_id) for t in transforms
    ]
    assert batch.stamp.tolist() == [t.stamp for t in transforms]
    assert batch.translation.tolist() == [list(t.translation) for t in transforms]
    assert batch.rotation.tolist() == [list(t.rotation) for t in transforms]
    assert batch.static.all() and (batch.record_time == 7).all()
    assert list(batch.authorities) == (["/node"] if transforms else [])  # a message of no transform names none


def test_clock_serialized_by_ros2_decodes() -> None:
    typestore = store("jazzy")
    time = typestore.types["builtin_interfaces/msg/Time"](sec=1234, nanosec=567)
    for little in (True, False):
        data = bytes(typestore.serialize_cdr(typestore.types[CLOCK](clock=time), CLOCK, little_endian=little))
        assert message_clock(cdr.decode_clocks, data) == 1234 * NS_PER_S + 567


def rosbags_participant_info(
    typestore: Typestore, gid_size: int, participant: bytes, nodes: list[tuple[str, str, list[bytes]]]
) -> Any:
    types = typestore.types

    def gid(guid: bytes) -> Any:
        return types["rmw_dds_common/msg/Gid"](data=np.frombuffer(guid.ljust(gid_size, b"\0"), np.uint8))

    return types[PARTICIPANT_INFO](
        gid=gid(participant),
        node_entities_info_seq=[
            types["rmw_dds_common/msg/NodeEntitiesInfo"](
                node_namespace=namespace,
                node_name=name,
                reader_gid_seq=[gid(b"r" * 16)],
                writer_gid_seq=[gid(w) for w in writers],
            )
            for namespace, name, writers in nodes
        ],
    )


@pytest.mark.parametrize("distro", STORES)
@pytest.mark.parametrize("node_count", [0, 1, 3])
def test_ros_discovery_info_of_either_gid_size_decodes(distro: str, node_count: int) -> None:
    typestore, gid_size = store(distro), STORES[distro][1]
    rng = random.Random(node_count)

    def guid() -> bytes:
        return bytes(rng.randrange(256) for _ in range(16))

    participant = guid()
    nodes = [("/" if i % 2 else "/ns", f"node{i}", [guid() for _ in range(i + 1)]) for i in range(node_count)]
    info = rosbags_participant_info(typestore, gid_size, participant, nodes)
    decoded = decode_participant_entities(bytes(typestore.serialize_cdr(info, PARTICIPANT_INFO)))
    assert decoded.gid_size == gid_size and decoded.participant == participant
    assert [(n.full_name, n.writers) for n in decoded.nodes] == [
        (f"{ns.rstrip('/')}/{name}", tuple(writers)) for ns, name, writers in nodes
    ]


def test_what_is_not_a_message_is_refused() -> None:
    typestore = store("jazzy")
    good = bytes(typestore.serialize_cdr(rosbags_tf_message(typestore, [Transform.identity(0, "a", "b")]), TF))
    refused = {
        good[:-9]: f"message ends at byte {len(good) - 9}, a field needs {len(good)}",
        good[:10]: "1 transform cannot fit in 10 bytes",
        b"": "not a CDR payload",
        b"\x00\x09" + good[2:]: "not a CDR payload",
        good[:4] + b"\xff\xff\xff\x7f" + good[8:]: "2147483647 transforms cannot fit",
    }
    for bad, reason in refused.items():
        ((_, said),) = decode_received(cdr.decode_tf, [Received("/tf", bad, "", 0)]).unreadable
        assert re.search(reason, said)
    with pytest.raises(ValueError, match="not a ParticipantEntitiesInfo"):
        decode_participant_entities(good)


# --- QoS, domain, discovery ---------------------------------------------------------------------


def test_qos_is_tf2_ros_s() -> None:
    # tf2_ros/qos.hpp: DynamicListenerQoS(depth = 100) : rclcpp::QoS(depth) (reliable, volatile);
    # StaticListenerQoS(depth = 100) and StaticBroadcasterQoS(depth = 1) add transient_local().
    assert QosProfile(depth=100, reliable=True, transient_local=False) == ros2.TF_QOS
    assert ros2.listener_qos("/tf") == ros2.TF_QOS
    assert ros2.listener_qos("/tf_static") == QosProfile(depth=100, reliable=True, transient_local=True)
    assert QosProfile(depth=1, reliable=True, transient_local=True) == ros2.TF_STATIC_BROADCASTER_QOS
    # rclcpp::ClockQoS: KeepLast(1), best_effort(); rmw_node.cpp: ros_discovery_info written
    # reliable, transient local, keep last 1, read keep all (tfx: keep last 64, a flood held gigabytes).
    assert QosProfile(depth=1, reliable=False, transient_local=False) == ros2.CLOCK_QOS
    assert QosProfile(depth=1, reliable=True, transient_local=True) == ros2.DISCOVERY_WRITER_QOS
    assert QosProfile(depth=64, reliable=True, transient_local=True) == ros2.DISCOVERY_READER_QOS


def test_domain_id_is_read_as_rcl_reads_it() -> None:
    assert ros2.domain_id({}) == 0 and ros2.domain_id({"ROS_DOMAIN_ID": " "}) == 0
    assert ros2.domain_id({"ROS_DOMAIN_ID": "42"}) == 42 and ros2.domain_id({"ROS_DOMAIN_ID": "232"}) == 232
    for bad in ("233", "-1", "one", "4.2"):
        with pytest.raises(DomainIdError, match=f"ROS_DOMAIN_ID='{bad}' is not a ROS 2 domain id"):
            ros2.domain_id({"ROS_DOMAIN_ID": bad})


def test_discovery_settings_become_cyclone_configuration_as_in_rmw_cyclonedds() -> None:
    subnet = ros2.discovery_config({})
    assert "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32<" in subnet
    assert "AllowMulticast" not in subnet and "<Peers>" not in subnet
    local = ros2.discovery_config({"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_STATIC_PEERS": "10.0.0.2; b"})
    assert "<AllowMulticast>false</AllowMulticast>" in local
    assert '<Peers><Peer address="localhost"/><Peer address="10.0.0.2"/><Peer address="b"/></Peers>' in local
    hostile = ros2.discovery_config({"ROS_STATIC_PEERS": "a\"<&'b"}).split(",")[1]
    peer = ElementTree.fromstring(hostile).find(".//Peer")
    assert peer is not None and peer.get("address") == "a\"<&'b"
    assert ros2.discovery_config({"ROS_LOCALHOST_ONLY": "1"}) == ros2.discovery_config(
        {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}
    )
    off = ros2.discovery_config({"ROS_AUTOMATIC_DISCOVERY_RANGE": "OFF", "ROS_STATIC_PEERS": "x"})
    assert "<Tag>ros_discovery_off_" in off and "<Peers>" not in off
    user = "file:///etc/cyclone.xml"
    system = ros2.discovery_config({"ROS_AUTOMATIC_DISCOVERY_RANGE": "SYSTEM_DEFAULT", "CYCLONEDDS_URI": user})
    assert system.endswith("</CycloneDDS>," + user) and "Discovery" not in system
    for config in (subnet, local, off, system):  # a peer's sample is not reassembled past 64 MiB
        assert f"<MaxSampleSize>{64 << 20}B</MaxSampleSize>" in config
    assert ros2.discovery_config({"CYCLONEDDS_URI": user}).endswith("</CycloneDDS>," + user)


# --- with Cyclone DDS ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def idl() -> ModuleType:
    require_cyclonedds()
    from tftools.sources.live.ros2 import idl

    return idl


def idl_struct_layout(cls: type) -> list[tuple[str, str]]:
    return [(f.name, str(f.type)) for f in dataclasses.fields(cls)]


@pytest.mark.parametrize("distro", STORES)
def test_idl_structs_are_ros2s_types(idl: ModuleType, distro: str) -> None:
    typestore, gid_size = store(distro), STORES[distro][1]
    info = idl.participant_entities_info(gid_size)
    structs = [info, info.Gid, info.NodeEntitiesInfo]
    structs += [idl.ros2_struct(name) for name in [*nested(typestore, TF), *nested(typestore, CLOCK)]]
    by_dds_name = {s.__idl_typename__.replace(".", "::"): s for s in structs}
    for name in [*nested(typestore, TF), *nested(typestore, CLOCK), *nested(typestore, PARTICIPANT_INFO)]:
        struct = by_dds_name[ros2.dds_type(name)]
        assert [f.name for f in dataclasses.fields(struct)] == [f for f, _ in typestore.fielddefs[name][1]], name
        struct.__idl__.populate()
        assert struct.__idl__.keyless, f"{name}: rmw_cyclonedds registers every type without a key"


@settings(max_examples=40, deadline=None)
@given(st.lists(transform, max_size=5))
def test_tftools_writes_the_bytes_ros2_writes(idl: ModuleType, transforms: list[Transform]) -> None:
    """What the broadcaster writes (``cdr.encode_tf_message``) is what the type it registers serializes."""
    written = cdr.encode_tf_message(transforms)
    sample = idl.ros2_struct(TF).deserialize(written)
    assert sample.serialize(use_version_2=False) == written
    assert written[:2] == b"\x00\x01"  # plain CDR, little endian: XCDR1
    for distro in STORES:
        typestore = store(distro)
        assert written == bytes(typestore.serialize_cdr(rosbags_tf_message(typestore, transforms), TF))


@pytest.mark.parametrize("distro", STORES)
def test_node_announcements_are_the_bytes_rmw_dds_common_writes(idl: ModuleType, distro: str) -> None:
    typestore, gid_size = store(distro), STORES[distro][1]
    participant, writers = b"P" * 16, [b"W" * 16, b"X" * 16]
    ours = idl.announcement(gid_size, participant, "/", "tfx_static", writers).serialize()
    theirs = rosbags_participant_info(typestore, gid_size, participant, [("/", "tfx_static", writers)])
    theirs.node_entities_info_seq[0].reader_gid_seq = []
    assert ours == bytes(typestore.serialize_cdr(theirs, PARTICIPANT_INFO))


def test_cyclone_qos_is_rmw_cyclonedds_s(idl: ModuleType) -> None:
    from cyclonedds.core import Policy

    from tftools.sources.live.ros2.dds import qos

    static = qos(ros2.TF_STATIC_BROADCASTER_QOS, writer=True)
    infinite = 0x7FFFFFFFFFFFFFFF
    assert static[Policy.Reliability] == Policy.Reliability.Reliable(infinite)
    assert static[Policy.Durability] == Policy.Durability.TransientLocal
    assert static[Policy.History] == Policy.History.KeepLast(1)
    # "Cyclone uses durability service QoS for determining what to retain as historical data"
    assert static[Policy.DurabilityService] == Policy.DurabilityService(0, Policy.History.KeepLast(1), -1, -1, -1)
    assert static[Policy.WriterDataLifecycle] == Policy.WriterDataLifecycle(autodispose=False)
    assert static[Policy.DataRepresentation] == Policy.DataRepresentation(use_cdrv0_representation=True)
    listener = qos(ros2.TF_QOS)
    assert listener[Policy.Durability] == Policy.Durability.Volatile
    assert listener[Policy.History] == Policy.History.KeepLast(100)
    assert listener[Policy.WriterDataLifecycle] is None and listener[Policy.DurabilityService] is None
    assert qos(ros2.CLOCK_QOS)[Policy.Reliability] == Policy.Reliability.BestEffort
    assert qos(ros2.DISCOVERY_READER_QOS)[Policy.History] == Policy.History.KeepLast(64)


@pytest.mark.parametrize("scope", ["SUBNET", "LOCALHOST", "OFF", "SYSTEM_DEFAULT"])
def test_cyclone_accepts_each_discovery_configuration(
    idl: ModuleType, scope: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tftools.sources.live.ros2.dds import Participant

    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", scope)
    monkeypatch.setenv("ROS_STATIC_PEERS", "127.0.0.1")
    participant = Participant(random.randrange(100, 200))
    try:
        assert len(participant.guid) == 16
    finally:
        participant.close()


def test_transforms_round_trip_through_tftools_types(idl: ModuleType) -> None:
    transforms = [Transform.from_rpy((1.0, -2.0, 3.5), (0.1, 0.2, math.pi / 2), 5 * NS_PER_S + 7, "map", "odom")]
    data = idl.ros2_struct(TF).deserialize(cdr.encode_tf_message(transforms)).serialize()
    batch = decode_received(cdr.decode_tf, [Received("/tf", data, "a", 1)]).batch
    assert batch.translation.tolist() == [list(transforms[0].translation)]
    assert batch.rotation.tolist() == [list(transforms[0].rotation)]
    assert batch.stamp.tolist() == [transforms[0].stamp]


def test_a_failing_step_is_said_and_the_waiter_goes_on(idl: ModuleType, monkeypatch: pytest.MonkeyPatch) -> None:
    from tftools.sources.live.ros2.dds import Participant, Waiter

    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")
    participant = Participant(random.randrange(100, 200))
    waiter = Waiter(participant)
    notices: list[str] = []
    calls = threading.Semaphore(0)

    def step() -> float:
        calls.release()
        raise KeyError("boom")

    try:
        waiter.start(step, "test-waiter", notices.append, "test samples")
        assert calls.acquire(timeout=5) and calls.acquire(timeout=5)  # called again after failing
    finally:
        waiter.stop()
        participant.close()
    assert notices[0] == "dropped test samples: KeyError: 'boom'"
