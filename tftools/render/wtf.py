"""``tfx wtf`` output: findings grouped by severity as text, one JSON document, or JUnit XML for CI."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import asdict
from typing import IO, Any

from rich.console import Console
from rich.text import Text

from tftools import __version__
from tftools.analysis.findings import Finding, Severity, causes, counted, explained, explaining, tallied
from tftools.analysis.wtf import CHECKS, Thresholds
from tftools.analysis.wtf.fleet import BagReport
from tftools.analysis.wtf.fleet_report import Verdict, recordings_per_day, tally, trends, verdict
from tftools.core.time import NS_PER_S
from tftools.render import jsonl
from tftools.render.escape import printable
from tftools.sources.timeline import NO_RECORD_CLOCK

_MARKS = {Severity.error: ("✗", "bold red"), Severity.warning: ("!", "yellow"), Severity.info: ("·", "cyan")}


# --- text -------------------------------------------------------------------------------------


def write_text(reports: Sequence[BagReport], console: Console, strict: bool = False) -> None:
    """Each recording's findings by severity with a hint each, then a one-line verdict."""
    for i, bag in enumerate(reports):
        if i:
            console.print()
        _write_bag(bag, console, strict)
    if len(reports) > 1:
        console.print()
        _write_fleet(reports, console)
        console.print(_fleet_line(reports, strict))


#: How many recordings the text names per check (JSON names them all).
NAMED = 5


def _write_fleet(reports: Sequence[BagReport], console: Console) -> None:
    """Per check, how many recordings have it and the worst of them; per check, the day it started."""
    tallies = tally(reports)
    if tallies:
        console.print(Text("ACROSS THE FLEET", style="bold"))
    for checked in tallies:
        line = _marked(checked.severity, checked.code)
        named = ", ".join(checked.recordings[:NAMED])
        more = f" and {len(checked.recordings) - NAMED} more" if len(checked.recordings) > NAMED else ""
        line.append(f": {len(checked.recordings)} of {len(reports)} recordings: {printable(named)}{more}")
        console.print(line)
    days = recordings_per_day(reports)
    started = [(t.code, t.since, t.per_day) for t in trends(reports) if t.since is not None]
    if started:
        console.print(Text(f"TRENDS ({len(days)} days, {min(days)} to {max(days)})", style="bold"))
    for code, since, per_day in started:
        having = sum(n for day, n in per_day.items() if day >= since)
        dated = sum(n for day, n in days.items() if day >= since)
        console.print(f"  {code}: started on {since}, every day since: {having} of the {dated} recordings")


def _write_bag(bag: BagReport, console: Console, strict: bool) -> None:
    header = Text(printable(bag.name), style="bold")
    if bag.usable:
        header.append(
            f"  {printable(', '.join(bag.formats))}, {_span(bag)}, {bag.transforms} transforms, {bag.frames} frames"
        )
        for fetched in bag.fetched:
            header.append(f", {fetched.describe()}")
        if bag.sensor_topics and bag.sensor_target:  # no tree, no frame to check them in
            header.append(
                f", {counted(len(bag.sensor_topics), 'topic')} of sensor data checked in "
                f"{printable(bag.sensor_target)} ({printable(bag.sensor_target_reason)})"
            )
    console.print(header)
    findings = [bag.error] if bag.error is not None else bag.findings
    for severity in Severity:
        mine = [f for f in causes(findings) if f.severity is severity]
        if not mine:
            continue
        more = explaining(findings, severity)
        also = f", explaining {more} more" if more else ""
        console.print(Text(f"{severity.noun.upper()}S ({len(mine)}{also})", style=_MARKS[severity][1]))
        for finding in mine:
            _write_finding(finding, console)
            _write_explained(finding, explained(findings, finding), console)
    console.print(_bag_line(bag, strict))


def _span(bag: BagReport) -> str:
    """The time the recording covers: its record span, or tf's stamps' where the record times are no clock
    (a script's writer that recorded every message within 74 ns: "0.0 s recorded" would say nothing true)."""
    if bag.stamped is not None:
        first, last = bag.stamped
        return f"tf stamped over {(last - first) / NS_PER_S:.1f} s ({NO_RECORD_CLOCK})"
    return f"{(bag.end - bag.start) / NS_PER_S:.1f} s recorded"


def _write_finding(finding: Finding, console: Console) -> None:
    console.print(_marked(finding.severity, finding.code).append(f": {printable(finding.message)}"))
    if finding.hint:
        console.print(Text(f"      hint: {printable(finding.hint)}", style="dim"))


#: How many findings of one code the text shows beneath their cause (JSON has every one).
SHOWN_PER_CODE = 5


