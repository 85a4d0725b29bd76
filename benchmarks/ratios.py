"""Issue 41's ratios against tf2 in one run: tf2's time over tftools', per measure, run by run.

Run: ``python benchmarks/ratios.py [--runs 5] [--against PYTHON]``. Each run starts every side afresh
(a new process each), the sides interleaved (tf2, tftools, then the other tftools of ``--against``), so
that a shared machine's load falls on all of them alike; each figure is the median of the runs, and
each ratio is shown as its median and its range over the runs (a goal "every run" is met when the
range's low end meets it). ``--against`` is an interpreter whose ``tftools`` is another version (a
"before"), measured the same way in the same runs. The workload is ``vs_tf2.py``'s 300 s robot
(258k transforms) as .bag, .db3 and .mcap; tf2 is Debian's rosbag + tf2_py (``tf2_side.py``).

The whole script is the wall time of a process that imports, loads the bag and looks one transform up
(``tftools.read_recording`` / rosbag + ``BufferCore``); ingest is ``ours_side.py``'s (imports paid before the
clock, as on tf2's side) and, as a user's first ``load`` pays them, with tftools' lazy imports counted.
Every process reads its modules' cached bytecode, as an installed package's (pip and Debian compile
theirs at install): checkouts have none when ``PYTHONDONTWRITEBYTECODE`` is set, and then every process
compiled tftools' sources again (~65 ms of a whole script's ~240 ms), while tf2's came compiled. The
bytecode is kept under a temporary ``PYTHONPYCACHEPREFIX`` (no checkout written to), filled by one
unmeasured warm-up run of every side; ``--compile-each-run`` measures as before, with the environment as it is.

Every run's own figures are kept, both sides', with the CPU time of the same span where there is one (the
whole script and ``tfx frames``: the child process's; the ingest and first load: the measured span's, from
within; the calls' (lookup, ``can_transform``, ``set_transform``): their loop's; the ingest's also the time it
waited for a CPU and the machine's steal time, ``spent.py``; the batch's, per time, its threads' CPU time over
their count, so that on free cores it is about the wall time). A span
is disturbed, and named below the table whichever side it is on, where it spent a good part of its wall
time off the CPU (another process held it, or the disk was read) or took a good deal more CPU time than
its other runs (the same work slowed by a neighbour's: see ``DISTURBED``); ``--raw`` prints every run's
figures, ``--json FILE`` writes them.
Asserts nothing; prints the table and the machine's load.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import robot
from vs_tf2 import HERE, LOOKUPS, ROS_PYTHON, UNIT_SECONDS, real_rosbag, settle, write_bags

SAMPLE = HERE.parent / "sample_bags" / "robot.bag"
#: A user's whole script, and a user's first load (tftools imported, the rest paid inside the clock).
SCRIPT = (
    "import tftools; b = tftools.read_recording([{bag!r}]).buffer; "
    "print(b.lookup({target!r}, {source!r}, {at}).translation[0])"
)
FIRST_LOAD = (
    "import json, time, tftools; cpu, began = time.process_time(), time.perf_counter(); "
    "tftools.read_recording([{bag!r}]); "
    "print(json.dumps({{'first_load_s': time.perf_counter() - began, 'first_load_cpu_s': time.process_time() - cpu}}))"
)
#: Each measure's goal: tf2's time over ours, at least (None: shown only).
GOALS = {"script": 10.0, "ingest": 30.0, "first_load": None, "lookup": 10.0, "can_transform": None,
         "batch": 150.0, "set_transform": 5.0, "frames": None}  # fmt: skip
#: A span's wall time over its CPU time, or its CPU time over the median of its runs', above which it is
#: called disturbed (quiet, these spans are single-threaded: wall 1.00-1.05 times CPU; CPU within 5% run to run).
DISTURBED = 1.15
#: A run's figures: each measure's seconds, and beside those with a CPU time, ``cpu(measure)``'s.
Run = dict[str, float]


def cpu(key: str) -> str:
    """The key of ``key``'s CPU time in a ``Run``."""
    return f"{key} cpu"


#: The environment of every measured process (``cached_bytecode`` sets it).
ENV = dict(os.environ)


