"""What corpus46's recordings showed (3d-SWAP's multi-UAV experiments of 2017: two real drones, three UAVs on a
simulated record clock), fixed on the recordings that showed it; the designed reproduction is beside the code's own
tests (tests/analysis/test_robots_alike.py)."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

REAL = "ros1-two-real-drones-mavros-frames-without-robot-prefix-wifi-outage-clocks-2.3-s-apart-3d-swap-2017-bag"
SIM = "ros1-three-uavs-sitl-record-clock-simulated-tf-on-wall-clock-three-mavros-one-unprefixed-static-3d-swap-2017-bag"


def test_two_drones_mavros_frames_are_one_frame_for_both_not_a_second_publisher(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/uav_2/mavros and /uav_3/mavros each send fcu -> lidarlite_laser: the hint said to turn the transform off
    in all but one publisher (robot_localization's publish_tf...), and the tree apart was a second error with a
    hint of typos. Now one cause, the frames of two robots named alike, with the tree apart beneath it."""
    code, findings = _findings(tfx, corpus(BY_ID[REAL]))
    (two,) = [f for f in findings if f["code"] == "multiple_authorities"]
    assert two["severity"] == "error" and two["frames"] == ["fcu", "lidarlite_laser"], two
    assert two["message"].endswith("(the same node in the namespaces of 2 robots, /uav_2 and /uav_3)"), two["message"]
    assert "uav_2/fcu" in two["hint"] and "robot_localization" not in two["hint"], two["hint"]
    (apart,) = [f for f in findings if f["code"] == "disconnected"]
    assert apart["cause"] == two["key"] and "typos" not in apart["hint"], apart
    assert code == 1


def test_two_drones_delays_are_one_clock_and_one_outage(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Every sample of both drones arrives at least 2.30 s after its stamp, and for 12.0 s nothing arrived while the
    stamps went on: three delay warnings said the same thing three times, and none said the outage."""
    _, findings = _findings(tfx, corpus(BY_ID[REAL]))
    late = [f for f in findings if f["code"] == "delay"]
    (cause,) = [f for f in late if not f["cause"]]
    assert len(late) == 3 and all(f["cause"] == cause["key"] for f in late if f is not cause)
    assert "none arrived sooner than 2.3 s after its stamp" in cause["hint"], cause["hint"]
    assert (
        "; none arrived for 12.0 s from 1510765253.155 (+17.8 s) (and 9 shorter times, of 0.527 s to 1.5 s) while its "
        "stamps went on" in cause["message"]
    ), cause["message"]


def test_three_uavs_mavros_static_is_one_frame_for_all(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Three MAVROS send the same local_origin -> local_origin_ned: a note said 'fine ... one publisher is enough',
    beside a disconnected error whose hint named typos. Now the frames of three robots named alike, the cause."""
    code, findings = _findings(tfx, corpus(BY_ID[SIM]))
    (three,) = [f for f in findings if f["code"] == "multiple_authorities"]
    assert three["severity"] == "error" and "the same node in the namespaces of 3 robots" in three["message"]
    assert "fine" not in three["hint"] and "uav_1/local_origin" in three["hint"], three["hint"]
    (apart,) = [f for f in findings if f["code"] == "disconnected"]
    assert apart["cause"] == three["key"]
    assert code == 1
