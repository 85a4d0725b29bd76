"""``tfx wtf --dask`` on a real cluster on loopback: a scheduler and two workers, each its own process
(the scheduler runs a task on at most two workers that die: allowed-failures 1). The same report as
``--jobs``; a worker killed mid-run; a task over its timeout retried once, then reported."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.analysis.wtf_scenes import PROBLEMS, healthy, write
from tests.bags import BagFormat

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[2]
HOOK = Path(__file__).with_name("dask_hook.py")


@dataclass
class Cluster:
    address: str
    marks: Path  # where the workers' hook says which worker tried which recording

    def tries(self, name: str) -> list[int]:
        """The worker processes that tried the recording ``name``, in order."""
        found = sorted(self.marks.glob(f"started-*-{name}"), key=lambda p: int(p.name.split("-")[2]))
        return [int(p.name.split("-")[1]) for p in found]

    def ready(self) -> None:
        from distributed import Client

        with Client(self.address, timeout="10s") as client:  # type: ignore[no-untyped-call]  # distributed is unannotated
            client.wait_for_workers(2, timeout=60)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Cluster]:
    pytest.importorskip("distributed")
    directory = tmp_path_factory.mktemp("dask")
    marks = directory / "marks"
    marks.mkdir()
    env = {
        **os.environ,
        "PYTHONPATH": str(REPO),
        "TFX_TEST_MARKS": str(marks),
        "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "1",
    }
    scheduler_file = directory / "scheduler.json"
    started: list[subprocess.Popen[bytes]] = []

    def start(name: str, *args: str | Path) -> None:
        with (directory / f"{name}.log").open("wb") as log:
            command = [sys.executable, "-m", *(str(a) for a in args), "--no-dashboard"]
            started.append(
                subprocess.Popen(command, env=env, cwd=directory, stdout=log, stderr=log, start_new_session=True)
            )

    try:
        start(
            "scheduler",
            "distributed.cli.dask_scheduler",
            "--host",
            "127.0.0.1",
            "--port",
            "0",
            "--scheduler-file",
            scheduler_file,
        )
        for n in range(2):
            worker = ("--nthreads", "1", "--preload", HOOK, "--local-directory", directory / f"worker{n}")
            start(
                f"worker{n}",
                "distributed.cli.dask_worker",
                "--scheduler-file",
                scheduler_file,
                "--host",
                "127.0.0.1",
                *worker,
            )
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        running = Cluster(json.loads(scheduler_file.read_text())["address"], marks)
        running.ready()
        yield running
    finally:
        for process in reversed(started):  # each started in its own session: the nanny's worker goes too
            os.killpg(process.pid, signal.SIGTERM)
        for process in started:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """ROS 1, .db3 and .mcap recordings, healthy and not, a corrupt one, and the hook's slow ones."""
    directory = tmp_path_factory.mktemp("fleet")
    made = {"healthy": write(directory, "healthy", BagFormat.ros1, healthy())}
    made["stale"] = write(directory, "stale", BagFormat.rosbag2_sqlite3, PROBLEMS["stale"].make())
    made["cycle"] = write(directory, "cycle", BagFormat.rosbag2_mcap, PROBLEMS["cycle"].make())
    made["delay"] = write(directory, "delay", BagFormat.ros1, PROBLEMS["delay"].make())
    made["corrupt"] = directory / "corrupt.mcap"
    made["corrupt"].write_bytes(b"\x89MCAP0\r\n" + b"not a bag" * 100)
    for slow in ("slow_once", "slow_always"):
        made[slow] = directory / f"{slow}.bag"
        shutil.copyfile(made["healthy"], made[slow])
    return made


