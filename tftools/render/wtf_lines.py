"""``tfx wtf --format jsonl``: one line per recording as its check finishes, then a summary line; and
reading such a report back (``--resume``) within limits, tolerating a last line cut short."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import IO, Any

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import Thresholds
from tftools.analysis.wtf.fleet import BagReport
from tftools.core.errors import TfToolsError
from tftools.core.time import NS_PER_S
from tftools.render import jsonl
from tftools.render.wtf import as_dict, bag_dict

#: A recording's line longer than this is not one tfx wrote (a line holds one recording's findings).
MAX_LINE_BYTES = 16 * 1024 * 1024
MAX_RECORDINGS = 1_000_000


class ReportError(TfToolsError):
    """A report to resume from that is not a ``tfx wtf --format jsonl`` report."""

    hint = "give a report written by write_recording and write_summary"


def write_recording(bag: BagReport, out: IO[str], strict: bool) -> None:
    """The recording's line, flushed: a long run can be followed, and resumed from what was written."""
    jsonl.write_lines([{"type": "recording", **bag_dict(bag, strict)}], out)
    out.flush()


def write_summary(
    reports: Sequence[BagReport], out: IO[str], strict: bool, thresholds: Thresholds, exit_code: int
) -> None:
    """The last line: the whole report (``--format json``'s) but its recordings, which came before."""
    whole = as_dict(reports, strict, thresholds, exit_code)
    del whole["bags"]
    jsonl.write_lines([{"type": "summary", **whole}], out)


@dataclass
class Resumed:
    reports: list[BagReport]
    cut_short: bool  # the last line was incomplete (the run was stopped while writing it): ignored


def read_report(source: IO[bytes], name: str) -> Resumed:
    """The recordings a JSON-lines report holds (a later line for the same recording replaces an earlier
    one); its summary lines are skipped."""
    found: dict[tuple[str, ...], BagReport] = {}
    number = 0
    while line := source.readline(MAX_LINE_BYTES + 1):
        number += 1
        complete = line.endswith(b"\n")
        if len(line) > MAX_LINE_BYTES:
            raise ReportError(f"{name}: line {number} is longer than {MAX_LINE_BYTES // 2**20} MiB")
        try:
            entry = json.loads(line)
        except ValueError:
            if not complete:
                return Resumed(list(found.values()), cut_short=True)
            raise ReportError(f"{name}: line {number} is not JSON") from None
        if not isinstance(entry, dict) or entry.get("type") not in ("recording", "summary"):
            raise ReportError(f"{name}: line {number} is not a line of a tfx wtf report")
        if entry["type"] == "recording":
            bag = _bag(entry, name, number)
            found[bag.paths] = bag
            if len(found) > MAX_RECORDINGS:
                raise ReportError(f"{name}: more than {MAX_RECORDINGS:,} recordings")
    return Resumed(list(found.values()), cut_short=False)


def _bag(entry: dict[str, Any], name: str, number: int) -> BagReport:
    try:
        error = entry["error"]
        return BagReport(
            paths=tuple(_strings(entry["paths"])),
            findings=[_finding(f) for f in entry["findings"]],
            error=_finding(error) if error is not None else None,
            formats=tuple(_strings(entry["formats"])),
            start=_ns(entry["start"]),
            end=_ns(entry["end"]),
            stamped=_stamped(entry.get("stamped")),  # older reports have none
            transforms=int(entry["transforms"]),
            frames=int(entry["frames"]),
            **_sensor_data(entry["sensor_data"]),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as problem:
        raise ReportError(f"{name}: line {number} is not a recording of a tfx wtf report ({problem!r})") from None


def _finding(entry: dict[str, Any]) -> Finding:
    return Finding(
        severity=Severity(entry["severity"]),
        code=str(entry["code"]),
        message=str(entry["message"]),
        hint=str(entry["hint"]),
        frames=tuple(_strings(entry["frames"])),
        authorities=tuple(_strings(entry["authorities"])),
        first_time=_ns(entry["first_time"]),
        last_time=_ns(entry["last_time"]),
        count=int(entry["count"]),
        skipped=bool(entry["skipped"]),
        key=str(entry.get("key", "")),  # older reports have no causes
        cause=str(entry.get("cause", "")),
        figures=dict(entry.get("figures") or {}),
    )


def _sensor_data(entry: dict[str, Any] | None) -> dict[str, Any]:
    if entry is None:
        return {}
    return {
        "sensor_topics": tuple(_strings(entry["topics"])),
        "sensor_target": str(entry["target"] or ""),  # null: no tree
        "sensor_target_reason": str(entry["target_reason"]),
    }


def _stamped(entry: dict[str, Any] | None) -> tuple[int, int] | None:
    return None if entry is None else (_ns(entry["start"]), _ns(entry["end"]))


def _strings(values: list[Any]) -> list[str]:
    if not isinstance(values, list) or not all(isinstance(v, str) for v in values):
        raise TypeError("expected a list of strings")
    return values


def _ns(seconds: float | None) -> int:
    return 0 if seconds is None else round(float(seconds) * NS_PER_S)
