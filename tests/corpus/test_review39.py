"""Issue 39's `tfx diff` read as a user (brief review39): a recording against the tree file `wtf --init` wrote of
it, and the URDF joint `echo --format urdf` writes, on the real recordings whose static edges sit at a pitch of 90
degrees (where tf2's roll, pitch, yaw lose part of the rotation)."""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, RECORDINGS, Corpus
from tftools.analysis.differences import rotation_angle_deg
from tftools.core.rotation import quat_from_rpy

#: Each recording with its static edges at a pitch of +-90 degrees (before: `diff A tree.yaml` said each moved).
LOCKED = {
    "ros2-husky-ur-moveit2-gazebo-long-2025-db3": ["ur_flange"],  # 90.00° apart
    "ros2-husky-ur-moveit2-gazebo-2025-db3": ["ur_flange"],
    "ros2-gazebo-drone-beside-ackermann-car-two-static-publishers-pfms-2024-db3": ["bottom_cam_link", "sonar_link"],
    "ros2-potted-plant-agv-real-fastlio-icp-ekf-2026-db3": ["right_camera"],  # 180.00° apart
}


@pytest.mark.parametrize("recording_id", sorted(LOCKED))
def test_a_recording_has_no_difference_from_its_own_tree_file(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """`tfx diff A tree.yaml` (tree.yaml: `tfx wtf --init A`) said `moved by 0.0 mm and 90.00°` (180.00° on the
    potted-plant AGV's right camera, the PFMS drone's downward camera and sonar), the two values printed alike:
    the file's rpy_deg were tf2's, which at a pitch of 90 degrees lose the rest of the rotation. Both ways now
    no differences, exit 0, and the file holds each edge's rotation."""
    path = corpus(BY_ID[recording_id])
    tree = tmp_path / "tree.yaml"
    init = tfx("wtf", "--init", path)
    assert init.code == 0, init.stderr
    tree.write_text(init.stdout)
    for first, second in ((path, tree), (tree, path)):
        said = tfx("diff", first, second)
        assert said.code == 0 and "no differences" in said.stdout, said.stdout
    for frame in LOCKED[recording_id]:
        line = next(t for t in init.stdout.splitlines() if t.strip().startswith(f"{frame}:"))
        roll, pitch, yaw = (float(v) for v in line.split("rpy_deg: [")[1].split("]")[0].split(","))
        assert abs(pitch) == 90.0, line
        parent = line.split("parent: ")[1].split(",")[0]
        echoed = json.loads(tfx("echo", parent, frame, "-b", path, "--format", "json", "--at", "0").stdout)
        radians = (math.radians(roll), math.radians(pitch), math.radians(yaw))
        assert rotation_angle_deg(quat_from_rpy(*radians), tuple(echoed["rotation"])) < 1e-6, line


def test_the_ur_flanges_urdf_joint_is_its_rotation(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """`tfx echo ur_wrist_3_link ur_flange --format urdf` wrote rpy "0 -pi/2 0" for (-0.5, -0.5, -0.5, 0.5), a
    joint 90 degrees off the arm's (its URDF: rpy "0 -pi/2 -pi/2"); now angles that make the rotation again."""
    path = corpus(BY_ID["ros2-husky-ur-moveit2-gazebo-long-2025-db3"])
    joint = ElementTree.fromstring(tfx("echo", "ur_wrist_3_link", "ur_flange", "-b", path, "--format", "urdf").stdout)
    origin = joint.find("origin")
    assert origin is not None
    roll, pitch, yaw = (float(v) for v in origin.get("rpy", "").split())
    lines = tfx("echo", "ur_wrist_3_link", "ur_flange", "-b", path, "--format", "json").stdout.splitlines()
    assert json.loads(lines[0])["rotation"] == pytest.approx([-0.5, -0.5, -0.5, 0.5], abs=1e-12)
    assert rotation_angle_deg(quat_from_rpy(roll, pitch, yaw), (-0.5, -0.5, -0.5, 0.5)) < 1e-9


#: The recordings holding no transforms at all (the ebot's `tf` of TransformStamped is one tfx cannot read: still
#: unusable, exit 2, saying so).
NO_TF = sorted(
    r.id for r in RECORDINGS if not r.meta["frames"] and r.id != "ros2-ebot-nav2-tf-as-transformstamped-2024-db3"
)


@pytest.mark.parametrize("recording_id", NO_TF)
def test_a_recording_without_transforms_has_no_difference_from_itself(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """`tfx diff A A` and `tfx wtf --init A` exited 2 'no transforms on /tf, /tf_static' for each: now an empty
    tree, said so; `tfx diff A tree.yaml` both ways no differences, exit 0; wtf's no_tf error unchanged."""
    path = corpus(BY_ID[recording_id])
    said = tfx("diff", path, path)
    assert said.code == 0, said.stderr
    assert f"A: {path} (0 frames: no transforms on /tf, /tf_static)" in said.stdout, said.stdout
    assert said.stdout.endswith("no differences beyond the tolerances (1 mm, 0.1°, rates 20%)\n")
    init = tfx("wtf", "--init", path)
    assert init.code == 0 and "frames: {}" in init.stdout, init.stderr
    tree = tmp_path / "tree.yaml"
    tree.write_text(init.stdout)
    assert tfx("diff", path, tree).code == tfx("diff", tree, path).code == 0
    assert tfx("wtf", "--expect", tree, path).code == 1  # no_tf, an error as before


#: Recordings whose frames are stamped on clocks apart, with the span (s) their report's timelines should cover:
#: their record span, or (no record clock) their tf's on the main clock. Before: 7.0 days, 5.8 h, 55 years.
CLOCKS_APART = {
    "ros1-raspimouse-replayed-with-its-map-odom-beside-live-gmapping-2018-bag": 54.0,
    "ros1-sail-zed-ekf-gps-two-odometries-2022-bag": 15.9,
    "ros2-logistic-cobot-pymoveit2-no-record-clock-2024-db3": 27.7,
}


@pytest.mark.parametrize("recording_id", sorted(CLOCKS_APART))
def test_a_reports_timelines_span_the_recording_not_its_clocks_apart(
    recording_id: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """tfx report drew each edge by its stamps on one axis: the raspimouse's map -> odom from a replay a week
    behind beside live gmapping spread 54 s over 7 days (2000 s bins, the edge at 1.7e-06 Hz), the SAIL boat's
    IMU and EKF on a machine 5.8 h ahead squeezed its 15.9 s into one 50 s bin, the logistic cobot's detections
    on the wall clock beside its simulated arm (no record clock) its 27.7 s into one of 5e6 s. Now the axis is
    the recording's: samples on a clock apart at their arrival, or, where no arrival places them, not drawn (and
    said so); every drawn edge holds monitor's samples."""
    path = corpus(BY_ID[recording_id])
    page = tmp_path / "page.html"
    assert tfx("report", "-b", path, "-o", page).code in (0, 1)
    text = page.read_text()
    data = json.loads(re.findall(r'<script type="application/json" class="report-data">(.*?)</script>', text, re.S)[0])
    axis = data["axis"]["step"] * data["axis"]["count"]
    assert CLOCKS_APART[recording_id] <= axis <= 1.2 * CLOCKS_APART[recording_id] + 1, data["axis"]
    counts = {
        f"{e['parent']} -> {e['child']}": e["count"]
        for e in json.loads(tfx("monitor", "-b", path, "-f", "json").stdout)["edges"]
    }
    undrawn = set(re.findall(r"<b>([^<]*) &#8594; ([^<]*)</b><small>[^<]*not drawn: stamped on another clock", text))
    for edge in data["edges"]:
        parent, child = edge["name"].split(" -> ")
        drawn = sum(edge["samples"])
        assert drawn == (0 if (parent, child) in undrawn else counts[edge["name"]]), edge["name"]
        rates = [r for r in edge["rate"] if r is not None]
        assert not rates or min(rates) > 0.1, edge["name"]
    assert bool(undrawn) == (recording_id == "ros2-logistic-cobot-pymoveit2-no-record-clock-2024-db3")
