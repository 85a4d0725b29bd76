"""Defects left by sweep19 and fixed by polish23, each on the recording that showed it; the designed reproductions
are beside the code's own tests."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording, load_manifest
from tftools.sources.recording import read_recording

_, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]

JETACKER_SLAM = "ros2-jetacker-gazebo-slam-toolbox-static-map-2025-db3"


def _verdict(tfx: Tfx, path: Path) -> list[tuple[str, str]]:  # noqa: F811
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    return sorted((f["code"], f["severity"]) for f in bag["findings"])


def test_a_repaired_copy_keeps_what_tf2_holds_of_a_frame_on_tf_static_and_tf(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    tmp_path: Path,
) -> None:
    """A JetAcker under slam_toolbox: an identity map -> odom on /tf_static (229 s before the recording) and
    slam_toolbox's map -> odom on /tf. Its repaired copy re-sent the identity every 5 s, and ROS 2's tf2 empties a
    frame's cache at each switch between the two: the copy's map -> odom fell from 44 samples to 3, and its wtf
    gained a `clock` error the recording has as a note. Repeated only before the first /tf sample, the copy's
    tf2 holds what the recording's did."""
    path = corpus(BY_ID[JETACKER_SLAM])
    copy = tmp_path / "repaired"
    tfx("static", "--repair", "-b", path, "-o", copy)
    was, now = (read_recording([p]).buffer.history("odom") for p in (path, copy))
    assert was is not None and now is not None
    assert len(was.stamps) == 44 and np.array_equal(now.stamps, was.stamps)  # 43 stamps, one of them re-valued
    verdict = _verdict(tfx, copy)
    assert ("clock", "info") in verdict and ("clock", "error") not in verdict
    assert verdict == [f for f in _verdict(tfx, path) if f[0] != "statics_early"]
