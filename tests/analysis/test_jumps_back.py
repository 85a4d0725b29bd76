"""The one rule of a step that comes back (``jumps.comes_back``): a spike or a toggle comes back, motion goes on."""

from __future__ import annotations

import numpy as np

from tftools.analysis.wtf.jumps import BACK_WITHIN, comes_back
from tftools.core.arrays import FloatArray


def _turned(angles_deg: list[float]) -> FloatArray:
    """A joint's samples: turned about y by ``angles_deg``."""
    values = np.zeros((len(angles_deg), 7))
    half = np.radians(angles_deg) / 2
    values[:, 4], values[:, 6] = np.sin(half), np.cos(half)
    return values


def _back_at(angles_deg: list[float], step: int) -> tuple[bool, bool]:
    """(out, returns) of the step from sample ``step`` to the next."""
    values = _turned(angles_deg)
    begin = np.array([step])
    degrees = np.array([abs(angles_deg[step + 1] - angles_deg[step])])
    back = comes_back(values, begin, begin, np.array([len(values) - 1]), np.zeros(1), degrees)
    return bool(back.out[0]), bool(back.returns[0])


def test_a_toggle_held_for_a_few_samples_comes_back_both_ways() -> None:
    """ros2_db3_jetacker_slam_toolbox_static_map's wheel: at rest, 85.9° for two or three samples, at rest."""
    toggling = [0.0, 0.0, 0.0, 85.9, 85.9, 0.0, 0.0, 0.0, 85.9]
    assert _back_at(toggling, 2) == (True, False)  # out, back at sample 5
    assert _back_at(toggling, 4) == (True, True)  # back to where it was before sample 3, and out again at 8
    assert _back_at(toggling[:7], 4) == (False, True)  # the way back alone
    assert _back_at([0.0, 0.0, 180.0, 0.0, 0.0], 1) == (True, False)  # a one-sample spike


def test_a_step_that_stays_or_moves_on_does_not_come_back() -> None:
    assert _back_at([0.0, 0.0, 60.0, 60.0, 60.0, 60.0, 60.0], 1) == (False, False)  # a reset
    assert _back_at([0.0, 10.0, 40.0, 60.0, 70.0, 70.0], 1) == (False, False)  # a pulse of motion


def test_a_wheel_wandering_faster_than_its_samples_does_not_come_back_by_chance() -> None:
    """ros1_unity_robot_sim_time_2022's wheel (about a turn a sample, seen modulo a turn): 0, 78.9, 138.5, 150.8,
    18.3 degrees: near the start again three samples on, but it went on between, never held a place."""
    assert _back_at([38.7, 21.5, 8.2, 0.0, 78.9, 138.5, 150.8, 18.3, 2.4], 3) == (False, False)


def test_back_later_than_the_window_is_not_back() -> None:
    out = [0.0, *[89.0] * BACK_WITHIN]  # out for as many samples as the window holds
    assert _back_at([*out, 0.0], 0) == (True, False)
    assert _back_at([*out, 89.0, 0.0], 0) == (False, False)
