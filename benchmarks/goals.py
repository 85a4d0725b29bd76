"""Every goal of issue 17 with today's figure, tf2's and transform-tree's, from one run.

Run: ``python benchmarks/goals.py [--parts calls ingest startup fresh memory] [--runs 5]``
(``scripts/benchmark.sh --goals`` does). Prints ``goal | figure | tf2 | transform-tree | met?``,
asserts nothing. Each measure runs ``--runs`` times, each in a fresh process, and its median is
shown: a shared machine's figures vary run to run (the load is printed with them). The workload
is ``vs_tf2.py``'s: the 300 s robot (258k transforms) as .bag/.db3/.mcap, its 4,800 s recording
(4.1M transforms) for memory, and its 14,400 s one (12.4M, 3.6 GB in the three formats, written once
into /tmp/tftools-bench in ~16 min) for a streamed replay's. tf2 is tf2_py under Debian's Python (``tf2_side.py``),
transform-tree its PyPI wheel built with tf2's interpolation (``transform_tree_side.py``), and
tftools this checkout (``ours_side.py``, ``python -m tftools``).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import robot
import vs_tf2
from vs_tf2 import HERE, LOOKUPS, ROS_PYTHON, UNIT_SECONDS, measure, settle, write_bags

REPO = HERE.parent
SAMPLE = REPO / "sample_bags" / "robot.bag"
#: A measured command's key: its name, or its recording's length and format.
Key = str | tuple[int, str]
PARTS = ("calls", "ingest", "startup", "fresh", "memory")
MEMORY_SCALE = 16  # 4,800 s: 4.1M transforms
STREAMED_SCALES = (16, 48)  # 4,800 s and 14,400 s (4 h, 12.4M transforms)
#: Each command's arguments on a bag (BAG).
COMMANDS = {
    "frames": ["frames", "-b", "BAG"],
    "echo": ["echo", robot.TARGET, "gripper", "-b", "BAG"],
    "monitor": ["monitor", "-b", "BAG"],
    "view-frames": ["view-frames", "-b", "BAG", "-o", "/tmp/tftools-bench/goals_frames", "--force"],
    "wtf": ["wtf", "BAG"],
}


class Goals:
    """The table: one row per goal."""

    def __init__(self) -> None:
        self.rows: list[tuple[str, str, str, str, str]] = []

    def add(self, goal: str, figure: str, tf2: str = "", tt: str = "", met: bool | None = None) -> None:
        self.rows.append((goal, figure, tf2 or "-", tt or "-", "" if met is None else ("yes" if met else "NO")))

    def print(self) -> None:
        header = ("goal", "figure", "tf2", "transform-tree", "met?")
        widths = [max(len(row[i]) for row in [header, *self.rows]) for i in range(len(header))]
        for row in [header, *self.rows]:
            print(" | ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip())


def median_run(command: list[str], bag: Path | None = None) -> dict:
    """``command``'s JSON, run ``RUNS`` times in fresh processes: each time (``*_s``) the median."""
    runs = []
    for _ in range(vs_tf2.RUNS):
        if bag is not None:
            settle(bag, cold=False)
        runs.append(measure(command))
    medians = {key: statistics.median(run[key] for run in runs) for key in runs[0] if key.endswith(("_s", "_bytes"))}
    return {**runs[0], **medians}


def side(script: str, *args: object, python: str = sys.executable, bag: Path | None = None) -> dict:
    return median_run([python, str(HERE / script), *map(str, args)], bag)


def us(seconds: float) -> str:
    return f"{seconds * 1e6:.2f} us"


def ns(seconds: float) -> str:
    return f"{seconds * 1e9:.0f} ns/time"


def mcap_file(bag: Path) -> Path:
    return next(bag.glob("*.mcap"))


def calls(goals: Goals) -> None:
    seconds = UNIT_SECONDS
    bags = write_bags(seconds, False)
    tf2 = side("tf2_side.py", "measure", bags["ros1"], LOOKUPS, seconds, python=ROS_PYTHON, bag=bags["ros1"])
    ours = side("ours_side.py", "lookups", bags["ros1"], LOOKUPS, seconds, bag=bags["ros1"])
    tt = side("transform_tree_side.py", mcap_file(bags["mcap"]), LOOKUPS, seconds)
    batch = side("ours_side.py", "batch", bags["ros1"], seconds, bag=bags["ros1"])
    agree = abs(ours["checksum"] - tf2["checksum"]) < 1e-5 * max(1.0, abs(tf2["checksum"]))
    goals.add("same answers as tf2 (1000 lookups)", "yes" if agree else "NO", "", "", agree)
    goals.add("one set_transform call <= 1 us", us(ours["set_transform_s"]), us(tf2["set_transform_s"]),
              us(tt["set_transform_s"]), ours["set_transform_s"] <= 1e-6)  # fmt: skip
    goals.add("one lookup (10 edges) <= 1.5 us", us(ours["lookup_s"]), us(tf2["lookup_s"]), us(tt["lookup_s"]),
              ours["lookup_s"] <= 1.5e-6)  # fmt: skip
    goals.add("can_transform <= 1.5 us", us(ours["can_transform_s"]), us(tf2["can_transform_s"]), "",
              ours["can_transform_s"] <= 1.5e-6)  # fmt: skip
    goals.add("batch (1M random times) <= 60 ns/time, next", ns(batch["batch_next_s"]), "",
              ns(tt["batch_next_s"]), batch["batch_next_s"] <= 60e-9)  # fmt: skip
    goals.add("first batch in a process within 2x of next", ns(batch["batch_first_s"]), "",
              ns(tt["batch_first_s"]), batch["batch_first_s"] <= 2 * batch["batch_next_s"])  # fmt: skip


