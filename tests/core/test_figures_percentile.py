"""``figures.percentile``: numpy's percentile, to the bit, without the import of numpy.ma its first call makes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from tftools.core.figures import median_and_percentile, median_ns, percentile


def test_percentile_is_numpys_to_the_bit() -> None:
    rng = np.random.default_rng(7)
    for count in [*range(1, 60), 101, 1_000, 4_097]:
        for scale in (10, 1_000_000, 2**62):
            values = rng.integers(0, scale, count, dtype=np.int64)
            for q in (0, 1, 5, 25, 50, 95, 99, 99.9, 100, 95.0, 33.3):
                assert percentile(values, q) == np.percentile(values, q), (count, scale, q)
    ties = np.array([5, 5, 5, 7, 7, 1], np.int64)
    assert [percentile(ties, q) for q in (0, 50, 95, 100)] == [np.percentile(ties, q) for q in (0, 50, 95, 100)]


def test_percentile_leaves_its_values_and_numpy_ma_alone() -> None:
    values = np.array([3, 1, 2], np.int64)
    percentile(values, 95)
    assert values.tolist() == [3, 1, 2]
    code = "import sys, numpy as np; from tftools.core.figures import percentile; "
    code += "percentile(np.arange(10), 95); print('numpy.ma' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


def test_median_and_percentile_from_one_partition_are_each_ones() -> None:
    rng = np.random.default_rng(3)
    for count in [1, 2, 3, 4, 5, 20, 21, 1_000, 4_097]:
        for values in (rng.integers(0, 2**62, count, dtype=np.int64), np.arange(count, dtype=np.int64) * 7):
            for q in (0, 50, 95, 99.9, 100):
                copy = values.copy()
                assert median_and_percentile(copy, q) == (median_ns(values), percentile(values, q)), (count, q)
                assert copy.tobytes() == values.tobytes()
