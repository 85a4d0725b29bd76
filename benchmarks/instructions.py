"""Instructions per lookup, which a busy machine does not change: callgrind counts a loop of calls on a
10-edge chain, less the same script without the loop, divided by the calls.

Run: ``python benchmarks/instructions.py [--python PYTHON] [--calls 20000] [MEASURE ...]`` (needs
valgrind). Each part of a lookup's cost is measured apart, each in its own process: ``lookup``
(``Buffer.lookup``, a success), ``failed`` (an extrapolation: the error worded), ``can_transform``,
``dispatch`` (the same lookup through the binding's ordinary call, ``BufferCore.lookup_frames``:
nanobind's dispatch is the difference), ``wrap`` (building the answer in Python, ``Transform(...)``,
as a binding returning a tuple would need) and ``set_transform`` (its sample's building, ``wrap``,
taken off) and ``batch`` (``lookup_many`` per time, the random times' making included). Prints JSON.

The ``robot_*`` measures take issue 41's workload instead (``ours_side.py``'s: vs_tf2.py's 300 s robot bag, written
first by ``vs_tf2.py`` or ``ratios.py``; ``--bag``): ``robot_lookup`` (map -> arm_link6 at tf2_side's times, each
far from the last: 8 moving edges that slerp, 2 static), ``robot_can_transform``, ``robot_set_transform`` (the
robot's moving transforms in record order, built beforehand, into a new buffer) and ``robot_batch`` (one
``lookup_many`` of 1M random times, per time); the same script without the calls is subtracted.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

#: The loop each measure runs ``n`` times; the same script with no loop is subtracted.
CALLS = {
    "lookup": "f = buf.lookup\nfor _ in range(n): f(target, source, at)",
    "failed": "f = buf.lookup\nfor _ in range(n):\n    try: f(target, source, late)\n    except TransformError: pass",
    "can_transform": "f = buf.can_transform\nfor _ in range(n): f(target, source, at)",
    "dispatch": "f = buf._core.lookup_frames\nfor _ in range(n): f(target, source, at)",
    "wrap": "for _ in range(n): Transform(t, r, at, target, source)",
    # per time of a batch: ``n`` random times in 10 calls of ``lookup_many`` (its threads counted alike)
    "batch": "times = np.random.default_rng(1).integers(S, 99 * S, n // 10)\n"
    "for _ in range(10): buf.lookup_many(target, source, times)",
    # its samples built in the loop: ``wrap`` is subtracted from it
    "set_transform": "f = buf.set_transform\nfor k in range(n): f(Transform(t, r, (100 + k) * S, 'f9', 'f10'), 'a')",
}

SETUP = """
import sys
import numpy as np
from tftools.core.buffer import Buffer
from tftools.core.errors import TransformError
from tftools.core.transform import Transform
n = int(sys.argv[1])
S = 1_000_000_000
buf = Buffer(cache_time=None)
frames = [f"f{i}" for i in range(11)]
t, r = (1.0, 0.5, 0.25), (0.0, 0.0, 0.38268343, 0.92387953)
for parent, child in zip(frames, frames[1:]):
    for k in range(100):
        buf.set_transform(Transform(t, r, k * S, parent, child), "a")
target, source, at, late = frames[0], frames[-1], 50 * S + 123_456_789, 200 * S
buf.lookup(target, source, at)
"""


#: Issue 41's workload: ``n`` calls (``robot_batch``: one batch of BATCH times), their arguments made whatever ``n``.
ROBOT_CALLS = {
    "robot_lookup": "f = buf.lookup\nfor t in times[:n]: f(T, S, t)",
    "robot_can_transform": "f = buf.can_transform\nfor t in times[:n]: f(T, S, t)",
    "robot_set_transform": "f = Buffer(cache_time=None).set_transform\nfor call in calls[:n]: f(*call)",
    "robot_batch": "if n: buf.lookup_many(T, S, many)",
}
BATCH = 1_000_000

ROBOT_SETUP = f"""
import sys
sys.path.insert(0, {str(Path(__file__).resolve().parent)!r})
import numpy as np
import ours_side, robot
from tftools import read_recording
from tftools.core.buffer import Buffer
from tftools.core.transform import Transform
n, COUNT = int(sys.argv[1]), int(sys.argv[2])
buf = read_recording([sys.argv[3]]).buffer
T, S = robot.TARGET, robot.SOURCE
times = ours_side.lookup_times(COUNT, 300)
many = np.random.default_rng(1).integers(robot.START + robot.NS, robot.START + 299 * robot.NS, {BATCH})
calls = [(Transform(v[:3], v[3:], st, p, c), cid) for p, c, st, v, cid in robot.dynamic_transforms(300, COUNT)]
buf.lookup(T, S, times[0]), buf.lookup_many(T, S, many[:10])
"""


def instructions(python: str, code: str, n: int, setup: str = SETUP, *arguments: str) -> int:
    """Instructions callgrind counts for the setup and ``code`` run with ``n`` (and ``arguments``)."""
    with tempfile.TemporaryDirectory() as tmp:
        script, out = Path(tmp) / "run.py", Path(tmp) / "callgrind.out"
        script.write_text(setup + code + "\n")
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", python, str(script), str(n), *arguments],
            check=True,
            capture_output=True,
            cwd="/",
            # The same start-up in every process (its count is subtracted); numpy's BLAS threads, which spin a
            # varying while, kept out.
            env={**os.environ, "PYTHONHASHSEED": "0", "OPENBLAS_NUM_THREADS": "1"},
        )
        for line in out.read_text().splitlines():
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise RuntimeError("callgrind wrote no totals")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--python", default=sys.executable)
    parser.add_argument("--calls", type=int, default=20_000)
    parser.add_argument("--bag", default="/tmp/tftools-bench/robot_300s.bag", help="the robot_* measures' bag")
    parser.add_argument("measures", nargs="*", default=list(CALLS), help=f"of {[*CALLS, *ROBOT_CALLS]}")
    args = parser.parse_args()
    out = {}
    simple = [name for name in args.measures if name in CALLS]
    if simple:
        empty = instructions(args.python, "", 0)
        for name in simple:
            out[name] = round((instructions(args.python, CALLS[name], args.calls) - empty) / args.calls)
    on_robot = [name for name in args.measures if name in ROBOT_CALLS]
    if on_robot:
        if not Path(args.bag).exists():
            parser.error(f"{args.bag}: no such bag; write it with benchmarks/vs_tf2.py --scales 1, or give --bag")
        robot_args = (str(args.calls), args.bag)
        empty = instructions(args.python, "", 0, ROBOT_SETUP, *robot_args)
        for name in on_robot:
            total = instructions(args.python, ROBOT_CALLS[name], args.calls, ROBOT_SETUP, *robot_args) - empty
            out[name] = round(total / (BATCH if name == "robot_batch" else args.calls))
    if "set_transform" in out and "wrap" in out:
        out["set_transform"] -= out["wrap"]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
