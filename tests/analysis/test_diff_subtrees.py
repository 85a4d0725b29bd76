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


def _seen(child: str, parent: str = "camera", hz: float = 5.0) -> FrameShape:
    return FrameShape(child, parent, rate_hz=hz, detection=True)


def test_a_detectors_objects_lost_together_are_one_line_and_their_rates_no_difference() -> None:
    """e-Yantra Agri Bot's two runs (2021): the detector named its tomatoes by their place in a list, obj0..obj43 in
    one, obj0 and obj1 in the other: 42 'lost' lines, and obj0's '0.1 Hz in B, 4.8 Hz in A' (how often the camera
    saw it). Detections lost under one camera are one line; their rates are no difference; a robot's frame is."""
    camera = FrameShape("camera", "base_link", static=True, translation=(0.1, 0.0, 0.0), rotation=(0.0, 0.0, 0.0, 1.0))
    wheel = FrameShape("wheel", "base_link", rate_hz=50.0)
    a = [FrameShape("base_link", None), camera, wheel, *(_seen(f"obj{n}") for n in range(5))]
    b = [FrameShape("base_link", None), camera, FrameShape("wheel", "base_link", rate_hz=10.0), _seen("obj0", hz=0.1)]
    one, two = (TreeShape({f.frame: f for f in fs}, "here") for fs in (a, b))
    found = whole_subtrees(compare(one, two, Tolerances()))
    assert [(d.change, d.frame, d.said_with) for d in found] == [
        (Change.rate, "wheel", ()),
        (Change.lost, "obj1", ("obj2", "obj3", "obj4")),
    ], found
    assert describe(found[1]).endswith(
        "not in B, nor 3 more detections of camera (a detector's, named as it names what it sees): obj2, obj3, obj4"
    )
