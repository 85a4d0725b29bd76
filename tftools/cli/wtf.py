"""``tfx wtf [BAG ...] [-b BAG ...]``: roswtf's tf checks and more, on bags, fleets of bags and live systems."""

from __future__ import annotations

import difflib
import enum
import functools
import os
import sys
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Annotated

import typer
from rich.table import Table

from tftools.analysis.expected import TreeShape
from tftools.analysis.wtf import CHECKS, Thresholds
from tftools.analysis.wtf.fleet import BagReport, check_bags, check_recording
from tftools.cli import expected as expected_tree
from tftools.cli import live
from tftools.cli.arguments import positive_seconds
from tftools.cli.common import (
    BagOption,
    Exit,
    Tf2Option,
    TopicOption,
    UsageError,
    exit_with,
    local_size,
    progress_bar,
    say_error,
    stdout,
    warn,
)
from tftools.core.semantics import Semantics
from tftools.render import wtf as render
from tftools.sources.storage.locations import expand


class WtfFormat(str, enum.Enum):
    text = "text"
    json = "json"
    junit = "junit"


_DEFAULTS = Thresholds()

PathsArgument = Annotated[
    list[str] | None,
    typer.Argument(
        help="Bags to check, each on its own: a fleet (e.g. logs/*.bag). ROS1 .bag, ROS2 .db3/.mcap or bag directory, "
        "local or a URL (s3://bucket/fleet/ checks every recording below it, 's3://bucket/*.bag' the matches; "
        "needs tftools[fleet]).",
        metavar="BAG",
        show_default=False,
    ),
]
FormatOption = Annotated[
    WtfFormat, typer.Option("--format", "-f", help="text, json (one document), or junit (XML for CI).")
]
StrictOption = Annotated[bool, typer.Option("--strict", help="Warnings fail too (exit 1, JUnit failures).")]
JobsOption = Annotated[
    int, typer.Option("--jobs", "-j", help="Check this many recordings at once (0: one per CPU).", min=0)
]
IgnoreOption = Annotated[
    list[str] | None,
    typer.Option(
        "--ignore", help="Skip the check with this code (repeat for more; see --list-checks).", show_default=False
    ),
]
ListOption = Annotated[
    bool, typer.Option("--list-checks", help="List the checks, their codes and severities, and exit.")
]
StaleOption = Annotated[
    float,
    typer.Option("--stale-after", help="An edge silent this many seconds before the end has stopped (and 10 periods)."),
]
GapOption = Annotated[
    float, typer.Option("--max-gap", help="A pause longer than this many seconds (and 10 periods) is a gap.")
]
DelayOption = Annotated[
    float,
    typer.Option(
        "--delay", help="An edge whose transforms arrive this many seconds after their stamp (over 5%) is late."
    ),
]
FutureOption = Annotated[
    float, typer.Option("--future", help="Stamps this many seconds ahead of their arrival are from the future.")
]
TargetOption = Annotated[
    str | None,
    typer.Option(
        "--target",
        help="Check sensor data (messages with a header) against tf in this frame "
        "(default: odom or map, else the tree's root; so too where a recording lacks the frame).",
        show_default=False,
    ),
]
SensorOption = Annotated[
    list[str] | None,
    typer.Option(
        "--sensor",
        help="Check this topic's data against tf (repeat for more). Default: every topic of a bag whose messages "
        "start with a Header; live, none (listening to every camera would load the network).",
        show_default=False,
    ),
]
InitOption = Annotated[
    bool,
    typer.Option("--init", help="Write the bag's tree as a tree file for --expect (tfx wtf --init BAG > tree.yaml)."),
]
ExpectOption = Annotated[
    Path | None,
    typer.Option(
        "--expect",
        help="Check against this tree file (--init writes one): frames missing or new, other parents, static "
        "edges moved beyond the tolerances, slower edges, other publishers.",
        show_default=False,
    ),
]
ClockOption = Annotated[
    float, typer.Option("--clock", help="Stamps this many seconds behind their arrival (median) are on another clock.")
]


