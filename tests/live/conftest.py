"""A real ROS1 master (Debian's roscore) per test module, and processes that die with each test."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import pytest

from tests.cli.conftest import tfx  # noqa: F401 - the in-process `tfx` fixture, for tests without a master
from tests.patience import patient

ROS_PYTHON = "/usr/bin/python3"
T = TypeVar("T")
NODES = Path(__file__).with_name("ros1_nodes.py")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def _unavailable() -> str | None:
    if shutil.which("roscore") is None:
        return "roscore is not installed (apt-get install ros-core; see /work/shared/REFERENCE.md)"
    probe = subprocess.run([ROS_PYTHON, "-c", "import rospy, tf2_ros, rosbag"], capture_output=True)
    if probe.returncode != 0:
        return "rospy/tf2_ros are not installed for /usr/bin/python3 (apt-get install python3-tf2-ros python3-rosbag)"
    return None


@pytest.fixture(scope="session")
def ros1_available() -> None:
    """Skip without the real ROS1; in CI it must be there."""
    reason = _unavailable()
    if reason is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the live ROS1 tests, but {reason}")
        pytest.skip(reason)


def wait_until(condition: Callable[[], T], timeout: float, what: str, every: float = 0.05) -> T:
    """Poll ``condition()`` until it returns something true; fail after ``timeout`` seconds."""
    deadline = time.monotonic() + patient(timeout)
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            pytest.fail(f"timed out after {timeout} s waiting for {what}")
        time.sleep(every)


class Master:
    """A roscore on a free port, with the environment its clients need."""

    def __init__(self, home: Path) -> None:
        self.port = free_port()
        self.uri = f"http://127.0.0.1:{self.port}"
        self.env = {
            **os.environ,
            "ROS_MASTER_URI": self.uri,
            "ROS_HOSTNAME": "127.0.0.1",
            "ROS_HOME": str(home),
            "ROS_LOG_DIR": str(home / "log"),
            "PYTHONUNBUFFERED": "1",
        }
        self.env.pop("ROS_IP", None)
        self.process = subprocess.Popen(
            ["roscore", "-p", str(self.port)],
            env=self.env,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        wait_until(self.answers, 30, f"roscore on port {self.port}", every=0.1)

    def master(self) -> Any:
        """The master's XML-RPC API (its answers are untyped lists)."""
        return xmlrpc.client.ServerProxy(self.uri)

    def answers(self) -> bool:
        try:
            code, _, _ = self.master().getSystemState("/test")
            return code == 1 and self.param("/run_id") is not None
        except OSError:
            return False

    def param(self, key: str) -> Any:
        code, _, value = self.master().getParam("/test", key)
        return value if code == 1 else None

    def set_param(self, key: str, value: object) -> None:
        self.master().setParam("/test", key, value)

    def delete_param(self, key: str) -> None:
        self.master().deleteParam("/test", key)

    def publishers(self, topic: str) -> list[str]:
        _, _, (publishers, _, _) = self.master().getSystemState("/test")
        return next((nodes for name, nodes in publishers if name == topic), [])

    def subscribers(self, topic: str) -> list[str]:
        _, _, (_, subscribers, _) = self.master().getSystemState("/test")
        return next((nodes for name, nodes in subscribers if name == topic), [])

    def stop(self) -> None:
        with _suppress():
            os.killpg(self.process.pid, signal.SIGTERM)
        try:
            self.process.wait(10)
        except subprocess.TimeoutExpired:
            with _suppress():
                os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait()


def _suppress() -> contextlib.suppress:
    return contextlib.suppress(ProcessLookupError)


@pytest.fixture(scope="module")
def master(ros1_available: None, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Master]:
    running = Master(tmp_path_factory.mktemp("ros_home"))
    yield running
    running.stop()


class Ros:
    """Start processes against the master; each is killed (its whole group) when the test ends."""

    def __init__(self, master: Master) -> None:
        self.master = master
        self.env = master.env
        self._processes: list[subprocess.Popen[str]] = []

    def spawn(self, *command: str, env: dict[str, str] | None = None, stdin: bool = False) -> subprocess.Popen[str]:
        """``command`` in its own process group; ``stdin``: a pipe to write to (else none)."""
        process = subprocess.Popen(
            list(command),
            env=env or self.env,
            stdin=subprocess.PIPE if stdin else None,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
        self._processes.append(process)
        return process

    def node(self, *arguments: str, stdin: bool = False) -> subprocess.Popen[str]:
        """A rospy helper node from ``ros1_nodes.py``."""
        return self.spawn(ROS_PYTHON, str(NODES), *arguments, stdin=stdin)

    def tfx(self, *arguments: str) -> subprocess.Popen[str]:
        return self.spawn(sys.executable, "-m", "tftools", *arguments)

    def run_tfx(
        self, *arguments: str, timeout: float = 30, env: dict[str, str] | None = None
    ) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "tftools", *arguments],
            env=env or self.env,
            capture_output=True,
            text=True,
            timeout=timeout,
        )

    def run(self, *command: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
        return subprocess.run(list(command), env=self.env, capture_output=True, text=True, timeout=timeout)

    def kill_all(self) -> None:
        for process in self._processes:
            if process.poll() is None:
                with _suppress():
                    os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            for stream in (process.stdin, process.stdout, process.stderr):
                if stream is not None:
                    stream.close()


@pytest.fixture
def ros(master: Master) -> Iterator[Ros]:
    system = Ros(master)
    yield system
    system.kill_all()


def read_line(process: subprocess.Popen[str], contains: str, timeout: float, stream: str = "stdout") -> list[str]:
    """Lines of ``process``'s stream up to the first containing ``contains`` (fail after ``timeout`` s)."""
    import selectors

    pipe = getattr(process, stream)
    lines: list[str] = []
    selector = selectors.DefaultSelector()
    selector.register(pipe, selectors.EVENT_READ)
    deadline = time.monotonic() + patient(timeout)
    try:
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not selector.select(remaining):
                pytest.fail(f"no line with {contains!r} within {timeout} s; got {lines!r}")
            line = pipe.readline()
            if not line:
                pytest.fail(f"{stream} ended before a line with {contains!r}; got {lines!r}")
            lines.append(line)
            if contains in line:
                return lines
    finally:
        selector.unregister(pipe)


STATIC_PUBLISHER = "/usr/lib/tf2_ros/static_transform_publisher"
TF_ECHO = "/usr/lib/tf/tf_echo"


def tf_echo_block(ros: Ros, target: str, source: str) -> str:
    """The first transform the real tf_echo prints."""
    echo = ros.spawn(TF_ECHO, target, source)
    lines = read_line(echo, "in RPY (degree)", timeout=20)
    echo.kill()
    start = max(i for i, line in enumerate(lines) if line.startswith("At time"))
    return "".join(lines[start:])