def cached_bytecode(prefix: str) -> None:
    """Let every measured process read (and the first one write) its bytecode under ``prefix``."""
    ENV.pop("PYTHONDONTWRITEBYTECODE", None)
    ENV["PYTHONPYCACHEPREFIX"] = prefix


def run_json(command: list[str]) -> dict:
    """``command`` run from ``/`` (no checkout on its path but its own), its last line's JSON."""
    done = subprocess.run(command, capture_output=True, text=True, check=False, cwd="/", env=ENV)
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{done.stderr}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def wall(command: list[str]) -> tuple[float, float]:
    """Seconds the process ``command`` took, start to end, and the CPU seconds it spent."""
    children, began = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
    done = subprocess.run(command, capture_output=True, check=False, cwd="/", env=ENV)
    took, now = time.perf_counter() - began, resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{done.stderr.decode(errors='replace')}")
    return took, now.ru_utime - children.ru_utime + now.ru_stime - children.ru_stime


def timed(out: Run, key: str, measured: tuple[float, float]) -> None:
    out[key], out[cpu(key)] = measured


def spanned(out: Run, key: str, got: dict, prefix: str) -> None:
    """``key``'s span as a side measured it from within (``spent.py``): wall, CPU, waiting and steal times."""
    timed(out, key, (got[f"{prefix}_s"], got[f"{prefix}_cpu_s"]))
    for name in ("waited", "steal"):
        if f"{prefix}_{name}_s" in got:
            out[f"{key} {name}"] = got[f"{prefix}_{name}_s"]


def tftools_run(python: str, bags: dict[str, Path]) -> Run:
    """One run of every tftools measure, each in a fresh process of ``python``."""
    ours = str(HERE / "ours_side.py")
    at = robot.START + 100 * robot.NS
    code = SCRIPT.format(bag=str(bags["ros1"]), target=robot.TARGET, source=robot.SOURCE, at=at)
    settle(bags["ros1"], cold=False)
    out: Run = {}
    timed(out, "script", wall([python, "-c", code]))
    for fmt, bag in bags.items():
        settle(bag, cold=False)
        spanned(out, f"ingest {fmt}", run_json([python, ours, "ingest", str(bag)]), "ingest")
    got = run_json([python, "-c", FIRST_LOAD.format(bag=str(bags["ros1"]))])
    timed(out, "first_load", (got["first_load_s"], got["first_load_cpu_s"]))
    calls = run_json([python, ours, "lookups", str(bags["ros1"]), str(LOOKUPS), str(UNIT_SECONDS)])
    for key in ("lookup", "can_transform", "set_transform"):
        timed(out, key, (calls[f"{key}_s"], calls[f"{key}_cpu_s"]))
    batch(out, run_json([python, ours, "batch", str(bags["ros1"]), str(UNIT_SECONDS)]))
    timed(out, "frames", wall([python, "-m", "tftools", "frames", "-b", str(SAMPLE)]))
    return out


def batch(out: Run, got: dict) -> None:
    """The batch's second call, per time: its wall time and, as its CPU time, its threads' CPU time shared
    among them (on free cores about the wall time: the threads share the work as they go), so that a core
    another process held shows as time off the CPU, and slower work as CPU time over the median."""
    per_time = {key: value / got["batch_times"] for key, value in got.items() if key.startswith("batch_next_")}
    per_time["batch_next_cpu_s"] /= got["batch_threads"]
    per_time["batch_next_s"] = got["batch_next_s"]  # per time already
    spanned(out, "batch", per_time, "batch_next")
    out["batch faults"] = got["batch_next_minor_faults"]  # (a fresh page's first write: none where memory is reused)


