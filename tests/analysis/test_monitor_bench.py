"""How long the statistics of a long recording take (printed, not asserted: figures, not timing tests)."""

from __future__ import annotations

import time

import numpy as np
import pytest

from tftools.analysis.edges import TimeWindow
from tftools.analysis.monitor import monitor_buffer
from tftools.core.batch import TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.figures import seconds
from tftools.core.time import NS_PER_S, SimClock

START = 1_700_000_000 * NS_PER_S
RATES = [10, 50, 30, 50, 100, 100, 50, 50, 30, 20]  # a chain l0 -> l1 -> ... -> l10


def _long_recording(seconds: int) -> Buffer:
    ids, stamps = [], []
    for edge, hz in enumerate(RATES):
        n = seconds * hz
        ids.append(np.full(n, edge, np.int32))
        stamps.append(START + np.arange(n, dtype=np.int64) * (NS_PER_S // hz))
    edge_ids, stamp = np.concatenate(ids), np.concatenate(stamps)
    order = np.argsort(stamp + 2_000_000, kind="stable")
    edge_ids, stamp = edge_ids[order], stamp[order]
    n = len(stamp)
    batch = TransformBatch(
        [f"l{i}" for i in range(len(RATES) + 1)], ["/pub"], edge_ids, edge_ids + 1, stamp,
        np.zeros((n, 3)), np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)), np.zeros(n, bool), stamp + 2_000_000,
    )  # fmt: skip
    buffer = Buffer(cache_time=None, clock=SimClock(int(stamp[-1]) + 2_000_000))
    buffer.insert(batch)
    return buffer


def test_twenty_minutes_of_ten_edges(capsys: pytest.CaptureFixture[str]) -> None:
    buffer = _long_recording(20 * 60)
    began = time.perf_counter()
    report = monitor_buffer(buffer, "l0", "l10", TimeWindow(by_record_time=True))
    took = time.perf_counter() - began
    rows = sum(len(h) for _, h in buffer.histories())
    with capsys.disabled():
        print(f"\nmonitor with a 10-edge chain over {rows} transforms: {took * 1000:.0f} ms")
    assert [round(e.rate_hz, 6) for e in report.edges] == RATES
    assert report.chain is not None and report.chain.limiting == ("l0", "l1")  # the 10 Hz edge
    assert seconds(report.chain.delay_max) == pytest.approx(0.1 + 0.002, abs=1e-9)
