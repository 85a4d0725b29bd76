"""What corpus25's recordings showed, fixed each on the recording that showed it; the designed reproductions are
beside the code's own tests."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording, load_manifest

_, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]

TILT_LASER = "ros1-tilting-laser-xsens-imu-tf1-messages-imu-frame-unjoined-2012-bag"


def test_a_tf1_recording_s_unnamed_imu_frame_is_a_mount_never_sent(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """A real tilting laser and Xsens IMU of 2012: /tf is tf1's tf/tfMessage, its two mounts sent on it at 10 Hz by
    tf's static_transform_publisher, the Xsens topics in /base_imu, which no transform names. The hint said the
    mounts 'were not recorded' and to record /tf_static, a topic tf1 did not have."""
    path = corpus(BY_ID[TILT_LASER])
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (finding,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert finding["hint"].startswith("this recording's /tf is tf1's (tf/tfMessage), from before /tf_static")
    assert "nothing published the missing ones" in finding["hint"]
    assert "rosbag record" not in finding["hint"] and "not recorded" not in finding["hint"]
