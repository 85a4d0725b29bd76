"""``tfx monitor`` output: tf_monitor's results as rich tables, or one JSON object."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import IO, Any

from rich.console import Group, RenderableType
from rich.table import Table
from rich.text import Text

from tftools.analysis.edges import AuthorityStats, EdgeStats
from tftools.analysis.listed import Listed
from tftools.analysis.monitor import ChainStats, MonitorReport
from tftools.core.figures import Sightings, apart_in_words, seconds, silence_in_words
from tftools.core.time import NS_PER_S, signed_seconds, to_sec
from tftools.render import jsonl
from tftools.render.escape import printable
from tftools.render.fitted import Fitted, Lines, Row
from tftools.sources.timeline import OTHER_CLOCK


def _sec(ns: float) -> str:
    """A figure (ns) in seconds, "-" where unknown."""
    return "-" if math.isnan(ns) else f"{seconds(ns):.4f}"


#: What jitter is (``core.figures.jitter``), said once where it is shown: under the wide table, in the key of
#: the narrow lines.
JITTER = "Jitter: how irregular an edge's stamps are, the standard deviation of the intervals between them"
#: What the figures are, said once above the lines of a narrow terminal (the table's headers say it wide).
KEY = f"Rate: stamps/s; {JITTER}; Gap: the largest; times in s"
#: The chain's "Net delay" is another figure than its edges' delays, said under it (``ChainStats``).
NET_DELAY = (
    "Net delay: how far the chain's newest common stamp is behind ROS time, at every moment (tf_monitor's): the "
    "time since its oldest edge's last sample counts, not only how late each sample arrived (Average Delay)"
)


def _table(title: str, names: Sequence[str], numbers: Sequence[str], names_after: Sequence[str]) -> Table:
    """A table whose name columns (frames, publishers) are never cut or folded: it is shown only where it
    fits (``fitted.Fitted``)."""
    table = Table(title=title, title_justify="left", title_style="bold", header_style="bold", box=None, padding=(0, 1))
    for name in names:
        table.add_column(name, no_wrap=True)
    for name in numbers:
        table.add_column(name, justify="right", no_wrap=True)
    for name in names_after:
        table.add_column(name, no_wrap=True)
    return table


def _delay_cells(mean: float, largest: float, apart: int, other_clock: bool = False) -> list[Text]:
    """The mean and largest delay; where the stamps are on a clock ahead of the arrivals', or on another clock
    (``other_clock``), why there is none."""
    if said := _unmeasurable(mean, apart, other_clock):
        return [Text(said, style="dim"), Text("-")]
    return [Text(_sec(mean)), Text(_sec(largest))]


#: The figures' headers: tf_monitor's words, but for what each rate counts: an edge's its stamps a second (over
#: their span), a publisher's its messages a second (over their arrivals), as tf_monitor's "Node:" lines count:
#: one publisher of one edge differs by its missed and re-sent stamps (the Pioneer 3-DX's 9.96 against 10.08).
_RATE, _MESSAGE_RATE = "Rate (stamps/s)", "Rate (msgs/s)"
_DELAY_MEAN, _DELAY_MAX = "Average Delay (s)", "Max Delay (s)"


def _edge_cells(e: EdgeStats, other_clock: bool) -> tuple[Text, Text, Text, list[Text]]:
    """An edge's parent, child, publishers and figures (static edges have no rate, jitter, gap or delay;
    ``other_clock``: its stamps are on another clock than its arrivals', no delay)."""
    long_interval = not e.static and e.rate_hz > 0 and seconds(e.longest_interval) > 2.0 / e.rate_hz
    once = e.once
    gap = "-" if _no_gap(e) else _sec(e.longest_interval)
    figures = [
        Text(str(e.count)),
        Text("static", style="cyan") if e.static else Text("-" if once else f"{e.rate_hz:.2f}"),
        Text("" if e.static else "-" if once else _sec(e.jitter)),
        Text("" if e.static else gap, style="yellow" if long_interval else ""),
        *(_delay_cells(e.delay_mean, e.delay_max, e.apart, other_clock) if not e.static else [Text(""), Text("")]),
    ]
    publishers = printable(", ".join(e.authorities)) or "?"
    by = Text(publishers, style="yellow" if len(e.authorities) > 1 else "magenta")
    return Text(printable(e.parent)), Text(printable(e.child), style="bold"), by, figures


