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


def test_a_frame_that_kept_its_place_under_a_turned_parent_is_said_with_it() -> None:
    """The GrandTour box's two calibrations: alphasense_base turned 180 degrees about z, cam4 under it moved 208 mm
    and turned 180 degrees the other way, 1.0 mm from its place in box_base: one line, with cam4's figures. Here the
    robot turned about z, local_map 409 mm and 180 degrees the other way, 1.0 mm from its place in odom."""
    a, b = (
        _tree((0.37, 0.0, 0.07), 0.0, 0.0, (0.104, 0.0, 0.0)),
        _tree((0.37, 0.0, 0.07), 180.0, 180.0, (-0.305, 0.0, 0.0)),
    )
    (d,) = kept_places(compare(a, b, Tolerances()), a, b, Tolerances())
    assert (d.frame, d.said_with) == ("base_footprint", ("local_map",))
    assert describe(d).endswith(
        "; beneath it, local_map kept its place in odom (within 1.0 mm and 0.00°): its own edge (laser -> local_map) "
        "moved by 409.0 mm and 180.00° to undo it"
    ), describe(d)
