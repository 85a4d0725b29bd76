"""A step at a pace its edge sustains elsewhere is its own motion (corpus
``ros1-raspimouse-gmapping-robot-clock-ahead-2018-bag``): a Raspberry Pi Mouse's odometry heading turns in pulses
of 6-9 degrees a sample, and a 10 degree step after a stalled sample, among neighbours at rest, is not a jump."""

from __future__ import annotations

import numpy as np

from tftools.analysis.wtf import jumps

PERIOD_NS = 100_000_000  # 10 Hz, as the robot's odometry


def _heading(steps_deg: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """An odometry edge driving 0.02 m a sample along a heading that turns by ``steps_deg``."""
    yaw = np.radians(np.concatenate([[0.0], np.cumsum(steps_deg)]))
    values = np.zeros((len(yaw), 7))
    values[:, 0] = np.arange(len(yaw)) * 0.02
    values[:, 5], values[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    return np.arange(len(yaw), dtype=np.int64) * PERIOD_NS, values


STRAIGHT = [0.1, -0.1, 0.2, -0.2, 0.1, -0.05, 0.15, -0.1, 0.05, 0.1, -0.1, 0.2]
TURN = [8.2, 9.1, 8.9, 7.5, 5.1, 1.8]  # a turn held for half a second


def test_a_catch_up_step_at_a_pace_the_edge_sustains_is_no_jump() -> None:
    stamps, values = _heading([*STRAIGHT, 6.2, 5.7, 6.3, -0.7, 10.1, 0.2, -0.8, -0.9, *STRAIGHT, *TURN, *STRAIGHT])
    assert len(jumps.jumps(stamps, values)) == 0


def test_a_step_far_beyond_the_pace_the_edge_sustains_still_jumps() -> None:
    stamps, values = _heading([*STRAIGHT, 6.2, 5.7, 6.3, -0.7, 60.0, 0.2, -0.8, -0.9, *STRAIGHT, *TURN, *STRAIGHT])
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and round(float(found.degrees[0])) == 60


def test_a_lone_step_makes_no_run_of_its_own() -> None:
    """Without a sustained turn anywhere, the same 10 degree step among slow neighbours stays a jump."""
    stamps, values = _heading([*STRAIGHT, 0.1, 0.2, 10.1, 0.2, -0.1, *STRAIGHT])
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and round(float(found.degrees[0])) == 10


def test_a_heading_wobbling_for_a_sample_on_an_edge_that_turns_fast_is_no_jump() -> None:
    """The same robot's heading dips 6 degrees for one sample and comes back (a flip and back, as two sources
    taking turns leave): at the tens of degrees a sample it turns elsewhere, that is its own motion."""
    stamps, values = _heading([*STRAIGHT, 0.2, -6.1, 7.0, 0.7, -0.2, *STRAIGHT, *TURN, *STRAIGHT])
    assert len(jumps.jumps(stamps, values)) == 0


def test_a_flip_and_back_on_an_edge_that_never_turns_still_jumps() -> None:
    stamps, values = _heading([*STRAIGHT, 0.2, -6.1, 7.0, 0.7, -0.2, *STRAIGHT])
    assert len(jumps.jumps(stamps, values)) >= 1


def _odometry(steps_m: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """An odometry edge moving along x by ``steps_m`` a sample, its heading fixed."""
    values = np.zeros((len(steps_m) + 1, 7))
    values[:, 0] = np.concatenate([[0.0], np.cumsum(steps_m)])
    values[:, 6] = 1.0
    return np.arange(len(values), dtype=np.int64) * PERIOD_NS, values


DRIVE = [0.02, 0.04, 0.04, 0.04, 0.04, 0.03, 0.01]  # a real Neato's fastest: 0.4 m/s held for 0.4 s
STILL = [0.0] * 8


def test_a_step_six_times_the_pace_the_edge_sustains_between_standstills_jumps() -> None:
    """Corpus ``ros2-neato-real-fsm-odom-jump-2023-db3``: a real Neato's odometry, standing still, moves 0.238 m
    in one 0.1 s step and stands still again, six times the 0.04 m a sample it sustains when it drives; the
    noise floor is for an edge that barely moves, not an allowance on top of five times its pace."""
    stamps, values = _odometry([*STILL, *DRIVE, *STILL, *DRIVE, *STILL, 0.2377, *STILL])
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and round(float(found.metres[0]), 3) == 0.238


def test_a_step_within_five_times_the_pace_the_edge_sustains_is_its_own_motion() -> None:
    stamps, values = _odometry([*STILL, *DRIVE, *STILL, *DRIVE, *STILL, 0.19, *STILL])
    assert len(jumps.jumps(stamps, values)) == 0


def test_a_pose_toggling_between_two_solutions_is_no_sustained_run() -> None:
    """Corpus ``ros2-aruco-camera-drone-markers-two-robots-real-2024-db3``: a marker's pose toggles 12 degrees
    between its two solutions every sample for half a second, each toggle coming back: no motion the edge
    sustains, so it excuses no flip that stays (the real marker's run of toggles, 234 degrees a second, let 7 of
    its 8 flips too far for their 9-27 ms by)."""
    toggles = [12.0, -12.0] * 3
    stamps, values = _heading([*STRAIGHT, *toggles, *STRAIGHT, 15.0, 0.1, -0.2, *STRAIGHT])
    found = jumps.jumps(stamps, values)
    assert len(found) == 1 and round(float(found.degrees[0])) == 15
