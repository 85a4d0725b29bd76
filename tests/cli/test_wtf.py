"""``tfx wtf`` as a user and a CI job run it: bags, fleets, formats, exit codes, options."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

from tests.analysis.wtf_scenes import MS, PROBLEMS, ekf, healthy, write
from tests.bags import BagFormat, TfMessage
from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tftools.analysis.findings import Severity
from tftools.analysis.wtf import CHECKS
from tftools.analysis.wtf.causes import Rule, severity_as_cause

DB3 = BagFormat.rosbag2_sqlite3


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A healthy bag, one per problem (db3), a corrupt one, one cut short, and a recording split in two."""
    directory = tmp_path_factory.mktemp("wtf")
    made = {"healthy": write(directory, "healthy", DB3, healthy())}
    for name in ("stale", "rate", "cycle", "delay", "future", "clock_replay"):
        made[name] = write(directory, name, DB3, PROBLEMS[name].make())
    corrupt = directory / "corrupt.mcap"
    corrupt.write_bytes(b"\x89MCAP0\r\n" + b"not a bag" * 100)
    made["corrupt"] = corrupt
    ros1 = write(directory, "whole", BagFormat.ros1, healthy())
    cut = directory / "cut.bag"
    cut.write_bytes(ros1.read_bytes()[: ros1.stat().st_size * 2 // 5])
    made["cut"] = cut
    messages = healthy(ekf=ekf(end=4.0))  # /ekf stops at 4 s: stale, but only the whole recording shows it
    split = 5_000 * MS + messages[0].record_time
    made["part1"] = write(directory, "part1", DB3, [m for m in messages if m.record_time < split])
    made["part2"] = write(directory, "part2", DB3, [m for m in messages if m.record_time >= split])
    return made


def as_json(stdout: str) -> dict[str, Any]:
    document: dict[str, Any] = json.loads(stdout)
    return document


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
def test_the_sample_bags_pass_with_no_finding(tfx: Tfx, fmt: str) -> None:
    result = tfx("wtf", SAMPLE_BAGS[fmt])
    assert result.code == 0, result.stdout + result.stderr
    assert "no problems found: PASSED" in result.stdout
    assert "ERRORS" not in result.stdout and "WARNINGS" not in result.stdout


def test_a_problem_is_listed_by_severity_with_its_hint_and_exits_1(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["stale"])
    assert result.code == 1
    lines = result.stdout.splitlines()
    assert lines[0].startswith(str(bags["stale"])) and "rosbag2-sqlite3" in lines[0]
    assert lines[1] == "ERRORS (1)"
    assert lines[2].startswith("  ✗ stale: odom -> base_link on /tf stopped at")
    assert lines[3].startswith("      hint: its publisher stopped")
    assert lines[-1] == "1 error, 0 warnings, 0 notes: FAILED"


def test_warnings_pass_unless_strict(tfx: Tfx, bags: dict[str, Path]) -> None:
    relaxed = tfx("wtf", bags["rate"])
    assert relaxed.code == 0 and "WARNINGS (1)" in relaxed.stdout and relaxed.stdout.endswith("PASSED\n")
    strict = tfx("wtf", bags["rate"], "--strict")
    assert strict.code == 1 and strict.stdout.endswith("FAILED\n")


def test_a_fleet_with_one_bad_bag_exits_1_and_says_which(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["healthy"], bags["stale"], SAMPLE_BAGS["mcap"])
    assert result.code == 1
    last = result.stdout.splitlines()[-1]
    assert last.startswith("3 recordings checked: 2 passed, 1 failed, 0 unusable (1 error, 0 warnings, 0 notes)")
    assert last.endswith(f"failing: {bags['stale']}")


def test_a_corrupt_bag_in_a_fleet_is_reported_and_the_others_still_checked(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["corrupt"], bags["cycle"], bags["healthy"], "--format", "json")
    assert result.code == 1
    report = as_json(result.stdout)
    corrupt, cycle, good = report["bags"]
    assert corrupt["error"]["code"] == "unreadable" and "corrupt" in corrupt["error"]["message"]
    assert corrupt["findings"] == [] and corrupt["passed"] is False
    assert [f["code"] for f in cycle["findings"]] == ["cycle"] and cycle["passed"] is False
    assert good["findings"] == [] and good["passed"] is True and good["error"] is None
    assert report["summary"] == {
        "recordings": 3, "passed": 1, "failed": 1, "unusable": 1, "errors": 1, "warnings": 0, "notes": 0,
        "explained": 0,
    }  # fmt: skip
    assert report["exit_code"] == 1


def test_no_readable_bag_at_all_exits_2(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    alone = tfx("wtf", tmp_path / "missing.bag")
    assert alone.code == 2 and alone.stdout == ""
    assert alone.stderr.startswith("tfx: error: ") and "missing.bag: no such file or directory" in alone.stderr
    fleet = tfx("wtf", tmp_path / "missing.bag", bags["corrupt"])
    assert fleet.code == 2 and "0 passed, 0 failed, 2 unusable" in fleet.stdout
    document = tfx("wtf", bags["corrupt"], "--format", "json")
    assert document.code == 2 and as_json(document.stdout)["exit_code"] == 2


def test_a_bag_cut_short_is_checked_as_far_as_it_goes_with_a_warning(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["cut"], "--format", "json")
    bag = as_json(result.stdout)["bags"][0]
    assert result.code == 0 and bag["error"] is None and bag["transforms"] > 0
    assert [f["code"] for f in bag["findings"]] == ["bag_problem"]
    assert bag["findings"][0]["severity"] == "warning" and "truncated" in bag["findings"][0]["message"]
    assert tfx("wtf", bags["cut"], "--strict").code == 1


def test_b_bags_are_one_recording_and_positional_bags_each_their_own(tfx: Tfx, bags: dict[str, Path]) -> None:
    merged = as_json(tfx("wtf", "-b", bags["part1"], "-b", bags["part2"], "--format", "json").stdout)
    assert len(merged["bags"]) == 1 and merged["bags"][0]["paths"] == [str(bags["part1"]), str(bags["part2"])]
    assert [f["code"] for f in merged["bags"][0]["findings"]] == ["stale"]
    apart = as_json(tfx("wtf", bags["part1"], bags["part2"], "--format", "json").stdout)
    first, second = apart["bags"]
    assert first["findings"] == []  # /ekf stopped only 1 s before this part ends
    assert [f["code"] for f in second["findings"]] == ["disconnected"]  # odom -> base_link is in the first part


def test_json_findings_carry_every_field_with_times_in_seconds(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["stale"], "--format", "json")
    report = as_json(result.stdout)
    assert report["tool"] == "tfx wtf" and report["strict"] is False
    assert report["thresholds"] == {"stale_after": 1.0, "max_gap": 0.5, "delay": 0.2, "future": 1.0, "clock": 10.0}
    bag = report["bags"][0]
    assert bag["formats"] == ["rosbag2-sqlite3"] and bag["frames"] == 6
    assert bag["start"] == pytest.approx(1_700_000_000.002) and bag["end"] == pytest.approx(1_700_000_009.982)
    (finding,) = bag["findings"]
    assert set(finding) == {
        "severity", "code", "message", "hint", "frames", "authorities", "first_time", "last_time", "count", "skipped",
        "key", "cause", "figures",
    }  # fmt: skip
    assert finding["severity"] == "error" and finding["frames"] == ["odom", "base_link"]
    assert finding["skipped"] is False
    assert finding["authorities"] == ["/tf"] and finding["count"] == 200
    assert finding["first_time"] == pytest.approx(1_700_000_003.98) and finding["last_time"] == bag["end"]


def test_jobs_check_a_fleet_in_parallel_with_the_same_report(tfx: Tfx, bags: dict[str, Path]) -> None:
    fleet = [bags[n] for n in ("healthy", "stale", "corrupt", "rate", "delay")]
    serial = tfx("wtf", *fleet, "--format", "json")
    parallel = tfx("wtf", *fleet, "--format", "json", "--jobs", "3")
    assert serial.code == parallel.code == 1
    assert as_json(serial.stdout) == as_json(parallel.stdout)


def test_junit_has_a_suite_per_bag_and_a_case_per_check(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["healthy"], bags["stale"], bags["rate"], bags["corrupt"], "--format", "junit")
    assert result.code == 1
    root = ET.fromstring(result.stdout)
    assert root.tag == "testsuites"
    healthy_suite, stale, rate, corrupt = root.findall("testsuite")
    runnable = [code for code, c in CHECKS.items() if c.run is not None]
    for suite in (healthy_suite, stale, rate):
        assert [case.get("name") for case in suite.findall("testcase")] == runnable
        assert suite.get("tests") == str(len(runnable)) and suite.get("errors") == "0"
    assert stale.get("name") == str(bags["stale"]) and stale.get("failures") == "1"
    failed = [case for case in stale.findall("testcase") if case.find("failure") is not None]
    assert [case.get("name") for case in failed] == ["stale"]
    failure = failed[0].find("failure")
    assert failure is not None and failure.get("message", "").startswith("odom -> base_link")
    assert "hint:" in (failure.text or "")
    assert rate.get("failures") == "0"  # a warning: in the output, not a failure
    gap = next(case for case in rate.findall("testcase") if case.get("name") == "rate")
    assert gap.find("failure") is None and "went silent" in (gap.findtext("system-out") or "")
    assert corrupt.get("errors") == "1" and corrupt.find("testcase/error") is not None
    assert root.get("failures") == "1" and root.get("errors") == "1"


def test_junit_strict_fails_on_warnings(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["rate"], "--format", "junit", "--strict")
    assert result.code == 1
    suite = ET.fromstring(result.stdout).find("testsuite")
    assert suite is not None and suite.get("failures") == "1"
    assert suite.find("testcase[@name='rate']/failure") is not None


def test_thresholds_have_flags(tfx: Tfx, bags: dict[str, Path]) -> None:
    assert tfx("wtf", bags["delay"]).code == 0  # a warning
    assert "WARNINGS (1)" in tfx("wtf", bags["delay"]).stdout
    assert "no problems found" in tfx("wtf", bags["delay"], "--delay", "0.6").stdout
    assert tfx("wtf", bags["stale"], "--stale-after", "7").code == 0
    assert "no problems found" in tfx("wtf", bags["rate"], "--max-gap", "5").stdout
    bad = tfx("wtf", bags["delay"], "--delay", "0")
    assert bad.code == 2 and "--delay 0: must be above 0" in bad.stderr


def test_future_and_clock_thresholds_have_flags(tfx: Tfx, bags: dict[str, Path]) -> None:
    def codes(*args: str | Path) -> set[str]:
        (bag,) = as_json(tfx("wtf", *args, "--format", "json").stdout)["bags"]
        return {f["code"] for f in bag["findings"]}

    assert "future" in codes(bags["future"])  # stamps 3 s ahead of their arrival
    assert "future" in codes(bags["future"], "--future", "2.5")
    assert "future" not in codes(bags["future"], "--future", "3.5")
    assert "clock" in codes(bags["clock_replay"])  # stamps 3 days behind their arrival
    assert "clock" not in codes(bags["clock_replay"], "--clock", str(4 * 86400))
    bad = tfx("wtf", bags["future"], "--future", "-1")
    assert bad.code == 2 and "--future" in bad.stderr


def test_ignore_skips_checks_and_refuses_unknown_codes(tfx: Tfx, bags: dict[str, Path]) -> None:
    assert tfx("wtf", bags["stale"], "--ignore", "stale").code == 0
    wrong = tfx("wtf", bags["stale"], "--ignore", "staler")
    assert wrong.code == 2 and "there is no such check" in wrong.stderr and "did you mean stale?" in wrong.stderr
    junit = ET.fromstring(tfx("wtf", bags["stale"], "--ignore", "stale", "--format", "junit").stdout)
    assert "stale" not in [case.get("name") for case in junit.iter("testcase")]


def test_list_checks_names_every_code_with_its_severity(tfx: Tfx) -> None:
    """Each check with the most it reports on its own (multiple_authorities: an error, where two publishers at once
    contradict each other), and where a finding of it can explain worse ones (a root cause, as severe as what
    follows from it: ``causes.explain``), that severity too: a warning with an error following is an error."""
    result = tfx("wtf", "--list-checks")
    assert result.code == 0
    severities = {code: c.severity for code, c in CHECKS.items()}
    for code, c in CHECKS.items():
        assert any(
            line.split()[:2] in ([code, c.severity.value], [code, f"{c.severity.value},"])
            for line in result.stdout.splitlines()
        )
    text = " ".join(result.stdout.split())
    raised = [code for code in CHECKS if severity_as_cause(code, severities) is not severities[code]]
    assert severities["multiple_authorities"] is Severity.error
    follows = Rule(frozenset({"cause"}), frozenset({"effect"}), lambda cause, it: True, "")
    as_cause = {"cause": Severity.warning, "effect": Severity.error}
    assert severity_as_cause("cause", as_cause, (follows,)) is Severity.error
    assert text.count("error as a cause") == len(raised) + 1  # and the caption's example
    assert "as severe as the worst of them" in text


def test_help_documents_fleets_and_exit_codes(tfx: Tfx) -> None:
    text = " ".join(tfx("wtf", "--help").stdout.split())  # as read: the help is wrapped at 80 columns
    for words in ("each on its own", "Exit codes", "--strict", "--jobs", "junit", "--stale-after"):
        assert words in text


def test_a_bag_without_transforms_is_the_no_tf_error(tfx: Tfx, tmp_path: Path) -> None:
    bag = write(
        tmp_path, "odom_only", DB3, [TfMessage("/odom_tf", 1_700_000_000 * 10**9 + i, [], "/x") for i in range(3)]
    )
    result = tfx("wtf", bag)
    assert result.code == 1
    assert "no_tf: no transforms on /tf, /tf_static in" in result.stdout and "topics present: /odom_tf" in result.stdout


def test_no_tf_names_the_recorded_transform_topics_to_read(tfx: Tfx, tmp_path: Path) -> None:
    """A real TurtleBot3 bag read with ``--topic /odom`` (its nav_msgs/Odometry): no_tf's hint said to record
    the transforms (ros2 bag record /tf /tf_static), which it holds, and hid /tf behind 'and 1 more'. The
    recording's transform topics come first and the hint says to read them; a robot under a namespace
    (/robot1/tf) is told which --topic reads it, by wtf, echo and monitor."""
    robot = healthy()
    bag = write(tmp_path, "robot", DB3, robot)
    wrong = tfx("wtf", bag, "--topic", "/odom")
    said = " ".join(wrong.stdout.split())
    assert wrong.code == 1 and "no_tf: no transforms on /odom in" in said
    assert "topics present: /tf, /tf_static" in said and "ros2 bag record" not in said
    assert "hint: /tf and /tf_static carry transforms: leave out --topic" in said  # every command's hint
    spaced = write(tmp_path, "robot1", DB3, [replace(m, topic=f"/robot1{m.topic}") for m in robot])
    default = tfx("wtf", spaced)
    said = " ".join(default.stdout.split())
    assert default.code == 1 and "topics present: /robot1/tf, /robot1/tf_static" in said
    assert (
        "/robot1/tf, /robot1/tf_static: of a transform type, read with --topic /robot1/tf --topic /robot1/tf_static"
        in said
    )
    read = tfx("wtf", spaced, "--topic", "/robot1/tf", "--topic", "/robot1/tf_static")
    assert read.code == 0 and "no problems found" in read.stdout
    # the commands that need transforms to start say it in one line alike ('was /tf recorded?' until now)
    echo = tfx("echo", "odom", "base_link", "-b", bag, "--topic", "/odom")
    assert echo.code == 2 and "(/tf and /tf_static carry transforms: leave out --topic)" in echo.stderr
    monitor = tfx("monitor", "-b", spaced)
    assert monitor.code == 2 and "topics present: /robot1/tf, /robot1/tf_static" in monitor.stderr
    assert "read with --topic /robot1/tf --topic /robot1/tf_static" in monitor.stderr


@pytest.mark.parametrize(("fmt", "record"), [(DB3, "ros2 bag record"), (BagFormat.ros1, "rosbag record")])
def test_no_tf_is_told_in_its_own_ros_words_without_an_empty_frame(
    tfx: Tfx, tmp_path: Path, fmt: BagFormat, record: str
) -> None:
    """ros2_mcap_abitobot_no_tf (a gz simulation's /imu and /joint_states, no tf): the hint gave ROS 1's and
    ROS 2's commands together, and the header said '1 topic of sensor data checked in  (the root of the
    largest tree)' with no tree. The hint is now every command's for a recording without transforms (issue 39),
    which names no other ROS's command."""
    bag = write(tmp_path, "no_tf", fmt, [TfMessage("/odom_tf", 1_700_000_000 * 10**9 + i, [], "/x") for i in range(3)])
    result = tfx("wtf", bag)
    assert result.code == 1
    other = "rosbag record" if record == "ros2 bag record" else "ros2 bag record"
    assert "hint: /odom_tf: of a transform type, read with --topic /odom_tf" in result.stdout
    assert record not in result.stdout and other not in result.stdout
    assert "checked in" not in result.stdout.splitlines()[0]