def tf2_run(bags: dict[str, Path]) -> Run:
    """One run of tf2's measures, each in a fresh process of Debian's Python."""
    side = str(HERE / "tf2_side.py")
    settle(bags["ros1"], cold=False)
    out: Run = {}
    timed(out, "script", wall([ROS_PYTHON, side, "script", str(bags["ros1"])]))
    theirs = run_json([ROS_PYTHON, side, "measure", str(bags["ros1"]), str(LOOKUPS), str(UNIT_SECONDS)])
    for key in ("lookup", "can_transform", "set_transform"):
        timed(out, key, (theirs[f"{key}_s"], theirs[f"{key}_cpu_s"]))
    timed(out, "batch", (theirs["lookup_s"], theirs["lookup_cpu_s"]))  # its one lookup, against our batch's per time
    for key in ("first_load", *(f"ingest {fmt}" for fmt in bags)):
        spanned(out, key, theirs, "ingest")  # one ingest, the same in every row
    return out


def shown(seconds: float) -> str:
    if seconds >= 0.01:
        return f"{seconds:.3f} s"
    return f"{seconds * 1e6:.2f} us" if seconds >= 1e-6 else f"{seconds * 1e9:.0f} ns"


def ratios(theirs: list[Run], ours: list[Run], key: str) -> str:
    """tf2's time over ours, run by run: the median and the range."""
    each = [t[key] / o[key] for t, o in zip(theirs, ours, strict=True)]
    return f"{statistics.median(each):.1f}x ({min(each):.1f}-{max(each):.1f})"


def lowest(theirs: list[Run], ours: list[Run], key: str) -> tuple[float, int]:
    """The lowest of the runs' ratios, and its run (counted from 1)."""
    return min((t[key] / o[key], k) for k, (t, o) in enumerate(zip(theirs, ours, strict=True), 1))


def disturbance(runs: list[Run], k: int, key: str) -> str:
    """What disturbed ``key``'s span in run ``k`` of a side's ``runs`` ("" where nothing did): time off the
    CPU (its wall time more than ``DISTURBED`` times its CPU time: another process held the CPU, or the disk
    was read), or a CPU time more than ``DISTURBED`` times the median of the side's runs (the same work done
    slower: caches shared with a neighbour's work, the hypervisor's, or the work itself varying)."""
    run = runs[k]
    if cpu(key) not in run:
        return ""
    said = []
    if run[key] > DISTURBED * run[cpu(key)]:
        waited = f", {shown(run[f'{key} waited'])} of it waiting for a CPU" if f"{key} waited" in run else ""
        said.append(f"off the CPU {shown(run[key] - run[cpu(key)])}{waited}")
    usual = statistics.median(r[cpu(key)] for r in runs)
    if run[cpu(key)] > DISTURBED * usual:
        said.append(f"CPU time {run[cpu(key)] / usual:.2f}x its median")
    if said and run.get(f"{key} steal"):
        said.append(f"steal {shown(run[f'{key} steal'])}")
    return ", ".join(said)


def met(runs: dict[str, list[Run]], key: str, goal: float) -> str:
    """Whether tftools' ratio meets ``goal`` in every run; where not, which run, and which sides of it
    were disturbed."""
    ratio, run = lowest(runs["tf2"], runs["tftools"], key)
    if ratio >= goal:
        return "yes"
    hit = [name for name, side in runs.items() if disturbance(side, run - 1, key)]
    return f"NO (run {run}{': ' + ', '.join(hit) + ' disturbed' if hit else ''})"


def print_raw(runs: dict[str, list[Run]], keys: list[str]) -> None:
    """Every run's figures of the measures with a CPU time: each side's wall time and CPU time."""
    rows = [("measure", "run", *(f"{name} (cpu)" for name in runs), *(f"ratio {n}" for n in runs if n != "tf2"))]
    for key in (key for key in keys if cpu(key) in runs["tftools"][0]):
        for k, theirs in enumerate(runs["tf2"]):
            figures = [f"{shown(side[k][key])}{cpu_shown(side[k], key)}{' *' * bool(disturbance(side, k, key))}"
                       if key in side[k] else "-" for side in runs.values()]  # fmt: skip
            ratio = [f"{theirs[key] / side[k][key]:.1f}x" if key in theirs else "-"
                     for name, side in runs.items() if name != "tf2"]  # fmt: skip
            rows.append((key, str(k + 1), *figures, *ratio))
    print_table(rows)
    print("* disturbed (listed below the table)\n")


def cpu_shown(run: Run, key: str) -> str:
    return f" ({shown(run[cpu(key)])})" if cpu(key) in run else ""


