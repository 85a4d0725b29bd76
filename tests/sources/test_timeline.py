"""A recording's timeline: each frame's clock medians as numpy's median gives them."""

from __future__ import annotations

import numpy as np
import pytest

from tftools import BatchBuilder, Buffer
from tftools.sources.contents import ClockSamples
from tftools.sources.timeline import timeline_of

START = 1_700_000_000 * 10**9


@pytest.mark.parametrize("rows", [1, 2, 7, 10])
@pytest.mark.parametrize("records_in_order", [True, False])
def test_edge_medians_are_numpys(rows: int, records_in_order: bool) -> None:
    """Stamps far apart (np.median rounds their mean through a double), record times in or out of order."""
    rng = np.random.default_rng(rows)
    stamps = np.sort(START + rng.integers(0, 10**12, rows))
    records = stamps + rng.integers(1, 10**9, rows)
    if not records_in_order:
        records = records[::-1].copy()
    builder = BatchBuilder()
    for stamp, record in zip(stamps.tolist(), records.tolist(), strict=True):
        builder.add("odom", "base", stamp, (0, 0, 0), (0, 0, 0, 1), record_time=record)
    builder.add("base", "laser", START, (0, 0, 0), (0, 0, 0, 1), static=True, record_time=START)
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    (edge,) = timeline_of(buffer, ClockSamples.empty(), START, START + 10**12).edges
    assert (edge.child, edge.arrivals) == ("base", rows)
    assert edge.median_stamp == int(np.median(stamps))
    assert edge.median_record == int(np.median(records))
    assert edge.offset_record == int(np.median(records - stamps))
