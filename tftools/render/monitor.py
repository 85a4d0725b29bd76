"""``tfx monitor`` output: tf_monitor's results as rich tables, or one JSON object."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from typing import IO, Any

from rich.console import Console, ConsoleOptions, Group, RenderableType, RenderResult
from rich.measure import Measurement
from rich.segment import Segment
from rich.style import Style
from rich.table import Table
from rich.text import Text

from tftools.analysis.edges import AuthorityStats, EdgeStats
from tftools.analysis.monitor import ChainStats, MonitorReport
from tftools.core.figures import seconds
from tftools.core.time import to_sec
from tftools.render import jsonl
from tftools.render.escape import printable


def _sec(ns: float) -> str:
    """A figure (ns) in seconds, "-" where unknown."""
    return "-" if math.isnan(ns) else f"{seconds(ns):.4f}"


def _table(
    title: str, names: Sequence[str], numbers: Sequence[str], names_after: Sequence[str], compact: bool
) -> Table:
    """A table whose name columns (frames, publishers) are never cut: on a narrow terminal (``compact``)
    the figures' headers take two lines and the columns one space apart, and names fold onto more lines."""
    padding = (0, 1, 0, 0) if compact else (0, 1)
    table = Table(title=title, title_justify="left", title_style="bold", header_style="bold", box=None, padding=padding)

    def header(name: str) -> str:
        return name if compact else name.replace("\n", " ")

    for name in names:
        table.add_column(header(name), overflow="fold")
    for name in numbers:
        table.add_column(header(name), justify="right", no_wrap=True)
    for name in names_after:
        table.add_column(header(name), overflow="fold")
    return table


class _Fitted:
    """A table as wide as it needs where the width allows (tf_monitor's headers on one line), else compact."""

    def __init__(self, table: Callable[[bool], Table]) -> None:
        self._table = table

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> RenderResult:
        wide = self._table(False)
        if wide.row_count > MAX_LAID_OUT_ROWS:
            yield from _plain(wide)
            return
        natural = Measurement.get(console, options.update_width(1_000_000), wide).maximum  # unclamped
        yield wide if natural <= options.max_width else self._table(True)


#: Past this many rows a table is written as plain columns: rich lays a table out at 0.3 ms a row, minutes
#: for the 20,000 frames of a simulated fleet.
MAX_LAID_OUT_ROWS = 2000


def _plain(table: Table) -> Iterator[Segment]:
    """``table``'s title, headers and rows in columns two spaces apart, names whole, without colours."""
    columns = [[column.header if isinstance(column.header, str) else "", *column.cells] for column in table.columns]
    texts = [[cell.plain if isinstance(cell, Text) else str(cell) for cell in cells] for cells in columns]
    widths = [max(len(text) for text in column) for column in texts]
    right = [column.justify == "right" for column in table.columns]
    if isinstance(table.title, str):
        yield Segment(table.title + "\n", Style(bold=True))
    for row in zip(*texts, strict=True):
        laid = zip(row, widths, right, strict=True)
        cells = (text.rjust(width) if r else text.ljust(width) for text, width, r in laid)
        yield Segment("  ".join(cells).rstrip() + "\n")


#: The figures' headers: tf_monitor's words, on two lines where the width is short.
_RATE, _DELAY_MEAN, _DELAY_MAX = "Rate\n(Hz)", "Average\nDelay (s)", "Max\nDelay (s)"


def _edges_table(edges: Sequence[EdgeStats], compact: bool) -> Table:
    numbers = ("Samples", _RATE, "Jitter\n(s)", "Largest\ngap (s)", _DELAY_MEAN, _DELAY_MAX)
    table = _table("Frames:", ("Parent", "Frame", "published\nby"), numbers, (), compact)
    for e in edges:
        long_interval = not e.static and e.rate_hz > 0 and seconds(e.longest_interval) > 2.0 / e.rate_hz
        table.add_row(
            Text(printable(e.parent)),
            Text(printable(e.child), style="bold"),
            Text(printable(", ".join(e.authorities)) or "?", style="yellow" if len(e.authorities) > 1 else "magenta"),
            str(e.count),
            Text("static", style="cyan") if e.static else f"{e.rate_hz:.2f}",
            "" if e.static else _sec(e.jitter),
            "" if e.static else Text(_sec(e.longest_interval), style="yellow" if long_interval else ""),
            "" if e.static else _sec(e.delay_mean),
            "" if e.static else _sec(e.delay_max),
        )
    return table