def print_disturbed(runs: dict[str, list[Run]], keys: list[str]) -> None:
    """The spans disturbed, each side's and run's once (tf2's one ingest stands in several rows)."""
    print(f"disturbed spans (off the CPU, or a CPU time over {DISTURBED:.2f} times the median of its runs):")
    said: set[tuple[str, int, float]] = set()
    for key in keys:
        for name, side in runs.items():
            for k, run in enumerate(side):
                why = disturbance(side, k, key)
                if why and (name, k, run[key]) not in said:
                    said.add((name, k, run[key]))
                    print(f"  {key}, run {k + 1}, {name}: {shown(run[key])}, cpu {shown(run[cpu(key)])}: {why}")
    if not said:
        print("  none")


def print_table(rows: list[tuple[str, ...]]) -> None:
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    for row in rows:
        print(" | ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5, help="runs, each side in fresh processes; medians shown")
    parser.add_argument("--against", help="an interpreter whose tftools is another version, measured alike")
    each_run = "no bytecode cache set up (with PYTHONDONTWRITEBYTECODE, sources compiled in each process)"
    parser.add_argument("--compile-each-run", action="store_true", help=each_run)
    parser.add_argument("--raw", action="store_true", help="every run's wall and CPU times, both sides, first")
    parser.add_argument("--json", type=Path, help="every run's figures written to this file")
    args = parser.parse_args()
    if not real_rosbag():
        sys.exit(f"tf2 is missing ({ROS_PYTHON} -c 'import rosbag, tf2_py' fails): see scripts/install-reference.sh")
    bags = write_bags(UNIT_SECONDS, False)
    if not args.compile_each_run:
        prefix = tempfile.TemporaryDirectory(prefix="tftools-bytecode-")
        cached_bytecode(prefix.name)
    loads = [os.getloadavg()[0]]
    sides: dict[str, Callable[[], dict[str, float]]] = {"tf2": lambda: tf2_run(bags)}
    if args.against:
        sides["before"] = lambda: tftools_run(args.against, bags)
    sides["tftools"] = lambda: tftools_run(sys.executable, bags)
    if not args.compile_each_run:
        for side in sides.values():
            side()  # a warm-up, unmeasured: the bytecode of what each side imports written once
    runs: dict[str, list[Run]] = {name: [] for name in sides}
    for _ in range(args.runs):
        for name, side in sides.items():
            runs[name].append(side())
        loads.append(os.getloadavg()[0])
    if args.json:
        args.json.write_text(json.dumps({"runs": runs, "loads": loads}, indent=1))
    header = ["measure", *sides, *(f"ratio {name}" for name in sides if name != "tf2"), "goal", "met every run?"]
    rows = [tuple(header)]
    keys = ["script", *(f"ingest {fmt}" for fmt in bags), "first_load", "lookup", "can_transform", "batch",
            "set_transform", "frames"]  # fmt: skip
    if args.raw:
        print_raw(runs, keys)
    for key in keys:
        goal = GOALS[key.split()[0]]
        figures = [shown(statistics.median(run[key] for run in runs[name])) if key in runs[name][0] else "-"
                   for name in sides]  # fmt: skip
        if key in runs["tf2"][0]:
            shown_ratios = [ratios(runs["tf2"], runs[name], key) for name in sides if name != "tf2"]
            met_goal = "-" if goal is None else met(runs, key, goal)
        else:
            shown_ratios, met_goal = ["-" for name in sides if name != "tf2"], "-"
        rows.append((key, *figures, *shown_ratios, "-" if goal is None else f">= {goal:.0f}x", met_goal))
    print_table(rows)
    print_disturbed(runs, keys)
    print(f"\nmedians of {args.runs} runs, sides interleaved, each measure a fresh process; batch = 1M random "
          f"times, per time (its ratio: tf2's one lookup over it); load average (1 min) {min(loads):.1f}-"
          f"{max(loads):.1f} on {os.cpu_count()} cores; bytecode "
          f"{'compiled in every process' if args.compile_each_run else 'cached, as installed'}")  # fmt: skip


if __name__ == "__main__":
    main()
