"""Messages in JSON, as Foxglove writes them, parsed one by one: missing numbers are 0, as in protobuf."""

# foxglove.FrameTransform: {"timestamp": {"sec", "nsec"}, "parent_frame_id", "child_frame_id",
#   "translation": {x, y, z}, "rotation": {x, y, z, w}}; FrameTransforms: {"transforms": [...]}.
# tf2_msgs/msg/TFMessage: {"transforms": [{"header": {"stamp": {"sec", "nanosec"}, "frame_id"},
#   "child_frame_id", "transform": {"translation": {x, y, z}, "rotation": {x, y, z, w}}}]}.
# rosgraph_msgs/msg/Clock: {"clock": {"sec", "nanosec"}}. A time's nanoseconds may be "nsec"
# (ROS 1's name) or "nanosec" (ROS 2's), its seconds "sec" or "secs".
# Read whole (``codecs.robot``): std_msgs/msg/String {"data"} (a recorded /robot_description) and
# sensor_msgs/msg/JointState {"header", "name": [...], "position": [...]}.

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs.decoded import Clocks, Decoded, DecodeError, FrameNames
from tftools.sources.codecs.parsed import Parsed, one_by_one
from tftools.sources.user_files import number

#: Reads one transform object into ``parsed``.
_Transform = Callable[[Parsed, dict[str, Any]], None]


def decode_frame_transform(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    return one_by_one(raw, starts, lengths, frames, lambda data: _parsed([load(data)], _foxglove))


def decode_frame_transforms(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    return one_by_one(raw, starts, lengths, frames, lambda data: _parsed(load(data).get("transforms", []), _foxglove))


def decode_tf(raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames) -> Decoded:
    return one_by_one(raw, starts, lengths, frames, lambda data: _parsed(load(data).get("transforms", []), _ros))


def decode_clocks(raw: UInt8Array, starts: Int64Array, lengths: Int64Array) -> Clocks:
    """``rosgraph_msgs/Clock`` messages, as ``decoded.ClockDecoder`` says."""
    messages: list[int] = []
    times: list[int] = []
    failures: list[tuple[int, str]] = []
    for message, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            times.append(_time(_object(load(raw[start : start + length].tobytes()).get("clock"), "clock")))
            messages.append(message)
        except DecodeError as e:
            failures.append((message, str(e)))
    return np.array(messages, np.int64), np.array(times, np.int64), failures


def decode_whole(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, read: Callable[[dict[str, Any]], Any]
) -> tuple[list[int], list[Any], list[tuple[int, str]]]:
    """Each message's object read by ``read``: the messages read, their values, and the (message, reason) of those
    that could not be (``robot.WholeDecoder``)."""
    read_ok: list[int] = []
    values: list[Any] = []
    failures: list[tuple[int, str]] = []
    for message, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            values.append(read(load(raw[start : start + length].tobytes())))
        except DecodeError as e:
            failures.append((message, str(e)))
            continue
        read_ok.append(message)
    return read_ok, values, failures


def string_of(message: dict[str, Any]) -> str:
    """A std_msgs/msg/String's text."""
    data = message.get("data", "")
    if not isinstance(data, str):
        raise DecodeError("'data' is not a string")
    return data


def joint_state_of(message: dict[str, Any]) -> tuple[int, list[str], list[float]]:
    """A sensor_msgs/msg/JointState's stamp (ns), joint names and positions."""
    header = _object(message.get("header"), "header")
    names, positions = message.get("name", []), message.get("position", [])
    if not isinstance(names, list) or not all(isinstance(name, str) for name in names):
        raise DecodeError("'name' is not a list of strings")
    if not isinstance(positions, list):
        raise DecodeError("'position' is not a list")
    return _time(_object(header.get("stamp"), "stamp")), names, [_number(p) for p in positions]


def load(data: bytes) -> dict[str, Any]:
    """The JSON object of a message."""
    try:
        return _object(json.loads(data), "message")
    except (ValueError, RecursionError) as e:
        raise DecodeError(f"invalid JSON ({e})") from None


def _parsed(transforms: Any, add: _Transform) -> Parsed:
    """The transform objects of a message, each read by ``add``."""
    parsed = Parsed()
    if not isinstance(transforms, list):
        raise DecodeError("'transforms' is not a list")
    for transform in transforms:
        add(parsed, _object(transform, "transform"))
    return parsed


def _foxglove(parsed: Parsed, transform: dict[str, Any]) -> None:
    stamp = _object(transform.get("timestamp"), "timestamp")
    _add(parsed, transform.get("parent_frame_id", ""), transform, _time(stamp), transform)


def _ros(parsed: Parsed, transform: dict[str, Any]) -> None:
    header = _object(transform.get("header"), "header")
    stamp = _object(header.get("stamp"), "stamp")
    values = _object(transform.get("transform"), "transform")
    _add(parsed, header.get("frame_id", ""), transform, _time(stamp), values)


def _add(parsed: Parsed, parent: Any, transform: dict[str, Any], stamp: int, values: dict[str, Any]) -> None:
    translation = _object(values.get("translation"), "translation")
    rotation = _object(values.get("rotation"), "rotation")
    parsed.parents.append(_text(parent))
    parsed.children.append(_text(transform.get("child_frame_id", "")))
    parsed.stamps.append(stamp)
    parsed.values.append(
        tuple(_number(translation.get(k, 0.0)) for k in "xyz") + tuple(_number(rotation.get(k, 0.0)) for k in "xyzw")
    )


def _time(stamp: dict[str, Any]) -> int:
    sec = stamp.get("sec", stamp.get("secs", 0))
    nsec = stamp.get("nsec", stamp.get("nanosec", stamp.get("nsecs", 0)))
    return _integer(sec) * 1_000_000_000 + _integer(nsec)


def _object(value: Any, what: str) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise DecodeError(f"{what} is not a JSON object")
    return value


def _text(value: Any) -> str:
    if not isinstance(value, str):
        raise DecodeError(f"frame id {value!r} is not a string")
    return value


def _integer(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DecodeError(f"time {value!r} is not a number")
    return int(value)


def _number(value: Any) -> float:
    try:  # not refused where not finite: tf2 refuses it, and wtf says so
        return number(value, text=False, finite=False)
    except ValueError as error:
        raise DecodeError(str(error)) from None
