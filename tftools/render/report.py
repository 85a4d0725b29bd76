"""``tfx report``'s page: one self-contained HTML file (its script, styles and plotting library inside) that
shows recordings' facts, findings, trees and timelines, and opens without a network or a server.

The text is written here, escaped; the page's script (``page/report.js``) only draws the timelines from
the data embedded as JSON, and links findings, tree and timelines together.
"""

from __future__ import annotations

import html
import json
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from typing import Any

from tftools import __version__
from tftools.analysis.edges import EdgeStats
from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.graph import GraphEdge
from tftools.analysis.report import RecordingReport
from tftools.analysis.timelines import FATE_GROUPS, EdgeTimeline, StreamTimeline
from tftools.core.arrays import FloatArray
from tftools.core.figures import KEEP, apart_in_words, seconds, wait_in_words, within_in_words
from tftools.core.time import NS_PER_S, format_sec, signed_seconds
from tftools.render import drawing, scene3d
from tftools.render.escape import printable
from tftools.render.filter import fates_in_words
from tftools.render.graph import problem_summary, to_digraph
from tftools.sources.timeline import OTHER_CLOCK, seconds_since

#: Significant digits of the plotted figures: what a plot can show, and a smaller file.
DIGITS = 4
#: What the tree's lines and colours mean (view-frames' legend, which the page's picture leaves out).
TREE_KEY = (
    "Each arrow from a parent to its child frame, with its publisher and rate; dashed blue: static; red: errors "
    "(lookups fail there), orange: warnings, as the findings' numbers say. Click an edge for its timeline."
)

#: What a recording without any transform shows instead of its tree, timelines and frames in 3D.
NO_TRANSFORMS = (
    '<h3>Tree</h3><p class="none">No transforms: no tree, timeline or frame in 3D to draw. The facts above say '
    "what the recording holds, and the findings what to do.</p>"
)


@dataclass(frozen=True)
class Section:
    """One recording's part of the page, and what the fleet's summary says of it."""

    anchor: str
    name: str
    verdict: str  # "failed", "warnings" or "passed"
    summary: str
    html: str


def page(title: str, sections: Sequence[Section]) -> str:
    """The whole page: a summary of the recordings when there are several, then each one's section."""
    assets = resources.files("tftools.render") / "page"
    vendor = assets / "vendor"
    style = (vendor / "uPlot.min.css").read_text() + (assets / "report.css").read_text()
    scripts = [(vendor / "uPlot.iife.min.js").read_text(), (assets / "report.js").read_text()]
    scripts += [(assets / name).read_text() for name in scene3d.SCRIPTS]
    fleet = _fleet_table(sections) if len(sections) > 1 else ""
    body = "".join(s.html for s in sections)
    inline = "".join(f"<script>{_script_text(s)}</script>" for s in scripts)
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f'<meta name="viewport" content="width=device-width, initial-scale=1">'
        f'<meta name="generator" content="tfx report {__version__}"><title>{_esc(title)}</title>'
        f"<style>{style}</style></head><body><header><h1>{_esc(title)}</h1>"
        f'<p class="about">Written by tfx report {__version__}. Click a finding to zoom every timeline to its time '
        f"and mark its edges; drag across a timeline to zoom, double-click to zoom out.</p></header>"
        f"{fleet}{body}{inline}</body></html>"
    )


def recording_section(index: int, report: RecordingReport) -> Section:
    """One recording's section: verdict, facts, findings, tree, timelines and sensor streams."""
    anchor = f"r{index}"
    verdict, summary = _verdict(report.findings)
    rows = [i for i, e in enumerate(report.edges) if not e.static]
    # each edge's id in the tree's SVG: Graphviz numbers edges in the order they were added
    svg_ids = {e.key: f"{anchor}-edge{k + 1}" for k, e in enumerate(report.graph.edges)}
    tree = _tree(report, anchor) if report.graph.nodes else ""
    data = {
        "anchor": anchor,
        "axis": {
            "start": _seconds(report.bins.start, report.origin),
            "step": report.bins.width / NS_PER_S,
            "count": report.bins.count,
        },
        "delays": report.delays_shown,  # else no delay is drawn, nor its axis
        "edges": [_edge_data(report, report.edges[i], svg_ids) for i in rows],
        "findings": [_finding_data(report, i, rows, svg_ids, anchor) for i in range(len(report.findings))],
        "streams": [_stream_data(s) for s in report.streams],
        "scene3d": scene3d.poses_data(report.poses, report.origin),  # the timelines' zero
    }
    origin = report.origin
    drawn = [
        f'<h3>Tree</h3><p class="axis">{TREE_KEY}</p><div class="tree">{tree}</div>',
        scene3d.scene_html(report.poses),
        _timelines(report, rows, origin),
        _streams(report.streams),
        _statics(report.graph.edges),
    ]
    parts = [
        '<div class="top">',
        _facts(report.facts),
        _findings(report.findings, origin, report.other_clock),
        "</div>",
        *(drawn if report.graph.nodes else [NO_TRANSFORMS]),
        f'<script type="application/json" class="report-data">{_json(data)}</script>',
    ]
    return _section(anchor, report.name, verdict, summary, "".join(parts))


