"""``tfx report``: one HTML page a person can look at: a recording's (or a fleet's) tree, timelines, findings
and sensor data."""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import findings_file, live, options
from tftools.cli.common import Exit, exit_with, hinted, progress_bar, say_written, warn
from tftools.cli.errors import UsageError, unfinished_hint, worded
from tftools.cli.outputs import check_output, check_replaceable

if TYPE_CHECKING:  # the analyses and the page load when a report is written: --help needs none of them
    from tftools.analysis.report import ReportQuery
    from tftools.render.report import Section

DEFAULT_OUTPUT = "report.html"


def command(
    paths: options.Paths = None,
    bags: options.Bags = None,
    output: Annotated[
        Path,
        typer.Option("--output", "-o", help="The HTML file to write (never over, into or above an input)."),
    ] = Path(DEFAULT_OUTPUT),
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    target: options.Target = None,
    sensors: options.Sensors = None,
    urdf: Annotated[
        Path | None,
        typer.Option(
            help="Check against this robot description (a URDF file), as tfx wtf --urdf does; without it, a "
            "recorded /robot_description is used.",
        ),
    ] = None,
    jobs: Annotated[
        int, typer.Option("--jobs", "-j", help="Read and check this many recordings at once (0: one per CPU).", min=0)
    ] = 1,
    duration: options.Listen = 5.0,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
    mcap: findings_file.McapOption = None,
    force: options.Force = False,
) -> None:
    """Write one HTML page to look at: findings, tree, each edge over time, every frame in 3D.

    The tree as view-frames draws it, problems in colour; each edge over time (rate, delay, samples,
    gaps, re-parentings) on one time axis; tfx wtf's findings linked to the edges and times they are
    about; every frame in 3D over time; the sensor data a tf2 MessageFilter would have dropped and
    when; and the recording's facts: files, formats, clocks, span.

    The file holds everything it shows (scripts and styles too): it opens in any browser without a
    network or a server, and can be attached to a bug report. Click a finding to zoom every timeline to
    its time; drag across a timeline to zoom, double-click to zoom out.

    Each BAG is a recording of its own (a fleet: one section and verdict each, [cyan]tfx report logs/*.bag[/]);
    the -b bags together make one more (a split bag). Without bags, listens --duration seconds to the
    live system (and to the --sensor topics).

    A recording without any transform gets its page too: what it holds, and tfx wtf's no_tf error.

    Exit codes: 0 written, no errors found; 1 written, errors found (no transforms among them, or some
    recordings could not be read); 2 unusable input, nothing written.

    Examples: [cyan]tfx report -b robot.bag -o robot.html[/], [cyan]tfx report logs/*.bag -o fleet.html[/],
    [cyan]tfx report --ros1 -d 10 -o live.html[/]
    """
    from tftools.analysis.findings import counted
    from tftools.analysis.report import ReportQuery
    from tftools.render.files import write_atomically
    from tftools.render.report import page
    from tftools.sources.urdf import read_urdf

    groups = options.recordings_given(paths, bags)
    _check_output(output, [p for group in groups for p in group], force)
    if mcap is not None:
        findings_file.refuse(mcap, findings_file.one_recording(groups), force)
        if mcap.resolve() == output.resolve():
            raise UsageError(f"--mcap {mcap} is the page's -o", "give them different names")
    query = ReportQuery(
        topics=tuple(topics) if topics else None,
        semantics=tf2,
        target=target,
        sensor_topics=tuple(sensors) if sensors else None,
        urdf=read_urdf(urdf) if urdf is not None else None,
    )
    if groups:
        sections = _bag_sections(groups, query, jobs or os.cpu_count() or 1)
    else:
        from tftools.analysis.report import report
        from tftools.render.report import recording_section

        source = live.start_listening(ros1, use_sim_time, duration, topics)
        recording = live.capture_recording(source, duration, query.sensor_topics, tf2)
        sections = [recording_section(0, report(recording, query))]
    title = "tfx report: " + (sections[0].name if len(sections) == 1 else counted(len(sections), "recording"))
    write_atomically(output, page(title, sections).encode())
    failed = sum(s.verdict == "failed" for s in sections)
    said = ", ".join(s.summary for s in sections) if len(sections) == 1 else f"{failed} of {len(sections)} failed"
    say_written(str(output), said)
    if mcap is not None:  # the same checks as the page's, the recording read once more
        findings_file.check_into_mcap(groups[0], query.checks(), mcap, force)
    exit_with(Exit.PROBLEMS if failed else Exit.OK)


def _check_output(output: Path, inputs: Sequence[str], force: bool) -> None:
    """Refuse, before any reading, an output that would touch an input, a folder, a file there (without
    ``force``), or a place not writable."""
    check_output(output, inputs, file_name=DEFAULT_OUTPUT)
    check_replaceable(output, force)
    folder = output.resolve().parent
    if not os.access(folder, os.W_OK):
        raise UsageError(f"-o {output}: cannot write in {folder}", "write elsewhere with -o")


def _bag_sections(groups: Sequence[Sequence[str]], query: ReportQuery, jobs: int = 1) -> list[Section]:
    """One section per recording, ``jobs`` at once; one that cannot be read is an error of its own in a
    fleet, and the command's error when it is the only one (or none can be read)."""
    from tftools.analysis.fleet import Fleet
    from tftools.analysis.report import Unreadable, report_fleet
    from tftools.render.report import recording_section, unreadable_section

    sections: dict[int, Section] = {}
    unread: list[Unreadable] = []
    here = jobs <= 1 or len(groups) <= 1  # each recording read here: one bar at a time
    for index, result in report_fleet(groups, query, Fleet(jobs), progress=progress_bar if here else None):
        if isinstance(result, Unreadable):
            if result.cause is not None:
                result = replace(result, hint=unfinished_hint(result.cause.value, result.hint))
            elif result.error is not None:  # worded as every other command words it
                said = worded(result.error)[0]
                result = replace(result, message=str(said), hint=said.hint)
            if len(groups) == 1:
                raise UsageError(result.message, result.hint)
            warn(hinted(result.message, result.hint))
            unread.append(result)
            sections[index] = unreadable_section(index, result.name, result.message, result.hint)
            continue
        for problem in result.problems:
            warn(problem)
        sections[index] = recording_section(index, result)
    if len(unread) == len(groups):
        raise UsageError(unread[0].message, unread[0].hint)
    return [sections[i] for i in range(len(groups))]
