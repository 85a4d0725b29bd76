"""tfx's live ROS 2 commands against hostile peers at the rate of issue 44: samples of 60 MiB back to back, a
``ros_discovery_info`` flood of new participants, from ``--peers`` writer processes each writing serialized-once
bytes as fast as Cyclone DDS takes them (tests/live/ros2_nodes.py hostile huge|participants), or another hostile
kind (longnames: new names of 4 KiB and 1 MiB), or clockloop (/clock back every 50 ms, --use-sim-time).

On a private domain on loopback, for each peer kind and command, prints tfx's exit code, wall time, peak RSS
(``/usr/bin/time -v``), its stderr lines, and how many bytes the peers' writers sent meanwhile.

    .venv/bin/python benchmarks/hostile_ros2.py [--peers 3] [--seconds 8] [--kinds huge participants]
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.live.ros2_processes import Ros2Domain

#: Peers other than ``hostile KIND``: a /clock going back every 50 ms (a replay looping as fast as it can).
PEERS = {"clockloop": ("dynamic", "robot", "odom", "base_link", "--hz", "200", "--sim", "100", "--loop", "0.05")}

COMMANDS = {
    "monitor": ["monitor", "--ros2", "--duration", "{s}", "-f", "json"],
    "wtf": ["wtf", "--ros2", "-d", "{s}"],
    "echo": ["echo", "--ros2", "root", "base", "--wait", "{s}"],
    "frames": ["frames", "--ros2", "-d", "{s}"],
}


def measure(domain: Ros2Domain, command: list[str]) -> dict[str, object]:
    started = time.monotonic()
    finished = subprocess.run(
        ["/usr/bin/time", "-v", sys.executable, "-m", "tftools", *command],
        env=domain.env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    seconds = time.monotonic() - started
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", finished.stderr)
    said = finished.stderr.splitlines()
    lines = [line for line in said if not line.startswith("\t") and "Command exited" not in line]
    return {
        "exit": finished.returncode,
        "seconds": round(seconds, 1),
        "peak_mb": int(rss.group(1)) // 1024 if rss else -1,
        "stderr": lines,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--peers", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=8.0)
    parser.add_argument("--kinds", nargs="+", default=["huge", "participants"])
    parser.add_argument("--commands", nargs="+", default=list(COMMANDS))
    options = parser.parse_args()
    for kind in options.kinds:
        for name in options.commands:
            domain = Ros2Domain()
            try:
                for _ in range(options.peers):
                    domain.node(*PEERS.get(kind, ("hostile", kind))).wait_for("ready", timeout=60)
                command = [word.format(s=options.seconds) for word in COMMANDS[name]]
                if kind == "clockloop":
                    command.insert(2, "--use-sim-time")
                result = measure(domain, command)
            finally:
                domain.stop()
            print(f"{kind:13} {name:8} exit {result['exit']}  {result['seconds']:5} s  {result['peak_mb']:5} MB")
            for line in result["stderr"]:  # type: ignore[attr-defined]
                print(f"    | {line[:200]}")


if __name__ == "__main__":
    main()
