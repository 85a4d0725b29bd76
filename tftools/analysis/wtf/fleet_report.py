"""A fleet's report: per check, the recordings that have it (worst first); per recording, its verdict;
per check, the days it showed on and the day it started (recordings dated by their first record time, UTC)."""

from __future__ import annotations

import datetime
import enum
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import BagReport
from tftools.core.time import EPOCH_FLOOR, NS_PER_S


class Verdict(str, enum.Enum):
    passed = "passed"
    failed = "failed"
    unusable = "unusable"  # could not be read, or not checked (a worker died, it timed out)


def verdict(bag: BagReport, strict: bool = False) -> Verdict:
    if not bag.usable:
        return Verdict.unusable
    return Verdict.failed if bag.failed(strict) else Verdict.passed


@dataclass(frozen=True)
class CheckTally:
    """One check across the fleet: its worst severity and the recordings showing it, worst first."""

    code: str
    severity: Severity
    recordings: tuple[str, ...]


@dataclass(frozen=True)
class Trend:
    """One check over the days of the fleet: how many recordings showed it each day (days without
    recordings are left out), and ``since``: the day from which every day had it, when an earlier day
    did not (a problem that started then and persists)."""

    code: str
    per_day: dict[datetime.date, int]
    since: datetime.date | None

    @property
    def first_day(self) -> datetime.date:
        return min(self.per_day)


def problems(bag: BagReport) -> list[Finding]:
    """What a recording shows: its findings (checks that could not run are no problem), or its error."""
    return [bag.error] if bag.error is not None else [f for f in bag.findings if not f.skipped]


def tally(reports: Sequence[BagReport]) -> list[CheckTally]:
    """Each check found: worst severity first, then most recordings; within a check, the recordings
    where it is worst first (severity, then samples involved, then name)."""
    found: dict[str, dict[str, tuple[int, int]]] = {}  # code -> name -> (severity rank, -samples)
    for bag in reports:
        for finding in problems(bag):
            mine = found.setdefault(finding.code, {})
            rank, samples = mine.get(bag.name, (len(Severity), 0))
            mine[bag.name] = (min(rank, finding.severity.rank), samples - max(finding.count, 1))
    tallies = []
    for code, worst in found.items():
        names = sorted(worst, key=lambda n: (*worst[n], n))
        severity = next(s for s in Severity if s.rank == worst[names[0]][0])
        tallies.append(CheckTally(code, severity, tuple(names)))
    return sorted(tallies, key=lambda t: (t.severity.rank, -len(t.recordings), t.code))


def day_of(bag: BagReport) -> datetime.date | None:
    """The UTC day of a recording's first record time; None when it could not be read, or its record clock
    does not count from the epoch (simulated time, time since boot: 1970-01-01 is no day it was made)."""
    if not bag.usable or bag.start < EPOCH_FLOOR:
        return None
    return datetime.datetime.fromtimestamp(bag.start / NS_PER_S, tz=datetime.timezone.utc).date()


def recordings_per_day(reports: Sequence[BagReport]) -> dict[datetime.date, int]:
    days = Counter(day for bag in reports if (day := day_of(bag)) is not None)
    return dict(sorted(days.items()))


def trends(reports: Sequence[BagReport]) -> list[Trend]:
    """Each check found on a dated recording, over the days; those that started on a day first (latest
    start first), then the rest by code."""
    days = list(recordings_per_day(reports))
    per_code: dict[str, Counter[datetime.date]] = {}
    for bag in reports:
        day = day_of(bag)
        if day is None:
            continue
        for code in dict.fromkeys(f.code for f in problems(bag)):
            per_code.setdefault(code, Counter())[day] += 1
    found = [Trend(code, dict(sorted(counts.items())), _since(days, counts)) for code, counts in per_code.items()]
    return sorted(found, key=lambda t: (t.since is None, -t.since.toordinal() if t.since else 0, t.code))


#: A problem is a trend when it showed on at least this many days in a row, up to the last (one day's
#: recording having it is that recording's finding, not a trend).
TREND_DAYS = 2


def _since(days: list[datetime.date], counts: dict[datetime.date, int]) -> datetime.date | None:
    """The first day of the last unbroken run of days with the problem (at least ``TREND_DAYS`` long,
    up to the last day), if a day before it had none."""
    absent = [i for i, day in enumerate(days) if day not in counts]
    if not absent or len(days) - 1 - absent[-1] < TREND_DAYS:
        return None
    return days[absent[-1] + 1]