def tfx(*args: str | Path) -> subprocess.Popen[str]:
    command = [sys.executable, "-m", "tftools", "wtf", *(str(a) for a in args)]
    return subprocess.Popen(command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def finished(process: subprocess.Popen[str]) -> tuple[int, str, str]:
    out, err = process.communicate(timeout=120)
    return process.returncode, out, err


def test_dask_gives_the_same_report_as_jobs(cluster: Cluster, bags: dict[str, Path]) -> None:
    fleet = [bags[n] for n in ("healthy", "stale", "cycle", "delay", "corrupt")]
    code, out, err = finished(tfx(*fleet, "--dask", cluster.address, "--format", "json"))
    jobs_code, jobs_out, _ = finished(tfx(*fleet, "--jobs", "2", "--format", "json"))
    assert code == jobs_code == 1, err
    assert json.loads(out) == json.loads(jobs_out)
    assert [b["verdict"] for b in json.loads(out)["bags"]] == ["passed", "failed", "failed", "passed", "unusable"]


def test_a_worker_killed_mid_run_is_retried_and_the_fleet_completes(cluster: Cluster, bags: dict[str, Path]) -> None:
    cluster.ready()
    fleet = [bags[n] for n in ("healthy", "slow_once", "stale", "cycle")]
    run = tfx(*fleet, "--dask", cluster.address, "--format", "jsonl")
    deadline = time.monotonic() + 120
    while not cluster.tries("slow_once.bag") and time.monotonic() < deadline:
        time.sleep(0.1)
    (worker,) = cluster.tries("slow_once.bag")
    os.kill(worker, signal.SIGKILL)  # the worker process, hung in the check; its nanny starts a new one
    code, out, err = finished(run)
    *recordings, summary = [json.loads(line) for line in out.splitlines()]
    assert code == 1 and summary["summary"]["recordings"] == 4, err
    slow = next(r for r in recordings if r["paths"] == [str(bags["slow_once"])])
    assert slow["verdict"] == "passed" and slow["error"] is None and slow["transforms"] > 0
    tries = cluster.tries("slow_once.bag")
    assert len(tries) == 2 and tries[1] != worker
    _, jobs_out, _ = finished(tfx(*fleet, "--jobs", "2", "--format", "json"))
    assert json.loads(jobs_out)["fleet"] == summary["fleet"]


def test_a_task_over_its_timeout_is_retried_once_then_reported(cluster: Cluster, bags: dict[str, Path]) -> None:
    cluster.ready()
    code, out, err = finished(
        tfx(bags["healthy"], bags["slow_always"], "--dask", cluster.address, "--timeout", "1", "--format", "json")
    )
    good, slow = json.loads(out)["bags"]
    assert code == 1 and good["verdict"] == "passed", err
    assert slow["verdict"] == "unusable" and slow["error"]["code"] == "unchecked"
    assert slow["error"]["message"].endswith("not checked: its check took longer than 1 s, twice")
    assert len(cluster.tries("slow_always.bag")) == 2


def test_a_scheduler_that_is_not_there_is_one_line_and_exit_2(bags: dict[str, Path]) -> None:
    pytest.importorskip("distributed")
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    code, out, err = finished(tfx(bags["healthy"], "--dask", f"tcp://127.0.0.1:{port}"))
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "cannot reach the Dask scheduler" in err and "dask scheduler" in err


@pytest.mark.parametrize(
    "address", ["", "garbage", "inproc://x", "ucx://127.0.0.1:8786", "tcp://[::1", "tcp://host", "tcp://:8786"]
)
def test_an_address_that_names_no_scheduler_is_one_line_and_exit_2(bags: dict[str, Path], address: str) -> None:
    """Refused before Dask sees it: no traceback from a half-built client, now or when it is collected."""
    code, out, err = finished(tfx(bags["healthy"], "--dask", address))
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "not a scheduler address" in err and "tcp://127.0.0.1:8786" in err


def test_a_scheduler_that_accepts_and_never_answers_is_given_up_on(bags: dict[str, Path]) -> None:
    """A peer that takes the connection and says nothing: refused within the connect deadline, one line."""
    pytest.importorskip("distributed")
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen(16)  # accepted by the kernel, never read nor answered
        started = time.monotonic()
        code, out, err = finished(tfx(bags["healthy"], "--dask", f"tcp://127.0.0.1:{silent.getsockname()[1]}"))
        took = time.monotonic() - started
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "Dask scheduler" in err
    print(f"given up after {took:.1f} s")  # a figure, not a timed assertion: the machine may be busy
