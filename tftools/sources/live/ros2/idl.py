"""The ROS 2 message types tftools reads and writes, as Cyclone DDS IDL structs with ROS 2's DDS type
names: keyless and final, as rmw_cyclonedds registers every ROS type (serdata.cpp create_sertype), so they
match by name. A type ROS 2 defines is built from rosbags' type stores (``ros2_struct``); rmw_dds_common's
ParticipantEntitiesInfo, whose Gid size differs between distributions, is written out here."""

# mypy: disable-error-code="type-arg, assignment, arg-type, valid-type, attr-defined, misc"
# (Cyclone DDS's IDL annotations are not types mypy knows.)
# No `from __future__ import annotations`: Cyclone DDS reads these annotations as types at run time.

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.idl import IdlStruct, make_idl_struct
from cyclonedds.idl import types as idl

from tftools.sources.codecs.types import ROS2_STORES, typestore
from tftools.sources.live.ros2 import conventions as ros2

#: rosidl's primitive types as Cyclone DDS's Python IDL spells them (rosidl maps char to uint8).
_PRIMITIVES: dict[str, Any] = {
    "bool": bool,
    "byte": idl.byte,
    "char": idl.uint8,
    "int8": idl.int8,
    "uint8": idl.uint8,
    "int16": idl.int16,
    "uint16": idl.uint16,
    "int32": idl.int32,
    "uint32": idl.uint32,
    "int64": idl.int64,
    "uint64": idl.uint64,
    "float32": idl.float32,
    "float64": idl.float64,
    "string": str,
    "wstring": str,
}


def ros2_definitions() -> list[dict[str, Any]]:
    """rosbags' ROS 2 message definitions (``fielddefs``), one per type store of ``ROS2_STORES``."""
    return [typestore(name).fielddefs for name in ROS2_STORES]


@functools.cache
def ros2_struct(rosidl: str, store: int = 0) -> type[IdlStruct]:
    """``rosidl`` (e.g. ``tf2_msgs/msg/TFMessage``) as the ``store``-th of ``ros2_definitions`` defines it,
    its nested types built once."""
    _constants, fields = ros2_definitions()[store][rosidl]
    members = {name: _member(kind, store) for name, kind in fields}
    return make_idl_struct(rosidl.rsplit("/", 1)[-1], ros2.dds_type(rosidl), members)


def _member(kind: tuple[Any, Any], store: int) -> Any:
    """A field's IDL type from rosbags' (node type, detail): 1 a primitive (name, string bound), 2 a
    message, 3 a fixed array (element, length), 4 a sequence (element, bound, 0 for none)."""
    node, detail = kind
    if node == 1:
        name, bound = detail
        return idl.bounded_str[bound] if name == "string" and bound else _PRIMITIVES[name]
    if node == 2:
        return ros2_struct(detail, store)
    element, size = detail
    if node == 3:
        return idl.array[_member(element, store), size]
    if size:
        return idl.sequence[_member(element, store), size]
    return idl.sequence[_member(element, store)]


@functools.cache
def participant_entities_info(gid_size: int) -> type[Any]:
    """``rmw_dds_common/msg/ParticipantEntitiesInfo`` with ``gid_size``-byte Gids (16 since Iron, 24
    before): rmw_dds_common's IDL, keys dropped as rmw_cyclonedds drops them."""

    @dataclass
    class Gid(IdlStruct, typename=ros2.GID):
        data: idl.array[idl.uint8, gid_size] = field(default_factory=lambda: [0] * gid_size)

    @dataclass
    class NodeEntitiesInfo(IdlStruct, typename=ros2.NODE_ENTITIES_INFO):
        node_namespace: idl.bounded_str[256] = "/"
        node_name: idl.bounded_str[256] = ""
        reader_gid_seq: idl.sequence[Gid, 1024] = field(default_factory=list)
        writer_gid_seq: idl.sequence[Gid, 1024] = field(default_factory=list)

    @dataclass
    class ParticipantEntitiesInfo(IdlStruct, typename=ros2.PARTICIPANT_ENTITIES_INFO):
        gid: Gid = field(default_factory=Gid)
        node_entities_info_seq: idl.sequence[NodeEntitiesInfo, 1024] = field(default_factory=list)

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
