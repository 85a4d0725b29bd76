"""``gather.among``: ``np.isin`` of integers, without the import of numpy.ma its ``np.unique`` makes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from tftools.sources.codecs.gather import among


def test_among_is_numpys_isin() -> None:
    rng = np.random.default_rng(11)
    for count in (0, 1, 2, 7, 1_000, 30_000):
        for members_count in (0, 1, 5, 3_000):
            values = rng.integers(-50, 5_000, count).astype(np.int64) << 30
            members = rng.integers(-50, 5_000, members_count).astype(np.int64) << 30
            for side in (members, np.sort(members), np.sort(members)[::-1].copy()):
                assert among(values, side).tolist() == np.isin(values, side).tolist(), (count, members_count)
    assert among(np.array([3, 1, 3], np.int64), np.array([3, 3], np.int64)).tolist() == [True, False, True]


def test_among_leaves_numpy_ma_unimported() -> None:
    code = "import sys, numpy as np; from tftools.sources.codecs.gather import among; "
    code += "among(np.arange(10**5) << 40, np.arange(0, 10**5, 3) << 40); print('numpy.ma' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