def command(
    paths: PathsArgument = None,
    bags: BagOption = None,
    fmt: FormatOption = WtfFormat.text,
    strict: StrictOption = False,
    jobs: JobsOption = 1,
    ignore: IgnoreOption = None,
    list_checks: ListOption = False,
    stale_after: StaleOption = _DEFAULTS.stale_after,
    max_gap: GapOption = _DEFAULTS.max_gap,
    delay: DelayOption = _DEFAULTS.delay,
    future: FutureOption = _DEFAULTS.future,
    clock: ClockOption = _DEFAULTS.clock,
    topics: TopicOption = None,
    tf2: Tf2Option = None,
    target: TargetOption = None,
    sensors: SensorOption = None,
    init: InitOption = False,
    expect: ExpectOption = None,
    tolerance_mm: expected_tree.ToleranceMmOption = None,
    tolerance_deg: expected_tree.ToleranceDegOption = None,
    tolerance_rate: expected_tree.ToleranceRateOption = None,
    duration: live.ListenOption = 5.0,
    ros1: live.RosOption = None,
    use_sim_time: live.UseSimTimeOption = None,
) -> None:
    """Check tf for what breaks lookups, and say how to fix each problem (roswtf's tf checks and more).

    Each BAG is checked on its own (a fleet: [cyan]tfx wtf logs/*.bag --jobs 4[/]); the -b bags together
    make one more recording (a split bag). Without bags, listens --duration seconds to the live system.

    Errors (loops, several trees, re-parenting, stale edges, stamps on another clock or from the
    future, NaN or bad rotations, empty or self frame ids, stamps going back, no tf) break lookups;
    warnings (several publishers, leading '/', fixed transforms on /tf, gaps, late arrival) are
    tolerated by tf2 but off; notes are for information. --list-checks lists every check. Sensor data
    (a bag's messages with a header, or the --sensor topics) is replayed through a tf2 MessageFilter
    into --target: frames not in the tree, streams that wait for tf, and messages lost for good are
    reported too.

    Exit codes: 0 no errors (warnings allowed, unless --strict); 1 errors found, or some recordings
    could not be read (each reported as an error of its own); 2 no recording could be read, or bad
    arguments.

    The expected tree: [cyan]tfx wtf --init good.bag > tree.yaml[/] writes what a healthy recording
    looks like (hand-editable YAML); [cyan]tfx wtf --expect tree.yaml run.bag[/] reports what differs.

    Examples: [cyan]tfx wtf robot.bag[/], [cyan]tfx wtf logs/*.bag --format junit > wtf.xml[/],
    [cyan]tfx wtf -b run_0.bag -b run_1.bag --strict[/]
    """
    if list_checks:
        _list_checks()
        return
    if init:
        if len(paths or []) + bool(bags) > 1:
            raise UsageError("--init writes the tree of one recording", "give one bag (or its parts with -b)")
        expected_tree.write_init(list(paths or []) or list(bags or []), topics, tf2)
        return
    tolerances = (tolerance_mm, tolerance_deg, tolerance_rate)
    if expect is None and any(t is not None for t in tolerances):
        raise UsageError("the tolerances are for --expect", "e.g. tfx wtf --expect tree.yaml run.bag --tolerance-mm 2")
    expected = expected_tree.read_expected(expect, *tolerances) if expect is not None else None
    thresholds = _thresholds(stale_after=stale_after, max_gap=max_gap, delay=delay, future=future, clock=clock)
    ignored = _ignored(ignore or [])
    groups: list[list[str]] = [[p] for p in expand(paths or [])] + ([list(bags)] if bags else [])
    if groups:
        jobs = jobs or os.cpu_count() or 1
        reports = _check_groups(groups, topics, thresholds, ignored, jobs, tf2, target, sensors, expected)
    else:
        feed = (ros1, use_sim_time, duration)
        reports = [_check_live(*feed, topics, thresholds, ignored, tf2, target, sensors, expected)]
    code = outcome(reports, strict)
    if fmt is WtfFormat.json:
        render.write_json(reports, sys.stdout, strict, thresholds, code)
    elif fmt is WtfFormat.junit:
        render.write_junit(reports, sys.stdout, strict, ignored)
    elif len(reports) == 1 and reports[0].error is not None:
        error = reports[0].error
        raise UsageError(error.message, error.hint)
    else:
        render.write_text(reports, stdout, strict)
    if code == Exit.UNUSABLE and fmt is not WtfFormat.text:  # the document says it; so does stderr, in one line
        first = next(r.error for r in reports if r.error is not None)
        more = f" (and {len(reports) - 1} more recordings)" if len(reports) > 1 else ""
        say_error(f"{first.message}{more} ({first.hint})" if first.hint else f"{first.message}{more}")
    exit_with(code)