def unreadable_section(index: int, name: str, message: str, hint: str) -> Section:
    """A recording of a fleet that could not be read: what went wrong, and what to do."""
    return _section(f"r{index}", name, "failed", f"could not be read: {message}", f'<p class="hint">{_esc(hint)}</p>')


def _section(anchor: str, name: str, verdict: str, summary: str, body: str) -> Section:
    """A recording's section: its verdict and name, its summary, then ``body``."""
    html = (
        f'<section class="recording {verdict}" id="{anchor}"><h2><span class="verdict {verdict}">{verdict}</span> '
        f'{_esc(name)}</h2><p class="summary">{_esc(summary)}</p>{body}</section>'
    )
    return Section(anchor, name, verdict, summary, html)


def _verdict(findings: Sequence[Finding]) -> tuple[str, str]:
    errors = any(f.severity is Severity.error for f in findings)
    warnings = any(f.severity is Severity.warning for f in findings)
    verdict = "failed" if errors else "warnings" if warnings else "passed"
    return verdict, problem_summary(findings)


def _fleet_table(sections: Sequence[Section]) -> str:
    rows = "".join(
        f'<tr><td><span class="verdict {s.verdict}">{s.verdict}</span></td>'
        f'<td><a href="#{s.anchor}">{_esc(s.name)}</a></td><td>{_esc(s.summary)}</td></tr>'
        for s in sections
    )
    failed = sum(s.verdict == "failed" for s in sections)
    return (
        f'<section class="fleet"><h2>{counted(len(sections), "recording")}, {failed} failed</h2>'
        f"<table><thead><tr><th>verdict</th><th>recording</th><th>findings</th></tr></thead>"
        f"<tbody>{rows}</tbody></table></section>"
    )


def _facts(facts: Sequence[tuple[str, str]]) -> str:
    rows = "".join(f"<tr><th>{_esc(label)}</th><td>{_esc(value)}</td></tr>" for label, value in facts)
    return f'<table class="facts">{rows}</table>'


def _findings(findings: Sequence[Finding], origin: int, other_clock: frozenset[int]) -> str:
    if not findings:
        return '<div class="findings"><h3>Findings</h3><p class="healthy">No problems found.</p></div>'
    items = []
    cause_of = {f.key: i for i, f in enumerate(findings) if f.key}  # each cause's number: what follows is beneath it
    for i, f in enumerate(findings):
        when = (
            f' <span class="when">{_esc(_span_text(f, origin, other_clock))}</span>'
            if f.first_time or f.last_time
            else ""
        )
        follows = f'<span class="follows">follows from [{cause_of[f.cause] + 1}]</span> ' if f.cause else ""
        items.append(
            f'<li class="finding {f.severity.value}{" explained" if f.cause else ""}" data-finding="{i}" tabindex="0">'
            f'{follows}<span class="badge {f.severity.value}">[{i + 1}] {f.severity.noun}</span> '
            f"<code>{_esc(f.code)}</code>{when}"
            f'<div class="message">{_esc(f.message)}</div><div class="hint">{_esc(f.hint)}</div></li>'
        )
    return f'<div class="findings"><h3>Findings</h3><ol>{"".join(items)}</ol></div>'


def _span(finding: Finding) -> tuple[int, int]:
    """A finding's first and last time, either standing for both where only one is known (0: none)."""
    return finding.first_time or finding.last_time, finding.last_time or finding.first_time


def _span_text(finding: Finding, origin: int, other_clock: frozenset[int]) -> str:
    first, last = _span(finding)
    if first == last:
        return f"at {_offset(first, origin, other_clock)}"
    return f"{_offset(first, origin, other_clock)} to {_offset(last, origin, other_clock)}"