def _edges(edges: Sequence[EdgeStats], other_clock: Sequence[str], unnamed: bool = False) -> Fitted:
    """The edges' table; ``unnamed``: their publishers are the topics they came on (``MonitorReport.unnamed``)."""
    numbers = ("Samples", _RATE, "Jitter (s)", "Largest gap (s)", _DELAY_MEAN, _DELAY_MAX)
    table = _table("Frames:", ("Parent", "Frame", "published on" if unnamed else "published by"), numbers, ())
    table.caption, table.caption_justify, table.caption_style = JITTER, "left", "dim"
    rows = []
    for e in edges:
        parent, child, by, figures = _edge_cells(e, e.child in other_clock)
        table.add_row(parent, child, by, *figures)
        publishers = [Text(f"{a}," if k < len(e.authorities) - 1 else a, style=by.style) for k, a in enumerate(
            printable(a) for a in e.authorities)] or [by]  # fmt: skip
        by_word = Text("on" if unnamed else "by", style="dim")
        rows.append(Row(figures, [Text.assemble(parent, " -> ", child), by_word, *publishers]))
    headers = ("Samples", "Rate", "Jitter", "Gap", "Delay", "Max")
    said = "Parent -> Frame on topics" if unnamed else "Parent -> Frame by publishers"
    return Fitted(table, Lines("Frames:", headers, said, rows, KEY))


#: Under the broadcasters of a recording that names no publisher (``MonitorReport.unnamed``): what a row is.
UNNAMED = (
    "The recording names no publisher (a ROS 2 bag records none; nor does a ROS 1 bag without callerids): each "
    "row is a topic's messages, of however many nodes sent on it (tfx wtf tells publishers apart where it can)"
)


def unnamed_caption(listed: Sequence[tuple[str, Listed]]) -> str:
    """``UNNAMED``, with what the recording lists of the topics' publishers: "...; metadata.yaml lists 2
    publishers of /tf_static and 1 publisher of /tf"."""
    if not listed:
        return UNNAMED
    sources = list(dict.fromkeys(n.source for _, n in listed))
    said = [n.said(topic) for topic, n in listed]
    if len(sources) == 1:  # the source once: "metadata.yaml lists 2 publishers of /tf_static and 1 publisher of /tf"
        said = [said[0], *(s.removeprefix(f"{sources[0]} lists ") for s in said[1:])]
    return f"{UNNAMED}; {' and '.join(said)}"


def _authorities(
    authorities: list[AuthorityStats], unnamed: bool = False, listed: Sequence[tuple[str, Listed]] = ()
) -> Fitted:
    """The publishers' table; ``unnamed``: they are the topics the transforms came on, said so with what the
    recording lists of their publishers (``listed``)."""
    numbers = ("Messages", _MESSAGE_RATE, _DELAY_MEAN, _DELAY_MAX)
    who = "Topic" if unnamed else "Node"
    table = _table("All Broadcasters:", (who,), numbers, ("Frames",))
    caption = unnamed_caption(listed) if unnamed else ""
    if unnamed:
        table.caption, table.caption_justify, table.caption_style = caption, "left", "dim"
    rows = []
    for a in authorities:
        node = Text(printable(a.authority) or "?", style="magenta")
        figures = [
            Text(str(a.messages)),
            Text("static", style="cyan") if a.static else Text("-" if a.once else f"{a.rate_hz:.2f}"),
            *_delay_cells(a.delay_mean, a.delay_max, a.apart),
        ]
        children = list(dict.fromkeys(printable(child) for _, child in a.edges))  # a frame under two parents: once
        table.add_row(node, *figures, Text(", ".join(children), style="dim"))
        frames = [Text(f"{c}," if k < len(children) - 1 else c, style="dim") for k, c in enumerate(children)]
        rows.append(Row(figures, [Text.assemble(node, ":"), *frames]))
    headers = ("Messages", "Msgs/s", "Delay", "Max")
    return Fitted(table, Lines("All Broadcasters:", headers, f"{who}: frames", rows, caption))


def _chain_lines(chain: ChainStats, other_clock: Sequence[str]) -> Text:
    text = Text(f"RESULTS: for {printable(chain.target)} to {printable(chain.source)}\n", style="bold")
    text.append(f"Chain is: {printable(' -> '.join(chain.frames))}\n")
    text.append(f"Net delay     avg = {_sec(chain.delay_mean)}: max = {_sec(chain.delay_max)}")
    if chain.limiting is not None:
        text.append(
            f"  (held back most by {printable(chain.limiting[0])} -> {printable(chain.limiting[1])})", style="dim"
        )
    elif all(e.static for e in chain.edges):
        text.append("  (every edge is static: never stale)", style="dim")
    elif math.isnan(chain.delay_mean) and any(e.child in other_clock for e in chain.edges):
        text.append(f"  ({OTHER_CLOCK})", style="dim")
    if not math.isnan(chain.delay_mean):
        text.append(f"\n{NET_DELAY}", style="dim")
    return text


