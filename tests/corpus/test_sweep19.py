"""Defects found by sweep19 (every command on every recording, as a new user would), each on the recording that
showed it; the designed reproductions are beside the code's own tests."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

NEATO_URDF_BESIDE_DRIVER = "ros1-neato-urdf-beside-driver-2018-bag"


def test_odometry_ending_at_a_link_of_the_description_is_not_two_descriptions_of_a_mount(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """A real Neato: the URDF's base_footprint -> base_link on /tf_static, the driver's odom -> base_link moving
    on /tf (413 samples). The hint said "two descriptions of one mount ... Keep one description of it": dropping
    either breaks the robot. The odometry should end at the description's root (odom -> base_footprint)."""
    result = tfx("wtf", corpus(BY_ID[NEATO_URDF_BESIDE_DRIVER]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (parents,) = [f for f in bag["findings"] if f["code"] == "multiple_parents"]
    assert parents["frames"][0] == "base_link"
    hint = parents["hint"]
    assert "moves under odom on /tf (odometry or localization)" in hint, hint
    assert "(odom -> base_footprint: e.g. the driver's odometry child frame set to base_footprint)" in hint, hint
    assert "one mount" not in hint and "Keep one description" not in hint, hint
    assert result.code == 1


CREATE3 = "ros2-create3-real-two-urdfs-2022-db3"


def test_a_chain_s_header_is_the_span_all_frames_have(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """A real TurtleBot 4 Lite: `tfx monitor odom base_link` said "50.902 s from 1663967370.849 to 1663967421.751"
    (its first stamp to the last record time) where `tfx monitor` says "tf stamped over 50.850 s ... to
    1663967421.699": one span for one recording."""
    path = corpus(BY_ID[CREATE3])
    whole = tfx("monitor", "-b", path).stdout.splitlines()[0]
    chain = tfx("monitor", "odom", "base_link", "-b", path).stdout.splitlines()[0]
    assert whole == chain == f"{path}: tf stamped over 50.850 s from 1663967370.849 to 1663967421.699"


OKOSLAM = "ros1-okoslam-real-scanner-cartographer-beside-odometry-bridge-at-rest-2019-bag"


def test_a_scanners_own_frame_is_not_asked_whether_it_meant_base_link(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """okoslam's real robot: 22 scans in 'base_scan', a frame tf never names (no /tf_static). wtf asked "did you
    mean 'base_link'?" (a shared prefix is no misspelling) and offered a typo's remedy in its hint."""
    result = tfx("wtf", corpus(BY_ID[OKOSLAM]), "--format", "json")
    (bag,) = json.loads(result.stdout)["bags"]
    (missing,) = [f for f in bag["findings"] if f["code"] == "sensor_frame"]
    assert missing["message"] == "/scan: 22 of 22 messages are in frame 'base_scan', which no transform names"
    assert "did you mean" not in missing["message"] and "typo" not in missing["hint"], missing
    assert "this recording holds no /tf_static" in missing["hint"]
