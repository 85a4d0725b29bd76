"""DDS types for reading ROS 2 sensor topics: which advertised types start with a Header, and an IDL
struct for each that a publisher's writer matches. rmw_cyclonedds's writers match a reader by type name
alone, but a DDS peer sending XTypes information (Cyclone DDS's Python package) only a reader of the same
layout: so a type ROS 2 defines is read with its whole layout (from rosbags' type stores). Either way
tftools takes the samples' bytes and decodes the header only."""

from __future__ import annotations

import functools
from typing import Any

from cyclonedds.idl import IdlStruct, make_idl_struct
from cyclonedds.idl import types as idl

from tftools.sources.codecs.types import ROS2_STORES, starts_with_header, typestore
from tftools.sources.live.ros2 import conventions as ros2
from tftools.sources.live.ros2.idl import Header

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


def _definitions() -> list[dict[str, Any]]:
    return [typestore(name).fielddefs for name in ROS2_STORES]


def sensor_type(dds_type_name: str, *, unknown_too: bool = False) -> type[IdlStruct] | None:
    """The struct to read a writer of ``dds_type_name`` with, when its messages start with a header:
    the type's whole layout where ROS 2 defines it; for a type no store knows, with ``unknown_too``,
    its name over a header alone (None otherwise, and for types without a header)."""
    rosidl = ros2.ros_type(dds_type_name)
    for store, fielddefs in enumerate(_definitions()):
        if rosidl in fielddefs:
            return _struct(rosidl, store) if starts_with_header(rosidl, fielddefs) else None
    return _header_only(dds_type_name) if unknown_too else None


@functools.cache
def _header_only(dds_type_name: str) -> type[IdlStruct]:
    return make_idl_struct("HeaderOnly", dds_type_name, {"header": Header})


@functools.cache
def _struct(rosidl: str, store: int) -> type[IdlStruct]:
    """``rosidl`` as the ``store``-th of ``_definitions`` defines it, its nested types built once."""
    _constants, fields = _definitions()[store][rosidl]
    members = {name: _member(kind, store) for name, kind in fields}
    return make_idl_struct(rosidl.rsplit("/", 1)[-1], ros2.dds_type(rosidl), members)


def _member(kind: tuple[Any, Any], store: int) -> Any:
    """A field's IDL type from rosbags' (node type, detail): 1 a primitive (name, string bound), 2 a
    message, 3 a fixed array (element, length), 4 a sequence (element, bound, 0 for none)."""
    node, detail = kind
    # Cyclone DDS's IDL types are indexed as annotations, which mypy does not know them as.
    if node == 1:
        name, bound = detail
        return idl.bounded_str[bound] if name == "string" and bound else _PRIMITIVES[name]  # type: ignore[misc]
    if node == 2:
        return _struct(detail, store)
    element, size = detail
    if node == 3:
        return idl.array[_member(element, store), size]  # type: ignore[misc]
    if size:
        return idl.sequence[_member(element, store), size]  # type: ignore[misc]
    return idl.sequence[_member(element, store)]  # type: ignore[misc]