def _write_explained(cause: Finding, following: Sequence[Finding], console: Console) -> None:
    """What follows from a cause, beneath it: a line each (their hint is the cause's), a few per code. Findings
    of the cause's own code are its like (one publisher's edges, one subtree), not its effects."""
    if not following:
        return
    if all(f.code == cause.code for f in following):
        heading = f"      and {counted(len(following), 'more finding')} of the same cause:"
    else:
        heading = f"      which explains {counted(len(following), 'more finding')}:"
    console.print(Text(heading, style="dim"))
    for code in dict.fromkeys(f.code for f in following):
        mine = [f for f in following if f.code == code]
        for finding in mine[:SHOWN_PER_CODE]:
            mark, style = _MARKS[finding.severity]
            console.print(Text(f"      {mark} {code}: {printable(finding.message)}", style=style))
        if len(mine) > SHOWN_PER_CODE:
            rest = len(mine) - SHOWN_PER_CODE
            console.print(Text(f"      {mark} and {rest} more {code} (--format json lists each)", style=style))


def _marked(severity: Severity, code: str) -> Text:
    """A check's line as it begins: the severity's mark and the code, in the severity's colour."""
    mark, style = _MARKS[severity]
    return Text(f"  {mark} {code}", style=style)


def _bag_line(bag: BagReport, strict: bool) -> Text:
    if not bag.usable:
        done = "read" if bag.error is not None and bag.error.code == "unreadable" else "checked"
        return Text(f"could not be {done}: UNUSABLE", style="bold red")
    summary = ", ".join(tallied(bag.findings, s, s.noun) for s in Severity) if bag.findings else "no problems found"
    if bag.failed(strict):
        return Text(f"{summary}: FAILED", style="bold red")
    return Text(f"{summary}: PASSED", style="bold green")


def _fleet_line(reports: Sequence[BagReport], strict: bool) -> Text:
    outcomes = ", ".join(f"{n} {outcome}" for outcome, n in _outcomes(reports, strict).items())
    totals = ", ".join(counted(n, s.noun) for s, n in _totals(reports).items())
    failing = [r.name for r in reports if r.failed(strict)]
    line = Text(f"{len(reports)} recordings checked: {outcomes} ({totals})")
    if failing:
        line.append(f"; failing: {printable(', '.join(failing))}", style="red")
    return line


# --- JSON -------------------------------------------------------------------------------------


def finding_dict(finding: Finding) -> dict[str, Any]:
    """A finding's fields, its times in seconds (null where unknown)."""
    return {
        **asdict(finding),
        "severity": finding.severity.value,
        "first_time": finding.first_time / NS_PER_S if finding.first_time else None,
        "last_time": finding.last_time / NS_PER_S if finding.last_time else None,
    }


def _totals(reports: Sequence[BagReport]) -> dict[Severity, int]:
    """Findings of each severity in the recordings that could be read."""
    return {s: sum(r.count(s) for r in reports if r.usable) for s in Severity}


def _counts(reports: Sequence[BagReport]) -> dict[str, int]:
    """Findings of each severity that follow from no other, and ``explained``: those that do (``Finding.cause``)."""
    follow = sum(len(r.findings) - len(causes(r.findings)) for r in reports if r.usable)
    return {**{f"{s.noun}s": n for s, n in _totals(reports).items()}, "explained": follow}


def _outcomes(reports: Sequence[BagReport], strict: bool) -> dict[str, int]:
    """How many recordings passed, failed, or could not be used."""
    verdicts = [verdict(r, strict) for r in reports]
    return {v.value: verdicts.count(v) for v in Verdict}


def bag_dict(bag: BagReport, strict: bool) -> dict[str, Any]:
    return {
        "paths": list(bag.paths),
        "formats": list(bag.formats),
        "start": bag.start / NS_PER_S if bag.usable else None,
        "end": bag.end / NS_PER_S if bag.usable else None,
        "stamped": {"start": bag.stamped[0] / NS_PER_S, "end": bag.stamped[1] / NS_PER_S} if bag.stamped else None,
        "transforms": bag.transforms,
        "frames": bag.frames,
        "fetched": [asdict(f) for f in bag.fetched] or None,
        "sensor_data": {
            "topics": list(bag.sensor_topics),
            "target": bag.sensor_target or None,  # no tree, no frame (its reason: targets.NO_TREE)
            "target_reason": bag.sensor_target_reason,
        }
        if bag.sensor_topics
        else None,
        "passed": not bag.failed(strict),
        "verdict": verdict(bag, strict).value,
        "error": finding_dict(bag.error) if bag.error is not None else None,
        "summary": _counts([bag]),
        "findings": [finding_dict(f) for f in bag.findings],
    }


