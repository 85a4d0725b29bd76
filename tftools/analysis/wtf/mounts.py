"""What a detector's two views of its markers say of two trees apart: where each marker is sent under a frame of one
tree and, at the same instant, under a camera frame of the other (``detections.by_siblings``), the pair places that
camera frame on the other tree's frame. Where every sighting agrees, that fixed transform is the camera's mount: the
detector used it, and tf never got it (``disconnected``'s hint)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tftools.analysis.differences import rotation_angle_deg
from tftools.analysis.wtf.scene import Scene, and_joined
from tftools.core.arrays import FloatArray
from tftools.core.rotation import rpy_rebuilding
from tftools.core.transform import Transform

#: Sightings that place the camera frame further apart than this (m, or rad) do not show one fixed mount: a camera on
#: a moving arm, or markers that are not one another's siblings.
MOUNT_SPREAD_M = 0.05
MOUNT_SPREAD_RAD = math.radians(5.0)


@dataclass(frozen=True)
class Mount:
    """A camera frame (``camera``) placed on a frame of another tree (``parent``) by ``sightings`` pairs of a
    detector's markers (``markers``: under ``parent``; ``siblings``: under ``camera``), each within ``spread`` m of
    ``transform`` (the sighting at the middle)."""

    parent: str
    camera: str
    transform: Transform
    sightings: int
    spread: float
    markers: tuple[str, ...]
    siblings: tuple[str, ...]


def mount_between(scene: Scene, trees: dict[str, str]) -> Mount | None:
    """The camera mount that the detections by siblings (``Scene.siblings``) whose two edges lie in two of the trees
    (``trees``: each frame's root) show, agreeing within ``MOUNT_SPREAD_M`` and ``MOUNT_SPREAD_RAD`` in every
    sighting; of several such pairs of frames, the one the most sightings show; None where none does."""
    samples = {e.key: e for e in scene.dynamic_edges}
    seen: dict[tuple[str, str], list[tuple[Transform, str, str]]] = {}
    for (parent, marker), sibling in scene.siblings.items():
        camera, other = sibling.edge
        if trees.get(parent) is None or trees.get(parent) == trees.get(camera):
            continue
        mine, theirs = samples[(parent, marker)].values, samples[sibling.edge].values
        for a, b in zip(mine, theirs, strict=True):
            seen.setdefault((parent, camera), []).append((_transform(a) * _transform(b).inverse(), marker, other))
    if not seen:
        return None
    (parent, camera), placed = max(seen.items(), key=lambda item: len(item[1]))
    translations = np.array([t.translation for t, _, _ in placed])
    apart = np.linalg.norm(translations - np.median(translations, axis=0), axis=1)
    middle = placed[int(np.argmin(apart))][0]
    turned = math.radians(max(rotation_angle_deg(middle.rotation, t.rotation) for t, _, _ in placed))
    spread = float(np.linalg.norm(translations - np.array(middle.translation), axis=1).max())
    if spread > MOUNT_SPREAD_M or turned > MOUNT_SPREAD_RAD:
        return None
    markers = tuple(sorted({m for _, m, _ in placed}, key=_natural))
    siblings = tuple(sorted({s for _, _, s in placed}, key=_natural))
    return Mount(parent, camera, middle, len(placed), spread, markers, siblings)


def mount_hint(mount: Mount, ros2: bool) -> str:
    """``disconnected``'s hint where a detector's markers show the camera's mount: what they show, then what to
    publish, with its numbers."""
    t = mount.transform
    x, y, z = t.translation
    roll, pitch, yaw = rpy_rebuilding(t.rotation)  # a command to paste: the angles that make the rotation
    angles = (("roll", roll), ("pitch", pitch), ("yaw", yaw))
    degrees = ", ".join(f"{name} {_num(math.degrees(a), 1)}" for name, a in angles)
    if ros2:
        flags = " ".join(f"--{name} {_num(v, 4)}" for name, v in (("x", x), ("y", y), ("z", z), *angles))
        command = f"ros2 run tf2_ros static_transform_publisher {flags} --frame-id {mount.parent} "
        command += f"--child-frame-id {mount.camera}"
    else:
        numbers = " ".join(_num(v, 4) for v in (x, y, z, yaw, pitch, roll))
        command = f"rosrun tf2_ros static_transform_publisher {numbers} {mount.parent} {mount.camera}"
    return (
        f"a detector sends each of its markers twice, {and_joined(list(mount.markers))} under {mount.parent} and "
        f"{and_joined(list(mount.siblings))} under {mount.camera}, at the same instants: all {mount.sightings} "
        f"sightings place {mount.camera} at ({_num(x, 3)}, {_num(y, 3)}, {_num(z, 3)}) m from {mount.parent}, turned "
        f"{degrees} deg "
        f"(each within {_mm(mount.spread)}): the camera's mount, which the detector used and tf never got; publish it "
        f"to join the trees ({command})"
    )


def _natural(frame: str) -> tuple[int, str]:
    """obj_3 before obj_49."""
    return len(frame), frame


def _transform(values: FloatArray) -> Transform:
    """A sample's ``EdgeHistory.values`` row (tx ty tz qx qy qz qw) as a transform."""
    tx, ty, tz, qx, qy, qz, qw = (float(v) for v in values)
    return Transform((tx, ty, tz), (qx, qy, qz, qw))


def _num(value: float, digits: int) -> str:
    """``value`` to ``digits`` decimals, never "-0.000"."""
    return f"{round(value, digits) + 0.0:.{digits}f}"


def _mm(metres: float) -> str:
    return "1 mm" if metres < 0.0015 else f"{metres * 1000:.0f} mm"
