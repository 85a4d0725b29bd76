"""How far two named publishers of one moving edge disagree, at the same times (``multiple_authorities``)."""

from __future__ import annotations

import math

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.figures import disagreement
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START = 100 * NS_PER_S


def _odometry(node: str, hz: int, offset_m: float, yaw_deg: float, phase_ms: int) -> list[TfMessage]:
    """odom -> base_link moving at 1 m/s and turning 10°/s, from ``node`` at ``hz``, its value ``offset_m``
    ahead and ``yaw_deg`` more turned than the true motion; stamps ``phase_ms`` into each period."""
    messages = []
    for i in range(10 * hz):
        stamp = START + phase_ms * 1_000_000 + i * NS_PER_S // hz
        t = (stamp - START) / NS_PER_S
        yaw = math.radians(10 * t + yaw_deg)
        value = Transform.from_rpy((t + offset_m, 0.0, 0.0), (0.0, 0.0, yaw), stamp, "odom", "base_link")
        messages.append(TfMessage("/tf", stamp + 2_000_000, [value], node))
    return messages


def _finding(*publishers: list[TfMessage]) -> str:
    messages = sorted((m for p in publishers for m in p), key=lambda m: m.record_time)
    (found,) = [f for f in findings_of(Scene(recording(messages))) if f.code == "multiple_authorities"]
    return found.message


def test_two_publishers_of_one_edge_say_how_far_apart_they_are_at_the_same_times() -> None:
    """Issue 39 (Stage bag: stageros and robot_state_publisher 10.2 mm apart on base_footprint -> base_link,
    not said). Two odometries at 10 and 7 Hz, never the same stamp, 50 mm and 2° apart while moving: compared
    at the same instants (the other's value interpolated there), not at the nearest sample (up to 100 mm off)."""
    message = _finding(_odometry("/wheels", 10, 0.0, 0.0, 0), _odometry("/ekf", 7, 0.05, 2.0, 13))
    assert "at the same times their values are up to 50.0 mm (at " in message and "and 2.00° (at " in message


def test_publishers_sending_the_same_values_are_said_to_agree() -> None:
    message = _finding(_odometry("/wheels", 10, 0.0, 0.0, 0), _odometry("/copy", 10, 0.0, 0.0, 50))
    assert "their values are the same" in message and "mm" not in message


def test_streams_that_never_overlap_in_time_have_no_disagreement() -> None:
    values = np.tile([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0], (2, 1))
    early, late = np.array([1, 2], np.int64), np.array([3, 4], np.int64)
    assert disagreement(early, values, late, values + 1) is None
    moved = values + np.array([0.3, 0.4, 0.0, 0.0, 0.0, 0.0, 0.0])
    both = disagreement(early, values, np.array([1, 2], np.int64), moved)
    assert both is not None and math.isclose(both.metres, 0.5) and both.instants == 4
