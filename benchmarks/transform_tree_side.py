"""transform-tree's side of the benchmark (``pip install transform-tree``, imported as ``tf_tree``),
run by this interpreter, one measurement per process as the other sides.

``measure MCAP LOOKUPS SECONDS``: the robot built by hand with tf2's interpolation (``lerpslerp``)
and its statics declared static: ``push`` one call per transform, ``Tree.lookup`` per call at
tf2_side's times, a ``Plan``'s batch of a million times (the first in this process, then the
next); then ``ingest_bag`` on the robot's MCAP file (its own reader, its own interpolation).
Prints one JSON object.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import tf_tree

sys.path.insert(0, str(Path(__file__).resolve().parent))
import robot
from ours_side import BATCH, SET_CALLS, lookup_times, per_call, random_times


def pose(values: tuple[float, ...]) -> list[float]:
    """tftools' (tx ty tz qx qy qz qw) as transform-tree's (qw qx qy qz tx ty tz)."""
    tx, ty, tz, qx, qy, qz, qw = values
    return [qw, qx, qy, qz, tx, ty, tz]


def config(seconds: int) -> str:
    """The robot's topology: its statics with their poses, its moving edges with room for every sample."""
    _record, _topic, _callerid, statics = next(robot.messages(seconds))
    edges = [
        f'[[edge]]\nparent = "{parent}"\nchild = "{child}"\nkind = "static"\npose = {pose(values)}\n'
        for parent, child, _stamp, values in statics  # type: ignore[attr-defined]
    ]
    for _callerid, hz, pairs in robot.PUBLISHERS:
        edges += [
            f'[[edge]]\nparent = "{parent}"\nchild = "{child}"\nkind = "dynamic"\n'
            f'capacity = {seconds * hz + 16}\ninterp = "lerpslerp"\n'
            for parent, child in pairs
        ]
    return "".join(edges)


def measure(mcap: str, lookups: int, seconds: int) -> dict:
    tree = tf_tree.build(config(seconds))
    moving = robot.dynamic_transforms(seconds, SET_CALLS)
    calls = [(child, parent, stamp, pose(values)) for parent, child, stamp, values, _ in moving]
    set_transform_s = per_call(lambda call: tf_tree.push(tree, *call), calls)[0]
    tree = tf_tree.build(config(seconds))
    for parent, child, stamp, values, _ in robot.dynamic_transforms(seconds, 10**12):
        tf_tree.push(tree, child, parent, stamp, pose(values))
    times = lookup_times(lookups, seconds)
    lookup_s = per_call(lambda t: tree.lookup(robot.TARGET, robot.SOURCE, t), times)[0]
    result = {"set_transform_s": set_transform_s, "lookup_s": lookup_s}
    plan = tree.plan(robot.TARGET, robot.SOURCE)
    for which in ("first", "next"):
        many = random_times(seconds)
        began = time.perf_counter()
        plan.at(many)
        result[f"batch_{which}_s"] = (time.perf_counter() - began) / BATCH
    first = [tree.lookup(robot.TARGET, robot.SOURCE, t)[:3, 3] for t in times[:1000]]
    began = time.perf_counter()
    ingested = tf_tree.ingest_bag(mcap)
    result["mcap_ingest_s"] = time.perf_counter() - began
    assert ingested.frames()
    return {**result, "checksum": float(np.sum(first))}


def main() -> None:
    mcap, lookups, seconds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    print(json.dumps(measure(mcap, lookups, seconds)))


if __name__ == "__main__":
    main()
