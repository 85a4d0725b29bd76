"""The frame graph as Graphviz dot source (view_frames' labels, problems in colour) and as PDF/SVG/PNG files."""

from __future__ import annotations

import html
import textwrap
from collections.abc import Sequence
from pathlib import Path
from typing import cast

import graphviz

from tftools.analysis.edges import EdgeStats
from tftools.analysis.findings import Finding, Severity, causes, counted, tallied
from tftools.analysis.graph import FrameGraph, GraphEdge, GraphNode
from tftools.core.figures import age_in_words, apart_in_words, seconds
from tftools.core.time import NS_PER_S, format_sec, span_from_to
from tftools.render.escape import is_printable, printable
from tftools.sources.recording import Recording
from tftools.sources.timeline import NO_RECORD_CLOCK, OTHER_CLOCK, Reference

#: The first line of every dot source tfx writes, to recognise its own files.
SIGNATURE = "tfx view-frames"

#: Problems in the legend wrap at this many characters, and stop after this many lines (tfx wtf says all).
MESSAGE_WIDTH = 110
MESSAGE_LINES = 4
HANGING_INDENT = "&#160;" * 8

#: A name (frame, publisher, file) is cut to this many characters in a label; the tooltip has it whole.
LABEL_CHARS = 100
#: Tooltips are cut to this many characters.
TOOLTIP_CHARS = 2000
#: Starts the Graphviz id of a frame whose name cannot be one as it is; never in a name used as an id.
ID_MARK = "\u2063"

FONT = "Helvetica"
INK = "#333333"
STATIC_INK = "#2b6cb0"
ROOT_FILL = "#dbe7f6"
FRAME_FILL = "#f4f6f9"
COLOURS = {Severity.error: "#d62728", Severity.warning: "#e67e00", Severity.info: "#6b6b6b"}
FILLS = {Severity.error: "#fde2e1", Severity.warning: "#fff0d9", Severity.info: FRAME_FILL}


def recording_legend(recording: Recording) -> list[str]:
    """What the legend says of a recording: its time span, as view_frames' "Recorded at time" (tf's stamps' where
    the record times are no clock: ``Timeline.stamped``), and its files (or the live system it listened to)."""
    timeline = recording.timeline
    if timeline.stamped is not None:
        lines = [f"tf stamped over {span_from_to(*timeline.stamped)} ({NO_RECORD_CLOCK})"]
    else:
        span = (recording.end - recording.start) / NS_PER_S
        start, end = format_sec(recording.start, 3), format_sec(recording.end, 3)
        lines = [f"Recorded at time: {start} to {end} ({span:.3f} s)"]
    if timeline.reference is Reference.CLOCK:
        lines.append(f"Ages on {timeline.clock.topic} (simulated time) at the end: {format_sec(timeline.end, 3)}")
    elif timeline.reference is Reference.NONE:
        # The reason is the clock finding's, listed below: said once.
        newest = format_sec(timeline.tf_end, 3)
        lines.append(f"Ages from the newest tf stamp ({newest}): the recording does not tell ROS time at its end")
    files = recording.contents.files
    bags = [Path(f.path).name for f in files if not f.live]
    lines += [f"Listened to: {f.path}" for f in files if f.live]
    if bags:
        lines.append(f"{'Bag' if len(bags) == 1 else 'Bags'}: {', '.join(bags)}")
    return lines


