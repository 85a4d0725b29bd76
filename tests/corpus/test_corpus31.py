"""What corpus31's recordings showed, fixed on the recording that showed it; the designed reproduction is beside
the code's own tests (tests/analysis/test_wtf.py)."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

NO_WORLD = "ros1-stage-three-robots-no-world-three-trees-all-slashed-clock-pfms-a4-2020-bag"


def test_robots_in_trees_of_their_own_lack_a_common_parent_not_a_letter(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Three robots in Stage, no world recorded: robot_0/odom, robot_1/odom and robot_2/odom head the same frames
    under their own prefixes. wtf and echo called 'robot_1/odom' a misspelling of 'robot_2/odom' (and of
    'robot_0/odom')."""
    path = corpus(BY_ID[NO_WORLD])
    (bag,) = json.loads(tfx("wtf", path, "--format", "json").stdout)["bags"]
    (finding,) = [f for f in bag["findings"] if f["code"] == "disconnected"]
    assert "robot_0/odom, robot_1/odom and robot_2/odom head trees of the same frames" in finding["hint"]
    echoed = tfx("echo", "robot_0/odom", "robot_1/odom", "-b", path).stderr
    assert "robot_0/odom and robot_1/odom head trees of the same frames" in echoed
    for text in (finding["hint"], echoed):
        assert "misspelling" not in text and "not a typo" in text
