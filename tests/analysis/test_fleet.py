"""The fleet API from Python, without the CLI: ``run_fleet`` (here, in processes, with a time limit),
``check_fleet`` (tfx wtf's checks of each recording) and ``report_fleet`` (tfx report's data)."""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

import pytest

from tests.analysis.wtf_scenes import PROBLEMS, healthy, write
from tests.bags import BagFormat
from tftools.analysis.fleet import Fleet, Unfinished, UnfinishedCause, run_fleet
from tftools.analysis.report import RecordingReport, ReportQuery, Unreadable, report, report_fleet
from tftools.analysis.wtf.fleet import check, check_fleet, in_order, remaining
from tftools.analysis.wtf.query import CheckQuery
from tftools.render.report import recording_section
from tftools.sources.recording import read_recording


@pytest.fixture(scope="module")
def bags(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    directory = tmp_path_factory.mktemp("fleet")
    made = {
        "healthy": write(directory, "healthy", BagFormat.ros1, healthy()),
        "stale": write(directory, "stale", BagFormat.rosbag2_mcap, PROBLEMS["stale"].make()),
        "broken": directory / "broken.bag",
    }
    made["broken"].write_bytes(b"#ROSBAG V2.0\n" + b"not a bag" * 10)
    return {name: str(path) for name, path in made.items()}


def first_name(paths: Sequence[str]) -> str:
    return Path(paths[0]).name


def sleepy(paths: Sequence[str]) -> str:
    if "slow" in paths[0]:
        time.sleep(2)
    return paths[0]


@pytest.mark.parametrize("jobs", [1, 2])
def test_run_fleet_gives_each_result_with_its_index(jobs: int) -> None:
    groups = [["a/one.bag"], ["b/two.bag", "b/two_1.bag"], ["c/three.db3"]]
    results = dict(run_fleet(groups, first_name, Fleet(jobs=jobs)))
    assert results == {0: "one.bag", 1: "two.bag", 2: "three.db3"}


def test_a_task_over_its_time_is_unfinished_and_the_others_finish() -> None:
    results = dict(run_fleet([["fast"], ["slow"]], sleepy, Fleet(timeout=0.5)))
    assert results[0] == "fast"
    assert results[1] == Unfinished("its check took longer than 0.5 s", UnfinishedCause.TIMED_OUT)
    assert "--" not in results[1].hint and "tfx" not in results[1].hint  # the library names no option


def test_check_fleet_checks_each_recording_as_check_does(bags: dict[str, str]) -> None:
    groups = [[bags["healthy"]], [bags["stale"]], [bags["broken"]]]
    reports = list(check_fleet(groups, fleet=Fleet(jobs=2)))
    ordered = in_order(groups, reports)
    assert [r.paths for r in ordered] == [tuple(g) for g in groups]
    assert [r.failed() for r in ordered] == [False, True, True]
    assert "stale" in {f.code for f in ordered[1].findings} and ordered[2].error is not None
    assert ordered[0].findings == check(CheckQuery().reading().read(groups[0])).findings


def test_check_fleet_skips_what_was_done_and_yields_it_first(bags: dict[str, str]) -> None:
    groups = [[bags["healthy"]], [bags["stale"]]]
    (done,) = list(check_fleet(groups[:1]))
    assert remaining(groups, [done]) == [[bags["stale"]]]
    reports = list(check_fleet(groups, done=[done]))
    assert reports[0] is done and [r.paths for r in reports] == [(bags["healthy"],), (bags["stale"],)]


def test_report_fleet_reports_each_recording_and_says_which_could_not_be_read(bags: dict[str, str]) -> None:
    groups = [[bags["healthy"]], [bags["broken"]]]
    results = dict(report_fleet(groups))
    healthy_report, broken = results[0], results[1]
    assert isinstance(healthy_report, RecordingReport) and healthy_report.name == bags["healthy"]
    assert healthy_report.edges and not healthy_report.problems
    assert isinstance(broken, Unreadable) and broken.name == bags["broken"] and bags["broken"] in broken.message


def test_check_fleet_passes_its_checks_options_to_each_check(bags: dict[str, str]) -> None:
    (checked,) = list(check_fleet([[bags["stale"]]], CheckQuery(ignore=("stale",)), Fleet(jobs=2)))
    assert "stale" not in {f.code for f in checked.findings} and checked.transforms > 0


def test_check_of_a_recording_asks_what_its_query_says(bags: dict[str, str]) -> None:
    recording = read_recording([bags["stale"]])
    assert "stale" in {f.code for f in check(recording).findings}
    assert "stale" not in {f.code for f in check(recording, CheckQuery(ignore=("stale",))).findings}
    with pytest.raises(ValueError, match="no such check: stail"):
        check(recording, CheckQuery(ignore=("stail",)))


def test_report_fleet_reports_each_recording_as_report_does(bags: dict[str, str]) -> None:
    query = ReportQuery(target="odom")
    [(index, shown)] = list(report_fleet([[bags["healthy"]]], query, Fleet(jobs=2)))
    alone = report(query.reading().read([bags["healthy"]]), query)
    assert index == 0 and isinstance(shown, RecordingReport)
    assert shown.facts == alone.facts and shown.findings == alone.findings
    assert recording_section(0, shown).html == recording_section(0, alone).html


def test_a_query_is_a_frozen_value_with_the_commands_defaults() -> None:
    query = CheckQuery(ignore=("rate",))
    with pytest.raises(AttributeError):
        query.ignore = ()  # type: ignore[misc]  # the refused write is the test
    assert query == CheckQuery(ignore=("rate",)) and CheckQuery().thresholds is None
    # a recording without transforms is checked and reported alike (wtf's no_tf, the report's page saying so)
    assert query.reading().allow_empty and ReportQuery().reading() == CheckQuery().reading()
