"""``tfx wtf [BAG ...] [-b BAG ...]``: roswtf's tf checks and more, on bags, fleets of bags and live systems."""

from __future__ import annotations

import dataclasses
import difflib
import enum
import functools
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.table import Table

from tftools.cli import defaults, findings_file, live, options
from tftools.cli import expected as expected_tree
from tftools.cli.arguments import positive_seconds
from tftools.cli.common import Exit, count_bar, exit_with, hinted, progress_bar, say_error, stdout, warn
from tftools.cli.errors import UsageError, unfinished_hint

if TYPE_CHECKING:  # the checks and their renderers load when a command runs: --help needs none of them (nor numpy)
    from tftools.analysis.fleet import Fleet
    from tftools.analysis.reading import Progress
    from tftools.analysis.wtf import Thresholds
    from tftools.analysis.wtf.fleet import BagReport
    from tftools.analysis.wtf.query import CheckQuery


class WtfFormat(str, enum.Enum):
    text = "text"
    json = "json"
    jsonl = "jsonl"
    junit = "junit"


_DEFAULTS = defaults.thresholds()
#: The --help of each of the checks' thresholds (``Thresholds``, in seconds).
_THRESHOLD_HELP = {
    "stale_after": "An edge silent this many seconds before the end has stopped (and 10 periods).",
    "max_gap": "A pause longer than this many seconds (and 10 periods) is a gap.",
    "delay": "An edge whose transforms arrive this many seconds after their stamp (over 5%) is late.",
    "future": "Stamps this many seconds ahead of their arrival are from the future.",
    "clock": "Stamps this many seconds behind their arrival (median) are on another clock.",
}


