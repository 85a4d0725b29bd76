"""``figures.pause_rows``: a pause is an interval much longer than the stream's usual one, and than the
intervals around it (corpus ros2-neato-real-obstacle-avoider-burst-2023-db3: a Neato's driver sent 44 samples
10 ms apart at its start, then one every 0.32-0.55 s; its 0.55 s interval was a stall of every edge)."""

from __future__ import annotations

import numpy as np

from tftools.core.arrays import Int64Array
from tftools.core.figures import pause_rows, pauses

MS = 1_000_000
FLOOR = 500 * MS  # Thresholds.max_gap


def stamps(intervals_ms: list[float]) -> Int64Array:
    return np.concatenate(([0], np.cumsum(np.array(intervals_ms) * MS))).astype(np.int64)


def test_a_start_burst_does_not_make_the_sustained_rhythm_a_pause() -> None:
    burst = [10.0] * 44
    sustained = [400.0, 340.0, 450.0, 420.0, 550.0, 350.0, 440.0, 430.0, 410.0, 345.0, 405.0, 360.0]
    usual, _, rows = pause_rows(stamps([*burst, 80.0, *sustained]), FLOOR)
    assert usual == 10 * MS  # the median is still the burst's: the neighbours decide
    assert rows.tolist() == []
    assert pauses(stamps([*burst, 80.0, *sustained]), FLOOR) is None


def test_a_pause_among_its_sustained_rhythm_is_still_one() -> None:
    burst = [10.0] * 44
    sustained = [400.0] * 6 + [5000.0] + [400.0] * 6
    found = pauses(stamps(burst + sustained), FLOOR)
    assert found is not None and found.count == 1 and found.longest == 5000 * MS
    steady = [100.0] * 30 + [600.0] + [100.0] * 30  # six intervals of a 10 Hz stream
    assert pause_rows(stamps(steady), FLOOR)[2].tolist() == []
    assert pause_rows(stamps([100.0] * 30 + [1500.0] + [100.0] * 30), FLOOR)[2].tolist() == [30]
