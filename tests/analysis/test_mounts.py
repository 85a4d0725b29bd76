"""``disconnected``'s hint where a detector sends each marker in two trees apart (corpus
ros2_db3_ur5_topic_tf_two_clocks: obj_N under base_link, cam_N under camera_link, at the same instants): the pairs
place the camera frame on the other tree, and where every sighting agrees that is the mount to publish."""

from __future__ import annotations

import math

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

MS = 1_000_000
#: The UR5's camera mount, as its 12 sightings place it: (-0.97, 0, 1.04) m, pitched 15 degrees.
MOUNT = Transform.from_rpy((-0.97, 0.0, 1.04), (0.0, math.radians(15.0), 0.0), 0, "base_link", "camera_link")


def _sightings(moving_camera: bool = False) -> list[TfMessage]:
    """Markers 1 and 49 sighted every 2 s for 8 s: camera_link -> cam_N, then 0.2 ms later base_link -> obj_N
    (the mount composed with it; with ``moving_camera``, a mount that slides 10 cm a sighting)."""
    messages = []
    for k in range(4):
        stamp = scenes.START + k * 2 * NS_PER_S
        for n, seen in ((1, (1.4, 0.08, -0.02)), (49, (1.38, -0.44, -0.41))):
            cam = Transform(seen, (0.0, 0.0, 0.0, 1.0), stamp, "camera_link", f"cam_{n}")
            slid = Transform((0.1 * k if moving_camera else 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
            obj = slid * MOUNT * cam
            messages.append(TfMessage("/tf", stamp + MS, [cam], "/aruco"))
            placed = Transform(obj.translation, obj.rotation, stamp + MS // 5, "base_link", f"obj_{n}")
            messages.append(TfMessage("/tf", stamp + MS + MS // 5, [placed], "/aruco"))
    return messages


def _disconnected(messages: list[TfMessage]) -> Finding:
    recording = scenes.recording(scenes.healthy(aruco=messages), ros1=False)
    (apart,) = [f for f in findings_of(Scene(recording)) if f.code == "disconnected"]
    return apart


def test_a_detectors_markers_in_two_trees_show_the_camera_mount_that_joins_them() -> None:
    hint = _disconnected(_sightings()).hint
    assert hint.startswith(
        "a detector sends each of its markers twice, obj_1 and obj_49 under base_link and cam_1 and cam_49 under "
        "camera_link, at the same instants: all 8 sightings place camera_link at (-0.970, 0.000, 1.040) m from "
        "base_link, turned roll 0.0, pitch 15.0, yaw 0.0 deg (each within 1 mm): the camera's mount"
    ), hint
    assert hint.endswith(
        "(ros2 run tf2_ros static_transform_publisher --x -0.9700 --y 0.0000 --z 1.0400 --roll 0.0000 "
        "--pitch 0.2618 --yaw 0.0000 --frame-id base_link --child-frame-id camera_link)"
    ), hint


def test_sightings_that_disagree_show_no_mount() -> None:
    """A camera that moves against base_link (on an arm) between sightings: no fixed transform to publish."""
    hint = _disconnected(_sightings(moving_camera=True)).hint
    assert hint.startswith("publish the transform that attaches camera_link to the map tree"), hint
