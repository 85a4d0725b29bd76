"""The ROS 2 message types tftools writes, as Cyclone DDS IDL structs with ROS 2's DDS type names: keyless
and final, as rmw_cyclonedds registers every ROS type (serdata.cpp create_sertype), so they match by name."""

# mypy: disable-error-code="type-arg, assignment, arg-type, valid-type, attr-defined"
# (Cyclone DDS's IDL annotations are not types mypy knows.)
# No `from __future__ import annotations`: Cyclone DDS reads these annotations as types at run time.

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, bounded_str, float64, int32, sequence, uint8, uint32

from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.live.ros2 import conventions as ros2


@dataclass
class Time(IdlStruct, typename=ros2.TIME):
    sec: int32 = 0
    nanosec: uint32 = 0


@dataclass
class Header(IdlStruct, typename=ros2.HEADER):
    stamp: Time = field(default_factory=Time)
    frame_id: str = ""


@dataclass
class Vector3(IdlStruct, typename=ros2.VECTOR3):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0


@dataclass
class Quaternion(IdlStruct, typename=ros2.QUATERNION):
    x: float64 = 0.0
    y: float64 = 0.0
    z: float64 = 0.0
    w: float64 = 1.0


@dataclass
class TransformMsg(IdlStruct, typename=ros2.TRANSFORM):
    translation: Vector3 = field(default_factory=Vector3)
    rotation: Quaternion = field(default_factory=Quaternion)


@dataclass
class TransformStamped(IdlStruct, typename=ros2.TRANSFORM_STAMPED):
    header: Header = field(default_factory=Header)
    child_frame_id: str = ""
    transform: TransformMsg = field(default_factory=TransformMsg)

    @classmethod
    def of(cls, t: Transform) -> "TransformStamped":
        return cls(
            Header(Time(*divmod(t.stamp, NS_PER_S)), t.frame_id),
            t.child_frame_id,
            TransformMsg(Vector3(*t.translation), Quaternion(*t.rotation)),
        )


@dataclass
class TFMessage(IdlStruct, typename=ros2.TF_MESSAGE):
    transforms: sequence[TransformStamped] = field(default_factory=list)

    @classmethod
    def of(cls, transforms: Sequence[Transform]) -> "TFMessage":
        return cls([TransformStamped.of(t) for t in transforms])


@dataclass
class Clock(IdlStruct, typename=ros2.CLOCK):
    clock: Time = field(default_factory=Time)


@functools.cache
def participant_entities_info(gid_size: int) -> type[Any]:
    """``rmw_dds_common/msg/ParticipantEntitiesInfo`` with ``gid_size``-byte Gids (16 since Iron, 24
    before): rmw_dds_common's IDL, keys dropped as rmw_cyclonedds drops them."""

    @dataclass
    class Gid(IdlStruct, typename=ros2.GID):
        data: array[uint8, gid_size] = field(default_factory=lambda: [0] * gid_size)

    @dataclass
    class NodeEntitiesInfo(IdlStruct, typename=ros2.NODE_ENTITIES_INFO):
        node_namespace: bounded_str[256] = "/"
        node_name: bounded_str[256] = ""
        reader_gid_seq: sequence[Gid, 1024] = field(default_factory=list)
        writer_gid_seq: sequence[Gid, 1024] = field(default_factory=list)

    @dataclass
    class ParticipantEntitiesInfo(IdlStruct, typename=ros2.PARTICIPANT_ENTITIES_INFO):
        gid: Gid = field(default_factory=Gid)
        node_entities_info_seq: sequence[NodeEntitiesInfo, 1024] = field(default_factory=list)

    ParticipantEntitiesInfo.Gid = Gid
    ParticipantEntitiesInfo.NodeEntitiesInfo = NodeEntitiesInfo
    return ParticipantEntitiesInfo


def announcement(gid_size: int, participant: bytes, namespace: str, name: str, writers: Sequence[bytes]) -> Any:
    """What a participant with one node ``namespace``/``name`` owning ``writers`` (DDS GUIDs) says on
    ``ros_discovery_info``: rmw_cyclonedds's gid is the GUID, zero-padded to the Gid size."""
    info = participant_entities_info(gid_size)

    def gid(guid: bytes) -> Any:
        return info.Gid(list(guid.ljust(gid_size, b"\0")))

    node = info.NodeEntitiesInfo(namespace, name, [], [gid(w) for w in writers])
    return info(gid(participant), [node])
