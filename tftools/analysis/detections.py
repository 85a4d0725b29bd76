"""Which moving edges are a detector's (a marker, tag or object seen by a camera), from the evidence a recording
holds: a detector's frame names, a camera's frame above a child that appears and disappears, or a sibling under a
camera frame sent with a detector's frame at each of its sightings (``by_siblings``); what wtf says of
them (their staleness, their jumps, their rate) and what monitor and report show of them (``figures.sightings``)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from tftools.analysis.findings import counted
from tftools.core.arrays import Int64Array
from tftools.core.figures import Sightings, pauses, sightings
from tftools.core.time import NS_PER_S

#: A child frame named as detectors name what they see: ArUco's and AprilTag's markers (``marker_367``,
#: ``tag0``, ``tag36h11:0``, ar_track_alvar's ``ar_marker_3``, aruco_detect's ``fiducial_12``), find_object_2d's
#: ``object_1`` and the like (``obj_49``).
DETECTOR_CHILD = re.compile(r"^(ar_)?(aruco_)?(marker|tag|fiducial|object|obj|apriltag|aruco)[\w:\-]*?\d+$", re.I)
#: The figure that marks a finding about a detection (its value 1): a detector's edges, each told alike, are one
#: detector's findings (``causes``).
DETECTION = "detection"
#: A parent frame that is a camera's (``camera``, ``camera_link``, ``head_camera_rgb_optical_frame``, ``cam0``).
CAMERA_PARENT = re.compile(r"(camera|cam\d*|optical)", re.I)


def _base(frame: str) -> str:
    return frame.rsplit("/", 1)[-1]


def detection(parent: str, child: str, stamps: Int64Array, span: int = 0) -> str | None:
    """Why the edge ``parent -> child`` (its sorted ``stamps``; ``span``: their record span) is a detection,
    in words ("named as a detector names what it sees, under the camera frame camera", "under the camera frame
    camera, seen and lost"); None where nothing says so. A robot's own edge (odom -> base_link that stops) is
    never one."""
    return _why(parent, child, stamps, span, sightings(stamps, span))


def _why(parent: str, child: str, stamps: Int64Array, span: int, seen: Sightings | None) -> str | None:
    """``detection`` with the edge's ``figures.sightings`` (``seen``) given. A name alone is no evidence: a robot's
    own frame may be named ``tag_3`` or ``object_1`` and published steadily with the robot; the name counts beside
    a camera frame above it, or where the bytes show it seen and lost (seen once, or in bursts)."""
    child_name, parent_name = _base(child), _base(parent)
    under_camera = bool(CAMERA_PARENT.search(parent_name)) and not CAMERA_PARENT.search(child_name)
    if DETECTOR_CHILD.match(child_name) and not CAMERA_PARENT.search(child_name):
        if under_camera:
            return f"{child} is named as a detector names what it sees, under the camera frame {parent}"
        if len(stamps) == 1 or seen is not None:
            return f"{child} is named as a detector names what it sees, and comes and goes"
    if under_camera and _comes_and_goes(stamps, span):
        return f"under the camera frame {parent}, {child} comes and goes"
    return None


#: A child unseen this long (ns), and ``figures.PERIODS`` of its periods, went out of view (``_comes_and_goes``).
LOST = NS_PER_S // 2


def _comes_and_goes(stamps: Int64Array, span: int) -> bool:
    """Seen once, or paused (``figures.pauses``, for ``LOST`` at least) at least once: a stream published
    irregularly (a camera tracking a drone, every 0.4 to 104 ms) does not come and go."""
    return len(stamps) == 1 or pauses(stamps, LOST, span) is not None


#: How close (ns) a sibling's sample is stamped to each of a detection's: one detector's callback sending the marker
#: twice, in the camera's frame and in the robot's (the UR5's cam_49 and obj_49, 0.13 to 0.58 ms apart).
WITH = 10 * NS_PER_S // 1000

_NUMBER = re.compile(r"(\d+)$")


class Sibling(NamedTuple):
    """Why an edge is a detection by its sibling (``by_siblings``), and that sibling's edge (camera, child)."""

    why: str
    edge: tuple[str, str]


def by_siblings(edges: Sequence[tuple[str, str, Int64Array]]) -> dict[tuple[str, str], Sibling]:
    """The edges (parent, child, sorted stamps) that a sibling shows are a detector's where their own bytes need not:
    a child named as a detector names what it sees (``obj_1``) under no camera frame, sent at each of its stamps
    (within ``WITH``) with a frame of the same number under a camera frame: the UR5's base_link -> obj_1, 4 samples
    2 s apart, each 0.1 to 0.6 ms after camera_link -> cam_1 (the same ArUco marker in the camera's frame). Why, in
    words, and the sibling, by edge. The sibling itself (``cam_1``, named as a camera's frames are) is not one: its
    name does not say what it is."""
    under_camera: dict[str, list[tuple[str, str, Int64Array]]] = {}
    for parent, child, stamps in edges:
        number = _NUMBER.search(_base(child))
        if number is not None and CAMERA_PARENT.search(_base(parent)):
            under_camera.setdefault(str(int(number.group(1))), []).append((parent, child, stamps))
    found = {}
    for parent, child, stamps in edges:
        name = _base(child)
        if not DETECTOR_CHILD.match(name) or CAMERA_PARENT.search(name) or CAMERA_PARENT.search(_base(parent)):
            continue
        number = _NUMBER.search(name)
        for camera, sibling, theirs in under_camera.get(str(int(number.group(1))) if number else "", []):
            if sibling != child and _sent_with(stamps, theirs):
                found[(parent, child)] = Sibling(
                    f"{child} is named as a detector names what it sees, and {sibling}, under the camera frame "
                    f"{camera}, is sent with it at each of its {counted(len(stamps), 'sighting')}",
                    (camera, sibling),
                )
                break
    return found


def _sent_with(stamps: Int64Array, theirs: Int64Array) -> bool:
    """Whether each of ``stamps`` has one of ``theirs`` within ``WITH``, as many of each."""
    return len(stamps) == len(theirs) and bool((np.abs(stamps - theirs) <= WITH).all())


def detected(parent: str, child: str, stamps: Int64Array, span: int = 0) -> tuple[str, Sightings | None] | None:
    """Why the edge is a detection (``detection``) and how it was seen (``figures.sightings``: None where never
    unseen); None for an edge that is not one."""
    seen = sightings(stamps, span)
    why = _why(parent, child, stamps, span, seen)
    return None if why is None else (why, seen)


def detection_sightings(parent: str, child: str, stamps: Int64Array, span: int = 0) -> Sightings | None:
    """A detection's ``figures.sightings`` (None for an edge that is not one, ``detection``, or never unseen)."""
    found = detected(parent, child, stamps, span)
    return None if found is None else found[1]
