"""What rules46 fixed of issue 39's publisher inference and hints, each on the real recording that showed it (skipped
until placed); the designed reproductions are beside the code's own tests (tests/analysis/test_message_layouts.py,
tests/analysis/test_map_under_odom.py). The TurtleBot 4 simulator's wheels are in tests/corpus/test_corpus44b.py."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus
from tests.corpus.test_corpus35 import _findings  # one reading of wtf's JSON findings

JARVIS = "ros1-jarvis-tricycle-agv-real-nav350-reflector-localisation-map-odom-no-callerid-2014-bag"


def test_jarvis_s_laser_localizer_map_under_odom_is_corrected_not_jumping(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """odom -> map_contours_nav: 5,305 samples at ~208 Hz holding 101 values, a leaf, while map -> odom is sent at
    8 Hz; composed with map -> odom it stays within 0.9 m and 6 degrees of one place in map while the robot drives a
    3.3 m circle: a second localizer's map hung under odom. tfx warned `jump` with the hint "publish it as map ->
    odom", which the recording does already. Its steps are that localizer's corrections: a note, saying what shows
    it first."""
    code, findings = _findings(tfx, corpus(BY_ID[JARVIS]))
    assert not [f for f in findings if f["code"] == "jump"], findings
    (note,) = [f for f in findings if f["code"] == "map_corrections" and f["frames"] == ["odom", "map_contours_nav"]]
    assert (
        "odom -> map_contours_nav on /tf: it holds its value between steps (it changed value 100 times in 5,305 "
        "samples) and no frame hangs under it, while odom has its parent already (map -> odom): a localizer's own "
        "map under odom, it seems; it was corrected"
    ) in note["message"], note["message"]
    assert "at most 0.309 m and 2.4°" in note["message"], note["message"]
    assert "publish it as map -> odom" not in note["hint"], note["hint"]
    assert code == 0


JAXON = "ros1-jsk-jaxon-humanoid-hrpsys-multisense-two-publishers-of-the-force-sensors-2018-bag"


def test_the_humanoid_s_four_force_sensors_from_two_nodes_are_one_cause(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """/hrpsys_state_publisher (50 Hz) and /HrpsysSeqStateROSBridge (100 Hz) both send LLEG_LINK5 -> lfsensor,
    RLEG_LINK5 -> rfsensor (2.5 mm apart), LARM_LINK7 -> lhsensor and RARM_LINK7 -> rhsensor (equal): tfx said four
    warnings, each hinting at robot_localization's publish_tf and cartographer's provide_odom_frame. One pair of
    publishers: one warning with the other three beneath it, and a hint for a robot's links."""
    code, findings = _findings(tfx, corpus(BY_ID[JAXON]))
    authorities = [f for f in findings if f["code"] == "multiple_authorities"]
    (cause,) = [f for f in authorities if not f["cause"]]
    assert sorted(tuple(f["frames"]) for f in authorities) == [
        ("LARM_LINK7", "lhsensor"),
        ("LLEG_LINK5", "lfsensor"),
        ("RARM_LINK7", "rhsensor"),
        ("RLEG_LINK5", "rfsensor"),
    ]
    assert all(f["cause"] == cause["key"] for f in authorities if f is not cause), authorities
    assert cause["severity"] == "warning" and "two state publishers of one robot's links" in cause["hint"]
    assert "robot_localization" not in cause["hint"] and "cartographer" not in cause["hint"], cause["hint"]
    assert code == 0