def _authorities_table(authorities: list[AuthorityStats], static: set[tuple[str, str]], compact: bool) -> Table:
    numbers = ("Messages", _RATE, _DELAY_MEAN, _DELAY_MAX)
    table = _table("All Broadcasters:", ("Node",), numbers, ("Frames",), compact)
    for a in authorities:
        table.add_row(
            Text(printable(a.authority) or "?", style="magenta"),
            str(a.messages),
            Text("static", style="cyan") if set(a.edges) <= static else f"{a.rate_hz:.2f}",
            _sec(a.delay_mean),
            _sec(a.delay_max),
            Text(printable(", ".join(child for _, child in a.edges)), style="dim"),
        )
    return table


def _chain_lines(chain: ChainStats) -> Text:
    text = Text(f"RESULTS: for {printable(chain.target)} to {printable(chain.source)}\n", style="bold")
    text.append(f"Chain is: {printable(' -> '.join(chain.frames))}\n")
    text.append(f"Net delay     avg = {_sec(chain.delay_mean)}: max = {_sec(chain.delay_max)}")
    if chain.limiting is not None:
        text.append(
            f"  (held back most by {printable(chain.limiting[0])} -> {printable(chain.limiting[1])})", style="dim"
        )
    elif all(e.static for e in chain.edges):
        text.append("  (every edge is static: never stale)", style="dim")
    return text


def renderable(
    report: MonitorReport, header: str = "", target: str | None = None, source: str | None = None
) -> RenderableType:
    """The report as tf_monitor lays it out: ``header`` (lines), results heading (and chain), frames,
    broadcasters; ``target``/``source`` name a chain still being waited for when the report has none."""
    parts: list[RenderableType] = []
    if header:  # its lines each made printable (a file's name may hold anything)
        parts.append(Text("\n".join(printable(line) for line in header.split("\n")), style="dim"))
    if report.delays_unavailable:
        parts.append(Text(printable(f"delays unavailable: {report.delays_unavailable}"), style="dim"))
    if report.chain is not None:
        parts.append(_chain_lines(report.chain))
        edges: Sequence[EdgeStats] = report.chain.edges
    elif target is not None and source is not None:
        waiting = printable(f"Waiting for transform chain to become available between {target} and {source}")
        parts.append(Text(waiting, style="bold"))
        edges = report.edges
    else:
        parts.append(Text("RESULTS: for all Frames", style="bold"))
        edges = report.edges
    static = {e.key for e in report.edges if e.static}
    parts += [
        Text(""),
        _Fitted(lambda compact: _edges_table(edges, compact)),
        Text(""),
        _Fitted(lambda compact: _authorities_table(report.authorities, static, compact)),
    ]
    return Group(*parts)


def _edge_dict(e: EdgeStats) -> dict[str, Any]:
    return {
        "parent": e.parent,
        "child": e.child,
        "authorities": list(e.authorities),
        "count": e.count,
        "rate_hz": e.rate_hz,
        "jitter_s": seconds(e.jitter),
        "gap_max_s": seconds(e.longest_interval),
        "gap_start": to_sec(e.longest_interval_start),
        "delay_mean_s": seconds(e.delay_mean),
        "delay_max_s": seconds(e.delay_max),
        "static": e.static,
        "first_stamp": to_sec(e.first_stamp),
        "last_stamp": to_sec(e.last_stamp),
    }


def _authority_dict(a: AuthorityStats) -> dict[str, Any]:
    return {
        "authority": a.authority,
        "messages": a.messages,
        "rate_hz": a.rate_hz,
        "delay_mean_s": seconds(a.delay_mean),
        "delay_max_s": seconds(a.delay_max),
        "edges": [list(edge) for edge in a.edges],
    }


def as_dict(report: MonitorReport) -> dict[str, Any]:
    """The JSON object: window, ``edges``, ``authorities`` and, with two frames, ``chain``."""
    result: dict[str, Any] = {
        "window": {
            "start": to_sec(report.start) if report.start is not None else None,
            "end": to_sec(report.end) if report.end is not None else None,
        },
        "edges": [_edge_dict(e) for e in report.edges],
        "authorities": [_authority_dict(a) for a in report.authorities],
        "delays_unavailable": report.delays_unavailable or None,  # why delays are null, where they all are
    }
    if report.chain is not None:
        chain = report.chain
        result["chain"] = {
            "target": chain.target,
            "source": chain.source,
            "frames": list(chain.frames),
            "edges": [_edge_dict(e) for e in chain.edges],
            "delay_mean_s": seconds(chain.delay_mean),
            "delay_max_s": seconds(chain.delay_max),
            "limiting": list(chain.limiting) if chain.limiting is not None else None,
        }
    return result


def write_json(report: MonitorReport, out: IO[str]) -> None:
    """One JSON document (NaN as null)."""
    jsonl.write_document(as_dict(report), out)


def write_json_line(report: MonitorReport, out: IO[str]) -> None:
    """One compact JSON object per line, for each refresh of a live monitor."""
    jsonl.write_lines([as_dict(report)], out)
    out.flush()
