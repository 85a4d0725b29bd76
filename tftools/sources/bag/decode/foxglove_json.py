"""Parser of ``foxglove.FrameTransform(s)`` in JSON; missing numbers are 0, as in protobuf."""

# {"timestamp": {"sec", "nsec"}, "parent_frame_id", "child_frame_id", "translation": {x, y, z},
#  "rotation": {x, y, z, w}}; FrameTransforms: {"transforms": [...]}

from __future__ import annotations

import json
import math
from typing import Any

from tftools.sources.bag.decode.template import DecodeError, Parsed


def parse_frame_transform(data: bytes) -> Parsed:
    parsed = Parsed([], [], [], [])
    _add(parsed, _load(data))
    return parsed


def parse_frame_transforms(data: bytes) -> Parsed:
    parsed = Parsed([], [], [], [])
    transforms = _load(data).get("transforms", [])
    if not isinstance(transforms, list):
        raise DecodeError("'transforms' is not a list")
    for transform in transforms:
        _add(parsed, _object(transform, "transform"))
    return parsed


def _load(data: bytes) -> dict[str, Any]:
    try:
        return _object(json.loads(data), "message")
    except (ValueError, RecursionError) as e:
        raise DecodeError(f"invalid JSON ({e})") from None


def _object(value: Any, what: str) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise DecodeError(f"{what} is not a JSON object")
    return value


def _add(parsed: Parsed, transform: dict[str, Any]) -> None:
    stamp = _object(transform.get("timestamp"), "timestamp")
    translation = _object(transform.get("translation"), "translation")
    rotation = _object(transform.get("rotation"), "rotation")
    nsec = stamp.get("nsec", stamp.get("nanosec", 0))
    parsed.parents.append(_text(transform.get("parent_frame_id", "")))
    parsed.children.append(_text(transform.get("child_frame_id", "")))
    parsed.stamps.append(_integer(stamp.get("sec", 0)) * 1_000_000_000 + _integer(nsec))
    parsed.values.append(
        tuple(_number(translation.get(k, 0.0)) for k in "xyz") + tuple(_number(rotation.get(k, 0.0)) for k in "xyzw")
    )


def _text(value: Any) -> str:
    if not isinstance(value, str):
        raise DecodeError(f"frame id {value!r} is not a string")
    return value


def _integer(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DecodeError(f"time {value!r} is not a number")
    return int(value)


def _number(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DecodeError(f"{value!r} is not a number")
    return float(value)
