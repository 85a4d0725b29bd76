"""``tfx frames`` output: a rich tree, JSON, or YAML in tf2's ``allFramesAsYAML`` layout."""

from __future__ import annotations

from itertools import pairwise
from typing import IO, Any

from rich.console import Console
from rich.text import Text

from tftools.analysis.frames import FrameSummary, FrameTree, ParentEdge
from tftools.core.time import NS_PER_S, to_sec
from tftools.render import jsonl
from tftools.render.escape import printable, printable_lines


def _label(f: FrameSummary) -> Text:
    label = Text(printable(f.frame), style="bold")
    if f.parent is None:
        return label.append("  (root)", style="dim")
    label.append("  ")
    once = not f.static and f.count == 1  # one sample has no rate (a detection seen once)
    rate = "static" if f.static else "once" if once else f"{f.rate_hz:.1f} Hz"
    label.append(rate, style="cyan" if f.static else "green")
    label.append(
        f"  {printable(', '.join(f.authorities)) or '?'}", style="yellow" if len(f.authorities) > 1 else "magenta"
    )
    if once:
        label.append(f"  1 sample, stamped {to_sec(f.first_stamp):.3f}", style="dim")
    elif not f.static:
        span = (f.last_stamp - f.first_stamp) / NS_PER_S
        lasted = f"{span:.1f} s" if f.clocks == 1 else f"stamped on {f.clocks} clocks: no span"
        label.append(
            f"  {f.count} samples, {to_sec(f.first_stamp):.3f} → {to_sec(f.last_stamp):.3f} ({lasted})", style="dim"
        )
    if f.edges:  # each parent's samples, as tfx monitor's row of its edge counts them
        label.append(f"  {printable(_parents(f.edges))}", style="bold red")
    if len(f.authorities) > 1:
        label.append("  several publishers", style="bold yellow")
    return label


def _parents(edges: tuple[ParentEdge, ...]) -> str:
    """A re-parented frame's parents: one after another (an object picked up), or in turn where their spans overlap
    (two sources of one frame: aerostack2's Crazyflie's base_link under cf0 and cf0/odom at each stamp), each with
    its samples and then its own rate (the frame's counts both)."""
    moving = [e for e in edges if e.rate_hz > 0]
    overlap = any(a.first_stamp <= b.last_stamp and b.first_stamp <= a.last_stamp for a, b in pairwise(moving))
    if not overlap:
        return "parents over time (samples): " + " → ".join(f"{e.parent} ({e.count})" for e in edges)
    parts = [f"{e.parent} ({e.count}" + (f", {e.rate_hz:.1f} Hz)" if e.rate_hz > 0 else ")") for e in edges]
    return "parents in turn (samples): " + " ⇄ ".join(parts)


#: Deeper frames are drawn at this indent, with their depth written out: a 100,000-frame chain
#: prints in linear time, not as lines 400,000 characters wide.
MAX_DRAWN_DEPTH = 32
#: Larger trees are written as plain text, without colours.
MAX_STYLED_LINES = 2000


def write_tree(tree: FrameTree, console: Console) -> None:
    """The frames as a tree from each root (``FrameTree.walk``); frames in a loop are listed apart."""
    shown: set[str] = set()
    lasts: list[bool] = []  # of the frame at each depth down to this one: whether it is the last sibling
    lines: list[Text] = []
    for depth, frame, last in tree.walk():
        shown.add(frame)
        lasts[depth:] = [last]
        guides = "".join("    " if done else "│   " for done in lasts[1 : min(depth, MAX_DRAWN_DEPTH + 1)])
        line = Text(guides + ("" if depth == 0 else "└── " if last else "├── "))
        if depth > MAX_DRAWN_DEPTH:
            line.append(f"[depth {depth}] ", style="dim")
        lines.append(line.append_text(_label(tree.frames[frame])))
    if len(lines) <= MAX_STYLED_LINES:
        for line in lines:
            console.print(line)
    else:  # rich takes 0.3 ms a line: a minute for 100,000 frames
        console.file.write("".join(f"{line.plain}\n" for line in lines))
    loose = [name for name in tree.frames if name not in shown]
    if loose:
        console.print(Text(f"In a loop (no root): {printable(', '.join(sorted(loose)))}", style="bold red"))


def _as_dict(f: FrameSummary) -> dict[str, Any]:
    return {
        "frame": f.frame,
        "parent": f.parent,
        "static": f.static,
        "authorities": list(f.authorities),
        "count": f.count,
        "rate_hz": _rate(f.static, f.count, f.rate_hz),
        "clocks": f.clocks,
        "first_stamp": to_sec(f.first_stamp) if f.count else None,
        "last_stamp": to_sec(f.last_stamp) if f.count else None,
        "parents": list(f.parents),
        **({"edges": [_edge_dict(e, f.static) for e in f.edges]} if f.edges else {}),
    }


def _rate(static: bool, count: int, rate_hz: float) -> float | None:
    """A rate, null where there is none, as in monitor's JSON: a static edge, one sample, a root (no samples)."""
    return None if static or count < 2 else rate_hz


def _edge_dict(e: ParentEdge, static: bool) -> dict[str, Any]:
    return {
        "parent": e.parent,
        "authorities": list(e.authorities),
        "count": e.count,
        "rate_hz": _rate(static, e.count, e.rate_hz),
        "first_stamp": to_sec(e.first_stamp),
        "last_stamp": to_sec(e.last_stamp),
    }


def write_json(tree: FrameTree, out: IO[str]) -> None:
    jsonl.write_document({"roots": tree.roots, "frames": [_as_dict(f) for f in tree.frames.values()]}, out)


def write_yaml(yaml_text: str, out: IO[str]) -> None:
    """tf2's ``allFramesAsYAML``, exactly as ``tf2_ros`` prints it, but for control characters in names
    (shown escaped, as ``printable`` does; a newline in a name still ends its line)."""
    out.write(printable_lines(yaml_text))
