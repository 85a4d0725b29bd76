"""tftools' side of the benchmark, one measurement per process so peak memory is its own.

``ingest BAG``: ``read_recording`` (read every tf message, build the buffer), split into reading
(``BagReader``) and inserting (``recording_of``), the readers' modules imported first.

``lookups BAG N SECONDS``: ``Buffer.lookup`` and ``can_transform`` in a Python loop
at tf2_side's times, then ``lookup_many`` at a million times, and ``set_transform`` one call
per transform into a new buffer (tf2_side's transforms).

``batch BAG SECONDS``: the first ``lookup_many`` of a million times in a process that has looked
nothing up yet (what a script's first batch costs), then the next.

Each prints one JSON object.
"""

from __future__ import annotations

import json
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import robot
from spent import spent_since, usage
from timing import read_whole

from tftools.core.buffer import Buffer
from tftools.core.transform import Transform
from tftools.sources.recording import read_recording, recording_of

try:
    from tftools.core.kernels import threads_for
except ImportError:  # an earlier checkout (``ratios.py --against``): the same count, from before it was named

    def threads_for(n: int) -> int:
        return max(1, min(os.cpu_count() or 1, n // 50_000))


BATCH = 1_000_000
SET_CALLS = 100_000  # as tf2_side


def peak_rss() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def ingest(path: str) -> dict:
    import_readers()
    before = peak_rss()
    spent, began = usage(), time.perf_counter()
    contents = read_whole([path])
    read_s = time.perf_counter() - began
    began = time.perf_counter()
    recording = recording_of(contents)  # the buffer takes the rows: they are held once
    insert_s = time.perf_counter() - began
    return {
        "transforms": recording.transform_count,
        "read_s": read_s,
        "insert_s": insert_s,
        "ingest_s": read_s + insert_s,
        **spent_since(spent, "ingest"),
        "peak_rss_bytes": peak_rss(),
        "rss_before_bytes": before,
    }


def import_readers() -> None:
    """The bag readers' modules and what they import on first use, imported before the clock
    starts, as tf2's side imports rosbag: what is measured is reading, not importing (which
    ``vs_tf2.py --commands`` counts, in each command's whole run)."""
    import ruamel.yaml  # noqa: F401 (a metadata.yaml that yaml_subset does not read)

    from tftools.sources import yaml_subset  # noqa: F401 (rosbag2's metadata.yaml; its regexes: ~2.4 ms)
    from tftools.sources.bag import mcap, ros1, rosbag2  # noqa: F401
    from tftools.sources.bag.rosbag2 import db3  # noqa: F401
    from tftools.sources.codecs import cdr  # noqa: F401 (the codec table imports the codecs on first use)
    from tftools.sources.codecs import ros1 as ros1_codecs  # noqa: F401


def lookup_times(count: int, seconds: int) -> list[int]:
    """The times tf2_side looks up at (same formula)."""
    first, span = robot.START + robot.NS, (seconds - 2) * robot.NS
    return [first + (k * 7_919_000_017) % span for k in range(count)]


def per_call(action, items) -> tuple[float, float]:
    """Seconds a call, wall and CPU (as tf2_side's)."""
    cpu, began = time.process_time(), time.perf_counter()
    for item in items:
        action(item)
    return (time.perf_counter() - began) / len(items), (time.process_time() - cpu) / len(items)


def lookups(path: str, count: int, seconds: int) -> dict:
    buffer = read_recording([path]).buffer
    target, source = robot.TARGET, robot.SOURCE
    times = lookup_times(count, seconds)
    lookup_s, lookup_cpu_s = per_call(lambda t: buffer.lookup(target, source, t), times)
    can_s, can_cpu_s = per_call(lambda t: buffer.can_transform(target, source, t), times)
    many = random_times(seconds)
    buffer.lookup_many(target, source, many[:10])
    result = {
        "lookup_s": lookup_s,
        "lookup_cpu_s": lookup_cpu_s,
        "can_transform_s": can_s,
        "can_transform_cpu_s": can_cpu_s,
    }
    for order, asked in (("random", many), ("sorted", np.sort(many))):
        began = time.perf_counter()
        got = buffer.lookup_many(target, source, asked)
        result[f"lookup_many_{order}_s"] = (time.perf_counter() - began) / BATCH
        assert got.valid.all()
    first = [buffer.lookup(target, source, t).translation for t in times[:1000]]
    set_s, set_cpu_s = set_transform_per_call(seconds)
    result |= {"set_transform_s": set_s, "set_transform_cpu_s": set_cpu_s}
    return {**result, "checksum": float(np.sum(first))}


def set_transform_per_call(seconds: int) -> tuple[float, float]:
    """One ``Buffer.set_transform`` call's time, wall and CPU, on tf2_side's transforms built beforehand."""
    calls = [
        (Transform(values[:3], values[3:], stamp, parent, child), callerid)
        for parent, child, stamp, values, callerid in robot.dynamic_transforms(seconds, SET_CALLS)
    ]
    buffer = Buffer(cache_time=None)
    return per_call(lambda call: buffer.set_transform(*call), calls)


def random_times(seconds: int):
    rng = np.random.default_rng(1)
    return rng.integers(robot.START + robot.NS, robot.START + (seconds - 1) * robot.NS, BATCH)


def batch(path: str, seconds: int) -> dict:
    """Each call's wall time per time, and what it spent (``spent.py``: the CPU time of all its threads, the
    page faults, steal; the wait is the calling thread's alone, the others' ended with the call), with the
    threads it ran on."""
    buffer = read_recording([path]).buffer
    result: dict = {"batch_times": BATCH, "batch_threads": threads_for(BATCH)}
    for which in ("first", "next"):
        times = random_times(seconds)
        spent, began = usage(), time.perf_counter()
        buffer.lookup_many(robot.TARGET, robot.SOURCE, times)
        result[f"batch_{which}_s"] = (time.perf_counter() - began) / BATCH
        result.update(spent_since(spent, f"batch_{which}"))
    return result


def main() -> None:
    command, path, *numbers = sys.argv[1:]
    commands = {"ingest": ingest, "lookups": lookups, "batch": batch}
    result = commands[command](path, *map(int, numbers))
    print(json.dumps(result))


if __name__ == "__main__":
    main()
