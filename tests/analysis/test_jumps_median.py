"""The jump check's windowed median: numpy's nanmedian, computed at once (issue 32, H5)."""

from __future__ import annotations

import warnings

import numpy as np

from tftools.analysis.wtf.jumps import _nan_median


def test_the_median_of_each_row_skips_nans_as_numpy_does() -> None:
    rng = np.random.default_rng(32)
    rows = rng.exponential(1.0, (5000, 6))
    rows[rng.random(rows.shape) < 0.3] = np.nan
    rows[:50] = np.nan  # rows with no speed at all: no motion to explain
    rows[50:60, :] = np.inf
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        expected = np.nan_to_num(np.nanmedian(rows, axis=1), nan=0.0, posinf=np.inf)
    np.testing.assert_array_equal(_nan_median(rows), expected)
