"""``report_fleet``: each recording of a fleet read and reported (``report``), as they finish."""

from __future__ import annotations

import functools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from tftools.analysis.fleet import HERE, Fleet, Unfinished, UnfinishedCause, run_fleet
from tftools.analysis.reading import Progress, unwatched
from tftools.analysis.report.query import REPORT_DEFAULTS, ReportQuery
from tftools.analysis.report.recording import RecordingReport, report
from tftools.core.errors import TfToolsError


@dataclass(frozen=True)
class Unreadable:
    """A recording of a fleet that could not be read (or whose report did not finish): what went wrong,
    and what to do; ``error``: the error its reading raised, for a caller to word as it words that error
    elsewhere (None: its report did not finish)."""

    name: str
    message: str
    hint: str
    cause: UnfinishedCause | None = None  # why its report did not finish; None: it could not be read
    error: TfToolsError | None = None


def report_fleet(
    sources: Sequence[Sequence[str]],
    query: ReportQuery = REPORT_DEFAULTS,
    fleet: Fleet = HERE,
    *,
    progress: Progress | None = None,
) -> Iterator[tuple[int, RecordingReport | Unreadable]]:
    """Each group of paths or URLs in ``sources`` read as its own recording and reported (``report``) on
    ``fleet``, yielded with its index in ``sources`` as it finishes; one that cannot be read, or whose report
    did not finish, is an ``Unreadable``. ``progress``: for each recording read in this process, a context
    told the bytes read (a progress bar)."""
    task = functools.partial(_report_group, query, progress or unwatched)
    for index, result in run_fleet(sources, task, fleet):
        if isinstance(result, Unfinished):
            name = " + ".join(sources[index])
            result = Unreadable(name, f"{name}: not checked: {result.why}", result.hint, result.cause)
        yield index, result


def _report_group(query: ReportQuery, progress: Progress, paths: Sequence[str]) -> RecordingReport | Unreadable:
    """One recording of a fleet read and reported (``progress`` told of it throughout); one that cannot be
    read is an ``Unreadable``, not raised."""
    with progress(paths) as told:
        try:
            recording = query.reading().read(paths, told)
        except TfToolsError as error:
            return Unreadable(" + ".join(str(p) for p in paths), str(error), error.hint, error=error)
        return report(recording, query)
