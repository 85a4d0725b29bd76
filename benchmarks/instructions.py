"""Instructions per lookup, which a busy machine does not change: callgrind counts a loop of calls on a
10-edge chain, less the same script without the loop, divided by the calls.

Run: ``python benchmarks/instructions.py [--python PYTHON] [--calls 20000] [MEASURE ...]`` (needs
valgrind). Each part of a lookup's cost is measured apart, each in its own process: ``lookup``
(``Buffer.lookup``, a success), ``failed`` (an extrapolation: the error worded), ``can_transform``,
``dispatch`` (the same lookup through the binding's ordinary call, ``BufferCore.lookup_frames``:
nanobind's dispatch is the difference), ``wrap`` (building the answer in Python, ``Transform(...)``,
as a binding returning a tuple would need) and ``set_transform`` (its sample's building, ``wrap``,
taken off) and ``batch`` (``lookup_many`` per time, the random times' making included). Prints JSON.
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


def instructions(python: str, code: str, n: int) -> int:
    """Instructions callgrind counts for the setup and ``code`` run with ``n``."""
    with tempfile.TemporaryDirectory() as tmp:
        script, out = Path(tmp) / "run.py", Path(tmp) / "callgrind.out"
        script.write_text(SETUP + code + "\n")
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", python, str(script), str(n)],
            check=True,
            capture_output=True,
            cwd="/",
            env={**os.environ, "PYTHONHASHSEED": "0"},  # the same start-up in every process: its count is subtracted
        )
        for line in out.read_text().splitlines():
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise RuntimeError("callgrind wrote no totals")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--python", default=sys.executable)
    parser.add_argument("--calls", type=int, default=20_000)
    parser.add_argument("measures", nargs="*", default=list(CALLS))
    args = parser.parse_args()
    empty = instructions(args.python, "", 0)
    out = {
        name: round((instructions(args.python, CALLS[name], args.calls) - empty) / args.calls) for name in args.measures
    }
    if "set_transform" in out and "wrap" in out:
        out["set_transform"] -= out["wrap"]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
