"""ROS 2's conventions on the DDS wire: topic and type names, tf2_ros's QoS, domain and discovery;
plain data, usable (and tested) without Cyclone DDS installed."""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

from tftools.sources.contents import is_static_topic
from tftools.sources.live.errors import DomainIdError

# ROS 2 topic "/tf" is DDS topic "rt/tf": the "rt" prefix marks ROS topics (design.ros2.org,
# "Topic and Service name mapping to DDS"; rmw_cyclonedds namespace_prefix.hpp ROS_TOPIC_PREFIX).
TOPIC_PREFIX = "rt"

# rosidl type "pkg/msg/Name" is DDS type "pkg::msg::dds_::Name_" (rmw_cyclonedds serdata.cpp
# create_type_name, ``dds_type``): the types tftools listens to, and those it writes by hand.
TF_MESSAGE = "tf2_msgs::msg::dds_::TFMessage_"
CLOCK = "rosgraph_msgs::msg::dds_::Clock_"
GID = "rmw_dds_common::msg::dds_::Gid_"
NODE_ENTITIES_INFO = "rmw_dds_common::msg::dds_::NodeEntitiesInfo_"
PARTICIPANT_ENTITIES_INFO = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"

CLOCK_TOPIC = "/clock"

#: Where every rmw announces its participant's nodes and their readers and writers (rmw_dds_common;
#: design.ros2.org "Node to Participant mapping"). Not a ROS topic: no "rt/" prefix.
DISCOVERY_TOPIC = "ros_discovery_info"

#: rmw_dds_common's Gid: 24 bytes up to Humble (rmw_dds_common 1.x), 16 since Iron (2.0, "Change
#: Gid.msg to be 16 bytes"); rmw_cyclonedds fills the first 16 with the entity's DDS GUID.
GID_SIZES = (16, 24)
GUID_SIZE = 16

#: ROS_DOMAIN_ID's range: Cyclone maps domain d to UDP port 7400 + 250 d, which must stay below 65536.
MAX_DOMAIN_ID = 232


def dds_topic(ros_topic: str) -> str:
    """The DDS topic of a ROS 2 topic: ``/tf`` -> ``rt/tf``."""
    return f"{TOPIC_PREFIX}/{ros_topic.strip('/')}"


def dds_type(ros_type: str) -> str:
    """The DDS type name of a rosidl type: ``tf2_msgs/msg/TFMessage`` -> ``tf2_msgs::msg::dds_::TFMessage_``."""
    *namespace, name = ros_type.split("/")
    return "::".join([*namespace, "dds_", f"{name}_"])


def ros_type(dds_type_name: str) -> str:
    """Back from a DDS type name to the rosidl one, for messages: ``tf2_msgs/msg/TFMessage``."""
    *namespace, name = dds_type_name.split("::")
    if len(namespace) < 2 or namespace[-1] != "dds_" or not name.endswith("_"):
        return dds_type_name
    return "/".join([*namespace[:-1], name[:-1]])


@dataclass(frozen=True)
class QosProfile:
    """The QoS policies rclcpp sets, as rmw_cyclonedds maps them (create_readwrite_qos): keep last
    ``depth`` (keep all when 0), reliable or best effort, transient local or volatile; a transient
    local writer keeps its history as Cyclone's durability service (same kind and depth)."""

    depth: int
    reliable: bool = True
    transient_local: bool = False

    @property
    def keep_all(self) -> bool:
        return self.depth == 0


# tf2_ros/qos.hpp: DynamicListenerQoS and DynamicBroadcasterQoS are rclcpp::QoS(100), i.e.
# reliable, volatile, keep last 100; StaticListenerQoS(100) and StaticBroadcasterQoS(1) are
# transient local, so a late joiner gets the broadcaster's one latest message.
TF_QOS = QosProfile(depth=100)
TF_STATIC_LISTENER_QOS = QosProfile(depth=100, transient_local=True)
TF_STATIC_BROADCASTER_QOS = QosProfile(depth=1, transient_local=True)

# rclcpp::ClockQoS, which TimeSource subscribes /clock with: best effort, keep last 1 (it hears
# reliable writers too, e.g. `ros2 bag play --clock`).
CLOCK_QOS = QosProfile(depth=1, reliable=False)

# Sensor topics, read as a diagnostic tool reads them: best effort and volatile, so every writer
# matches (reliable or not, transient local or not); keep last 100, as rclcpp's default depth
# does not lose a burst (rclcpp::SensorDataQoS keeps 5).
SENSOR_QOS = QosProfile(depth=100, reliable=False)

