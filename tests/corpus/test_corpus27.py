"""Defects seen on the recordings added by corpus27, each on the recording that showed it.

Each test skips while its recording awaits placement in the shared corpus, as the rest of the corpus tests do."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.fetch import Recording, load_manifest

_, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]

HUSKY = "ros1-husky-real-gps-imu-tf1-robot-state-publisher-post-dated-half-second-2013-bag"


def test_the_husky_s_odometry_frame_is_told_its_tf_not_a_mount(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real Clearpath Husky of 2013 (tf1's /tf, before /tf_static): /encoder's Odometry is in odom_combined,
    robot_pose_ekf's frame, which did not run. Its own transform is missing, as `tfx filter /encoder` says; wtf
    told it "the sensors' mounts come on /tf ... run their publisher", the words for /fix's GPS mount."""
    result = tfx("wtf", corpus(BY_ID[HUSKY]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    missing = {tuple(f["frames"]): f for f in bag["findings"] if f["code"] == "sensor_frame"}
    assert sorted(missing) == [("/gps",), ("/world",), ("odom_combined",)]
    encoder = missing[("odom_combined",)]["hint"]
    assert "'odom_combined' is the frame of odometry (nav_msgs/Odometry)" in encoder and "mounts" not in encoder
    assert "from before /tf_static: the sensors' mounts come on /tf" in missing[("/gps",)]["hint"]
    assert result.code == 1


DELTA = "ros1-custom-diff-drive-real-hokuyo-scans-in-unnamed-frame-clock-at-2000-tf1-2013-bag"


def test_scans_in_a_frame_tf_never_names_are_told_the_frame_id_remedy_too(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real custom diff-drive robot of 2013 (tf1's /tf): its Hokuyo's scans are in base_laser, its laser mounted
    as 'laser'. wtf told only "run their publisher"; the driver's frame_id is the other remedy, as `tfx filter
    /scan` says ("publish its frame's transform, or fix the frame_id")."""
    result = tfx("wtf", corpus(BY_ID[DELTA]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (missing,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert missing["frames"] == ["base_laser"]
    assert "run their publisher, or set the driver's frame_id parameter" in missing["hint"]
    assert result.code == 1


JOHNNY5 = "ros1-hobby-diff-drive-real-neato-lidar-robot-clock-5.7-s-behind-recorder-2016-bag"


def test_a_robot_clock_behind_the_recorder_s_is_told_as_a_clock(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A hobby robot of 2016: its three publishers' edges all recorded 5.6-6.2 s after their stamps, none sooner.
    wtf said each 'arrives late' and to find a busy publisher or a slow link; the bytes show the robot's clock
    ~5.7 s behind the recorder's, which the delay's hint now says first."""
    result = tfx("wtf", corpus(BY_ID[JOHNNY5]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    late = [f for f in bag["findings"] if f["code"] == "delay"]
    assert len(late) == 6
    for finding in late:
        assert "most likely the publisher's clock runs behind the recorder's" in finding["hint"], finding["hint"]
    assert result.code == 0
