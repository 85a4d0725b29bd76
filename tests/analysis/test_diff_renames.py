"""``tfx diff`` says a frame renamed (one gone, another come under the same parent at nearly one place) as a rename
with its small move, and nothing of the kind where a frame really went and another came. The real pair that showed
it is in tests/corpus/test_diff48.py."""

from __future__ import annotations

import math

from tftools.analysis.diff.renames import renamed
from tftools.analysis.differences import Change, compare, describe
from tftools.analysis.expected import FrameShape, Tolerances, TreeShape

YAW = (0.0, 0.0, math.sin(math.radians(60)), math.cos(math.radians(60)))


def _wheel(name: str, x: float, y: float = -0.34, parent: str = "base_link") -> FrameShape:
    return FrameShape(name, parent, static=True, translation=(x, y, 0.18), rotation=YAW)


def _tree(*wheels: FrameShape) -> TreeShape:
    frames = {"base_link": FrameShape("base_link", None), **{w.frame: w for w in wheels}}
    return TreeShape(frames, "here")


def _said(a: TreeShape, b: TreeShape) -> list[tuple[str, str, str, float]]:
    return [
        (d.change.value, d.frame, d.other, round(d.translation_mm, 1))
        for d in renamed(compare(a, b, Tolerances()), Tolerances())
    ]


def test_two_wheels_renamed_in_turn_are_two_renames() -> None:
    """The hologlyph robot's two URDF versions: left_wheel's name passed to the rear wheel, the front wheel took the
    left's place's name, each moved 8.9 mm. A move of 1168.9 mm and a wheel lost and one added, before."""
    a = _tree(_wheel("left_wheel", 0.58), _wheel("rear_wheel", -0.58), _wheel("right_wheel", 0.0, 0.68))
    b = _tree(_wheel("front_wheel", 0.5889), _wheel("left_wheel", -0.5889), _wheel("right_wheel", 0.0, 0.68))
    assert _said(a, b) == [("renamed", "front_wheel", "left_wheel", 8.9), ("renamed", "left_wheel", "rear_wheel", 8.9)]
    first = renamed(compare(a, b, Tolerances()), Tolerances())[0]
    assert describe(first).startswith(
        "left_wheel in A is front_wheel in B, renamed: the one frame of base_link in each near that place, 8.9 mm and "
        "0.00° apart (static at xyz [0.5800, -0.3400, 0.1800] m"
    ), describe(first)


def test_a_frame_renamed_beside_one_that_went_elsewhere_names_its_namesake() -> None:
    """One wheel renamed, its old name given to a wheel at another place: the rename, and the namesake added."""
    a = _tree(_wheel("left_wheel", -0.5889), _wheel("front_wheel", 0.5889))
    b = _tree(_wheel("rear_wheel", -0.58), _wheel("left_wheel", 0.49, -0.30))
    assert _said(a, b) == [
        ("renamed", "rear_wheel", "left_wheel", 8.9),
        ("added", "left_wheel", "rear_wheel", 0.0),
        ("lost", "front_wheel", "", 0.0),
    ]
    added = renamed(compare(a, b, Tolerances()), Tolerances())[1]
    assert describe(added).endswith("is at no place of A's frames: A's left_wheel is rear_wheel in B, renamed")


def test_no_rename_where_a_frame_went_and_another_came_elsewhere_or_near_two() -> None:
    """A frame gone and another come 30 mm away, under another parent, at the parent's origin, or near two frames
    that went: a frame lost and one added, as they are."""
    gone = _tree(_wheel("laser", 0.20))
    for came in (
        _wheel("camera", 0.23),  # 30 mm away
        _wheel("camera", 0.20, parent="base_footprint"),  # another parent
    ):
        assert [d[0] for d in _said(gone, _tree(came))] == ["lost", "added"]
    at_origin = (_wheel("laser", 0.0, 0.0), _wheel("camera", 0.0, 0.0))
    origin = [FrameShape(w.frame, w.parent, static=True, translation=(0.0, 0.0, 0.0), rotation=YAW) for w in at_origin]
    assert [d[0] for d in _said(_tree(origin[0]), _tree(origin[1]))] == ["lost", "added"]
    two = _tree(_wheel("laser", 0.20), _wheel("sonar", 0.21))
    assert [d[0] for d in _said(two, _tree(_wheel("camera", 0.205)))] == ["lost", "lost", "added"]


def test_a_frame_moved_a_little_is_itself_not_a_rename() -> None:
    """A wheel moved 5 mm beside a frame come near its old place: the wheel moved, the frame added."""
    a = _tree(_wheel("left_wheel", 0.58))
    b = _tree(_wheel("left_wheel", 0.585), _wheel("caster", 0.578))
    assert [d[:2] for d in _said(a, b)] == [("moved", "left_wheel"), ("added", "caster")]


