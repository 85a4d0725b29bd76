"""Two named nodes sending the same links at once (a real JAXON humanoid, tests/corpus/test_rules46.py: its four
force-sensor frames from /hrpsys_state_publisher and /HrpsysSeqStateROSBridge): one pair of publishers, said once
with each edge beneath it, and a hint for a robot's links, not robot_localization's or cartographer's parameters."""

from __future__ import annotations

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import check
from tftools.core.transform import Transform

SENSORS = [("l_wrist", "l_force"), ("r_wrist", "r_force"), ("l_ankle", "l_foot_force")]


def _sensors(stamp: int) -> list[Transform]:
    return [scenes._t(parent, child, stamp, x=0.05) for parent, child in SENSORS]


def _two_state_publishers() -> list[TfMessage]:
    return scenes.with_extra(
        scenes.periodic("/state_publisher", 50, _sensors), scenes.periodic("/bridge", 100, _sensors)
    )


def _authorities(findings: list[Finding]) -> list[Finding]:
    return [f for f in findings if f.code == "multiple_authorities"]


def test_the_links_two_nodes_both_send_are_one_cause_with_a_state_publishers_hint() -> None:
    found = _authorities(check(scenes.recording(_two_state_publishers())))
    causes = [f for f in found if not f.cause]
    (cause,) = causes
    assert sorted(f.frames for f in found) == sorted(SENSORS)
    assert all(f.cause == cause.key for f in found if f is not cause) and len(found) == len(SENSORS)
    assert "two state publishers of one robot's links" in cause.hint and "robot_localization" not in cause.hint


def test_odometry_from_two_nodes_keeps_the_odometry_nodes_parameters() -> None:
    extra = scenes.periodic("/second_ekf", 50, scenes.odom_base, phase=0.01)
    (found,) = _authorities(check(scenes.recording(scenes.with_extra(extra))))
    assert found.frames == ("odom", "base_link") and "robot_localization's publish_tf" in found.hint
