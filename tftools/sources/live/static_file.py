"""Static transforms listed in a YAML file, for ``tfx static --from``.

Two shapes are read: what ``rostopic echo /tf_static`` (or ``ros2 topic echo``) prints, with
``header.frame_id``, ``child_frame_id`` and ``transform.translation/rotation``; and a flat list::

    - {frame_id: base_link, child_frame_id: laser, x: 0.2, z: 0.1, yaw: 3.1416}
    - {frame_id: base_link, child_frame_id: camera, translation: [0.1, 0, 0.3], rotation: [0, 0, 0, 1]}

either at the top level or under ``transforms:``; several documents (``---``) are merged.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

from tftools.core.transform import Transform
from tftools.sources import user_files
from tftools.sources.errors import SourceError
from tftools.sources.user_files import number

_RPY_KEYS = ("roll", "pitch", "yaw")
_QUATERNION_KEYS = ("qx", "qy", "qz", "qw")


class StaticFileError(SourceError):
    def __init__(
        self,
        path: str,
        problem: str,
        hint: str = "each entry needs frame_id, child_frame_id, and x y z with qx qy qz qw or roll pitch yaw",
    ) -> None:
        super().__init__(f"{path}: {problem}")
        self.hint = hint


def read_static_transforms(path: str | os.PathLike[str]) -> list[Transform]:
    """The transforms listed in the YAML file at ``path`` (stamp 0), in file order."""
    name = str(path)
    try:
        documents = user_files.load_all(path)
    except user_files.NotAFileError as error:
        raise StaticFileError(name, str(error), error.hint) from None
    except user_files.UserFileError as error:
        raise StaticFileError(name, f"cannot be read: {error}", "give a YAML text file") from None
    entries = [entry for document in documents for entry in _entries(name, document)]
    if not entries:
        raise StaticFileError(name, "lists no transforms")
    return [_transform(name, i, entry) for i, entry in enumerate(entries, start=1)]


def _entries(name: str, document: Any) -> list[Any]:
    if document is None:
        return []
    if isinstance(document, Mapping) and "transforms" in document:
        document = document["transforms"]
    elif isinstance(document, Mapping):
        document = [document]
    if not isinstance(document, list):
        raise StaticFileError(name, "expected a list of transforms")
    return document


def _transform(name: str, index: int, entry: Any) -> Transform:
    if not isinstance(entry, Mapping):
        raise StaticFileError(name, f"transform {index} is not a mapping")
    try:
        if "transform" in entry or "header" in entry:  # a TransformStamped as rostopic echo prints it
            t, q = entry["transform"]["translation"], entry["transform"]["rotation"]
            translation = (number(t["x"]), number(t["y"]), number(t["z"]))
            rotation = (number(q["x"]), number(q["y"]), number(q["z"]), number(q["w"]))
            parent, child = entry["header"]["frame_id"], entry["child_frame_id"]
        else:
            translation = _translation(entry)
            rotation = _rotation(name, index, entry)
            parent, child = entry["frame_id"], entry["child_frame_id"]
    except KeyError as missing:
        raise StaticFileError(name, f"transform {index} has no {missing.args[0]}") from None
    except (TypeError, ValueError) as error:
        raise StaticFileError(name, f"transform {index}: {error}") from None
    return Transform(translation, rotation, 0, str(parent), str(child))


def _translation(entry: Mapping[str, Any]) -> tuple[float, float, float]:
    if "translation" in entry:
        x, y, z = (number(v) for v in entry["translation"])
        return x, y, z
    return number(entry.get("x", 0)), number(entry.get("y", 0)), number(entry.get("z", 0))


def _rotation(name: str, index: int, entry: Mapping[str, Any]) -> tuple[float, float, float, float]:
    has_rpy = any(k in entry for k in (*_RPY_KEYS, "rpy"))
    has_quaternion = any(k in entry for k in (*_QUATERNION_KEYS, "rotation"))
    if has_rpy and has_quaternion:
        raise StaticFileError(name, f"transform {index} gives both a quaternion and roll/pitch/yaw")
    if "rotation" in entry:
        x, y, z, w = (number(v) for v in entry["rotation"])
        return x, y, z, w
    if has_quaternion:
        x, y, z, w = (number(entry.get(k, 1 if k == "qw" else 0)) for k in _QUATERNION_KEYS)
        return x, y, z, w
    roll, pitch, yaw = (
        (number(v) for v in entry["rpy"]) if "rpy" in entry else (number(entry.get(k, 0)) for k in _RPY_KEYS)
    )
    return Transform.from_rpy((0.0, 0.0, 0.0), (roll, pitch, yaw)).rotation