# rmw_cyclonedds rmw_node.cpp: ros_discovery_info is written reliable, transient local, keep last
# 1, and read keep all. tfx reads it keep last DISCOVERY_DEPTH: the topic is keyless, so keep all held
# every sample of a flood of new participants that tfx had not yet taken (1.1 GB in 8 s from 6 peers);
# a burst larger than that between two takes loses the oldest announcements (their writers go unnamed).
DISCOVERY_DEPTH = 64
DISCOVERY_WRITER_QOS = QosProfile(depth=1, transient_local=True)
DISCOVERY_READER_QOS = QosProfile(depth=DISCOVERY_DEPTH, transient_local=True)


def listener_qos(ros_topic: str) -> QosProfile:
    """How tf2_ros's TransformListener subscribes ``ros_topic``."""
    return TF_STATIC_LISTENER_QOS if is_static_topic(ros_topic) else TF_QOS


def domain_id(environ: Mapping[str, str] | None = None) -> int:
    """``ROS_DOMAIN_ID`` (0 when unset or empty, as rcl does); ``DomainIdError`` when not a domain id."""
    value = (os.environ if environ is None else environ).get("ROS_DOMAIN_ID", "").strip()
    if not value:
        return 0
    if not value.isdigit() or int(value) > MAX_DOMAIN_ID:
        raise DomainIdError(value)
    return int(value)


#: The largest sample (serialized) Cyclone takes from a peer; larger ones it drops with a warning
#: instead of reassembling them in memory (its default allows 2 GiB). As TCPROS's ``MAX_MESSAGE``.
MAX_SAMPLE_SIZE = 64 << 20

#: The largest /tf or /tf_static sample decoded: 100,000 transforms take 8.5 MB; a larger one is dropped, said
#: once (a peer sending 60 MiB samples back to back is not sending transforms).
MAX_TF_SAMPLE = 16 << 20
#: Participants whose ros_discovery_info announcement is kept (to name their writers' nodes): beyond, the
#: oldest is forgotten, said once (a flood of new participants held gigabytes).
MAX_PARTICIPANTS = 1024

#: Samples of one reliable writer Cyclone reassembles from their fragments at once (its default 16; 4 for a best
#: effort one, as here), each up to ``MAX_SAMPLE_SIZE``: 3 writers of 60 MiB samples back to back held 1,038 MB in
#: tfx echo --ros2 with 16, 656 MB with 4 (with 2 no sample of theirs was ever whole). A writer's samples arrive
#: in order: one or two are reassembled at a time but where fragments are lost and sent again.
DEFRAG_SAMPLES = 4

_LIMITS = (
    f"<CycloneDDS><Domain><Internal><MaxSampleSize>{MAX_SAMPLE_SIZE}B</MaxSampleSize>"
    f"<DefragReliableMaxSamples>{DEFRAG_SAMPLES}</DefragReliableMaxSamples></Internal></Domain></CycloneDDS>,"
)


def discovery_config(environ: Mapping[str, str] | None = None) -> str:
    """Cyclone DDS configuration for ROS 2's discovery settings, then ``CYCLONEDDS_URI`` (whose last word
    wins), as rmw_cyclonedds builds it (rmw_node.cpp check_create_domain): ``ROS_AUTOMATIC_DISCOVERY_RANGE``
    SUBNET (the default), LOCALHOST (no multicast, localhost a peer), OFF or SYSTEM_DEFAULT (Cyclone's
    own); ``ROS_LOCALHOST_ONLY=1`` (Humble's) means LOCALHOST; ``ROS_STATIC_PEERS``, hosts separated by
    ``;``, are peers for SUBNET and LOCALHOST. Always: samples up to ``MAX_SAMPLE_SIZE``, ``DEFRAG_SAMPLES``
    reassembled at once per writer."""
    env = os.environ if environ is None else environ
    scope = env.get("ROS_AUTOMATIC_DISCOVERY_RANGE", "").strip().upper()
    if not scope:
        scope = "LOCALHOST" if env.get("ROS_LOCALHOST_ONLY", "").strip() == "1" else "SUBNET"
    user = env.get("CYCLONEDDS_URI", "")
    if scope == "SYSTEM_DEFAULT":
        return _LIMITS + user
    peers = [p.strip() for p in env.get("ROS_STATIC_PEERS", "").split(";") if p.strip()]
    if scope == "LOCALHOST":
        peers.insert(0, "localhost")
    elif scope == "OFF":
        peers = []
    parts = [_LIMITS, "<CycloneDDS><Domain>"]
    if scope in ("LOCALHOST", "OFF"):
        parts.append("<General><AllowMulticast>false</AllowMulticast></General>")
    if scope == "OFF":  # a tag no one else has: nothing is discovered
        parts.append(f"<Discovery><ParticipantIndex>none</ParticipantIndex><Tag>ros_discovery_off_{os.getpid()}</Tag>")
    else:
        parts.append(
            "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>"
        )
    if peers:
        parts.append("<Peers>" + "".join(f"<Peer address={quoteattr(p)}/>" for p in peers) + "</Peers>")
    parts.append("</Discovery></Domain></CycloneDDS>,")
    return "".join(parts) + user
