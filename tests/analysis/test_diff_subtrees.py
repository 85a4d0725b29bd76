"""``tfx diff`` says a frame lost (or added) with the frames beneath it once, and keeps apart frames lost beside it.
The real pairs that showed it (a TurtleBot3 waffle's camera against a burger, the GrandTour zed2i chain) are in
tests/corpus/test_diff48.py."""

from __future__ import annotations

from tftools.analysis.diff.subtrees import whole_subtrees
from tftools.analysis.differences import Change, compare, describe
from tftools.analysis.expected import FrameShape, Tolerances, TreeShape


def _tree(*edges: tuple[str, str]) -> TreeShape:
    frames = [FrameShape("base_link", None)]
    frames += [FrameShape(child, parent, static=True, translation=(0.1, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0))
               for parent, child in edges]  # fmt: skip
    return TreeShape({f.frame: f for f in frames}, "here")


def test_a_camera_lost_with_the_frames_beneath_it_is_one_line() -> None:
    camera = (("base_link", "camera_link"), ("camera_link", "camera_rgb"), ("camera_rgb", "camera_optical"))
    waffle = _tree(*camera, ("base_link", "caster_left"))
    burger = _tree(("base_link", "caster"))
    found = whole_subtrees(compare(waffle, burger, Tolerances()))
    assert [(d.change, d.frame, d.said_with) for d in found] == [
        (Change.lost, "camera_link", ("camera_rgb", "camera_optical")),
        (Change.lost, "caster_left", ()),
        (Change.added, "caster", ()),
    ]
    assert describe(found[0]) == (
        "camera_link is in A (a child of base_link), not in B, nor the 2 frames beneath it: camera_rgb, camera_optical"
    )
    back = whole_subtrees(compare(burger, waffle, Tolerances()))
    assert next((d.change, d.frame, d.said_with) for d in back if d.change is Change.added)[2] == (
        "camera_rgb",
        "camera_optical",
    )
