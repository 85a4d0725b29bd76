"""Sensor data in a tree apart from the frame it is checked in, on the real recordings that show it: the trees apart
(``disconnected``) are the cause, each stream's ``sensor_frame`` said beneath it (counted once), with a hint that
names the lookups that fail (into the target) and not those that work (within the stream's own tree)."""

from __future__ import annotations

import json

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

#: (recording, the frame the sensor data is checked in, the streams in the tree apart from it)
APART = [
    ("ros2-ias0220-gazebo-diff-drive-beside-imu-device-2025-db3", "odom", ["/distance", "/imu"]),
    ("ros2-ias0220-gazebo-diff-drive-no-clock-2025-db3", "odom", ["/imu"]),
    ("ros2-ias0220-imu-device-static-elsewhere-2025-db3", "map", ["/distance", "/imu"]),
]


@pytest.mark.parametrize(("recording_id", "target", "topics"), APART, ids=[a[0] for a in APART])
def test_data_in_the_tree_apart_is_said_beneath_the_trees_apart(
    recording_id: str,
    target: str,
    topics: list[str],
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    path = corpus(BY_ID[recording_id])
    result = tfx("wtf", path, "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    findings = bag["findings"]
    (apart,) = [f for f in findings if f["code"] == "disconnected"]
    assert apart["severity"] == "error" and apart["key"] and not apart["cause"]
    beneath = [f for f in findings if f["code"] == "sensor_frame"]
    assert sorted(f["message"].split(":")[0] for f in beneath) == topics
    for f in beneath:
        assert f["cause"] == apart["key"], f
        assert f"into {target} fails (within its own tree they work)" in f["hint"], f["hint"]
    text = " ".join(tfx("wtf", path).stdout.split())
    assert f"which explains {len(topics)} more finding" in text
    assert "every tf lookup and MessageFilter on this data fails" not in text
