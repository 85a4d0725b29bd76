"""The expected tree as a hand-editable YAML file: ``tfx wtf --init`` writes it, ``--expect`` and ``tfx diff`` read it.

::

    tolerances: {translation_mm: 1.0, rotation_deg: 0.1, rate_percent: 20.0}
    frames:
      map: {}
      odom: {parent: map, rate_hz: 10.0, publishers: [/amcl]}
      laser: {parent: base_link, static: true, translation: [0.2, 0.0, 0.1], rpy_deg: [0.0, 0.0, 180.0]}

A frame without a parent is a root. A static edge's rotation is ``rpy_deg`` (fixed-axis roll, pitch,
yaw in degrees) or ``rotation`` (a quaternion, x y z w); without a value, any value is expected.
Without ``rate_hz``, any rate; without ``publishers``, any publisher.
"""

from __future__ import annotations

import math
import os
from collections.abc import Collection, Mapping
from dataclasses import asdict
from typing import IO, Any

from tftools.analysis.expected import FrameShape, Tolerances, TreeShape
from tftools.core.errors import TfToolsError
from tftools.core.rotation import Quat, Vec3, quat_from_rpy, rpy_rebuilding
from tftools.sources.user_files import NotAFileError, UserFileError, load, number

#: How far a rotation's length may be from 1 for it to be taken (and made unit).
QUATERNION_TOLERANCE = 0.01
_FRAME_KEYS = ("parent", "static", "rate_hz", "publishers", "translation", "rpy_deg", "rotation")
_HEADER = """\
The tf tree of a healthy recording ({source}), frame by frame. Edit freely:
tfx wtf --expect THIS_FILE BAG and tfx diff THIS_FILE BAG report where a recording differs.
A frame without a parent is a root. Static edges: translation (m) and rpy_deg (fixed-axis roll,
pitch, yaw in degrees; or rotation: [qx, qy, qz, qw]). Moving edges: rate_hz. Leave out a value
to accept any. tolerances: how far a static edge may move, how far a rate may fall short of the
other (percent: the slower's shortfall from the faster, whichever is expected)."""


#: What to do about a tree file that is not one: ``write_tree`` writes one of a recording's ``shape_of``.
WRITE_ONE = "write_tree(shape_of(recording), file) writes such a file"


class TreeFileError(TfToolsError):
    """The tree file at ``path`` cannot be used: ``problem`` says why; ``missing`` when it is not there (or is
    not a regular file), and ``fix`` what to do about that."""

    def __init__(self, path: str, problem: str, *, missing: bool = False, fix: str = "") -> None:
        super().__init__(f"{path}: {problem}")
        self.path, self.problem, self.missing, self.fix = path, problem, missing, fix
        self.hint = f"{fix}; {WRITE_ONE}" if missing else WRITE_ONE


def write_tree(tree: TreeShape, out: IO[str]) -> None:
    """``tree`` as YAML, with a header saying how to edit it: rates to the mHz, static values to
    the nanometre and nanodegree (far below any tolerance, and readable)."""
    from ruamel.yaml import YAML
    from ruamel.yaml.comments import CommentedMap

    def one_line(mapping: dict[str, Any]) -> CommentedMap:
        flow = CommentedMap(mapping)
        flow.fa.set_flow_style()
        return flow

    document = CommentedMap()
    document.yaml_set_start_comment(_HEADER.format(source=tree.source))
    document["tolerances"] = one_line(asdict(tree.tolerances))
    document["frames"] = CommentedMap((name, one_line(_entry(f))) for name, f in tree.frames.items())
    yaml = YAML()
    yaml.width = 1 << 16  # one line per frame
    yaml.dump(document, out)


def _entry(f: FrameShape) -> dict[str, Any]:
    entry: dict[str, Any] = {}
    if f.parent is not None:
        entry["parent"] = f.parent
    if f.static:
        entry["static"] = True
    elif f.rate_hz:
        entry["rate_hz"] = round(f.rate_hz, 3)
    if f.translation is not None and f.rotation is not None:
        entry["translation"] = [_rounded(v) for v in f.translation]
        entry["rpy_deg"] = [_rounded(math.degrees(a)) for a in rpy_rebuilding(f.rotation)]
    if f.publishers is not None:
        entry["publishers"] = list(f.publishers)
    return entry


def _rounded(value: float) -> float:
    return round(value, 9) + 0.0  # + 0.0: no -0.0