def command(
    paths: options.Paths = None,
    bags: options.Bags = None,
    fmt: Annotated[
        WtfFormat,
        typer.Option(
            "--format",
            "-f",
            help="text, json (one document), jsonl (a line per recording as it finishes, then a summary line: "
            "a long run can be followed, and resumed), or junit (XML for CI).",
        ),
    ] = WtfFormat.text,
    strict: Annotated[bool, typer.Option("--strict", help="Warnings fail too (exit 1, JUnit failures).")] = False,
    jobs: Annotated[
        int, typer.Option("--jobs", "-j", help="Check this many recordings at once (0: one per CPU).", min=0)
    ] = 1,
    dask: Annotated[
        str | None,
        typer.Option(
            envvar="DASK_SCHEDULER_ADDRESS",
            help="Check each recording as a task on this Dask cluster, its scheduler's address (e.g. "
            "tcp://10.0.0.5:8786; needs tftools\\[fleet] here and tftools on the workers).",
        ),
    ] = None,
    timeout: Annotated[
        float | None,
        typer.Option(
            help="Give up a recording's check after this many seconds (reported as not checked; on Dask, tried twice).",
        ),
    ] = None,
    resume: Annotated[
        Path | None,
        typer.Option(
            help="Skip the recordings this earlier --format jsonl report has done, and include its results "
            "(tfx wtf logs/*.bag -f jsonl --resume run1.jsonl > run2.jsonl).",
        ),
    ] = None,
    ignore: Annotated[
        list[str] | None,
        typer.Option(help="Skip the check with this code (repeat for more; see --list-checks)."),
    ] = None,
    list_checks: Annotated[
        bool, typer.Option("--list-checks", help="List the checks, their codes and severities, and exit.")
    ] = False,
    stale_after: Annotated[float, typer.Option(help=_THRESHOLD_HELP["stale_after"])] = _DEFAULTS["stale_after"],
    max_gap: Annotated[float, typer.Option(help=_THRESHOLD_HELP["max_gap"])] = _DEFAULTS["max_gap"],
    delay: Annotated[float, typer.Option(help=_THRESHOLD_HELP["delay"])] = _DEFAULTS["delay"],
    future: Annotated[float, typer.Option(help=_THRESHOLD_HELP["future"])] = _DEFAULTS["future"],
    clock: Annotated[float, typer.Option(help=_THRESHOLD_HELP["clock"])] = _DEFAULTS["clock"],
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    target: options.Target = None,
    sensors: options.Sensors = None,
    init: Annotated[
        bool,
        typer.Option(
            "--init", help="Write the bag's tree as a tree file for --expect (tfx wtf --init BAG > tree.yaml)."
        ),
    ] = False,
    expect: Annotated[
        Path | None,
        typer.Option(
            help="Check against this tree file (--init writes one): frames missing or new, other parents, static "
            "edges moved beyond the tolerances, slower edges, other publishers.",
        ),
    ] = None,
    urdf: Annotated[
        Path | None,
        typer.Option(
            help="Check against this robot description (a URDF file; xacro's output, not xacro): its joints on tf "
            "where robot_state_publisher puts them, as /joint_states says; links tf lacks, frames the URDF lacks. "
            "Without it, a recorded /robot_description is used.",
        ),
    ] = None,
    tolerance_mm: expected_tree.ToleranceMmOption = None,
    tolerance_deg: expected_tree.ToleranceDegOption = None,
    tolerance_rate: expected_tree.ToleranceRateOption = None,
    duration: options.Listen = 5.0,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
    watch: Annotated[
        bool,
        typer.Option(
            "--watch",
            help="Live, until Ctrl-C: every second, check the last --window seconds heard and publish tf's "
            "health on /diagnostics as diagnostic_updater does (for rqt_robot_monitor, Foxglove).",
        ),
    ] = False,
    window: Annotated[
        float, typer.Option(help="With --watch: the seconds of what was heard that each check covers.")
    ] = 10.0,
    mcap: findings_file.McapOption = None,
    force: options.Force = False,
) -> None:
    """Check tf for what breaks lookups, and say how to fix each problem (roswtf's tf checks and more).

    Each BAG is checked on its own (a fleet: [cyan]tfx wtf logs/*.bag --jobs 4[/]); the -b bags together
    make one more recording (a split bag). Without bags, listens --duration seconds to the live system.

    Errors (loops, several trees, re-parenting, stale edges, stamps on another clock or from the
    future, NaN or bad rotations, empty or self frame ids, stamps going back, no tf) break lookups;
    warnings (publishers that agree, leading '/', fixed transforms on /tf, gaps, late arrival) are
    tolerated by tf2 but off; notes are for information. --list-checks lists every check. Sensor data
    (a bag's messages with a header, or the --sensor topics) is replayed through a tf2 MessageFilter
    into --target: frames not in the tree, streams that wait for tf, and messages lost for good are
    reported too.

    Exit codes: 0 no errors (warnings allowed, unless --strict); 1 errors found, or some recordings
    could not be read (each reported as an error of its own); 2 no recording could be read, or bad
    arguments.

    The expected tree: [cyan]tfx wtf --init good.bag > tree.yaml[/] writes what a healthy recording
    looks like (hand-editable YAML); [cyan]tfx wtf --expect tree.yaml run.bag[/] reports what differs.
    The robot's description: [cyan]tfx wtf --urdf robot.urdf run.bag[/] (or a recorded /robot_description)
    reports joints tf lacks (a joint publisher or robot_state_publisher not running), fixed joints moved,
    moving joints not where /joint_states puts them.

    Fleets: [cyan]--jobs N[/] checks N recordings at once here, [cyan]--dask ADDRESS[/] each as a task on a
    Dask cluster; results come as they finish ([cyan]--format jsonl[/] streams them, [cyan]--resume[/] skips
    those an earlier jsonl report has), then what each check found across the fleet (worst recordings
    first) and the day a problem started, when the recordings span several days.

    Examples: [cyan]tfx wtf robot.bag[/], [cyan]tfx wtf logs/*.bag --format junit > wtf.xml[/],
    [cyan]tfx wtf -b run_0.bag -b run_1.bag --strict[/]
    """
    from tftools.analysis.expected import Tolerances
    from tftools.analysis.wtf.query import CheckQuery
    from tftools.render import wtf as render
    from tftools.render import wtf_lines as render_lines
    from tftools.sources.urdf import read_urdf

    if list_checks:
        _list_checks()
        return
    if init:
        if len(paths or []) + bool(bags) > 1:
            raise UsageError("--init writes the tree of one recording", "give one bag (or its parts with -b)")
        expected_tree.write_init(list(paths or []) or list(bags or []), topics, tf2)
        return
    tolerances = (tolerance_mm, tolerance_deg, tolerance_rate)
    if expect is None and urdf is None and any(t is not None for t in tolerances):
        raise UsageError(
            "the tolerances are for --expect and --urdf", "e.g. tfx wtf --expect tree.yaml run.bag --tolerance-mm 2"
        )
    expected = expected_tree.read_expected(expect, *tolerances) if expect is not None else None
    description = read_urdf(urdf) if urdf is not None else None
    robot_tolerances = expected_tree.tolerances(Tolerances(), *tolerances) if expected is None else expected.tolerances
    thresholds = _thresholds(stale_after=stale_after, max_gap=max_gap, delay=delay, future=future, clock=clock)
    ignored = _ignored(ignore or [])
    query = CheckQuery(
        topics=tuple(topics) if topics else None,
        semantics=tf2,
        thresholds=thresholds,
        ignore=ignored,
        target=target,
        sensor_topics=tuple(sensors) if sensors else None,
        expected=expected,
        urdf=description,
        urdf_tolerances=robot_tolerances,
    )
    groups = options.recordings_given(paths, bags)
    if watch:
        if groups or mcap is not None:
            raise UsageError("--watch listens to a live system", "give no bag (or drop --watch)")
        if fmt is not WtfFormat.text:
            raise UsageError("--watch says its changes as text lines", "drop --format; /diagnostics carries the rest")
        _watch(ros1, use_sim_time, topics, query, window)
        return
    if mcap is not None:
        findings_file.refuse(mcap, findings_file.one_recording(groups), force)
        reports = [findings_file.check_into_mcap(findings_file.one_recording(groups), query, mcap, force)]
    elif groups:
        stream = functools.partial(render_lines.write_recording, out=sys.stdout, strict=strict)
        fleet = _fleet(jobs or os.cpu_count() or 1, dask, timeout)
        reports = _check_groups(groups, query, fleet, resume, stream if fmt is WtfFormat.jsonl else lambda bag: None)
    elif dask is not None or resume is not None or timeout is not None:
        raise UsageError("--dask, --resume and --timeout are for recordings", "e.g. tfx wtf logs/*.bag --dask ADDRESS")
    else:  # nothing heard is the no_tf error; sensor data only from the topics named
        from tftools.analysis.wtf.fleet import check

        source = live.start_listening(ros1, use_sim_time, duration, topics)
        recording = live.capture_recording(source, duration, query.sensor_topics, tf2, require_tf=False)
        reports = [check(recording, query)]
    code = outcome(reports, strict)
    if fmt is WtfFormat.json:
        render.write_json(reports, sys.stdout, strict, thresholds, code)
    elif fmt is WtfFormat.jsonl:
        render_lines.write_summary(reports, sys.stdout, strict, thresholds, code)
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
        say_error(hinted(f"{first.message}{more}", first.hint))
    exit_with(code)