def ingest(goals: Goals) -> None:
    seconds = UNIT_SECONDS
    bags = write_bags(seconds, False)
    tf2 = side("tf2_side.py", "measure", bags["ros1"], 10, seconds, python=ROS_PYTHON, bag=bags["ros1"])
    tt = side("transform_tree_side.py", mcap_file(bags["mcap"]), 10, seconds, bag=bags["mcap"])
    for fmt, bag in bags.items():
        ours = side("ours_side.py", "ingest", bag, bag=bag)["ingest_s"]
        ratio = tf2["ingest_s"] / ours
        tt_shown = f"{tt['mcap_ingest_s']:.2f} s" if fmt == "mcap" else ""
        met = ratio >= 20 and (fmt != "mcap" or ours < tt["mcap_ingest_s"])
        goal = f"bag->buffer {fmt} >= 20x tf2" + (", < transform-tree" if fmt == "mcap" else "")
        goals.add(goal, f"{ours:.2f} s ({ratio:.0f}x tf2)", f"{tf2['ingest_s']:.2f} s (.bag)", tt_shown, met)


def wall_seconds(command: list[str]) -> float:
    """Median wall time of ``command`` as a whole process, from the repository (so this checkout runs)."""
    times = []
    for _ in range(max(vs_tf2.RUNS, 5)):
        began = time.perf_counter()
        subprocess.run(command, cwd=REPO, capture_output=True, check=True)
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def startup(goals: Goals) -> None:
    tfx = [sys.executable, "-m", "tftools"]
    version, python = wall_seconds([*tfx, "--version"]), wall_seconds([sys.executable, "-c", "pass"])
    goals.add("tfx --version < 60 ms (whole process)", f"{version * 1e3:.0f} ms (python alone {python * 1e3:.0f} ms)",
              "", "", version < 0.060)  # fmt: skip
    frames = wall_seconds([*tfx, "frames", "-b", str(SAMPLE)])
    goals.add("tfx frames -b sample_bags/robot.bag < 0.25 s", f"{frames:.2f} s", "", "", frames < 0.25)


def fresh(goals: Goals) -> None:
    bag = write_bags(UNIT_SECONDS, False)["ros1"]
    done = measure(["bash", str(HERE / "fresh_install.sh"), str(bag), str(vs_tf2.RUNS)])
    first, later = done["first_s"], done["later_s"]
    goals.add("first tfx echo --all after a fresh install <= 2x later", f"{first:.1f} s vs {later:.1f} s later",
              "", "", first <= 2 * later)  # fmt: skip


def peak_rss(command: list[str]) -> int:
    """Peak resident memory of ``command`` (bytes), run as a child of a fresh waiting process; a command that
    failed (exit 2 and up: 1 is findings) stops the benchmark with its error, not a figure of its failure."""
    code = (
        "import resource, subprocess, sys; done = subprocess.run(sys.argv[1:], capture_output=True, check=False);"
        "sys.exit(done.stderr.decode()[-500:]) if done.returncode > 1 else "
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024)"
    )
    done = subprocess.run([sys.executable, "-c", code, *command], cwd=REPO, capture_output=True, text=True, check=True)
    return int(done.stdout)


def median_peaks(commands: dict[Key, list[str]]) -> dict[Key, list[int]]:
    """Each command's peak memory in ``RUNS`` rounds of fresh processes (the commands alternated, so that the
    machine's state falls on all alike), the peaks of each in order (the median in the middle)."""
    peaks: dict[Key, list[int]] = {key: [] for key in commands}
    for _ in range(vs_tf2.RUNS):
        for key, command in commands.items():
            peaks[key].append(peak_rss(command))
    return {key: sorted(each) for key, each in peaks.items()}


def median(values: list[int]) -> float:
    return statistics.median(values)