def _offset(ns: int, origin: int, other_clock: frozenset[int]) -> str:
    since = None if ns in other_clock else seconds_since(origin, ns)
    return f"{signed_seconds(since, 3)} s" if since is not None else f"{format_sec(ns, 3)} (another clock)"


def _tree(report: RecordingReport, anchor: str) -> str:
    """The frame graph as view-frames draws it (short labels), as inline SVG with ids unique on the page;
    without Graphviz, a line saying how to get it. No legend in the picture: the page around it has the
    recording's facts, the findings and the key (``TREE_KEY``), and the picture keeps its size to be read."""
    dot = to_digraph(report.graph, None, rankdir="LR", brief=True)
    try:
        svg = drawing.draw(dot, "svg").decode()
    except drawing.GraphNotDrawnError as missing:
        return f'<p class="missing">{_esc(str(missing))} ({_esc(missing.hint)})</p>'
    return re.sub(r'\b(id="|href="#|url\(#)', lambda m: f"{m.group(1)}{anchor}-", svg[svg.index("<svg") :])


def _timelines(report: RecordingReport, rows: Sequence[int], origin: int) -> str:
    if not rows:
        return '<h3>Timelines</h3><p class="none">No moving transforms: nothing changes over time.</p>'
    header = (
        f'<h3>Timelines</h3><p class="axis">Time in seconds from {_esc(format_sec(origin, 3))} (the stamps\' clock); '
        f"rate in Hz{', delay in ms' if report.delays_shown else ''}. Shaded: gaps; violet lines: re-parentings; "
        f"red and orange: the errors' and warnings' times. "
        f'<button type="button" class="reset">Zoom out</button></p>'
    )
    if report.delays_unavailable:
        header += f'<p class="note">Delays unavailable: {_esc(report.delays_unavailable)}</p>'
    if report.delays_other_clock_why:
        header += f'<p class="note">Delays: {_esc(report.delays_other_clock_why)}</p>'
    stats = {(e.parent, e.child): e.stats for e in report.graph.edges}
    parts = []
    for row, i in enumerate(rows):
        e = report.edges[i]
        other_clock = e.child in report.delays_other_clock
        about = _edge_about(stats.get(e.key), delays_known=report.delays_shown, other_clock=other_clock)
        if e.at_arrival:
            about += "; placed at arrival: stamped on another clock"
        if e.unplaced:
            about += "; not drawn: stamped on another clock, which no time of the recording places on this axis"
        parts.append(
            f'<div class="row edge" data-row="{row}"><div class="label"><b>{_esc(e.parent)} &#8594; {_esc(e.child)}'
            f'</b><small>{_esc(about)}</small></div><div class="plot"></div></div>'
        )
    return header + f'<div class="timelines">{"".join(parts)}</div>'


def _edge_about(stats: EdgeStats | None, *, delays_known: bool, other_clock: bool = False) -> str:
    """An edge's figures over the whole recording, as ``tfx monitor`` gives them (delays only where the
    recording's clocks allow them; ``other_clock``: stamped on another clock than its arrivals'), and its
    publishers."""
    if stats is None:
        return ""
    delay = ""
    if delays_known and not math.isnan(stats.delay_mean):
        delay = f", delay {seconds(stats.delay_mean) * 1000:.1f} ms (max {seconds(stats.delay_max) * 1000:.1f})"
    elif delays_known and stats.apart:
        delay = f", delay {apart_in_words(stats.apart)}"
    elif delays_known and other_clock:
        delay = f", delay {OTHER_CLOCK}"
    figures = (
        "1 sample: no rate, no gap"
        if stats.once
        else f"{stats.rate_hz:.1f} Hz, {stats.count} samples, largest gap {seconds(stats.longest_interval):.3f} s"
    )
    seen = f"; a detection, {stats.sightings.in_words()}" if stats.sightings is not None else ""
    return f"{figures}{delay}{seen}; {', '.join(stats.authorities)}"


