"""The checker on bag files of every format, and against the real roswtf tf plugin and rosbag."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from tests.analysis.wtf_scenes import FORMATS, PROBLEMS, healthy, recording, write
from tests.bags import BagFormat, TfMessage
from tftools.analysis.findings import Finding, Severity, causes
from tftools.analysis.wtf.fleet import check
from tftools.sources.recording import read_recording

SAMPLES = Path(__file__).resolve().parents[2] / "sample_bags"
SAMPLE_BAGS = {
    BagFormat.ros1: "robot.bag",
    BagFormat.rosbag2_sqlite3: "robot_db3",
    BagFormat.rosbag2_mcap: "robot_mcap",
}
ROS_PYTHON = "/usr/bin/python3"
HARNESS = Path(__file__).with_name("wtf_ros1.py")

#: What each roswtf rule reports, as the codes of ours that cover it (roswtf takes a frame sent as
#: its own child, which tf2 refuses, for a re-parented frame, a loop and a second publisher).
ROSWTF_CODES = {
    "reparenting": {"multiple_parents", "self_transform"},
    "cycle_detection": {"cycle", "self_transform"},
    "multiple_authority": {"multiple_authorities", "multiple_parents", "self_transform"},
    "not_normalized": {"invalid_values"},
    "rostime_delta": {"clock", "future", "delay", "time_backwards"},  # a jump back in time leaves stamps behind
    "no_msgs": {"no_tf"},
}
#: The rule of roswtf that must see each scene's problem (where roswtf checks for it at all).
ROSWTF_SEES = {
    "cycle": "cycle_detection",
    "multiple_parents": "reparenting",
    "multiple_authorities": "multiple_authority",
    "invalid_values": "not_normalized",
    "clock": "rostime_delta",
    "clock_replay": "rostime_delta",
    "future": "rostime_delta",
    "no_tf": "no_msgs",
}


def loud(findings: list[Finding]) -> list[Finding]:
    """The findings a verdict counts (those that follow from another are counted with it), but notes."""
    return [f for f in causes(findings) if f.severity is not Severity.info]


@pytest.mark.parametrize("fmt", FORMATS)
def test_the_sample_robot_bags_give_no_finding(fmt: BagFormat) -> None:
    assert check(read_recording([SAMPLES / SAMPLE_BAGS[fmt]])).findings == []


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("name", list(PROBLEMS))
def test_each_problem_written_to_a_bag_gives_its_finding(tmp_path: Path, fmt: BagFormat, name: str) -> None:
    problem = PROBLEMS[name]
    if problem.streams is not None:
        pytest.skip("sensor data is not written to these bags: tests/cli/test_filter.py checks wtf on such bags")
    path = write(tmp_path, name, fmt, problem.make(), problem.clock() if problem.clock else None)
    findings = check(read_recording([path], problem.topics, allow_empty=True)).findings
    if problem.ros1_only and fmt is not BagFormat.ros1:  # ROS 2 bags answer as ROS 2's tf2, naming no publisher
        assert [f.code for f in loud(findings)] == ([problem.ros2_code] if problem.ros2_code else []), findings
        return
    shown = findings if problem.severity == "info" else loud(findings)
    assert [f.code for f in shown] == [problem.code], findings
    finding = findings[0]
    assert finding.severity.value == problem.severity
    assert set(problem.frames) <= set(finding.frames)
    for word in problem.words:
        assert word in finding.message + finding.hint
    if fmt is BagFormat.ros1 and problem.publisher:
        assert problem.publisher in finding.authorities


# --- the real roswtf and rosbag ------------------------------------------------------------------


def as_json(messages: list[TfMessage]) -> list[list[object]]:
    return [
        [
            m.topic,
            m.record_time,
            m.publisher,
            [[t.frame_id, t.child_frame_id, t.stamp, *t.translation, *t.rotation] for t in m.transforms],
        ]
        for m in messages
    ]


def run_harness(args: list[str], request: dict[str, object]) -> str:
    done = subprocess.run(
        [ROS_PYTHON, str(HARNESS), *args], input=json.dumps(request), capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def roswtf(tf2_available: None) -> dict[str, dict[str, object]]:
    """What roswtf's tf rules say about each scene (and "healthy")."""
    scenes = {"healthy": healthy(), **{name: p.make() for name, p in PROBLEMS.items()}}
    out = run_harness(["roswtf"], {"scenes": [as_json(m) for m in scenes.values()]})
    return dict(zip(scenes, json.loads(out)["results"], strict=True))


def test_roswtf_finds_nothing_on_the_healthy_robot_either(roswtf: dict[str, dict[str, object]]) -> None:
    assert not any(roswtf["healthy"].values()), roswtf["healthy"]


@pytest.mark.parametrize("name", list(ROSWTF_SEES))
def test_roswtf_agrees_each_scene_shows_its_problem(roswtf: dict[str, dict[str, object]], name: str) -> None:
    assert roswtf[name][ROSWTF_SEES[name]], roswtf[name]


@pytest.mark.parametrize("name", list(PROBLEMS))
def test_whatever_roswtf_reports_we_report_too(roswtf: dict[str, dict[str, object]], name: str) -> None:
    problem = PROBLEMS[name]
    ours = {f.code for f in check(recording(problem.make(), problem.topics)).findings}
    for rule, said in roswtf[name].items():
        if said:
            assert ours & ROSWTF_CODES[rule], f"roswtf {rule}: {said}; ours: {ours}"


def test_roswtf_and_we_name_the_same_reparenting_publisher(roswtf: dict[str, dict[str, object]]) -> None:
    said = roswtf["multiple_parents"]["reparenting"]
    assert said == ["reparenting of [base_link] to [map] by [/rogue]", "reparenting of [base_link] to [odom] by [/ekf]"]
    finding = next(
        f for f in check(recording(PROBLEMS["multiple_parents"].make())).findings if f.code == "multiple_parents"
    )
    assert finding.frames == ("base_link", "odom", "map") and set(finding.authorities) == {"/ekf", "/rogue"}


def test_roswtf_and_we_see_the_same_loop(roswtf: dict[str, dict[str, object]]) -> None:
    loops = roswtf["cycle"]["cycle_detection"]
    assert isinstance(loops, list) and loops
    finding = next(f for f in check(recording(PROBLEMS["cycle"].make())).findings if f.code == "cycle")
    for said in loops:  # "Frame X is in a loop. It's loop has elements:\nX -> Y -> Z"
        assert set(said.split("\n")[1].split(" -> ")) == set(finding.frames)


@pytest.mark.parametrize("name", ["invalid_values", "leading_slash", "self_transform", "empty_frame_id"])
def test_bags_written_by_the_real_rosbag_give_the_finding(tf2_available: None, tmp_path: Path, name: str) -> None:
    problem = PROBLEMS[name]
    path = tmp_path / f"{name}.bag"
    run_harness(["bag", str(path)], {"messages": as_json(problem.make())})
    findings = check(read_recording([path])).findings
    shown = findings if problem.severity == "info" else loud(findings)
    assert [f.code for f in shown] == [problem.code], findings
    assert set(problem.frames) <= set(findings[0].frames)
    for word in problem.words:
        assert word in findings[0].message + findings[0].hint
