"""What corpus34's recordings showed, fixed on the recording that showed it; the designed reproduction is beside
the command's own tests (tests/cli/test_diff.py)."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

REAL_CAR = (
    "ros1-mit-rss-racecar-real-statics-only-leading-slashes-odometry-frame-unplaced-robot-clock-36-days-behind-2022-bag"
)
SIMULATOR = "ros1-mit-racecar-simulator-circle-map-to-base-link-laser-and-steering-constant-on-tf-2022-bag"


def test_diff_of_the_real_racecar_and_its_simulator_says_how_far_the_laser_mount_sits_apart(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """MIT RSS 2022: the real car's static_transform_publisher mounts the laser at (0.285, 0, 0.127) on /tf_static,
    the course's racecar_simulator sends it on /tf at 50 Hz, never changing, at (0.275, 0, 0). diff said only that
    the edge was static in one and moving in the other; it now also says the mount sits 127.4 mm apart."""
    result = tfx("diff", corpus(BY_ID[REAL_CAR]), corpus(BY_ID[SIMULATOR]), "--format", "json")
    laser = [d for d in json.loads(result.stdout)["differences"] if d["frame"] == "laser"]
    assert [d["change"] for d in laser] == ["static", "moved", "publishers"], laser
    moved = laser[1]
    assert round(moved["translation_mm"], 1) == 127.4 and round(moved["rotation_deg"], 2) == 0.0, moved
    assert "in A (static)" in moved["message"] and "in B (on /tf, never changing)" in moved["message"], moved["message"]
    assert result.code == 1
