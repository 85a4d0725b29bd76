"""``tfx wtf`` on fleets, here: the fleet report, JSON lines as results arrive, --resume, --timeout, --dask's errors."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from tests.analysis.wtf_scenes import PROBLEMS, healthy, write
from tests.bags import BagFormat
from tests.cli.conftest import Tfx
from tftools.analysis.reading import Progress
from tftools.analysis.wtf import fleet
from tftools.analysis.wtf.query import CheckQuery

DB3 = BagFormat.rosbag2_sqlite3


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    directory = tmp_path_factory.mktemp("fleet")
    made = {"healthy": write(directory, "healthy", BagFormat.ros1, healthy())}
    for name in ("stale", "cycle", "rate"):
        made[name] = write(directory, name, DB3, PROBLEMS[name].make())
    made["stale2"] = write(directory, "stale2", BagFormat.rosbag2_mcap, PROBLEMS["stale"].make())
    return made


@pytest.fixture
def checked(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The recordings tfx checks (in this process: --jobs 1), in order."""
    seen: list[str] = []
    check_group = fleet._check_group

    def counting(query: CheckQuery, progress: Progress, paths: list[str]) -> fleet.BagReport:
        seen.append(paths[0])
        return check_group(query, progress, paths)

    monkeypatch.setattr("tftools.analysis.wtf.fleet._check_group", counting)
    return seen


def lines(stdout: str) -> list[dict[str, Any]]:
    return [json.loads(line) for line in stdout.splitlines()]


def test_the_text_report_ends_with_each_check_across_the_fleet_worst_first(tfx: Tfx, bags: dict[str, Path]) -> None:
    result = tfx("wtf", bags["healthy"], bags["stale"], bags["stale2"], bags["cycle"])
    assert result.code == 1
    across = result.stdout[result.stdout.index("ACROSS THE FLEET") :].splitlines()
    assert across[1].startswith("  ✗ stale: 2 of 4 recordings: ") and str(bags["stale2"]) in across[1]
    assert across[2] == f"  ✗ cycle: 1 of 4 recordings: {bags['cycle']}"
    assert across[-1].startswith("4 recordings checked: 1 passed, 3 failed")


def test_jsonl_is_a_line_per_recording_as_it_finishes_then_the_summary(tfx: Tfx, bags: dict[str, Path]) -> None:
    fleet_bags = [bags[n] for n in ("healthy", "stale", "cycle")]
    result = tfx("wtf", *fleet_bags, "--format", "jsonl", "--jobs", "2")
    document = json.loads(tfx("wtf", *fleet_bags, "--format", "json").stdout)
    *recordings, summary = lines(result.stdout)
    assert result.code == 1 and summary["exit_code"] == 1 and summary["type"] == "summary"
    assert sorted(r["paths"][0] for r in recordings) == sorted(str(b) for b in fleet_bags)
    by_path = {b["paths"][0]: b for b in document["bags"]}
    assert all({k: v for k, v in r.items() if k != "type"} == by_path[r["paths"][0]] for r in recordings)
    assert {k: v for k, v in summary.items() if k != "type"} == {k: v for k, v in document.items() if k != "bags"}
    assert [c["code"] for c in summary["fleet"]["checks"]] == ["cycle", "stale"]
    assert [r["verdict"] for r in document["bags"]] == ["passed", "failed", "failed"]


def test_resume_skips_what_is_done_and_reports_the_whole_fleet(
    tfx: Tfx, bags: dict[str, Path], checked: list[str], tmp_path: Path
) -> None:
    first = tfx("wtf", bags["healthy"], bags["stale"], "--format", "jsonl")
    report = tmp_path / "run1.jsonl"
    report.write_text(first.stdout)
    everything = [bags[n] for n in ("healthy", "stale", "cycle", "rate")]
    checked.clear()
    resumed = tfx("wtf", *everything, "--format", "json", "--resume", report)
    assert checked == [str(bags["cycle"]), str(bags["rate"])]
    assert resumed.code == 1
    assert json.loads(resumed.stdout) == json.loads(tfx("wtf", *everything, "--format", "json").stdout)
    assert report.read_text() == first.stdout  # the report given is never modified


