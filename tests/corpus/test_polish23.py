"""Defects left by sweep19 and fixed by polish23, each on the recording that showed it; the designed reproductions
are beside the code's own tests."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tftools.sources.recording import read_recording

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


#: Recordings with /joint_states beside other sensor data, and how many topics of it they have.
WITH_JOINT_STATES = {
    "ros2-webots-epuck-resends-2025-db3": 19,
    "ros1-gazebo-kobuki-free-space-nav-2017-bag": 2,
    "ros1-gazebo-kobuki-repeated-stamps-2017-bag": 2,
    "ros2-husky-ur-moveit2-gazebo-2025-db3": 1,
    "ros2-husky-ur-moveit2-gazebo-long-2025-db3": 1,
}


@pytest.mark.parametrize(("recording", "topics"), WITH_JOINT_STATES.items())
def test_filter_checks_the_sensor_topics_wtf_counts(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    recording: str,
    topics: int,
) -> None:
    """The Webots e-puck: `tfx filter` checked /joint_states (sensor_msgs/JointState, frame base_link) of its 20
    topics where wtf's header said "19 topics of sensor data" (it read /joint_states whole); the Kobukis 3 against
    2, the Huskies 2 against 1. One rule for both: joint states place nothing in space."""
    path = corpus(BY_ID[recording])
    checked = [t["topic"] for t in json.loads(tfx("filter", "-b", path, "--format", "json").stdout)["topics"]]
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    assert sorted(checked) == sorted(bag["sensor_data"]["topics"]) and len(checked) == topics
    assert "/joint_states" not in checked


CREATE3 = "ros2-create3-real-two-urdfs-2022-db3"


def test_a_chain_asked_without_a_window_has_none_in_json(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real TurtleBot 4 Lite: `tfx monitor odom base_link --format json` gave "window": {"start": null, "end":
    1663967421.751} (the recording's last record time, to which the chain's delays are counted) where no window was
    asked for and the text's header says the stamps' span: null/null, as without a chain."""
    path = corpus(BY_ID[CREATE3])
    chain = json.loads(tfx("monitor", "odom", "base_link", "-b", path, "--format", "json").stdout)
    whole = json.loads(tfx("monitor", "-b", path, "--format", "json").stdout)
    assert chain["window"] == whole["window"] == {"start": None, "end": None}
    assert sorted(chain["chain"]["frames"]) == ["base_link", "odom"]


def test_odometry_s_second_base_frame_is_said_odometry_s(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The create3's odometry moves base_footprint beside base_link under odom; urdf_extra's hint said "a camera or
    lidar driver's own frames". A child of odom on /tf is odometry's base frame (REP 105)."""
    (bag,) = json.loads(tfx("wtf", corpus(BY_ID[CREATE3]), "--format", "json").stdout)["bags"]
    (extra,) = [f for f in bag["findings"] if f["code"] == "urdf_extra" and f["frames"] == ["odom", "base_footprint"]]
    assert extra["message"].startswith("base_footprint (a child of odom on /tf) is not a link")
    assert "the robot's base as its odometry publishes it (REP 105: odom -> base_footprint" in extra["hint"]
    assert "camera" not in extra["hint"]
