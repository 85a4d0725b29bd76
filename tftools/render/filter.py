"""``tfx filter`` output: a table a person reads at a glance, or one JSON document for scripts."""

from __future__ import annotations

import dataclasses
from typing import IO, Any

from rich.console import Group, RenderableType
from rich.table import Table
from rich.text import Text

from tftools.analysis.filter import KEEP, FilterReport, StreamReport
from tftools.render import jsonl
from tftools.render.escape import printable


def renderable(report: FilterReport, header: str = "") -> RenderableType:
    """Per stream: messages, on arrival, later (and how long they waited), never (and why), the edge
    they waited for, and the filter settings that would keep ``KEEP`` of them."""
    title = f"MessageFilter into {printable(report.target)} ({report.target_reason}), {report.cache_s:g} s cache"
    table = Table(title=Text(title, style="bold"), title_justify="left", show_lines=False)
    for name, justify in (
        ("Topic", "left"), ("Frames", "left"), ("Msgs", "right"), ("On arrival", "right"), ("Later", "right"),
        ("Wait p50 / p99 / max (s)", "right"), ("Never", "right"), ("Why never", "left"), ("Undecided", "left"),
        ("Waited for", "left"), (f"To keep {KEEP:.1%}", "left"),
    ):  # fmt: skip
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    for s in report.streams:
        table.add_row(
            Text(printable(s.topic)),
            Text(printable(", ".join(s.frame_ids))),
            str(s.messages),
            str(s.on_arrival),
            Text(str(s.later), style="yellow" if s.later else ""),
            f"{s.wait_s['p50']:.3f} / {s.wait_s['p99']:.3f} / {s.wait_s['max']:.3f}" if s.later else "",
            Text(str(s.never), style="bold red" if s.never else ""),
            Text(_counted(s.reasons)),
            Text(_counted(s.undecided), style="dim"),
            Text(printable(_late(s))),
            Text(_advice(s)),
        )
    parts: list[RenderableType] = [Text(header, style="dim")] if header else []
    parts.append(table)
    if report.skipped:
        skipped = printable(", ".join(report.skipped))
        parts.append(Text(f"with a header but no frame_id (not tied to tf): {skipped}", style="dim"))
    return Group(*parts)


def _counted(reasons: dict[str, int]) -> str:
    return ", ".join(f"{reason.replace('_', ' ')} {n}" for reason, n in reasons.items())


def _late(s: StreamReport) -> str:
    if s.late_edge is None:
        return ""
    return f"{s.late_edge[0]} -> {s.late_edge[1]} ({s.late_by_s:.3f} s behind)"


def _advice(s: StreamReport) -> str:
    said = []
    if s.wait_needed_s is None:
        said.append("no timeout can")
    elif s.wait_needed_s > 0:
        said.append(f"wait {s.wait_needed_s:.3f} s")
    if s.queue_needed:
        said.append(f"queue {s.queue_needed}")
    if s.cache_needed_s is not None:
        said.append(f"cache {s.cache_needed_s:g} s")
    return ", ".join(said) or "fine as it is"


def as_dict(report: FilterReport) -> dict[str, Any]:
    return {
        "target": report.target,
        "target_reason": report.target_reason,
        "cache_s": report.cache_s,
        "topics": [dataclasses.asdict(s) for s in report.streams],  # tuples become JSON lists
        "skipped": report.skipped,
    }


def write_json(report: FilterReport, out: IO[str]) -> None:
    jsonl.write_document(as_dict(report), out)
