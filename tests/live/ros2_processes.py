"""A private ROS 2 domain per test (fixture ``domain``), and processes on it (tfx, stand-in ROS 2 nodes)
killed at its end."""

from __future__ import annotations

import contextlib
import os
import queue
import random
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import pytest

from tests.patience import patient

NODES = Path(__file__).with_name("ros2_nodes.py")


@dataclass
class Finished:
    returncode: int
    stdout: str
    stderr: str


class Process:
    """A started process whose output lines are read in the background, so a test can wait for one."""

    def __init__(self, command: list[str], env: dict[str, str]) -> None:
        self.popen = subprocess.Popen(
            command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
        )
        self.lines: queue.SimpleQueue[str] = queue.SimpleQueue()
        self.seen: list[str] = []
        self.output: dict[str, list[str]] = {"stdout": [], "stderr": []}
        self._readers = [
            threading.Thread(target=self._read, args=(stream, self.output[name]), daemon=True)
            for name, stream in (("stdout", self.popen.stdout), ("stderr", self.popen.stderr))
        ]
        for reader in self._readers:
            reader.start()

    def _read(self, stream: IO[str], kept: list[str]) -> None:
        for line in stream:
            kept.append(line)
            self.lines.put(line.rstrip("\n"))

    def wait_for(self, text: str, timeout: float = 15.0) -> str:
        """The first line (stdout or stderr) containing ``text``; fails after ``timeout`` seconds."""
        deadline = time.monotonic() + patient(timeout)
        while True:
            try:
                line = self.lines.get(timeout=max(0.0, min(0.2, deadline - time.monotonic())))
            except queue.Empty:
                if time.monotonic() > deadline or (self.popen.poll() is not None and self.lines.empty()):
                    pytest.fail(f"no line with {text!r} from {self.popen.args!r} (said: {self.seen[-5:]})")
                continue
            self.seen.append(line)
            if text in line:
                return line

    def finish(self, timeout: float = 30.0) -> Finished:
        """Wait for the process to end by itself; its exit code and all it printed."""
        returncode = self.popen.wait(patient(timeout))
        for reader in self._readers:
            reader.join(timeout)
        return Finished(returncode, "".join(self.output["stdout"]), "".join(self.output["stderr"]))

    def stop(self) -> None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.popen.pid, signal.SIGKILL)
        self.popen.wait()


#: Cyclone DDS on loopback only, discovering by unicast (loopback has no multicast): for every
#: participant of a test, the stand-in nodes (Cyclone reads it) and tftools (after ROS 2's settings).
LOOPBACK = (
    '<CycloneDDS><Domain><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>'
    "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
    '<MaxAutoParticipantIndex>40</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers>'
    "</Discovery></Domain></CycloneDDS>"
)


class Ros2Domain:
    """A random domain id (100-199) on loopback only."""

    def __init__(self) -> None:
        self.id = random.SystemRandom().randrange(100, 200)
        self.env = {k: v for k, v in os.environ.items() if not k.startswith(("ROS_", "CYCLONEDDS"))}
        self.env.update(ROS_DOMAIN_ID=str(self.id), CYCLONEDDS_URI=LOOPBACK, PYTHONUNBUFFERED="1")
        self._processes: list[Process] = []

    def node(self, *arguments: str) -> Process:
        """A stand-in ROS 2 node from ``ros2_nodes.py``, started (it says "ready" once it publishes)."""
        process = Process([sys.executable, str(NODES), *arguments], self.env)
        self._processes.append(process)
        return process

    def tfx(self, *arguments: str, env: dict[str, str] | None = None) -> Process:
        """``tfx ARGUMENTS`` started (several can run at once: ``finish()`` each)."""
        process = Process([sys.executable, "-m", "tftools", *arguments], env or self.env)
        self._processes.append(process)
        return process

    def run_tfx(self, *arguments: str, env: dict[str, str] | None = None) -> Finished:
        return self.tfx(*arguments, env=env).finish()

    def stop(self) -> None:
        for process in self._processes:
            process.stop()


def require_cyclonedds() -> None:
    """Skip without Cyclone DDS's Python package (the ros2 extra); in CI it must be there."""
    try:
        import cyclonedds.domain  # noqa: F401
    except (ImportError, OSError) as error:
        reason = f"Cyclone DDS's Python package (extra ros2) cannot be imported: {error}"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the live ROS 2 tests (scripts/test.sh installs the ros2 extra), but {reason}")
        pytest.skip(reason)


@pytest.fixture(name="domain")
def domain_fixture(monkeypatch: pytest.MonkeyPatch) -> Iterator[Ros2Domain]:
    """A private domain; this process's tftools joins it too. Skips where Cyclone DDS is missing."""
    require_cyclonedds()
    running = Ros2Domain()
    for name in ("ROS_MASTER_URI", "ROS_VERSION", "ROS_STATIC_PEERS", "ROS_LOCALHOST_ONLY"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.delenv("ROS_AUTOMATIC_DISCOVERY_RANGE", raising=False)
    for name in ("ROS_DOMAIN_ID", "CYCLONEDDS_URI"):
        monkeypatch.setenv(name, running.env[name])
    yield running
    running.stop()
