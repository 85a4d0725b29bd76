"""Defects seen on the ROS 1 bags and MCAP files added by corpus17, each on the recording that showed it.

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

MIR = "ros1-mir-gazebo-landmark-mcl-input-no-map-2021-bag"


def test_topics_in_the_unrecorded_map_frame_are_one_finding(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """ruvu/mcl's MiR bag is the input of a localization under test: /initialpose and /landmark_list are in map, and
    nothing recorded publishes map -> odom. One cause, one finding naming both topics, pointing at localization (it
    was two errors, each telling of odometry's odom -> base_link)."""
    result = tfx("wtf", corpus(BY_ID[MIR]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (missing,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert missing["frames"] == ["map"]
    assert "/initialpose (1 of 1 messages), /landmark_list (1 of 1 messages)" in missing["message"]
    assert "'map' is localization's frame" in missing["hint"] and "odom -> base_link" not in missing["hint"]
    assert bag["summary"]["errors"] == 1 and result.code == 1