def test_two_frames_that_swapped_names_are_one_line() -> None:
    """Two cameras each 0.1-0.6 mm from the other's place under a parent the same in both: one line, a swap. (Seen
    first between the GrandTour box's two calibrations, where it was wrong: their parent, alphasense_base, turned
    180 degrees between them, so that a place under it was not one place; under a moved parent no rename is said,
    next test.)"""
    a = _tree(_wheel("cam2", -0.055, 0.0), _wheel("cam3", 0.055, 0.0))
    b = _tree(_wheel("cam3", -0.0556, 0.0), _wheel("cam2", 0.0549, 0.0))
    (d,) = renamed(compare(a, b, Tolerances()), Tolerances())
    assert (d.change, d.other, d.frame, d.said_with) == (Change.renamed, "cam2", "cam3", ("cam2",))
    assert describe(d) == (
        "cam2 and cam3 swapped names, each the one frame of base_link near the other's place in A: A's cam2 is B's "
        "cam3, 0.6 mm and 0.00° apart; A's cam3 is B's cam2, 0.1 mm and 0.00° apart"
    )


def test_a_parent_renamed_is_one_line_its_children_compared_under_it() -> None:
    """IAS0220's IMU bags: world in one, map in the other, imu_link beneath each: one rename, where a child that
    moved under it is said moved; a root lost whose children are roots without it is one line."""
    world = TreeShape({"world": FrameShape("world", None), "imu": _wheel("imu", 0.1, parent="world")}, "a")
    map_ = TreeShape({"map": FrameShape("map", None), "imu": _wheel("imu", 0.1, parent="map")}, "b")
    assert _said(world, map_) == [("renamed", "map", "world", 0.0)]
    (d,) = renamed(compare(world, map_, Tolerances()), Tolerances())
    assert describe(d) == "world in A is map in B, renamed: a root in both, with its child beneath it in both: imu"
    moved = TreeShape({"map": FrameShape("map", None), "imu": _wheel("imu", 0.2, parent="map")}, "b")
    assert _said(world, moved) == [("renamed", "map", "world", 0.0), ("moved", "imu", "", 100.0)]
    apart = TreeShape({"imu": FrameShape("imu", None)}, "c")
    (gone,) = renamed(compare(world, apart, Tolerances()), Tolerances())
    assert (gone.change, gone.said_with) == (Change.lost, ("imu",))
    assert describe(gone) == "world is in A (a root), not in B; its child in A is a root in B: imu"


def test_no_rename_under_a_parent_that_moved() -> None:
    """The GrandTour box's 2024 and 2025 calibrations: alphasense_base turned 180 degrees about z, cam2 and cam3
    under it each at the other's place in it, and at its own place in box_base: no swap said, two moves."""
    a = _tree(_wheel("cam2", -0.055, 0.0, parent="alpha"), _wheel("cam3", 0.055, 0.0, parent="alpha"))
    b = _tree(_wheel("cam2", 0.055, 0.0, parent="alpha"), _wheel("cam3", -0.055, 0.0, parent="alpha"))
    turned = (0.0, 0.0, 1.0, 0.0)
    for tree, q in ((a, (0.0, 0.0, 0.0, 1.0)), (b, turned)):
        tree.frames["alpha"] = FrameShape("alpha", "base_link", static=True, translation=(0.37, 0.0, 0.07), rotation=q)
    assert [d[:2] for d in _said(a, b)] == [("moved", "cam2"), ("moved", "cam3"), ("moved", "alpha")]


def test_mounts_renamed_under_a_root_that_gained_a_parent_are_renames() -> None:
    """A mapping robot's bags before and after its EKF (robo_lape, 2018-09-20 and -25): base_link a root in A, under
    the EKF's odom in B, its mounts base_imu and base_laser renamed imu_frame and laser_frame at the same places:
    read lost and added, their parent counted unsettled as if it had moved. A tree joined moves none of its frames."""
    a = _tree(_wheel("base_imu", 0.045, 0.0), _wheel("base_laser", -0.07, 0.0))
    b = _tree(_wheel("imu_frame", 0.045, 0.0), _wheel("laser_frame", -0.07, 0.0))
    b.frames["odom"] = FrameShape("odom", None)
    b.frames["base_link"] = FrameShape("base_link", "odom", translation=(0.1, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0))
    said = _said(a, b)
    assert ("renamed", "imu_frame", "base_imu", 0.0) in said and ("renamed", "laser_frame", "base_laser", 0.0) in said
    assert not any(change in ("lost", "added") and frame != "odom" for change, frame, _, _ in said), said
