"""Messages in JSON, as Foxglove writes them, parsed one by one: missing numbers are 0, as in protobuf."""

# foxglove.FrameTransform: {"timestamp": {"sec", "nsec"}, "parent_frame_id", "child_frame_id",
#   "translation": {x, y, z}, "rotation": {x, y, z, w}}; FrameTransforms: {"transforms": [...]}.
# tf2_msgs/msg/TFMessage: {"transforms": [{"header": {"stamp": {"sec", "nanosec"}, "frame_id"},
#   "child_frame_id", "transform": {"translation": {x, y, z}, "rotation": {x, y, z, w}}}]}.
# rosgraph_msgs/msg/Clock: {"clock": {"sec", "nanosec"}}. A time's nanoseconds may be "nsec"
# (ROS 1's name) or "nanosec" (ROS 2's), its seconds "sec" or "secs".

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
