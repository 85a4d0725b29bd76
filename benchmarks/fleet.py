"""``tfx wtf`` on a fleet: 1,000 recordings with ``--jobs 2`` and on a 2-worker local Dask cluster.

Copies the sample robot (a 15 s ROS 1 bag, 0.7 MB, 6,307 transforms, 18 frames) 1,000 times into a temp
directory, times one check in this process (the work itself), then runs the real command, ``tfx wtf
BAG... --format jsonl``, with ``--jobs 2`` and with ``--dask`` on a scheduler and two one-thread workers
started as processes on loopback. Prints recordings per second and the overhead per recording: wall time
times workers over recordings, less the check itself. Asserts nothing.

    .venv/bin/python benchmarks/fleet.py [--recordings 1000]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tftools.analysis.wtf.fleet import check_fleet

REPO = Path(__file__).resolve().parents[1]
SAMPLE = REPO / "sample_bags" / "robot.bag"
WORKERS = 2


def check_seconds(bag: Path, runs: int = 20) -> float:
    """One recording's check in this process (warm), the work every executor does."""
    list(check_fleet([[str(bag)]]))
    began = time.perf_counter()
    for _ in range(runs):
        list(check_fleet([[str(bag)]]))
    return (time.perf_counter() - began) / runs


def run_tfx(bags: list[Path], *how: str) -> float:
    """Wall seconds of ``tfx wtf BAGS... --format jsonl`` (start-up included)."""
    command = [sys.executable, "-m", "tftools", "wtf", *(str(b) for b in bags), "--format", "jsonl", *how]
    began = time.perf_counter()
    done = subprocess.run(command, cwd=REPO, capture_output=True, text=True)
    seconds = time.perf_counter() - began
    summary = json.loads(done.stdout.splitlines()[-1])
    assert summary["summary"]["recordings"] == len(bags), done.stderr  # a benchmark of a broken run is no figure
    return seconds


def dask_cluster(directory: Path) -> tuple[str, list[subprocess.Popen[bytes]]]:
    """A scheduler and ``WORKERS`` one-thread workers, each its own process (and session)."""
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    scheduler_file = directory / "scheduler.json"
    common = ["--no-dashboard"]
    commands = [["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", "--scheduler-file"]]
    commands[0].append(str(scheduler_file))
    for n in range(WORKERS):
        worker = ["--scheduler-file", str(scheduler_file), "--host", "127.0.0.1", "--nthreads", "1"]
        commands.append(["distributed.cli.dask_worker", *worker, "--local-directory", str(directory / f"w{n}")])
    started = [
        subprocess.Popen(
            [sys.executable, "-m", *c, *common], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        for c in commands
    ]  # fmt: skip
    while not scheduler_file.exists():
        time.sleep(0.1)
    address = json.loads(scheduler_file.read_text())["address"]
    from distributed import Client

    with Client(address, timeout="30s") as client:
        client.wait_for_workers(WORKERS, timeout=60)
    return address, started


def stop(processes: list[subprocess.Popen[bytes]]) -> None:
    for process in reversed(processes):
        os.killpg(process.pid, signal.SIGTERM)
    for process in processes:
        process.wait(timeout=30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--recordings", type=int, default=1000)
    n = parser.parse_args().recordings
    with tempfile.TemporaryDirectory(prefix="tfx-fleet-") as temp:
        directory = Path(temp)
        bags = [directory / f"robot_{i:05d}.bag" for i in range(n)]
        for bag in bags:
            shutil.copyfile(SAMPLE, bag)
        work = check_seconds(bags[0])
        print(f"{n} recordings (the sample robot, {SAMPLE.stat().st_size / 1e6:.1f} MB each) on {os.cpu_count()} cores")
        print(f"  one check in this process: {work * 1e3:.0f} ms")
        results = {"--jobs 2": run_tfx(bags, "--jobs", str(WORKERS))}
        address, cluster = dask_cluster(directory)
        try:
            results[f"--dask ({WORKERS} workers, 1 thread each)"] = run_tfx(bags, "--dask", address)
        finally:
            stop(cluster)
        for how, seconds in results.items():
            overhead = seconds * WORKERS / n - work
            print(
                f"  {how:34} {seconds:6.1f} s  {n / seconds:6.1f} recordings/s  "
                f"overhead {overhead * 1e3:5.1f} ms a recording (a worker's time beyond the check)"
            )


if __name__ == "__main__":
    main()