def outcome(reports: Sequence[BagReport], strict: bool = False) -> Exit:
    """UNUSABLE when no recording could be read, PROBLEMS when any failed (or could not be read), else OK."""
    if not any(r.usable for r in reports):
        return Exit.UNUSABLE
    return Exit.PROBLEMS if any(r.failed(strict) for r in reports) else Exit.OK


def _thresholds(**seconds: float) -> Thresholds:
    for name, value in seconds.items():
        positive_seconds(value, f"--{name.replace('_', '-')}", "0.5")
    return Thresholds(**seconds)


def _ignored(codes: Sequence[str]) -> tuple[str, ...]:
    for code in codes:
        if code not in CHECKS:
            close = difflib.get_close_matches(code, list(CHECKS), n=1)
            hint = f"did you mean {close[0]}?" if close else "see tfx wtf --list-checks"
            raise UsageError(f"--ignore {code}: there is no such check", hint)
    return tuple(codes)


def _check_groups(
    groups: list[list[str]],
    topics: Sequence[str] | None,
    thresholds: Thresholds,
    ignore: Sequence[str],
    jobs: int,
    semantics: Semantics | None,
    target: str | None,
    sensors: Sequence[str] | None,
    expected: TreeShape | None,
) -> list[BagReport]:
    """Each group of paths checked as its own recording, ``jobs`` at a time; reports in the given order."""
    one = functools.partial(
        check_bags,
        topics=topics,
        thresholds=thresholds,
        ignore=tuple(ignore),
        semantics=semantics,
        target=target,
        sensor_topics=sensors,
        expected=expected,
    )
    if len(groups) == 1:
        size = sum(local_size(p) for p in groups[0])
        with progress_bar(enabled=size > 20_000_000) as progress:
            return [one(groups[0], progress=progress)]
    if jobs <= 1:
        return [one(g) for g in groups]
    with ProcessPoolExecutor(max_workers=min(jobs, len(groups))) as pool:
        futures = [pool.submit(one, [str(p) for p in g]) for g in groups]
        return [f.result() for f in futures]


def _check_live(
    ros1: bool | None,
    use_sim_time: bool | None,
    duration: float,
    topics: Sequence[str] | None,
    thresholds: Thresholds,
    ignore: Sequence[str],
    semantics: Semantics | None,
    target: str | None,
    sensors: Sequence[str] | None,
    expected: TreeShape | None,
) -> BagReport:
    """Listen ``duration`` seconds and check what was heard (nothing heard is the ``no_tf`` error),
    with the data of the ``sensors`` topics (none unless named)."""
    positive_seconds(duration, "--duration")
    from tftools.sources.live.capture import capture
    from tftools.sources.live.sensor_headers import capture_stamped

    source = live.open_source(ros1, use_sim_time, topics)
    live.say(f"listening to {source.describe()} for {duration:g} s")
    if not sensors:
        recording, streams = capture(source, duration, semantics=semantics), []
    else:
        recording, stamped = capture_stamped(source, duration, sensors, semantics=semantics)
        streams = stamped.streams
        for problem in stamped.problems:
            warn(problem)
    for problem in recording.problems:
        warn(problem)
    return check_recording(recording, streams, thresholds, ignore, target, expected)


def _list_checks() -> None:
    table = Table(box=None, header_style="bold")
    for name in ("Code", "Severity", "Looks for"):
        table.add_column(name)
    for code, c in CHECKS.items():
        table.add_row(code, c.severity.value, c.title)
    stdout.print(table)