def as_dict(reports: Sequence[BagReport], strict: bool, thresholds: Thresholds, exit_code: int) -> dict[str, Any]:
    """The whole run: settings, a summary, and one entry per recording (``bags``) in the order given."""
    return {
        "tool": "tfx wtf",
        "version": __version__,
        "strict": strict,
        "thresholds": asdict(thresholds),
        "exit_code": exit_code,
        "summary": {
            "recordings": len(reports),
            **_outcomes(reports, strict),
            **_counts(reports),
        },
        "fleet": fleet_dict(reports),
        "bags": [bag_dict(r, strict) for r in reports],
    }


def fleet_dict(reports: Sequence[BagReport]) -> dict[str, Any]:
    """Per check the recordings that have it (worst first); recordings per day, and per check its days."""
    return {
        "checks": [
            {"code": t.code, "severity": t.severity.value, "count": len(t.recordings), "recordings": list(t.recordings)}
            for t in tally(reports)
        ],
        "days": {str(day): n for day, n in recordings_per_day(reports).items()},
        "trends": [
            {
                "code": t.code,
                "first_day": str(t.first_day),
                "since": str(t.since) if t.since is not None else None,
                "per_day": {str(day): n for day, n in t.per_day.items()},
            }
            for t in trends(reports)
        ],
    }


def write_json(
    reports: Sequence[BagReport], out: IO[str], strict: bool, thresholds: Thresholds, exit_code: int
) -> None:
    jsonl.write_document(as_dict(reports, strict, thresholds, exit_code), out)


# --- JUnit ------------------------------------------------------------------------------------


def junit(reports: Sequence[BagReport], strict: bool = False, ignore: Sequence[str] = ()) -> ET.Element:
    """``<testsuites>``: one suite per recording, one case per check; errors fail (warnings too if
    ``strict``); a check that could not run is ``skipped``; other findings go to the case's
    ``system-out``. A recording that could not be read is a suite with one ``read`` case in error."""
    root = ET.Element("testsuites", name="tfx wtf")
    totals = {"tests": 0, "failures": 0, "errors": 0}
    for bag in reports:
        suite = ET.SubElement(root, "testsuite", name=printable(bag.name))
        properties = ET.SubElement(suite, "properties")
        for path in bag.paths:
            ET.SubElement(properties, "property", name="path", value=printable(path))
        counts = _bag_suite(suite, bag, strict, ignore)
        for key, value in counts.items():
            suite.set(key, str(value))
            totals[key] += value
    for key, value in totals.items():
        root.set(key, str(value))
    return root


def _bag_suite(suite: ET.Element, bag: BagReport, strict: bool, ignore: Sequence[str]) -> dict[str, int]:
    if bag.error is not None:
        case = ET.SubElement(suite, "testcase", classname=printable(bag.name), name="read")
        failure = ET.SubElement(case, "error", type=bag.error.code, message=printable(bag.error.message))
        failure.text = _finding_text(bag.error)
        return {"tests": 1, "failures": 0, "errors": 1}
    failures = tests = 0
    for code, check in CHECKS.items():
        if check.run is None or code in ignore:
            continue
        tests += 1
        case = ET.SubElement(suite, "testcase", classname=printable(bag.name), name=code)
        mine = [f for f in bag.findings if f.code == code]
        failing = [f for f in mine if f.severity.fails(strict) and not f.cause]  # a cause fails for what follows
        if failing:
            failures += 1
            severity = failing[0].severity.value
            failure = ET.SubElement(case, "failure", type=severity, message=printable(failing[0].message))
            failure.text = "\n\n".join(_finding_text(f, bag.findings) for f in failing)
        not_run = [f for f in mine if f.skipped]
        if not_run and not failing:
            ET.SubElement(case, "skipped", message=printable(not_run[0].message))
        rest = [f for f in mine if f not in failing and not f.skipped]
        if rest:
            ET.SubElement(case, "system-out").text = "\n\n".join(_finding_text(f, bag.findings) for f in rest)
    return {"tests": tests, "failures": failures, "errors": 0}


def _finding_text(finding: Finding, findings: Sequence[Finding] = ()) -> str:
    """A finding as JUnit text: names escaped (XML 1.0 cannot hold control characters); a cause with what
    follows from it, a finding that follows from another with its cause."""
    text = f"{finding.severity.value}: {finding.code}: {printable(finding.message)}\nhint: {printable(finding.hint)}"
    if finding.cause:
        return f"{text}\nfollows from {finding.cause} (reported in that check's case)"
    following = explained(findings, finding)
    if following:
        text += f"\nexplains {counted(len(following), 'more finding')} ({finding.key}):"
        text += "".join(f"\n  {f.severity.value}: {f.code}: {printable(f.message)}" for f in following)
    return text


def write_junit(reports: Sequence[BagReport], out: IO[str], strict: bool = False, ignore: Sequence[str] = ()) -> None:
    tree = ET.ElementTree(junit(reports, strict, ignore))
    ET.indent(tree)
    out.write('<?xml version="1.0" encoding="UTF-8"?>\n')
    tree.write(out, encoding="unicode")
    out.write("\n")