def _watch(
    ros1: bool | None, use_sim_time: bool | None, topics: Sequence[str] | None, query: CheckQuery, window: float
) -> None:
    """``--watch``: the live system checked every second, its health on /diagnostics and its changes on stdout."""
    from tftools.analysis.wtf.watch import Health, watch_live
    from tftools.render.escape import printable
    from tftools.sinks.diagnostics import open_diagnostics
    from tftools.sources.live.errors import LiveError

    positive_seconds(window, "--window", "10")
    if query.sensor_topics:
        raise UsageError("--watch checks tf only", "drop --sensor")
    source = live.open_source(ros1, use_sim_time, topics)
    try:
        publisher = open_diagnostics(source.format.startswith("ros1"), on_notice=warn)
    except LiveError:
        source.close()
        raise
    said: dict[str, int] = {}

    def tell(health: Health) -> None:  # on the terminal, what changed level (the figures change every second)
        publisher.publish(health.now, health.statuses)
        for status in health.statuses:
            if said.get(status.name, 0) != status.level:
                said[status.name] = status.level
                line = printable(f"{status.level.name:5} {status.name}: {status.message}")  # names from peers
                stdout.print(line, markup=False, highlight=False)

    live.say(f"watching {source.describe()}, publishing {publisher.describe()} once a second (Ctrl-C stops)")
    with publisher:
        watch_live(source, tell, window, query)


def outcome(reports: Sequence[BagReport], strict: bool = False) -> Exit:
    """UNUSABLE when no recording could be read, PROBLEMS when any failed (or could not be read), else OK."""
    from tftools.analysis.wtf.fleet import exit_code

    return Exit(exit_code(reports, strict))


