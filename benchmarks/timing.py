"""Timing for the ingest benchmarks: the best of a few runs, as transforms per second."""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from tftools.sources.bag import BagContents, BagReader, RecordWindow


def read_whole(paths: Sequence[str | os.PathLike[str]], window: RecordWindow | None = None) -> BagContents:
    """The recording at ``paths`` read at once through ``BagReader`` (a ``window`` of it: its record times)."""
    with BagReader(paths) as reader:
        return reader.read(window)


def timed(label: str, run: Callable[[], int], repeat: int = 3) -> int:
    """Run ``run`` (which returns how many transforms it read) ``repeat`` times; print the best."""
    best, count = math.inf, 0
    for _ in range(repeat):
        began = time.perf_counter()
        count = run()
        best = min(best, time.perf_counter() - began)
    print(f"{label:<52} {count:>8} transforms  {best:6.3f} s  {count / best / 1000:8.0f}k transforms/s")
    return count


def rosbags_transforms(bag: Path) -> int:
    """Every tf message of ``bag`` read and deserialized by rosbags, for comparison: its transforms."""
    from tftools.sources.codecs.types import typestore

    if bag.suffix == ".bag":
        from rosbags.rosbag1 import Reader

        deserialize = typestore("ros1_noetic").deserialize_ros1
    else:
        from rosbags.rosbag2 import Reader  # type: ignore[assignment]

        deserialize = typestore("ros2_humble").deserialize_cdr
    with Reader(bag) as reader:
        tf = [c for c in reader.connections if c.topic in ("/tf", "/tf_static")]
        return sum(len(deserialize(raw, c.msgtype).transforms) for c, _, raw in reader.messages(connections=tf))
