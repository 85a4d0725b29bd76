"""``tfx diff`` says once a fixed edge that only turned to undo a fixed edge above it that moved (its frame keeps its
orientation there), and keeps apart one that turned otherwise or moved too. The real pair that showed it (PFMS
Stage's local_map) is in tests/corpus/test_diff48.py."""

from __future__ import annotations

import math

from tftools.analysis.diff.kept import kept_places
from tftools.analysis.differences import compare, describe
from tftools.analysis.expected import FrameShape, Tolerances, TreeShape
from tftools.core.rotation import Quat, Vec3


def _yaw(deg: float) -> Quat:
    return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))


def _tree(robot: Vec3, yaw: float, local_map: float, local_map_at: Vec3 = (0.0, 0.0, 0.0)) -> TreeShape:
    def fixed(name: str, parent: str, t: Vec3, q: Quat) -> FrameShape:
        return FrameShape(name, parent, static=True, translation=t, rotation=q)

    frames = [
        FrameShape("odom", None),
        fixed("base_footprint", "odom", robot, _yaw(yaw)),
        fixed("laser", "base_footprint", (0.1, 0.0, 0.2), _yaw(0.0)),
        fixed("local_map", "laser", local_map_at, _yaw(local_map)),
    ]
    return TreeShape({f.frame: f for f in frames}, "here")


def _said(a: TreeShape, b: TreeShape) -> list[tuple[str, tuple[str, ...]]]:
    tolerances = Tolerances()
    return [(d.frame, d.said_with) for d in kept_places(compare(a, b, tolerances), a, b, tolerances)]


def test_a_frame_turned_only_to_undo_the_robots_yaw_is_said_with_the_robot() -> None:
    a, b = _tree((-0.5, -1.5, 0.0), 31.5, -31.5), _tree((0.0, 0.0, 0.0), -0.06, 0.06)
    assert _said(a, b) == [("base_footprint", ("local_map",))]
    (d,) = kept_places(compare(a, b, Tolerances()), a, b, Tolerances())
    assert describe(d).endswith(
        "; beneath it, local_map kept its orientation in odom: its own edge (laser -> local_map) turned by 31.56° "
        "only to undo it"
    ), describe(d)


def test_a_frame_turned_with_the_robot_or_moved_too_is_its_own_difference() -> None:
    robot = _tree((-0.5, -1.5, 0.0), 31.5, 0.0)
    assert _said(robot, _tree((0.0, 0.0, 0.0), 0.0, -31.5)) == [("base_footprint", ()), ("local_map", ())]
    moved_too = _tree((0.0, 0.0, 0.0), -0.06, 0.06, local_map_at=(0.05, 0.0, 0.0))
    assert _said(_tree((-0.5, -1.5, 0.0), 31.5, -31.5), moved_too) == [("base_footprint", ()), ("local_map", ())]
