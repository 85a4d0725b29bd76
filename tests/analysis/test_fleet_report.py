"""The fleet report: per check the recordings that have it, worst first; verdicts; the day a problem started."""

from __future__ import annotations

import datetime

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.fleet import Unfinished, UnfinishedCause
from tftools.analysis.wtf.fleet import BagReport, unchecked, unreadable
from tftools.analysis.wtf.fleet_report import Verdict, day_of, recordings_per_day, tally, trends, verdict
from tftools.core.time import NS_PER_S

DAY = 86_400 * NS_PER_S
MONDAY = datetime.date(2024, 5, 6)
MIDNIGHT = int(datetime.datetime(2024, 5, 6, tzinfo=datetime.timezone.utc).timestamp()) * NS_PER_S


def found(code: str, severity: Severity = Severity.error, count: int = 1, skipped: bool = False) -> Finding:
    return Finding(severity, code, f"{code} seen", "fix it", count=count, skipped=skipped)


def bag(name: str, *findings: Finding, day: int = 0) -> BagReport:
    start = MIDNIGHT + day * DAY + 3_600 * NS_PER_S
    return BagReport((name,), list(findings), start=start, end=start + 10 * NS_PER_S, transforms=10, frames=3)


def test_each_check_lists_its_recordings_worst_first_and_the_worst_checks_first() -> None:
    fleet = [
        bag("a", found("gap", Severity.warning, count=2)),
        bag("b", found("stale", count=5), found("gap", Severity.warning, count=9)),
        bag("c", found("stale", count=50)),
        bag("d", found("statics_early", Severity.info)),
        bag("e", found("static_volatile", Severity.info, skipped=True)),  # not checked is no problem
        unreadable(("f",), "f: corrupt", ""),
    ]
    tallies = {t.code: t for t in tally(fleet)}
    assert [t.code for t in tally(fleet)] == ["stale", "unreadable", "gap", "statics_early"]
    assert tallies["stale"].recordings == ("c", "b") and tallies["stale"].severity is Severity.error
    assert tallies["gap"].recordings == ("b", "a") and tallies["gap"].severity is Severity.warning
    assert tallies["unreadable"].recordings == ("f",)


def test_a_check_that_is_an_error_in_one_recording_and_a_warning_in_another_is_an_error_first() -> None:
    fleet = [bag("mild", found("delay", Severity.warning, count=100)), bag("bad", found("delay", count=1))]
    (delay,) = tally(fleet)
    assert delay.severity is Severity.error and delay.recordings == ("bad", "mild")


def test_verdicts() -> None:
    warned = bag("w", found("gap", Severity.warning))
    assert verdict(bag("ok")) is Verdict.passed
    assert verdict(bag("x", found("cycle"))) is Verdict.failed
    assert verdict(warned) is Verdict.passed and verdict(warned, strict=True) is Verdict.failed
    assert verdict(unreadable(("u",), "u: corrupt", "")) is Verdict.unusable
    assert verdict(unchecked(("k",), Unfinished("its worker died", UnfinishedCause.FAILED))) is Verdict.unusable


def test_recordings_are_dated_by_their_first_record_time_in_utc() -> None:
    assert day_of(bag("a", day=2)) == MONDAY + datetime.timedelta(days=2)
    assert day_of(unreadable(("u",), "u: corrupt", "")) is None
    fleet = [bag("a"), bag("b", day=1), bag("c", day=1), unreadable(("u",), "u: corrupt", "")]
    assert recordings_per_day(fleet) == {MONDAY: 1, MONDAY + datetime.timedelta(days=1): 2}


def test_a_problem_that_appears_on_a_day_and_persists_started_then() -> None:
    days = [MONDAY + datetime.timedelta(days=d) for d in range(4)]
    fleet = [
        bag("mon", found("gap", Severity.warning), day=0),
        bag("tue", day=1),
        bag("wed1", found("stale"), day=2),
        bag("wed2", day=2),
        bag("thu", found("stale"), found("gap", Severity.warning), day=3),
        bag("always", found("delay", Severity.warning), day=0),
        bag("always2", found("delay", Severity.warning), day=1),
        bag("always3", found("delay", Severity.warning), day=2),
        bag("always4", found("delay", Severity.warning), day=3),
    ]
    by_code = {t.code: t for t in trends(fleet)}
    assert by_code["stale"].since == days[2] and by_code["stale"].per_day == {days[2]: 1, days[3]: 1}
    assert by_code["stale"].first_day == days[2]
    # back on Thursday only: one day's recording having it is that recording's finding, not a trend (yet)
    assert by_code["gap"].since is None and by_code["gap"].first_day == days[0]
    assert by_code["delay"].since is None  # there from the first day: nothing started
    assert [t.code for t in trends(fleet)] == ["stale", "delay", "gap"]  # latest start first, then by code
    fleet.append(bag("fri", found("gap", Severity.warning), day=4))
    assert {t.code: t for t in trends(fleet)}["gap"].since == days[3]  # Thursday and Friday: it started then


def test_a_recording_on_simulated_time_has_no_day() -> None:
    """A record clock counting from a simulation's start (``ros2 bag record --use-sim-time``) dates a
    recording to 1970-01-01: no day it was made, and no trend that day "started"."""
    simulated = BagReport(("sim",), [found("stale")], start=12 * NS_PER_S, end=40 * NS_PER_S, transforms=9, frames=2)
    fleet = [simulated, bag("mon"), bag("tue", found("stale"), day=1), bag("wed", found("stale"), day=2)]
    assert day_of(simulated) is None
    assert recordings_per_day(fleet) == {MONDAY + datetime.timedelta(days=d): 1 for d in range(3)}
    (stale,) = trends(fleet)
    assert stale.since == MONDAY + datetime.timedelta(days=1) and stale.per_day == {
        MONDAY + datetime.timedelta(days=1): 1,
        MONDAY + datetime.timedelta(days=2): 1,
    }


def test_a_problem_gone_on_the_last_day_did_not_start() -> None:
    fleet = [bag("mon"), bag("tue", found("stale"), day=1), bag("wed", day=2)]
    (stale,) = trends(fleet)
    assert stale.since is None and stale.first_day == MONDAY + datetime.timedelta(days=1)
