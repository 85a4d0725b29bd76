"""What a window of record time costs ``BagReader`` against the whole recording, in each format: a
60 s window amid an hours-long recording, an empty one (the files' descriptions only), the whole.

Run: ``python3 benchmarks/window.py [BAG ...]`` (default: the 4800 s robot of benchmarks/vs_tf2.py
under /tmp/tftools-bench, as a ROS1 bag, a rosbag2 .db3 and a rosbag2 MCAP). Thread CPU time and
wall time (the files in the page cache), the best of a few interleaved runs; the load average
printed with them. Prints figures, asserts nothing.
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

from timing import read_whole

from tftools.core.time import NS_PER_S
from tftools.sources.bag.contents import RecordWindow

BENCH = Path("/tmp/tftools-bench")
BAGS = [BENCH / "robot_4800s.bag", BENCH / "robot_4800s_db3", BENCH / "robot_4800s_mcap"]
WIDTH = 60 * NS_PER_S
REPEAT = 3


def main(paths: list[Path]) -> None:
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    for path in paths:
        info = read_whole([path], window=RecordWindow(0, 0)).files[0]
        middle = (info.start + info.end) // 2
        reads = {
            "60 s window": RecordWindow(middle, middle + WIDTH),
            "empty window": RecordWindow(middle, middle),
            "whole": None,
        }
        best = dict.fromkeys(reads, math.inf)
        wall = dict.fromkeys(reads, math.inf)
        counts = dict.fromkeys(reads, 0)
        for _ in range(REPEAT):  # interleaved: the machine's load falls on each alike
            for label, window in reads.items():
                began, began_wall = time.thread_time(), time.perf_counter()
                contents = read_whole([path], window=window)
                best[label] = min(best[label], time.thread_time() - began)
                wall[label] = min(wall[label], time.perf_counter() - began_wall)
                counts[label] = sum(len(p) for p in contents.parts)
        print(f"{path.name} ({(info.end - info.start) / NS_PER_S:.0f} s, {info.format}, windowed {info.windowed})")
        for label in reads:
            share = best[label] / best["whole"]
            print(
                f"  {label:<14} {counts[label]:>9} transforms  {best[label]:7.3f} s thread time ({share:6.1%})"
                f"  {wall[label]:7.3f} s wall"
            )
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main([Path(p) for p in sys.argv[1:]] or BAGS)
