"""``figures.held_parts``, ``held_groups``: the one tolerance of "never changes" (``HELD_M``, ``HELD_DEG``)."""

from __future__ import annotations

import math

import numpy as np

from tftools.core.figures import HELD_DEG, HELD_M, held_groups, held_parts


def _turned(degrees: float, sign: float = 1.0) -> list[float]:
    half = math.radians(degrees) / 2
    return [0.0, 0.0, 0.0, 0.0, 0.0, sign * math.sin(half), sign * math.cos(half)]


def test_values_apart_at_float_rounding_are_held_and_beyond_it_are_not() -> None:
    still = np.array([_turned(0.0), _turned(0.4 * HELD_DEG), _turned(0.4 * HELD_DEG, -1.0)])
    still[1, 0] = 0.5 * HELD_M
    assert held_parts(still) == (True, True)  # q and -q are one rotation
    moved = still.copy()
    moved[2, 1] = 2 * HELD_M
    assert held_parts(moved) == (False, True)
    turned = np.array([_turned(0.0), _turned(3 * HELD_DEG)])
    assert held_parts(turned) == (True, False)
    far = np.random.default_rng(1).random((1000, 7))
    assert held_parts(far) == (False, False)
    assert held_parts(np.zeros((0, 7))) == (True, True)


def test_values_within_the_tolerance_of_an_earlier_one_are_that_value() -> None:
    values = np.array([_turned(0.0), _turned(0.0), _turned(0.0), _turned(45.0), _turned(0.0)])
    values[1, 0] = 1e-9  # a static re-published with noise
    values[4, 2] = 0.01
    assert held_groups(values).tolist() == [0, 0, 0, 1, 2]
