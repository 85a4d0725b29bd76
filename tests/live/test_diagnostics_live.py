"""``tfx wtf --watch``: tf's health on /diagnostics, heard by subscribers that are not tfx (rospy with Debian's
diagnostic_msgs, rosdiagnostic, a Cyclone DDS reader with its own type), matching ``tfx wtf`` on the bag played."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.corpus.fetch import shared_dir
from tests.live.conftest import ROS_PYTHON, Master, Ros, read_line, wait_until
from tests.live.ros2_processes import Process, Ros2Domain, domain_fixture  # noqa: F401 - fixture `domain`
from tftools.analysis.edges import edge_stats
from tftools.analysis.findings import Severity
from tftools.analysis.wtf.health import CHECKS_KEY, LEVELS, Level, check_name, edge_name
from tftools.sources.recording import read_recording

pytestmark = pytest.mark.live

HERE = Path(__file__).parent
ROS1_LISTENER = HERE / "ros1_diagnostics_listener.py"
ROS2_LISTENER = HERE / "ros2_diagnostics_listener.py"
#: A real recording with a finding all along (base_link -> base_laser_link, fixed, sent on /tf at 20 Hz)
#: and two moving edges: what the watcher says of its replay must be what wtf says of the bag.
NEATO = "ros1_neato_square_dance.bag"


def corpus(name: str) -> Path:
    path = shared_dir() / "corpus" / name
    if not path.exists():
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must have the corpus recording {path}")
        pytest.skip(f"no corpus recording {path}")
    return path


def heard(path: Path) -> list[dict[str, Any]]:
    """The arrays tfx published (a bag played may hold a robot's own /diagnostics)."""
    arrays = [json.loads(line) for line in path.read_text().splitlines() if line.startswith("{")]
    return [a for a in arrays if a.get("publisher", "/tfx_diagnostics").startswith("/tfx_diagnostics")]


@contextlib.contextmanager
def rospy_listener(ros: Ros, out: Path) -> Iterator[None]:
    """The rospy subscriber of /diagnostics, its lines into ``out`` (a file: a pipe would fill), killed after.
    Skips without Debian's diagnostic_msgs and rosdiagnostic (install-reference.sh); in CI they must be there."""
    probe = subprocess.run([ROS_PYTHON, "-c", "import diagnostic_msgs.msg, rosdiagnostic"], capture_output=True)
    if probe.returncode != 0:
        reason = "python3-diagnostic-msgs and rosdiagnostic are not installed (scripts/install-reference.sh)"
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the /diagnostics tests, but {reason}")
        pytest.skip(reason)
    with out.open("w") as sink:
        listener = subprocess.Popen([ROS_PYTHON, str(ROS1_LISTENER)], env=ros.env, stdout=sink, start_new_session=True)
    try:
        wait_until(lambda: "ready" in out.read_text(), 30, "the rospy listener")
        yield
    finally:
        listener.kill()
        listener.wait()


def watcher(ros: Ros, *options: str) -> subprocess.Popen[str]:
    """``tfx wtf --ros1 --watch OPTIONS``, once it says it is watching."""
    started = ros.tfx("wtf", "--ros1", "--watch", *options)
    read_line(started, "watching", 30, stream="stderr")
    return started


def levels_over(arrays: list[dict[str, Any]]) -> dict[str, int]:
    """Each status's worst level over ``arrays``."""
    worst: dict[str, int] = {}
    for array in arrays:
        for status in array["status"]:
            worst[status["name"]] = max(worst.get(status["name"], 0), status["level"])
    return worst


#: Checks of when transforms arrive, not of what they say: a replay on a loaded machine (these tests share
#: theirs) delivers them in bunches that the recording's own arrivals did not have.
ARRIVALS = frozenset({"rate", "delay"})
ARRIVAL_CHECKS = frozenset(check_name(code) for code in ARRIVALS)


def late_only(status: dict[str, Any]) -> bool:
    """Whether an edge's status is OK, or a warning that only the checks of arrivals set (its ``checks``): what the
    replay's own timing may cause of it, as of the checks' statuses (a fresh clone's CI run once heard the Neato's
    odom -> base_link WARN)."""
    checks = set(status["values"].get(CHECKS_KEY, "").split())
    return status["level"] == Level.OK or (status["level"] == Level.WARN and bool(checks) and checks <= ARRIVALS)


def unexplained(said: dict[str, int], expected: dict[str, int]) -> dict[str, int]:
    """The checks said above OK that the bag does not say, but for warnings the replay's own timing may cause."""
    return {
        name: level
        for name, level in said.items()
        if name not in expected and not (name in ARRIVAL_CHECKS and level == Level.WARN)
    }


def bag_says(tfx_run: Callable[..., subprocess.CompletedProcess[str]], bag: Path) -> dict[str, int]:
    """``tfx wtf BAG``'s findings as the levels of their checks' statuses."""
    done = tfx_run("wtf", str(bag), "-f", "json")
    [report] = json.loads(done.stdout)["bags"]
    said: dict[str, int] = {}
    for finding in report["findings"]:
        if not finding["skipped"]:
            name = check_name(finding["code"])
            said[name] = max(said.get(name, 0), int(LEVELS[Severity(finding["severity"])]))
    return said


def test_a_rospy_node_and_rosdiagnostic_hear_on_diagnostics_what_wtf_says_of_the_bag(
    ros: Ros, master: Master, tmp_path: Path
) -> None:
    bag = corpus(NEATO)
    expected = bag_says(ros.run_tfx, bag)
    assert expected == {check_name("static_on_dynamic"): Level.WARN}  # the manifest's verdict on it
    out = tmp_path / "heard.jsonl"
    with rospy_listener(ros, out):
        watching = watcher(ros, "--use-sim-time")
        wait_until(lambda: master.publishers("/diagnostics"), 15, "tfx on /diagnostics")
        wait_until(lambda: any("tfx" in n for n in master.subscribers("/tf")), 15, "tfx on /tf")
        play = ros.spawn("rosbag", "play", "--clock", "-q", str(bag))
        wait_until(lambda: len(heard(out)) >= 8, 60, "eight DiagnosticArrays")
        echo = ros.run(
            ROS_PYTHON,
            "-c",
            "from rosdiagnostic import rosdiagnosticmain; rosdiagnosticmain()",
            "--topic",
            "/diagnostics",
            "--nocolor",
            "-d",
            timeout=30,
        )
        assert play.wait(120) == 0
        watching.send_signal(signal.SIGINT)  # Ctrl-C: a clean stop, unregistered
        assert watching.wait(20) == 0, watching.stderr.read() if watching.stderr else ""
        wait_until(lambda: not master.publishers("/diagnostics"), 10, "/diagnostics unregistered")
    arrays = heard(out)
    hearing = [a for a in arrays if a["status"][0]["name"] == "tf: tree" and a["status"][0]["level"] != Level.STALE]
    assert len(hearing) >= 8
    said = levels_over(hearing)
    checks = {name: level for name, level in said.items() if name.startswith("tf check: ") and level}
    assert {name: checks.get(name) for name in expected} == expected  # each of the bag's, at its level
    assert not unexplained(checks, expected)
    assert said[edge_name("base_link", "base_laser_link")] == Level.WARN
    odom = [s for a in hearing for s in a["status"] if s["name"] == edge_name("odom", "base_link")]
    assert odom and all(late_only(s) for s in odom), [s for s in odom if not late_only(s)]
    assert all(s["hardware_id"] == "tf" for a in arrays for s in a["status"])

    recording = read_recording([bag])
    rates = {(e.parent, e.child): e.rate_hz for e in edge_stats(recording.buffer)}
    middle = hearing[len(hearing) // 2]
    for status in middle["status"]:
        values = status["values"]
        if "child" in values and values.get("rate (Hz)") not in (None, "static"):
            bag_rate = rates[(values["parent"], values["child"])]
            assert float(values["rate (Hz)"]) == pytest.approx(bag_rate, rel=0.1), status
            assert float(values["silent for the last (s)"]) < 2.0
    begin, end = recording.start, recording.end
    assert all(begin - 2 * 10**9 <= a["stamp"] <= end + 2 * 10**9 for a in hearing)  # on the bag's /clock

    assert echo.returncode == 0, echo.stderr
    assert "[ WARN  ] tf check: static_on_dynamic - base_link -> base_laser_link never changes" in echo.stdout
    assert "hardware_id: tf" in echo.stdout


def test_a_dead_publisher_is_said_stale_and_a_restarted_one_heard_again(
    ros: Ros, master: Master, tmp_path: Path
) -> None:
    out = tmp_path / "heard.jsonl"
    with rospy_listener(ros, out):
        watching = watcher(ros, "--wall-time", "--window", "3")
        robot = ros.node("dynamic", "robot", "odom", "base_link", "0")

        def level(wanted: int) -> bool:
            last = heard(out)[-1:] if heard(out) else []
            return any(
                s["name"] == edge_name("odom", "base_link") and s["level"] == wanted for a in last for s in a["status"]
            )

        wait_until(lambda: level(Level.OK), 30, "the edge OK")
        robot.kill()
        robot.wait()
        wait_until(lambda: level(Level.STALE), 30, "the edge STALE once out of the window")
        ros.node("dynamic", "robot", "odom", "base_link", "0")
        wait_until(lambda: level(Level.OK), 30, "the edge OK again")
        watching.send_signal(signal.SIGINT)
        assert watching.wait(20) == 0


def test_an_independent_dds_reader_hears_ros2_diagnostics_from_an_announced_node(
    domain: Ros2Domain, tmp_path: Path
) -> None:
    listener = Process([sys.executable, str(ROS2_LISTENER)], domain.env)
    try:
        listener.wait_for("ready")
        robot = domain.node("dynamic", "robot", "odom", "base_link")
        robot.wait_for("ready")
        watcher = domain.tfx("wtf", "--ros2", "--watch")
        watcher.wait_for("watching", timeout=30)
        line = ""
        deadline = time.monotonic() + 40
        while time.monotonic() < deadline:
            line = listener.wait_for('"status"', timeout=30)
            array = json.loads(line)
            edges = {s["name"]: s for s in array["status"]}
            if edge_name("odom", "base_link") in edges and array["status"][0]["level"] == Level.OK:
                break
        else:
            pytest.fail(f"no healthy array heard; last {line[:500]}")
        edge = edges[edge_name("odom", "base_link")]
        assert edge["level"] == Level.OK and edge["hardware_id"] == "tf"
        assert 0 < float(edge["values"]["rate (Hz)"]) <= 55  # the node's 50 Hz, less what a loaded machine loses
        assert abs(array["stamp"] - time.time_ns()) < 5 * 10**9  # wall time, as the source's clock
        checks = [s for s in array["status"] if s["name"].startswith("tf check: ")]
        assert checks and all(s["level"] == Level.OK for s in checks), [s for s in checks if s["level"]]
        graph = domain.node("discovery_listener", "16")  # as ros2 node list learns the nodes
        assert "/tfx_diagnostics_" in graph.wait_for("/tfx_diagnostics_", timeout=20)
        watcher.popen.send_signal(signal.SIGINT)
        assert watcher.finish().returncode == 0
    finally:
        listener.stop()


def rss_kib(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError(f"no VmRSS for {pid}")


#: The soak's length (s): TFX_SOAK_SECONDS=1800 for the 30 min soak; 2 min by default, as CI runs the slow tests
#: too, within its 90 min.
SOAK_SECONDS = float(os.environ.get("TFX_SOAK_SECONDS", "120"))


@pytest.mark.slow
def test_soak_a_looping_replay_memory_stays_bounded_and_the_jumps_back_are_no_findings(
    ros: Ros, master: Master, tmp_path: Path
) -> None:
    """``rosbag play --clock --loop`` for ``SOAK_SECONDS``: each loop is a jump back of ROS time. The watcher's
    memory (RSS, printed) after the first loops stays within a bound, and what it says of each pass is what
    wtf says of the bag."""
    bag = corpus(NEATO)
    expected = bag_says(ros.run_tfx, bag)
    out = tmp_path / "heard.jsonl"
    with rospy_listener(ros, out):
        watching = watcher(ros, "--use-sim-time")
        ros.spawn("rosbag", "play", "--clock", "--loop", "-q", str(bag))
        started = time.monotonic()
        samples: list[tuple[float, int]] = []
        while time.monotonic() - started < SOAK_SECONDS:
            time.sleep(min(10.0, SOAK_SECONDS / 20))
            samples.append((time.monotonic() - started, rss_kib(watching.pid)))
            print(f"soak: {samples[-1][0]:7.0f} s  RSS {samples[-1][1] / 1024:6.1f} MiB", flush=True)
        watching.send_signal(signal.SIGINT)
        assert watching.wait(30) == 0
        assert watching.stderr is not None
        told = watching.stderr.read()
    assert "ROS time jumped back" in told  # the loops were heard as jumps back (the bag is 20 s long)
    warm = max(rss for at, rss in samples if at <= SOAK_SECONDS / 4)
    last = max(rss for at, rss in samples if at >= SOAK_SECONDS * 3 / 4)
    print(f"soak: RSS after the first quarter {warm / 1024:.1f} MiB, in the last quarter at most {last / 1024:.1f} MiB")
    assert last <= warm + 20 * 1024  # bounded: no growth with the passes (a leak of a pass would be ~MiBs each)
    hearing = [a for a in heard(out) if a["status"][0]["level"] != Level.STALE]
    said = {n: level for n, level in levels_over(hearing).items() if n.startswith("tf check: ") and level}
    assert said.get(check_name("static_on_dynamic")) == Level.WARN
    assert not unexplained(said, expected)
