"""Where a single ``Buffer.lookup`` call's time goes, in parts measured apart (issue 41): the loop and a bare C
call, the arguments read and the names resolved (``can_transform`` of names the buffer does not know, which
stops there), the walk with its stamp searches (``can_transform`` of the benchmark's frames), and the whole
lookup (the edges sampled, composed, and the answer made). CPU time per call, the minimum over ``--runs``
passes of ``--calls`` calls each, in this process; the 300 s robot of ``vs_tf2.py`` at tf2_side's times.

Run: ``python benchmarks/lookup_parts.py [--runs 15] [--calls 20000]``. Prints one JSON object (ns a call).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import robot
from ours_side import lookup_times
from vs_tf2 import UNIT_SECONDS, write_bags

from tftools.sources.recording import read_recording


def per_call_ns(action: Callable[[int], object], times: list[int], runs: int) -> float:
    """The least CPU time a call of ``action`` took, over ``runs`` passes of ``times``."""
    best = float("inf")
    for _ in range(runs):
        began = time.process_time()
        for t in times:
            action(t)
        best = min(best, time.process_time() - began)
    return best / len(times) * 1e9


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--calls", type=int, default=20_000)
    args = parser.parse_args()
    buffer = read_recording([write_bags(UNIT_SECONDS, images=False)["ros1"]]).buffer
    target, source = robot.TARGET, robot.SOURCE
    times = lookup_times(args.calls, UNIT_SECONDS)
    assert buffer.can_transform(target, source, times[0]) and not buffer.can_transform("nowhere", "elsewhere")
    parts = {
        "loop_and_a_c_call": lambda t: len(target),
        "arguments_and_names": lambda t: buffer.can_transform("nowhere", "elsewhere", t),
        "arguments_names_and_walk": lambda t: buffer.can_transform(target, source, t),
        "lookup": lambda t: buffer.lookup(target, source, t),
        "lookup_one_time_again": lambda t: buffer.lookup(target, source, times[0]),
    }
    print(json.dumps({name: round(per_call_ns(action, times, args.runs), 1) for name, action in parts.items()}))


if __name__ == "__main__":
    main()