def _thresholds(**seconds: float) -> Thresholds:
    from tftools.analysis.wtf import Thresholds

    for name, value in seconds.items():
        positive_seconds(value, f"--{name.replace('_', '-')}", "0.5")
    return Thresholds(**seconds)


def _ignored(codes: Sequence[str]) -> tuple[str, ...]:
    from tftools.analysis.wtf import CHECKS

    for code in codes:
        if code not in CHECKS:
            close = difflib.get_close_matches(code, list(CHECKS), n=1)
            hint = f"did you mean {close[0]}?" if close else "see tfx wtf --list-checks"
            raise UsageError(f"--ignore {code}: there is no such check", hint)
    return tuple(codes)


def _fleet(jobs: int, dask: str | None, timeout: float | None) -> Fleet:
    """Where and how long the fleet's checks run, from --jobs, --dask and --timeout."""
    from tftools.analysis.fleet import Fleet

    if dask is not None and jobs != 1:
        raise UsageError("--jobs and --dask: choose one", "--dask runs as many at once as the cluster has threads")
    if timeout is not None:
        positive_seconds(timeout, "--timeout", "600")
    return Fleet(jobs, dask, timeout)


def _check_groups(
    groups: list[list[str]], query: CheckQuery, fleet: Fleet, resume: Path | None, stream: Callable[[BagReport], None]
) -> list[BagReport]:
    """Each group of paths checked as its own recording, ``stream`` ed as it finishes (those resumed first);
    reports in the given order (then those resumed that were not given)."""
    from tftools.analysis.wtf.fleet import check_fleet, in_order, remaining

    done = _resumed(resume) if resume is not None else []
    todo = remaining(groups, done)
    reports: list[BagReport] = []
    with count_bar("checking", len(todo)) as advance:
        for checked in check_fleet(groups, query, fleet, done=done, progress=_bytes_bar(todo, fleet)):
            bag = _worded(checked)
            stream(bag)
            reports.append(bag)
            if len(reports) > len(done):
                advance()
    return in_order(groups, reports)


def _worded(bag: BagReport) -> BagReport:
    """``bag`` with the hint of a check that did not finish (code ``unchecked``) in the options' words."""
    error = bag.error
    if error is None or error.code != "unchecked" or "cause" not in error.figures:
        return bag
    return dataclasses.replace(
        bag, error=dataclasses.replace(error, hint=unfinished_hint(error.figures["cause"], error.hint))
    )


def _bytes_bar(todo: list[list[str]], fleet: Fleet) -> Progress | None:
    """One local recording: a bar of the bytes read, when it is large."""
    return functools.partial(progress_bar, then="checking") if len(todo) == 1 and fleet.dask is None else None


def _resumed(path: Path) -> list[BagReport]:
    from tftools.render import wtf_lines as render_lines
    from tftools.sources.user_files import NotAFileError, UserFileError, open_regular

    try:
        with open_regular(path) as source:
            resumed = render_lines.read_report(source, str(path))
    except NotAFileError as error:
        raise UsageError(f"--resume {path}: {error}", error.hint) from None
    except (OSError, UserFileError) as error:
        raise UsageError(f"--resume {path}: {error}", "give the report of an earlier run") from None
    if resumed.cut_short:
        warn(f"{path}: its last line was cut short; that recording is checked again")
    return resumed.reports


def _list_checks() -> None:
    from tftools.analysis.wtf import CHECKS
    from tftools.analysis.wtf.causes import severity_as_cause

    caption = (
        "Severity: the most a check reports on its own; some findings are milder. A finding that explains others "
        "(a root cause, shown with what follows from it beneath, counted once) is as severe as the worst of them: "
        "'warning, error as a cause' is an error where errors follow from it"
    )
    table = Table(box=None, header_style="bold", caption=caption)
    for name in ("Code", "Severity", "Looks for"):
        table.add_column(name)
    severities = {code: c.severity for code, c in CHECKS.items()}
    for code, c in CHECKS.items():
        raised = severity_as_cause(code, severities)
        severity = c.severity.value if raised is c.severity else f"{c.severity.value}, {raised.value} as a cause"
        table.add_row(code, severity, c.title)
    stdout.print(table)