def live_header(now: int, origin: int | None, window: int, note: str = "") -> str:
    """A refreshing table's first line: the clock ``now``, seconds since ``origin`` (``LiveMonitor.origin``: a
    replay's first tf stamp, a live system's first transform's arrival; none yet: 0), the ``window`` it covers
    (ns), and ``note``."""
    since = signed_seconds((now - (origin if origin is not None else now)) / NS_PER_S)
    header = f"time {to_sec(now):.3f} ({since} s), last {window / NS_PER_S:g} s"
    return header + (f", {note}" if note else "")


def own_clock_stamps(report: MonitorReport) -> str:
    """A replayed table's line for a chain stamped on another clock than the replay's (``MonitorReport.other_clock``):
    the newest of its stamps in the window, on its own clock ("" for any other chain)."""
    chain = report.chain
    moving = [e for e in chain.edges if not e.static] if chain is not None else []
    if chain is None or not moving or not all(e.child in report.other_clock for e in moving):
        return ""
    newest = max(e.last_stamp for e in moving)
    return f"{chain.target} to {chain.source} stamped up to {to_sec(newest):.3f}, on a clock of its own"


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
    if report.other_clock_why:
        parts.append(Text(printable(f"delays: {report.other_clock_why}"), style="dim"))
    if report.chain is not None:
        parts.append(_chain_lines(report.chain, report.other_clock))
        edges: Sequence[EdgeStats] = report.chain.edges
    elif target is not None and source is not None:
        waiting = printable(f"Waiting for transform chain to become available between {target} and {source}")
        parts.append(Text(waiting, style="bold"))
        edges = report.edges
    else:
        parts.append(Text("RESULTS: for all Frames", style="bold"))
        edges = report.edges
    parts += [
        Text(""),
        _edges(edges, report.other_clock, report.unnamed),
        *_damaged_gaps(edges, report.damaged_gaps),
        *_silences(edges),
        *_sightings(edges),
        Text(""),
        _authorities(report.authorities, report.unnamed, report.listed),
        *_partly_timed(report.authorities),
        *_beyond_edges(report.authorities),
    ]
    return Group(*parts)


def _partly_timed(authorities: Sequence[AuthorityStats]) -> list[Text]:
    """A line for each publisher whose delay is over some of its edges only (``AuthorityStats.delay_of``): which."""
    return [
        Text(
            printable(
                f"{a.authority}: delay of {', '.join(a.delay_of)} alone; not measurable for {', '.join(a.no_delay_of)}"
            ),
            style="dim",
        )
        for a in authorities
        if a.delay_of
    ]


def beyond_edges(a: AuthorityStats) -> str:
    """What a publisher's delay is over where some of it is no frame's delay (``AuthorityStats.delays_beyond_edges``),
    so that its figure and its frames' cannot seem to contradict each other unsaid; "" where all of it is."""
    if not a.delays_beyond_edges:
        return ""
    return (
        f"{a.authority}: its delays are over the {a.delays_counted} transforms it sent on /tf (tf_monitor's Node "
        f"line), {a.delays_beyond_edges} of them in no frame's (re-sent stamps tf2 did not store again, transforms "
        "it refused, those of a frame it holds static); a frame's delays are over the samples tf2 stored"
    )


def _beyond_edges(authorities: Sequence[AuthorityStats]) -> list[Text]:
    """A line for each publisher whose delay is over more than its frames' (``beyond_edges``)."""
    return [Text(printable(said), style="dim") for a in authorities if (said := beyond_edges(a))]


def _damaged_gaps(edges: Sequence[EdgeStats], damaged: Sequence[tuple[str, str]]) -> list[Text]:
    """A line for each edge whose largest gap spans a damaged part of the file (``MonitorReport.damaged_gaps``):
    the file lost its transforms there; the gap is not its publisher's."""
    return [
        Text(
            printable(
                f"{e.parent} -> {e.child}: its largest gap ({_sec(e.longest_interval)} s from "
                f"{to_sec(e.longest_interval_start):.3f}) spans a damaged part of the file: transforms lost there, "
                "not a pause of its publisher"
            ),
            style="yellow",
        )
        for e in edges
        if e.key in damaged
    ]


def _silences(edges: Sequence[EdgeStats]) -> list[Text]:
    """A line for each edge silent since its last sample (``figures.silence_in_words``): said apart from its
    gaps, which lie between two samples."""
    said = [(e, silence_in_words(e.silent_for, e.rate_hz)) for e in edges if not e.static]
    return [Text(printable(f"{e.parent} -> {e.child}: {words}"), style="yellow") for e, words in said if words]


def _no_gap(e: EdgeStats) -> bool:
    """One sample and none before the window: no gap to show ("-", null)."""
    return e.once and not e.longest_interval


def _no_rhythm(e: EdgeStats) -> bool:
    """A static edge, or one sample: no rate, jitter, gap or silence (null in JSON, where 0.0 would say "a rate
    of zero" or "just arrived"; "static" and "-" in the table)."""
    return e.static or e.once


