"""Timing for the ingest benchmarks: the best of a few runs, as transforms per second."""

from __future__ import annotations

import math
import time
from collections.abc import Callable


def timed(label: str, run: Callable[[], int], repeat: int = 3) -> int:
    """Run ``run`` (which returns how many transforms it read) ``repeat`` times; print the best."""
    best, count = math.inf, 0
    for _ in range(repeat):
        began = time.perf_counter()
        count = run()
        best = min(best, time.perf_counter() - began)
    print(f"{label:<52} {count:>8} transforms  {best:6.3f} s  {count / best / 1000:8.0f}k transforms/s")
    return count
