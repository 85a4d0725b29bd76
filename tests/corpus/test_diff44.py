"""Issue 39 (brief diff44), on the real recordings that showed it: `tfx diff` tells a joint held at another position
from a calibration. The designed reproductions are beside the code's own tests (tests/cli/test_diff.py,
tests/analysis/test_expected.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import Corpus
from tests.corpus.test_corpus43a import JANUARY, OCTOBER
from tests.corpus.test_diff42 import _diff


def test_the_pr2s_torso_held_lower_is_a_joint_and_its_stereo_camera_a_calibration(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """JSK's real PR2 in October and January 2012 (tf1: every edge on /tf, the robot standing still). By the bytes
    (rosbags' reader): base_link -> torso_lift_link comes in robot_state_publisher's messages of 45 transforms with
    the tilting laser, which sweeps, at z 0.8492 m in all 348 of October's and 0.7512 m in all 135 of January's;
    double_stereo_link -> narrow_stereo_link in its messages of 48 (43 in January) fixed transforms, without the
    laser, at (0.0353, 0.0609, 0.0418) and (0.0575, 0.0595, 0.0484). diff said both 'moved (on /tf, never changing
    in either)'; the torso is a joint held 98.1 mm lower, with its 76 frames beneath, the camera a calibration."""
    code, found = _diff(tfx, corpus, OCTOBER, JANUARY)
    assert len(found) == 34 and code == 1  # 38 before the Kinect's five rate lines were one (test_diff46)
    parts = {d["frame"]: d for d in found if d["part"] is not None}
    joints = sorted(f for f, d in parts.items() if d["part"] == "joint")
    fixed = sorted(f for f, d in parts.items() if d["part"] == "fixed")
    assert len(joints) == 24 and fixed == [
        "double_stereo_link",
        "high_def_frame",
        "l_forearm_cam_frame",
        "laser_tilt_link",
        "narrow_stereo_link",
        "projector_wg6802418_frame",
        "r_forearm_cam_frame",
        "wide_stereo_link",
    ]
    torso = parts["torso_lift_link"]
    assert (torso["part"], torso["beneath"], round(torso["translation_mm"], 1)) == ("joint", 76, 98.1)
    assert torso["message"] == (
        "base_link -> torso_lift_link, a joint (it came with the joints that move), held at positions 98.1 mm and "
        "0.00° apart: xyz [-0.0500, 0.0000, 0.8492] m rpy [0.00, 0.00, 0.00]° in A, xyz [-0.0500, 0.0000, 0.7512] m "
        "rpy [0.00, 0.00, 0.00]° in B; the 76 frames beneath it moved with it"
    )
    camera = parts["narrow_stereo_link"]
    assert (round(camera["translation_mm"], 1), round(camera["rotation_deg"], 2)) == (23.2, 5.93)
    assert camera["message"].startswith(
        "double_stereo_link -> narrow_stereo_link, a fixed part (it came with the fixed transforms, apart from the "
        "joints), set 23.2 mm and 5.93° apart (a calibration, or another description of the robot)"
    )
    amcl = [d for d in found if d["frame"] == "odom_combined"]
    assert [(d["change"], d["part"]) for d in amcl] == [("moved", None)]  # amcl's estimate, sent alone: neither