def to_digraph(
    graph: FrameGraph, legend: Sequence[str] | None, *, rankdir: str = "TB", brief: bool = False
) -> graphviz.Digraph:
    """The graph as a ``graphviz.Digraph``: nodes, labelled edges, a legend listing the problems (none
    for ``legend`` None: where the page around the picture says it, as in ``tfx report``)."""
    dot = graphviz.Digraph("frames", comment=SIGNATURE)
    dot.attr(rankdir=rankdir, fontname=FONT, nodesep="0.3", ranksep="0.45", labelloc="t")
    dot.attr("node", fontname=FONT, fontsize="12", shape="box", style="rounded,filled", color=INK, fontcolor=INK)
    dot.attr("edge", fontname=FONT, fontsize="9", color=INK, fontcolor=INK, arrowsize="0.7")
    if not graph.nodes:
        dot.node("No tf data received", shape="plaintext", style="")
        return dot
    ids = node_ids([node.name for node in graph.nodes])
    for node in graph.nodes:
        _add_node(dot, graph, node, ids)
    for edge in graph.edges:
        _add_edge(dot, graph, edge, brief, ids)
    if legend is not None:
        _add_legend(dot, graph, legend, ids)
    return dot


def node_ids(names: Sequence[str]) -> dict[str, str]:
    """Each frame's Graphviz id: its name when Graphviz reads it back as it is, else a mark and a number
    (control characters, bytes that were not UTF-8, a final backslash, a colon, the mark itself); HTML-looking
    names are quoted as text (``graphviz.nohtml``)."""
    ids: dict[str, str] = {}
    for number, name in enumerate(names):
        safe = is_printable(name) and ID_MARK not in name and (len(name) - len(name.rstrip("\\"))) % 2 == 0
        safe = safe and ":" not in name  # the graphviz package reads a colon in an edge's end as a port
        ids[name] = cast(str, graphviz.nohtml(name)) if safe else f"{ID_MARK}{number}"
    return ids


def _name(text: str) -> str:
    """A name from a file as label text: escaped for HTML labels, control characters visible, cut short."""
    shown = printable(text)
    if len(shown) > LABEL_CHARS:
        shown = f"{shown[: LABEL_CHARS - 1]}\u2026 ({len(text)} characters)"
    return _esc(shown)


def _text_attribute(text: str) -> str:
    """Text for an escString attribute (a tooltip): control characters visible, backslashes and quotes
    escaped, cut short; never read as HTML."""
    shown = printable(text)
    if len(shown) > TOOLTIP_CHARS:
        shown = f"{shown[: TOOLTIP_CHARS - 1]}\u2026"
    return shown.replace("\\", "\\\\").replace('"', '\\"')


def _marked(graph: FrameGraph, problems: Sequence[int]) -> list[int]:
    """The problems drawn on a frame or an edge: errors and warnings. A note is in the legend only: it
    decorates nothing (the Nav2 recording's statics_early note tagged all 29 static edges, greyed)."""
    return [i for i in problems if graph.findings[i].severity is not Severity.info]


def _add_node(dot: graphviz.Digraph, graph: FrameGraph, node: GraphNode, ids: dict[str, str]) -> None:
    marked = _marked(graph, node.problems)
    severity = graph.severity(marked)
    lines = [f"<B>{_name(node.name)}</B>"]
    if node.root:
        lines.append('<FONT POINT-SIZE="9" COLOR="#555555">root</FONT>')
    lines += [_problem_line(graph, i) for i in marked]
    colour = COLOURS[severity] if severity else INK
    fill = FILLS[severity] if severity else ROOT_FILL if node.root else FRAME_FILL
    width = "2.5" if severity or node.root else "1"
    label = f"<{'<BR/>'.join(lines)}>"
    tooltip = _tooltip(graph, node.problems, node.name)
    dot.node(ids[node.name], label, color=colour, fillcolor=fill, penwidth=width, tooltip=tooltip)