def peaks_shown(values: list[int], unit: float, name: str, digits: int) -> str:
    """The median of ``values`` in ``unit`` (``name``), and their range where there are several."""
    each = [f"{value / unit:.{digits}f}" for value in (median(values), values[0], values[-1])]
    return f"{each[0]} {name}" + (f" ({each[1]}-{each[2]})" if len(values) > 1 else "")


@contextlib.contextmanager
def as_installed() -> Iterator[None]:
    """Within it, every tftools process reads its modules' bytecode as an installed package does (pip compiles
    at install), from a temporary ``PYTHONPYCACHEPREFIX`` written by an unmeasured run of each command on the
    sample bag first (as ``ratios.py``). Where ``PYTHONDONTWRITEBYTECODE`` is set and a checkout has no
    bytecode, each process compiled tftools' sources first, and the heap that left moved the checks' peak:
    ``view-frames`` on the 4,800 s robot 666 MB compiling, 693-695 MB reading bytecode, run after run."""
    saved = dict(os.environ)
    with tempfile.TemporaryDirectory(prefix="tftools-bytecode-") as prefix:
        os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
        os.environ["PYTHONPYCACHEPREFIX"] = prefix
        try:
            for args in [*COMMANDS.values(), ["monitor", "-b", "BAG", "--play", "--rate", "100000"]]:
                command = [sys.executable, "-m", "tftools", *(str(SAMPLE) if a == "BAG" else a for a in args)]
                subprocess.run(command, cwd=REPO, capture_output=True, check=False)
            yield
        finally:
            os.environ.clear()
            os.environ.update(saved)


def memory(goals: Goals) -> None:
    with as_installed():
        peaks_of_memory(goals)


def peaks_of_memory(goals: Goals) -> None:
    bag = write_bags(UNIT_SECONDS * MEMORY_SCALE, False)["ros1"]
    held = side("ours_side.py", "ingest", bag, bag=bag)
    per_transform = (held["peak_rss_bytes"] - held["rss_before_bytes"]) / held["transforms"]
    goals.add(f"bytes per transform held ({held['transforms'] / 1e6:.1f}M) <= 120 B", f"{per_transform:.0f} B",
              "", "", per_transform <= 120)  # fmt: skip
    peaks = median_peaks({
        name: [sys.executable, "-m", "tftools", *(str(bag) if a == "BAG" else a for a in args)]
        for name, args in COMMANDS.items()
    })  # fmt: skip
    frames = median(peaks["frames"])
    for name, each in peaks.items():
        ratio = median(each) / frames
        figure = f"{peaks_shown(each, 1e9, 'GB', 2)}: {ratio:.2f}x"
        goals.add(f"peak memory tfx {name} <= 1.3x frames", figure, "", "", ratio <= 1.3)
    streamed(goals, frames)


def streamed(goals: Goals, frames_peak: float) -> None:
    """A replay (``monitor --play``, as fast as it goes) of 1.3 h and of 4 h of the robot: the recording
    is streamed, so its peak memory must not grow with the recording's length."""
    commands = {}
    for seconds in (UNIT_SECONDS * STREAMED_SCALES[0], UNIT_SECONDS * STREAMED_SCALES[1]):
        for fmt, bag in write_bags(seconds, False).items():
            command = ["monitor", "-b", str(bag), "--play", "--rate", "100000", "--format", "json"]
            commands[seconds, fmt] = [sys.executable, "-m", "tftools", *command]
    peaks = median_peaks(commands)
    short, long = (UNIT_SECONDS * scale for scale in STREAMED_SCALES)
    for fmt in ("ros1", "db3", "mcap"):
        growth = median(peaks[long, fmt]) / median(peaks[short, fmt])
        figure = f"{peaks_shown(peaks[long, fmt], 1e6, 'MB', 0)} vs {peaks_shown(peaks[short, fmt], 1e6, 'MB', 0)}"
        figure += f": {growth:.2f}x"
        goals.add(f"{long / 3600:.0f} h replayed in the memory of {short / 3600:.1f} h (--play, {fmt}) <= 1.1x",
                  f"{figure}; frames holds {frames_peak / 1e9:.2f} GB of {short / 3600:.1f} h", "", "",
                  growth <= 1.1)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--parts", nargs="+", choices=PARTS, default=list(PARTS), help="which goals to measure")
    parser.add_argument("--runs", type=int, default=5, help="runs of each measure, the median shown")
    args = parser.parse_args()
    vs_tf2.RUNS = args.runs
    if not vs_tf2.real_rosbag():
        sys.exit(f"tf2 is missing ({ROS_PYTHON} -c 'import rosbag, tf2_py' fails): see scripts/install-reference.sh")
    goals = Goals()
    measures = {"calls": calls, "ingest": ingest, "startup": startup, "fresh": fresh, "memory": memory}
    for part in args.parts:
        measures[part](goals)
    goals.print()
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"\nmedian of {args.runs} runs, each in a fresh process; load average {load} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
