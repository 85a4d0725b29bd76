"""What a first load imports: ``python -X importtime`` of ``import tftools; tftools.read_recording([BAG])``,
summed over the modules, for one or more interpreters (each its own checkout's tftools), interleaved.

Run: ``python benchmarks/imports.py [--runs 5] [--bag sample_bags/robot.bag] [--top 15] [PYTHON ...]`` (no
PYTHON: this one). Prints, per interpreter, the median over the runs of the sum of every module's own
import time, of tftools' modules' alone, how many modules and tftools modules were loaded, and the
modules whose own time weighs most; with the machine's load (times under load are longer, counts are not).
Bytecode is cached as in ``ratios.py`` (``--compile-each-run``: as the environment has it).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from ratios import ENV, cached_bytecode

HERE = Path(__file__).resolve().parent
LOAD = "import tftools; tftools.read_recording([{bag!r}])"


def imported(python: str, bag: Path) -> dict[str, int]:
    """Each module's own import time (µs) in a fresh process of ``python`` that loads ``bag``."""
    done = subprocess.run(
        [python, "-X", "importtime", "-c", LOAD.format(bag=str(bag))], capture_output=True, text=True, cwd="/", env=ENV
    )
    if done.returncode != 0:
        sys.exit(f"{python} failed:\n{done.stderr}")
    own: dict[str, int] = {}
    for line in done.stderr.splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        self_us, _, name = line.removeprefix("import time:").split("|")
        own[name.strip()] = int(self_us)
    return own


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("pythons", nargs="*", help="interpreters, each with its own tftools (default: this one)")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--bag", type=Path, default=HERE.parent / "sample_bags" / "robot.bag")
    parser.add_argument("--top", type=int, default=15, help="modules shown by their median own time")
    parser.add_argument("--compile-each-run", action="store_true", help="no bytecode cache set up")
    args = parser.parse_args()
    if not args.compile_each_run:
        prefix = tempfile.TemporaryDirectory(prefix="tftools-bytecode-")
        cached_bytecode(prefix.name)
    pythons = [os.path.abspath(p) for p in args.pythons] or [sys.executable]
    loads = [os.getloadavg()[0]]
    runs: dict[str, list[dict[str, int]]] = {p: [] for p in pythons}
    if not args.compile_each_run:
        for python in pythons:
            imported(python, args.bag.resolve())  # a warm-up: the bytecode written once
    for _ in range(args.runs):
        for python in pythons:
            runs[python].append(imported(python, args.bag.resolve()))
        loads.append(os.getloadavg()[0])
    for python, each in runs.items():
        total = statistics.median(sum(r.values()) for r in each)
        ours = statistics.median(sum(t for m, t in r.items() if m.startswith("tftools")) for r in each)
        count = statistics.median(len(r) for r in each)
        our_count = statistics.median(sum(m.startswith("tftools") for m in r) for r in each)
        print(f"{python}: all modules {total / 1e3:.0f} ms ({count:.0f} modules), tftools' own "
              f"{ours / 1e3:.0f} ms ({our_count:.0f} modules)")  # fmt: skip
        names = {m for r in each for m in r}
        heavy = sorted(names, key=lambda m: -statistics.median(r.get(m, 0) for r in each))[: args.top]
        for name in heavy:
            print(f"  {statistics.median(r.get(name, 0) for r in each) / 1e3:6.1f} ms  {name}")
    bytecode = "compiled in every process" if args.compile_each_run else "cached"
    print(f"\nmedians of {args.runs} runs, interleaved; load average (1 min) {min(loads):.1f}-{max(loads):.1f} "
          f"on {os.cpu_count()} cores; bytecode {bytecode}")  # fmt: skip


if __name__ == "__main__":
    main()