def _add_edge(dot: graphviz.Digraph, graph: FrameGraph, edge: GraphEdge, brief: bool, ids: dict[str, str]) -> None:
    marked = _marked(graph, edge.problems)
    severity = graph.severity(marked)
    lines = _brief_lines(edge) if brief else _full_lines(edge, graph)
    lines += [f'<FONT COLOR="{COLOURS[Severity.error]}">rejected: {n} x {code}</FONT>' for code, n in edge.rejected]
    lines += [_problem_line(graph, i) for i in marked]
    label = "".join(f'{line}<BR ALIGN="LEFT"/>' for line in lines)
    style = "dotted" if edge.stats is None else "dashed" if edge.static else "solid"
    colour = COLOURS[severity] if severity else STATIC_INK if edge.static else INK
    width = "2.5" if severity is Severity.error else "2" if severity else "1.2"
    dot.edge(
        ids[edge.parent],
        ids[edge.child],
        f"<{label}>",
        style=style,
        color=colour,
        fontcolor=STATIC_INK if edge.static and not severity else INK,
        penwidth=width,
        tooltip=_tooltip(graph, edge.problems, f"{edge.parent} -> {edge.child}"),
    )


def _full_lines(edge: GraphEdge, graph: FrameGraph) -> list[str]:
    s, age = edge.stats, graph.age_of(edge)
    if s is None or age is None:
        return ["no sample accepted"]
    broadcaster = f"Broadcaster{'s' if len(s.authorities) > 1 else ''}: {_name(', '.join(s.authorities) or '?')}"
    if s.static:
        return [broadcaster, "<B>static</B>" + (f" ({s.count} samples)" if s.count > 1 else "")]
    return [
        broadcaster,
        "Average rate: - (1 sample)" if s.once else f"Average rate: {s.rate_hz:.2f} Hz",
        f"Samples: {s.count}",
        f"Most recent transform: {format_sec(s.last_stamp, 3)} ({age_in_words(age, graph.clock)})",
        *_silence_line(s),
        f"Oldest transform: {format_sec(s.first_stamp, 3)}",
        f"Buffer length: {(s.last_stamp - s.first_stamp) / NS_PER_S:.3f} s"
        if s.clocks == 1
        else f"Buffer length: stamped on {s.clocks} clocks, no span",
        *([] if s.once else [f"Largest gap: {seconds(s.longest_interval):.3f} s"]),
        *([f"Delay: {apart_in_words(s.apart)}"] if s.apart else []),
        *([f"Delay: {OTHER_CLOCK}"] if not s.apart and edge.child in graph.other_clock else []),
    ]


def _silence_line(s: EdgeStats) -> list[str]:
    """Since its last arrival, as monitor's ``silent_s`` (``figures.silence``): not its newest stamp's age, which
    differs by its delay, or a clock's offset."""
    if s.silent_for is None:
        return []
    return [f"Silent for the last {seconds(s.silent_for):.3f} s (since it last arrived)"]


def _brief_lines(edge: GraphEdge) -> list[str]:
    s = edge.stats
    if s is None:
        return []
    if s.static:  # dashed blue says it; 29 labels "/tf_static static" widened the Nav2 TurtleBot 4's tree
        return []
    return [_name(", ".join(s.authorities) or "?"), "once" if s.once else f"{s.rate_hz:.1f} Hz"]


def _problem_line(graph: FrameGraph, index: int) -> str:
    finding = graph.findings[index]
    return f'<FONT COLOR="{COLOURS[finding.severity]}"><B>[{index + 1}] {_esc(finding.code)}</B></FONT>'


def _tooltip(graph: FrameGraph, problems: Sequence[int], default: str) -> str:
    """What an SVG viewer shows on hover: each problem's message and hint."""
    lines = [f"[{i + 1}] {graph.findings[i].message} ({graph.findings[i].hint})" for i in problems]
    text = "\n".join(_text_attribute(line) for line in lines) or _text_attribute(default)
    return cast(str, graphviz.nohtml(text))