def _sightings(edges: Sequence[EdgeStats]) -> list[Text]:
    """A line for each detection seen in bursts (``figures.sightings``): its rate within them and the share of the
    window it was seen, which its rate over the window (the table's) does not tell."""
    return [
        Text(printable(f"{e.parent} -> {e.child}: a detection, {e.sightings.in_words()}"), style="dim")
        for e in edges
        if e.sightings is not None
    ]


def sightings_dict(seen: Sightings | None) -> dict[str, Any] | None:
    """A detection's bursts of sightings as JSON (``figures.sightings``; null for any other edge)."""
    if seen is None:
        return None
    return {
        "bursts": seen.bursts,
        "rate_hz": seen.rate_hz,
        "seen_share": seen.seen,
        "longest_unseen_s": seconds(seen.longest_unseen),
        "longest_unseen_start": to_sec(seen.longest_unseen_start),
    }


def _edge_dict(e: EdgeStats, other_clock: Sequence[str], damaged: Sequence[tuple[str, str]] = ()) -> dict[str, Any]:
    return {
        "parent": e.parent,
        "child": e.child,
        "authorities": list(e.authorities),
        "count": e.count,
        "rate_hz": None if _no_rhythm(e) else e.rate_hz,
        "jitter_s": None if _no_rhythm(e) else seconds(e.jitter),
        "gap_max_s": None if e.static or _no_gap(e) else seconds(e.longest_interval),
        "gap_start": None if e.static or _no_gap(e) else to_sec(e.longest_interval_start),
        "gap_in_damage": e.key in damaged,  # the largest gap spans a damaged part of the file
        "silent_s": None if e.static or e.silent_for is None else seconds(e.silent_for),
        "delay_mean_s": seconds(e.delay_mean),
        "delay_max_s": seconds(e.delay_max),
        "delay_unmeasurable": _unmeasurable(e.delay_mean, e.apart, e.child in other_clock),
        "static": e.static,
        "sightings": sightings_dict(e.sightings),
        "first_stamp": to_sec(e.first_stamp),
        "last_stamp": to_sec(e.last_stamp),
    }


def _authority_dict(a: AuthorityStats) -> dict[str, Any]:
    return {
        "authority": a.authority,
        "messages": a.messages,
        # only /tf_static messages ("static" in the table), or one-shot frames ("-"): no rhythm
        "rate_hz": None if a.static or a.once else a.rate_hz,
        "delay_mean_s": seconds(a.delay_mean),
        "delay_max_s": seconds(a.delay_max),
        "delay_unmeasurable": _unmeasurable(a.delay_mean, a.apart),
        "delay_of": list(a.delay_of) or None,  # the frames its delay is over, where it is over some only
        "no_delay_of": list(a.no_delay_of) or None,
        # the transforms its delay is over, and those of them in no frame's delay (``beyond_edges``)
        "delays_counted": a.delays_counted,
        "delays_beyond_edges": a.delays_beyond_edges,
        "edges": [list(edge) for edge in a.edges],
    }


def _unmeasurable(mean: float, apart: int, other_clock: bool = False) -> str | None:
    """Why a delay is null where its stamps are on a clock ahead of the arrivals' (``apart_in_words``), or on
    another clock (``other_clock``: ``Timeline.other_clock_delays`` says which and why, once)."""
    if not math.isnan(mean):
        return None
    return apart_in_words(apart) if apart else OTHER_CLOCK if other_clock else None


def as_dict(report: MonitorReport) -> dict[str, Any]:
    """The JSON object: window, ``edges``, ``authorities`` and, with two frames, ``chain``."""
    result: dict[str, Any] = {
        "window": {
            "start": to_sec(report.start) if report.start is not None else None,
            "end": to_sec(report.end) if report.end is not None else None,
        },
        "edges": [_edge_dict(e, report.other_clock, report.damaged_gaps) for e in report.edges],
        "authorities": [_authority_dict(a) for a in report.authorities],
        "publishers_named": not report.unnamed,  # false: each authority is the topic its transforms came on
        # where none is named: how many publishers of each of those topics the recording's files list, and which
        "publishers_listed": {topic: {"publishers": n.publishers, "in": n.source} for topic, n in report.listed},
        "delays_unavailable": report.delays_unavailable or None,  # why delays are null, where they all are
        "delays_other_clock": report.other_clock_why or None,  # why those of frames on another clock are null
    }
    if report.chain is not None:
        chain = report.chain
        result["chain"] = {
            "target": chain.target,
            "source": chain.source,
            "frames": list(chain.frames),
            "edges": [_edge_dict(e, report.other_clock, report.damaged_gaps) for e in chain.edges],
            # not its edges' delay_mean_s: how far its newest common stamp is behind, over time (``NET_DELAY``)
            "net_delay_mean_s": seconds(chain.delay_mean),
            "net_delay_max_s": seconds(chain.delay_max),
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