def test_resume_checks_again_a_recording_whose_line_was_cut_short(
    tfx: Tfx, bags: dict[str, Path], checked: list[str], tmp_path: Path
) -> None:
    first = tfx("wtf", bags["healthy"], bags["stale"], "--format", "jsonl")
    report = tmp_path / "stopped.jsonl"
    report.write_text("\n".join(first.stdout.splitlines()[:2])[:-30])  # stopped while writing the second line
    checked.clear()
    resumed = tfx("wtf", bags["healthy"], bags["stale"], "--format", "jsonl", "--resume", report)
    assert "last line was cut short" in resumed.stderr
    assert checked == [str(bags["stale"])] and lines(resumed.stdout)[1]["type"] == "recording"
    assert lines(resumed.stdout)[-1] == lines(first.stdout)[-1]


def test_resume_refuses_what_is_not_a_report_in_one_line(tfx: Tfx, bags: dict[str, Path], tmp_path: Path) -> None:
    result = tfx("wtf", bags["healthy"], "--resume", bags["healthy"])
    assert result.code == 2 and result.stderr.count("\n") == 1 and "is not JSON" in result.stderr
    missing = tfx("wtf", bags["healthy"], "--resume", tmp_path / "none.jsonl")
    assert missing.code == 2 and "none.jsonl" in missing.stderr


def test_a_recording_over_its_timeout_is_reported_as_not_checked(
    tfx: Tfx, bags: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    check_group = fleet._check_group

    def slow_for_stale(query: CheckQuery, progress: Progress, paths: list[str]) -> fleet.BagReport:
        if "stale" in paths[0]:
            time.sleep(3)
        return check_group(query, progress, paths)

    monkeypatch.setattr("tftools.analysis.wtf.fleet._check_group", slow_for_stale)
    result = tfx("wtf", bags["healthy"], bags["stale"], "--timeout", "0.5", "--format", "json")
    good, slow = json.loads(result.stdout)["bags"]
    assert result.code == 1 and good["verdict"] == "passed"
    assert slow["verdict"] == "unusable" and slow["error"]["code"] == "unchecked"
    assert slow["error"]["message"] == f"{bags['stale']}: not checked: its check took longer than 0.5 s"
    # the library's result says why (its cause), the command line words what to do with its options
    assert slow["error"]["figures"] == {"cause": "timed_out"}
    assert slow["error"]["hint"] == "raise --timeout, or check it alone (tfx wtf BAG)"


def test_dask_without_distributed_names_the_extra(
    tfx: Tfx, bags: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed raises ImportError
    result = tfx("wtf", bags["healthy"], "--dask", "tcp://127.0.0.1:8786")
    assert result.code == 2 and result.stdout == "" and result.stderr.count("\n") == 1
    assert "pip install 'tftools[fleet]'" in result.stderr


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (("--dask", "nonsense:::"), "--dask nonsense:::: not a scheduler address"),
        (("--dask", "tcp://127.0.0.1:8786", "--jobs", "3"), "--jobs and --dask: choose one"),
        (("--timeout", "0"), "--timeout"),
    ],
)
def test_bad_fleet_arguments_are_one_line_and_exit_2(
    tfx: Tfx, bags: dict[str, Path], args: tuple[str, ...], says: str
) -> None:
    result = tfx("wtf", bags["healthy"], *args)
    assert result.code == 2 and result.stderr.count("\n") == 1 and says in result.stderr


def test_fleet_options_need_recordings(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", "tcp://127.0.0.1:8786")
    result = tfx("wtf", "--ros1", "-d", "1")
    assert result.code == 2 and "are for recordings" in result.stderr
