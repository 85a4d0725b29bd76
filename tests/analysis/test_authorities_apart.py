"""How far two named publishers of one moving edge disagree, at the same times (``multiple_authorities``), and
what follows: an error where they contradict each other, a warning where they agree, a note for a hand-over."""

from __future__ import annotations

import math

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.broadcasters import FLOOR_DEG, FLOOR_M
from tftools.core.figures import disagreement
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START = 100 * NS_PER_S


def _odometry(
    node: str, hz: int, offset_m: float, yaw_deg: float, phase_ms: int, speed: float = 1.0, seconds: range = range(10)
) -> list[TfMessage]:
    """odom -> base_link moving at ``speed`` m/s and turning 10°/s, from ``node`` at ``hz``, its value ``offset_m``
    ahead and ``yaw_deg`` more turned than the true motion; stamps ``phase_ms`` into each period, over ``seconds``."""
    messages = []
    for i in range(seconds.start * hz, seconds.stop * hz):
        stamp = START + phase_ms * 1_000_000 + i * NS_PER_S // hz
        t = (stamp - START) / NS_PER_S
        yaw = math.radians(10 * t + yaw_deg)
        value = Transform.from_rpy((speed * t + offset_m, 0.0, 0.0), (0.0, 0.0, yaw), stamp, "odom", "base_link")
        messages.append(TfMessage("/tf", stamp + 2_000_000, [value], node))
    return messages


def _found(*publishers: list[TfMessage]) -> Finding:
    messages = sorted((m for p in publishers for m in p), key=lambda m: m.record_time)
    (found,) = [f for f in findings_of(Scene(recording(messages))) if f.code == "multiple_authorities"]
    return found


def _finding(*publishers: list[TfMessage]) -> str:
    return _found(*publishers).message


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


def test_two_publishers_at_once_far_apart_contradict_each_other_an_error() -> None:
    """Issue 39 (ros1_okoslam_cartographer_test-71.bag: /odometry_bridge and /cartographer_node both send odom ->
    base_link, interleaved, 1.7 m and 46-70° apart, each at rest). Two odometries half a metre and 20° apart,
    each moving 0.1 m and 1° a sample: said first what was observed, then what follows, an error."""
    found = _found(_odometry("/wheels", 10, 0.0, 0.0, 0), _odometry("/cartographer", 10, 0.5, 20.0, 50))
    assert found.severity is Severity.error, found
    message = found.message
    observed = message.index("up to 500.0 mm (at ")
    own = message.index(
        "each publisher's own value moves a median of at most 100.0 mm and 1.00° from one sample to its next"
    )
    follows = message.index("they contradict each other: tf2 keeps both in one cache")
    assert observed < own < follows and "the pose jumps by up to 0.50 m and 20.0° between them" in message
    assert found.figures["contradict"] == 1 and math.isclose(float(found.figures["apart_m_max"]), 0.5)
    step_m, step_deg = float(found.figures["own_step_m"]), float(found.figures["own_step_deg"])
    assert math.isclose(step_m, 0.1) and math.isclose(step_deg, 1.0)
    compared = found.figures["samples_compared"]
    assert found.figures["samples_contradicting"] == compared and f"; at every one of the {compared} further" in message


def test_publishers_that_part_halfway_say_at_how_many_times_they_contradict_each_other() -> None:
    """Issue 39 (ros1_okoslam moving bag: the two odometries agree within noise until cartographer's 21.8° turn,
    then are up to 24.5° apart at 358 of the 995 common times). An EKF that agrees with the wheels for 5 s, then
    half a metre off: the error says at how many of the times compared they are beyond the edge's step and noise."""
    parted = [
        *_odometry("/ekf", 10, 0.0, 0.0, 50, seconds=range(5)),
        *_odometry("/ekf", 10, 0.5, 0.0, 50, seconds=range(5, 10)),
    ]
    found = _found(_odometry("/wheels", 10, 0.0, 0.0, 0), parted)
    assert found.severity is Severity.error, found
    compared, contradicting = int(found.figures["samples_compared"]), int(found.figures["samples_contradicting"])
    assert 0.45 * compared <= contradicting <= 0.55 * compared, found.figures
    assert f"; at {contradicting} of the {compared} further apart than that plus noise (5 cm, 3°)" in found.message


def test_two_publishers_at_once_that_agree_within_noise_are_a_warning() -> None:
    """An EKF beside the driver's odometry, 4 cm and 2° apart (under noise: FLOOR_M, FLOOR_DEG): a warning."""
    found = _found(_odometry("/wheels", 10, 0.0, 0.0, 0), _odometry("/ekf", 10, FLOOR_M * 0.8, FLOOR_DEG - 1, 50))
    assert found.severity is Severity.warning and "contradict" not in found.message, found
    assert found.figures["contradict"] == 0 and found.figures["samples_contradicting"] == 0


def test_publishers_apart_by_less_than_the_edge_moves_a_sample_are_a_warning() -> None:
    """A car at 20 m/s, two publishers 0.5 m apart (one stamping 25 ms late, say): less than the 2 m the edge
    moves from one sample to its next, so a lookup landing on one then the other sees no more than its motion."""
    fast = _odometry("/wheels", 10, 0.0, 0.0, 0, speed=20.0)
    found = _found(fast, _odometry("/gps", 10, 0.5, 0.0, 50, speed=20.0))
    assert found.severity is Severity.warning, found
    assert float(found.figures["own_step_m"]) > float(found.figures["apart_m_max"]) > FLOOR_M


def test_one_publisher_after_the_other_is_a_hand_over_note() -> None:
    """The same two far-apart odometries, one after the other: no lookup mixes them, a note."""
    first = _odometry("/wheels", 10, 0.0, 0.0, 0, seconds=range(5))
    then = _odometry("/cartographer", 10, 0.5, 20.0, 50, seconds=range(6, 10))
    found = _found(first, then)
    assert found.severity is Severity.info and "handed over" in found.message, found
