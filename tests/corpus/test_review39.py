"""Issue 39's `tfx diff` read as a user (brief review39): a recording against the tree file `wtf --init` wrote of
it, and the URDF joint `echo --format urdf` writes, on the real recordings whose static edges sit at a pitch of 90
degrees (where tf2's roll, pitch, yaw lose part of the rotation)."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.test_issue39 import BY_ID, RECORDINGS, Corpus
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
) -> None:
    """`tfx diff A A` exited 2 'no transforms on /tf, /tf_static' for each: now an empty tree, said so, exit 0."""
    path = corpus(BY_ID[recording_id])
    said = tfx("diff", path, path)
    assert said.code == 0, said.stderr
    assert f"A: {path} (0 frames: no transforms on /tf, /tf_static)" in said.stdout, said.stdout
    assert said.stdout.endswith("no differences beyond the tolerances (1 mm, 0.1°, rates 20%)\n")