def read_tree(path: str | os.PathLike[str]) -> TreeShape:
    """The tree in the YAML file at ``path``; ``TreeFileError`` says what is wrong with it."""
    name = str(path)
    try:
        document = load(path)
    except NotAFileError as error:
        raise TreeFileError(name, str(error), missing=True, fix=error.hint) from None
    except UserFileError as error:
        raise TreeFileError(name, f"cannot be read: {error}") from None
    if not isinstance(document, Mapping) or not isinstance(document.get("frames"), Mapping):
        raise TreeFileError(name, "has no 'frames:' mapping of frame names")
    try:
        tolerances = _tolerances(document.get("tolerances") or {})
        frames = {str(k): _frame(str(k), v) for k, v in document["frames"].items()}
    except (TypeError, ValueError) as error:
        raise TreeFileError(name, str(error)) from None
    return TreeShape(frames, name, tolerances)


def _tolerances(entry: Any) -> Tolerances:
    if not isinstance(entry, Mapping):
        raise TypeError("tolerances: expected a mapping")
    _known_keys("tolerances", entry, Tolerances.__dataclass_fields__)
    return Tolerances(**{str(k): number(v, f"tolerances: {k}", text=False) for k, v in entry.items()})


def _frame(name: str, entry: Any) -> FrameShape:
    entry = entry if entry is not None else {}
    if not isinstance(entry, Mapping):
        raise TypeError(f"frame {name}: expected a mapping like {{parent: base_link}}")
    _known_keys(f"frame {name}", entry, _FRAME_KEYS)
    parent = entry.get("parent")
    static = entry.get("static", False)
    if not isinstance(static, bool):
        raise TypeError(f"frame {name}: static is true or false")
    publishers = entry.get("publishers")
    if publishers is not None and not isinstance(publishers, list):
        raise TypeError(f"frame {name}: publishers is a list")
    translation, rotation = _value(name, entry)
    rate = number(entry.get("rate_hz", 0.0), f"frame {name}: rate_hz", text=False)
    if rate < 0:
        raise ValueError(f"frame {name}: rate_hz {rate} is below 0")
    rate_hz = rate or None  # left out (or 0): any rate
    return FrameShape(
        frame=name,
        parent=None if parent is None else str(parent),
        static=static,
        rate_hz=rate_hz,
        publishers=None if publishers is None else tuple(sorted(str(p) for p in publishers)),
        translation=translation,
        rotation=rotation,
    )


def _known_keys(what: str, entry: Mapping[Any, Any], known: Collection[str]) -> None:
    unknown = [str(k) for k in entry if k not in known]
    if unknown:
        raise ValueError(f"{what}: unknown key {unknown[0]!r} (known: {', '.join(known)})")


def _value(name: str, entry: Mapping[str, Any]) -> tuple[Vec3 | None, Quat | None]:
    """A static edge's translation and quaternion (None, None where the entry gives neither)."""
    if "rpy_deg" in entry and "rotation" in entry:
        raise ValueError(f"frame {name}: give rpy_deg or rotation, not both")
    given = [k for k in ("translation", "rpy_deg", "rotation") if k in entry]
    if not given:
        return None, None
    if not entry.get("static", False):
        raise ValueError(f"frame {name}: {given[0]} is for static edges (add static: true)")
    x, y, z = _numbers(f"frame {name}: translation", entry.get("translation", [0, 0, 0]), 3)
    if "rotation" in entry:
        return (x, y, z), _unit_quaternion(
            f"frame {name}: rotation", _numbers(f"frame {name}: rotation", entry["rotation"], 4)
        )
    roll, pitch, yaw = _numbers(f"frame {name}: rpy_deg", entry.get("rpy_deg", [0, 0, 0]), 3)
    return (x, y, z), quat_from_rpy(math.radians(roll), math.radians(pitch), math.radians(yaw))


def _unit_quaternion(what: str, values: list[float]) -> Quat:
    """``values`` (x y z w) when their length is 1 to within 1% (a rounded file's); anything else (a zero
    rotation, a scaled one) is refused, as tf2's setTransform refuses it."""
    length = math.hypot(*values)
    if not abs(length - 1.0) <= QUATERNION_TOLERANCE:
        raise ValueError(
            f"{what}: {values} is not a unit quaternion (length {length:.6g}): give x y z w of length 1, or rpy_deg"
        )
    qx, qy, qz, qw = values
    return (qx, qy, qz, qw)


def _numbers(what: str, values: Any, count: int) -> list[float]:
    if not isinstance(values, list) or len(values) != count:
        raise ValueError(f"{what}: expected a list of {count} numbers")
    return [number(v, what, text=False) for v in values]
