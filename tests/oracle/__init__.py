"""The real tf2 as a test oracle: scenarios run through Debian's ROS1 tf2 in a subprocess."""

from __future__ import annotations

import json
import math
import os
import subprocess
import tempfile
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

ROS_PYTHON = "/usr/bin/python3"
HARNESS = Path(__file__).with_name("tf2_harness.py")

# One row of a scenario as the harness reads it, a JSON array read by position: an insert's frames, stamp and
# values, or a query's name then its frames and time (mixed types, so Any).
Row = list[Any]

ERROR_CLASSES = {
    "LookupException": "UnknownFrameError",
    "ConnectivityException": "ConnectivityError",
    "ExtrapolationException": "ExtrapolationError",
    "InvalidArgumentException": "InvalidArgumentError",
}


@cache
def unavailable_reason() -> str | None:
    """Why the real tf2 cannot be used here, or None when it can."""
    try:
        imports = "import tf2_py, rospy, rosbag, tf2_geometry_msgs, sensor_msgs.msg"
        probe = subprocess.run([ROS_PYTHON, "-c", imports], capture_output=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as e:
        return f"{ROS_PYTHON} cannot run: {e}"
    if probe.returncode != 0:
        return "the real tf2 is not installed (apt-get install python3-tf2 python3-rosbag; see README)"
    return None


def binding_time(ns: int) -> int:
    """The stamp tf2's Python binding stores for ``ns``: genpy's ``to_sec`` then ``fromSec``."""
    secs, nsecs = divmod(ns, 1_000_000_000)
    t = float(secs) + float(nsecs) / 1e9
    sec = math.floor(t)
    nsec = math.floor((t - sec) * 1e9 + 0.5)  # boost::math::round, on a non-negative value
    return sec * 1_000_000_000 + nsec


@dataclass
class Scenario:
    """Transforms to insert in order (or a ROS1 bag to read) and queries to answer."""

    inserts: list[Row] = field(default_factory=list)
    queries: list[Row] = field(default_factory=list)
    cache_time_s: int = 1_000_000
    bag: str | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"cache_time_s": self.cache_time_s, "queries": self.queries}
        if self.bag is not None:
            out["bag"] = self.bag
        else:
            out["inserts"] = self.inserts
        return out


def run_tf2(scenarios: list[Scenario]) -> list[dict[str, Any]]:
    """Each scenario's ``{"rejections": [codes], "answers": [...]}`` from the real tf2."""
    results: list[dict[str, Any]] = _harness({"scenarios": [s.to_json() for s in scenarios]})["results"]
    return results


def bag_rows(bag: str) -> list[Row]:
    """A ROS1 bag's /tf and /tf_static transforms as rosbag reads them, in order: insert rows whose
    stamps are the message's integers (every nanosecond, where tf2_py's ``set_transform`` rounds)."""
    rows: list[Row] = _harness({"bag_rows": bag})["rows"]
    return rows


def _harness(request: dict[str, Any]) -> dict[str, Any]:
    """``request`` answered by ``tf2_harness.py`` in Debian's Python."""
    done = subprocess.run(
        [ROS_PYTHON, str(HARNESS)], input=json.dumps(request), capture_output=True, text=True, timeout=600
    )
    if done.returncode != 0:
        raise RuntimeError(f"tf2 harness failed:\n{done.stderr[-3000:]}")
    answer: dict[str, Any] = json.loads(done.stdout)
    return answer


CORE_SOURCE = Path(__file__).with_name("tf2_core.cpp")


@cache
def cpp_core() -> Path | str:
    """ROS 1's tf2 ``BufferCore`` in C++ (``tf2_core.cpp`` built against Debian's libtf2, once per
    run): the path of the program, or why it cannot be built here. tf2_py rounds every stamp
    through a double; the C++ core, like a roscpp node, keeps every nanosecond."""
    built = Path(tempfile.gettempdir()) / f"tftools-tf2-core-{os.getuid()}-{CORE_SOURCE.stat().st_mtime_ns}"
    if built.exists():
        return built
    libraries = ["-ltf2", "-lrostime", "-lcpp_common", "-lconsole_bridge"]
    return _compile([str(CORE_SOURCE), *libraries], built, "ROS 1's tf2 core (needs Debian's libtf2-dev)")


def run_cpp_core(lines: list[str], cache_time_s: int = 10) -> tuple[list[str], str]:
    """``lines`` (``tf2_core.cpp``'s commands) through the C++ core: its answers, one a line, and its log."""
    return _drive(cpp_core(), lines, str(cache_time_s))


def cpp_insert(row: Row) -> str:
    """An insert row as the C++ core's ``set`` line (``repr`` of a double round-trips through ``strtod``)."""
    parent, child, sec, nsec, *values, authority, static = row
    words = [parent, child, authority]
    assert all(w and not any(c.isspace() for c in w) for w in words), f"not a word of tf2_core.cpp's lines: {words}"
    return " ".join(["set", parent, child, str(sec * 1_000_000_000 + nsec), *map(repr, map(float, values))]) + (
        f" {int(static)} {authority}"
    )


def _compile(arguments: list[str], built: Path, what: str) -> Path | str:
    """``g++ -O2 arguments``, written to ``built`` (through a temporary name): the program, or why
    ``what`` could not be built."""
    partial = built.with_name(f"{built.name}.{os.getpid()}")
    command = ["g++", "-std=c++17", "-O2", *arguments, "-o", str(partial)]
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=900)
    except (OSError, subprocess.SubprocessError) as e:
        return f"{what} could not be built: {e}"
    if done.returncode != 0:
        return f"{what} could not be built: {done.stderr[-500:]}"
    partial.replace(built)
    return built


def _drive(program: Path | str, lines: list[str], *arguments: str) -> tuple[list[str], str]:
    """``lines`` through a built oracle (run with ``arguments``): its answers, one a line, and its log."""
    assert isinstance(program, Path), program
    command = [str(program), *arguments]
    done = subprocess.run(command, input="\n".join(lines) + "\n", capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"{program.name} failed:\n{done.stderr[-3000:]}")
    return done.stdout.splitlines(), done.stderr
