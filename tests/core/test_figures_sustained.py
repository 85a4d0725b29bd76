"""``figures.sustained_period``: the interval a stream keeps up for most of its time, not a burst's."""

from __future__ import annotations

import numpy as np

from tftools.core.figures import period, sustained_period

MS = 1_000_000


def test_a_start_up_burst_does_not_set_the_interval_a_stream_keeps_up() -> None:
    """The real Neato's driver (ros2_db3_neato_obstacle_avoider_burst_2023): 43 intervals of 9-11 ms in its
    first 0.44 s, then 19 of 320-550 ms over 7.6 s."""
    burst = np.array([9, 10, 11] * 14 + [10], np.int64) * MS
    steady = np.array([320, 400, 450, 500, 550, 380, 420, 410, 390, 430, 440, 360, 470, 400, 410, 420, 400, 390, 548])
    intervals = np.concatenate([burst, steady.astype(np.int64) * MS])
    assert period(intervals) <= 11 * MS  # by count: the burst's
    assert sustained_period(intervals) == 410 * MS  # by time: half of the 8 s is held at 410 ms or less


def test_a_steady_stream_keeps_its_period_and_nothing_is_nothing() -> None:
    assert sustained_period(np.full(50, 20 * MS, np.int64)) == 20 * MS
    assert sustained_period(np.array([30 * MS], np.int64)) == 30 * MS
    assert sustained_period(np.array([], np.int64)) == 0
    assert sustained_period(np.zeros(3, np.int64)) == 0