def _streams(streams: Sequence[StreamTimeline]) -> str:
    if not streams:
        return ""
    parts = []
    for row, s in enumerate(streams):
        r = s.report
        lost = f", {r.never} lost ({fates_in_words(r.reasons)})" if r.never else ""
        kept = (
            f"{KEEP:.1%} {within_in_words(r.wait_needed, r.tick)}"
            if r.wait_needed is not None
            else f"no timeout keeps {KEEP:.1%}"
        )
        wait = f" (wait p50 {wait_in_words(r.wait['p50'], r.tick)}, {kept})" if r.later else ""
        open_ = sum(r.undecided.values())
        undecided = f", {open_} undecided ({fates_in_words(r.undecided)})" if open_ else ""
        about = (
            f"{r.type} in {', '.join(r.frame_ids)}: {r.messages} messages, {r.on_arrival} on arrival, "
            f"{r.later} later{wait}{lost}{undecided}"
        )
        parts.append(
            f'<div class="row stream" data-stream="{row}"><div class="label"><b>{_esc(r.topic)}</b>'
            f'<small>{_esc(about)}</small></div><div class="plot"></div></div>'
        )
    return (
        '<h3>Sensor data through a tf2 MessageFilter</h3><p class="axis">Messages per bin at their arrival: '
        "green on arrival, orange after a wait for tf, red lost for good, grey undecided (the recording "
        f'ended or began first).</p><div class="streams">{"".join(parts)}</div>'
    )


def _statics(edges: Sequence[GraphEdge]) -> str:
    items = "".join(
        f"<li>{_esc(e.parent)} &#8594; {_esc(e.child)} <small>{_esc(', '.join(e.stats.authorities))}</small></li>"
        for e in edges
        if e.static and e.stats is not None
    )
    return f'<h3>Static transforms</h3><ul class="statics">{items}</ul>' if items else ""


def _edge_data(report: RecordingReport, edge: EdgeTimeline, svg_ids: dict[tuple[str, str], str]) -> dict[str, Any]:
    origin = report.origin
    return {
        "name": printable(f"{edge.parent} -> {edge.child}"),
        "svg": svg_ids.get(edge.key, ""),
        "samples": edge.samples.tolist(),
        "rate": _figures(edge.rate_hz),
        "delayMean": _figures(seconds(edge.delay_mean) * 1000),
        "delayMax": _figures(seconds(edge.delay_max) * 1000),
        "gaps": [[_seconds(a, origin), _seconds(b, origin)] for a, b in edge.pauses],
        "reparentings": [
            [_seconds(r.time, origin), printable(f"{r.child}: {r.before} -> {r.after}")] for r in edge.reparentings
        ],
    }


def _finding_data(
    report: RecordingReport, index: int, rows: Sequence[int], svg_ids: dict[tuple[str, str], str], anchor: str
) -> dict[str, Any]:
    """Where a finding is: its time span on the axis, the timeline rows and tree elements it is pinned on
    (Graphviz numbers nodes in the order they were added, as edges)."""
    origin = report.origin
    graph, finding = report.graph, report.findings[index]
    keys = [e.key for e in graph.edges if index in e.problems]  # in the graph's order: the same page each run
    nodes = [f"{anchor}-node{j + 1}" for j, node in enumerate(graph.nodes) if index in node.problems]
    first, last = _span(finding)
    return {
        "code": finding.code,
        "severity": finding.severity.value,
        "from": _on_axis(first, origin, report.other_clock),
        "to": _on_axis(last, origin, report.other_clock),
        "rows": [row for row, i in enumerate(rows) if report.edges[i].key in keys],
        "svg": [svg_ids[key] for key in keys] + nodes,
        "frames": [printable(f) for f in dict.fromkeys(finding.frames)],
    }


def _stream_data(stream: StreamTimeline) -> dict[str, Any]:
    return {
        "topic": printable(stream.report.topic),
        "fates": {name: stream.fates[name].tolist() for name in FATE_GROUPS},
        "waitMax": _figures(seconds(stream.wait_max)),
    }


def _figures(values: FloatArray) -> list[float | None]:
    """Values rounded to ``DIGITS`` significant digits, NaN as null (JSON has no NaN)."""
    return [None if math.isnan(v) else float(f"{v:.{DIGITS}g}") for v in values.tolist()]


def _on_axis(ns: int, origin: int, other_clock: frozenset[int]) -> float | None:
    """A finding's time on the axis; None where unknown (0) or on another clock."""
    return _seconds(ns, origin) if ns and ns not in other_clock and seconds_since(origin, ns) is not None else None


def _seconds(ns: int, origin: int) -> float:
    return round((ns - origin) / NS_PER_S, 6)


def _json(data: Any) -> str:
    """JSON safe inside a <script> element: no '<', '>' or '&' to end it or open a comment."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _script_text(text: str) -> str:
    """A script's text as a <script> element's content: a '</script' inside it would end it early."""
    return re.sub(r"</(script)", r"<\\/\1", text, flags=re.IGNORECASE)


def _esc(text: str) -> str:
    return html.escape(printable(text), quote=True)
