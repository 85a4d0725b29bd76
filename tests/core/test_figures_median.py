"""``figures.median_ns``: the median of ns figures, exact where ``np.median``'s double rounds them."""

from __future__ import annotations

import numpy as np

from tftools.core.figures import median_ns

WALL = 1_778_233_424_607_813_633  # a record-minus-stamp offset of a real recording (ns): above 2**53


def test_a_median_of_wall_clock_ns_is_exact() -> None:
    """np.median gives 1778233424607813632 for this odd count: 1 ns off; an even count's mean too."""
    values = np.array([WALL + 2, WALL, WALL - 5], np.int64)
    assert median_ns(values) == WALL != int(np.median(values))
    assert median_ns(np.array([WALL, WALL + 3, WALL - 9, WALL + 100], np.int64)) == WALL + 1  # (WALL + WALL+3) / 2


def test_a_median_is_numpys_where_a_double_holds_it() -> None:
    rng = np.random.default_rng(3)
    for count in range(1, 40):
        values = rng.integers(-(10**12), 10**12, count, dtype=np.int64)
        assert median_ns(values) == int(np.median(values)), values
        assert median_ns(np.sort(values)) == int(np.median(values))  # read off the middle of sorted values
    assert median_ns(np.array([-3, -2], np.int64)) == -2 == int(np.median([-3, -2]))  # towards zero
    assert median_ns(np.zeros(0, np.int64)) == 0