def _add_legend(dot: graphviz.Digraph, graph: FrameGraph, legend: Sequence[str], ids: dict[str, str]) -> None:
    static = sum(edge.static for edge in graph.edges)
    rows = [_row(_esc(printable(line))) for line in legend]
    rows.append(_row(f"{graph_summary(graph)} ({static} static), {counted(len(graph.roots), 'tree')}"))
    rows += _problem_rows(graph)
    legend_id = "legend" if not {"legend", "legend_key"} & set(ids) else f"{ID_MARK}legend"
    with dot.subgraph(name="cluster_legend") as box:
        box.attr(label=f"<<B>{SIGNATURE}</B>>", style="rounded", color="#999999", fontsize="12")
        box.node(legend_id, _table(rows), shape="plaintext", style="", fontsize="10")
        box.node(f"{legend_id}_key", _table(_key_rows(graph)), shape="plaintext", style="", fontsize="10")
    for root in graph.roots or [graph.nodes[0].name]:  # as view_frames does: the legend sits above the tree(s)
        dot.edge(legend_id, ids[root], style="invis")


def _table(rows: Sequence[str]) -> str:
    return f'<<TABLE BORDER="0" CELLBORDER="0" CELLSPACING="1" CELLPADDING="1">{"".join(rows)}</TABLE>>'


def _key_rows(graph: FrameGraph) -> list[str]:
    """The colour key: a short line of each kind, and what it means."""
    key = [
        _swatch(INK, "solid", "1", "transform on /tf"),
        _swatch(STATIC_INK, "dashed", "1", "static transform (/tf_static)"),
        _swatch(COLOURS[Severity.error], "solid", "3", "error: lookups fail here"),
        _swatch(COLOURS[Severity.warning], "solid", "2", "warning: tf2 copes, something is off"),
    ]
    if any(edge.stats is None for edge in graph.edges):
        key.append(_swatch(COLOURS[Severity.error], "dotted", "2", "every sample rejected"))
    return key


def _problem_rows(graph: FrameGraph) -> list[str]:
    if not graph.findings:
        return [_row('<FONT COLOR="#2e8b57"><B>No problems found</B></FONT>')]
    rows = [_row(f"<B>Problems: {problem_summary(graph.findings)}</B>")]
    numbers = {f.key: i + 1 for i, f in enumerate(graph.findings) if f.key}
    for index, finding in enumerate(graph.findings):
        colour = COLOURS[finding.severity]
        lines = textwrap.wrap(printable(finding.message), MESSAGE_WIDTH, max_lines=MESSAGE_LINES, placeholder=" ...")
        text = f'<BR ALIGN="LEFT"/>{HANGING_INDENT}'.join(_esc(line) for line in lines)
        follows = f"{HANGING_INDENT}follows from [{numbers[finding.cause]}]: " if finding.cause else ""  # beneath it
        mark = f'<FONT COLOR="{colour}"><B>[{index + 1}] {finding.severity.noun}</B></FONT>'
        rows.append(_row(f"{follows}{mark} {text}"))
    return rows


def graph_summary(graph: FrameGraph) -> str:
    """``"18 frames, 17 transforms"``."""
    return f"{counted(len(graph.nodes), 'frame')}, {counted(len(graph.edges), 'transform')}"


def problem_summary(findings: Sequence[Finding]) -> str:
    """``"2 errors (explaining 21 more), 1 warning"``, or ``"no problems"``: findings that follow from another
    are counted with it."""
    shown = [s for s in Severity if any(f.severity is s for f in causes(findings))]
    return ", ".join(tallied(findings, s, s.noun) for s in shown) or "no problems"


def _row(content: str) -> str:
    return f'<TR><TD ALIGN="LEFT" BALIGN="LEFT">{content}</TD></TR>'


def _swatch(colour: str, style: str, width: str, meaning: str) -> str:
    """A key row: a short line drawn as a cell's bottom border, then what it means."""
    line = (
        f'<TD WIDTH="34" HEIGHT="10" FIXEDSIZE="TRUE" BORDER="{width}" SIDES="B" STYLE="{style}" COLOR="{colour}"></TD>'
    )
    return f'<TR>{line}<TD ALIGN="LEFT">  {meaning}</TD></TR>'


def _esc(text: str) -> str:
    return html.escape(text, quote=True)
