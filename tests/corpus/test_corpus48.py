"""What corpus48's recording showed (3d-SWAP's real flight of 2017-11-20: two drones whose clocks are 0.4 s behind
the recorder's), fixed on the recordings that showed it; the designed reproductions are beside the code's own tests
(tests/analysis/test_robots_alike.py)."""

from __future__ import annotations

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings
from tests.corpus.test_corpus46 import REAL as FIFTEENTH

TWENTIETH = (
    "ros1-two-real-drones-at-3-and-6-m-mavros-frames-without-robot-prefix-both-clocks-0.4-s-behind-3d-swap-2017-bag"
)


def test_two_drones_clocks_0_4_s_behind_are_one_offset(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Every sample of both drones' four publishers arrives 0.385-0.78 s after its stamp, each publisher's median
    within 0.05 s of its earliest: three delay warnings, grouped only from 1 s, each blamed a busy publisher or a
    slow link. Now one, with the other two beneath it, naming the clocks first."""
    _, findings = _findings(tfx, corpus(BY_ID[TWENTIETH]))
    late = [f for f in findings if f["code"] == "delay"]
    (cause,) = [f for f in late if not f["cause"]]
    assert len(late) == 3 and all(f["cause"] == cause["key"] for f in late if f is not cause)
    assert (
        "(none arrived sooner than 0.385 s after its stamp nor much later, as with 2 more edges: one steady offset, "
        "most likely the publishers' clock behind the recorder's" in cause["hint"]
    ), cause["hint"]


@pytest.mark.parametrize("recording", [TWENTIETH, FIFTEENTH])
def test_echo_between_a_drone_and_the_unprefixed_mavros_frames_names_the_robots(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
    recording: str,
) -> None:
    """`tfx echo uav_2 fcu`: the hint said to attach fcu to the map tree 'or check the frame names for typos',
    where wtf says both drones' MAVROS send fcu -> lidarlite_laser without a robot's prefix. Now echo says so too."""
    result = tfx("echo", "uav_2", "fcu", "-b", corpus(BY_ID[recording]), "--at", "+1")
    assert result.code == 1
    assert "fcu's tree is sent by the same node in the namespaces of 2 robots, /uav_2 and /uav_3" in result.stderr
    assert "uav_2/fcu" in result.stderr and "typos" not in result.stderr, result.stderr
