"""``sent_before``: a sample whose stamp, and value bit for bit, an earlier one of its stream carried."""

from __future__ import annotations

import numpy as np

from tftools.analysis.wtf.broadcasters import sent_before


def test_a_sample_is_sent_again_where_its_stamp_and_every_bit_of_its_value_were() -> None:
    stamps = np.array([5, 5, 5, 3, 5, 3, 5, 5], np.int64)
    values = np.zeros((8, 7))
    values[:, 6] = 1.0
    values[2, 0] = -0.0  # not 0.0's bits: another value
    values[4, 1] = values[6, 1] = np.nan  # the same NaN twice: the same bits
    values[7, 2] = 1e-300  # off by a hair
    assert sent_before(stamps, values).tolist() == [False, True, False, False, False, True, True, False]
    assert sent_before(stamps).tolist() == [False, True, True, False, True, True, True, True]


def test_the_first_of_each_sample_is_kept_however_the_stream_is_ordered() -> None:
    rng = np.random.default_rng(7)
    stamps = rng.integers(0, 20, 5000).astype(np.int64)
    values = rng.choice([0.0, -0.0, 1.0, np.nan], size=(5000, 7))
    again = sent_before(stamps, values)
    seen: set[bytes] = set()
    for stamp, value, repeated in zip(stamps.tolist(), values, again.tolist(), strict=True):
        key = np.int64(stamp).tobytes() + value.tobytes()
        assert repeated == (key in seen)
        seen.add(key)
