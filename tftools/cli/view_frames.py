"""``tfx view-frames``: the frame graph as a PDF (SVG, PNG, dot) that shows its problems, like view_frames."""

from __future__ import annotations

import enum
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated

import typer

from tftools.cli import options
from tftools.cli.common import Exit, exit_with, say_failure, say_written
from tftools.cli.errors import UsageError
from tftools.cli.outputs import check_output, check_replaceable
from tftools.cli.reading import open_recording


class GraphFormat(str, enum.Enum):
    pdf = "pdf"
    svg = "svg"
    png = "png"
    dot = "dot"


class RankDir(str, enum.Enum):
    TB = "TB"
    LR = "LR"
    BT = "BT"
    RL = "RL"


#: The format each output suffix names; the first of a format is its own (``frames.gv`` for dot).
SUFFIXES = {
    ".pdf": GraphFormat.pdf,
    ".svg": GraphFormat.svg,
    ".png": GraphFormat.png,
    ".gv": GraphFormat.dot,
    ".dot": GraphFormat.dot,
}


def command(
    bags: options.Bags = None,
    output: Annotated[
        str | None,
        typer.Option(
            "--output",
            "-o",
            help="Where to write (never over, into or above the input); - for stdout "
            "(default frames.pdf, or frames.FORMAT; a NAME without suffix: NAME.pdf, as ROS 2's view_frames -o).",
        ),
    ] = None,
    fmt: Annotated[
        GraphFormat | None,
        typer.Option(
            "--format",
            "-f",
            help="pdf, svg, png, or dot (the Graphviz source); default: from -o's suffix, else pdf.",
        ),
    ] = None,
    rankdir: Annotated[
        RankDir,
        typer.Option(help="Tree direction: TB top-down, LR left-right (wide trees), BT, RL.", case_sensitive=False),
    ] = RankDir.TB,
    brief: Annotated[bool, typer.Option("--brief", help="Short edge labels: publisher and rate only.")] = False,
    force: options.Force = False,
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    duration: options.Listen = 5.0,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
) -> None:
    """Draw the tf tree, view_frames style: each edge with its broadcaster, average rate, samples,
    most recent and oldest transform and largest gap; static edges dashed and blue.

    Problems (those `tfx wtf` finds) are drawn where they are, red (errors) or orange
    (warnings), and listed in the legend: several trees, a frame with several parents or
    publishers, a loop, an edge that went stale or silent, rejected samples, ... The legend gives
    the bag's time span and file names.

    Without -b, listens --duration seconds to the live system first, as view_frames does.

    Writes frames.pdf in the current directory unless told otherwise (-o). Drawing needs
    Graphviz's `dot` program; without it the Graphviz source is written beside the output
    (frames.gv) with one line saying how to install Graphviz, and the exit code is 1.

    Exit codes: 0 drawn, no errors; 1 drawn with errors shown (or dot missing); 2 unusable input.

    Examples: [cyan]tfx view-frames -b robot.bag[/],
    [cyan]tfx view-frames -b robot.bag -o tree.svg --rankdir LR --brief[/]
    """
    from tftools.analysis.findings import Severity
    from tftools.analysis.graph import view_frames
    from tftools.render import drawing
    from tftools.render import graph as render
    from tftools.sources.bag.robot import ROBOT_TOPICS

    _no_wait_time(topics or [])
    chosen, target = _output(output, fmt, bags or [], force)
    # read as tfx wtf reads a bag (its sensor data's headers, the robot's description): the same checks and count
    headers = () if bags else None  # live, as tfx wtf: no sensor topic unless named
    recording = open_recording(bags, topics, tf2, ros1, use_sim_time, duration, headers, ROBOT_TOPICS)
    graph = view_frames(recording)
    dot = render.to_digraph(graph, render.recording_legend(recording), rankdir=rankdir.value, brief=brief)
    try:
        if target == "-":
            sys.stdout.buffer.write(drawing.draw(dot, chosen.value))
            sys.stdout.flush()
        else:
            drawing.write_graph(dot, target, chosen.value)
    except drawing.GraphNotDrawnError as missing:
        say_failure(missing)
        exit_with(Exit.PROBLEMS)
    where = "the graph to stdout" if target == "-" else target
    say_written(where, f"{render.graph_summary(graph)}, {render.problem_summary(graph.findings)}")
    if any(f.severity is Severity.error for f in graph.findings):
        exit_with(Exit.PROBLEMS)


def _output(output: str | None, fmt: GraphFormat | None, bags: Sequence[str], force: bool) -> tuple[GraphFormat, str]:
    """The format and the path: from -o's suffix, --format, or view_frames' default frames.pdf;
    never an input, inside one or above one (``outputs.check_output``), nor a file named with -o already
    there without ``force`` (``outputs.check_replaceable``). The default frames.pdf is replaced as ROS's
    view_frames replaces it (running the command again redraws it), but never a FIFO, a device or a folder."""
    if output == "-":
        return fmt or GraphFormat.pdf, output
    if output is None:
        chosen = fmt or GraphFormat.pdf
        default = f"frames{_suffix(chosen)}"
        check_output(Path(default), bags, option="the default output")
        check_replaceable(Path(default), True, "the default output")
        return chosen, default
    if _bare(output):  # ROS 2's view_frames -o NAME writes NAME.pdf (and NAME.gv)
        output += _suffix(fmt or GraphFormat.pdf)
    implied = SUFFIXES.get(Path(output).suffix.lower())
    if fmt is not None and implied is not None and implied is not fmt:
        raise UsageError(
            f"--format {fmt.value} does not match the output name {output}",
            f"name it {Path(output).with_suffix(_suffix(fmt))}",
        )
    check_output(Path(output), bags, file_name="frames.pdf")
    check_replaceable(Path(output), force)
    return fmt or implied or GraphFormat.pdf, output


def _bare(output: str) -> bool:
    """Whether ``output`` names a file to be made without a suffix (not a folder, nor a device or file there)."""
    path = Path(output)
    return not path.suffix and path.name not in ("", ".", "..") and not output.endswith("/") and not path.exists()


def _suffix(fmt: GraphFormat) -> str:
    return next(suffix for suffix, named in SUFFIXES.items() if named is fmt)


def _no_wait_time(topics: Sequence[str]) -> None:
    """``tfx view-frames -t 10``: ROS 2's view_frames' ``-t`` is its listening time (``--wait-time``), tfx's a
    topic; a ROS name never starts with a digit, so a number there is the listening time."""
    for topic in topics:
        try:
            seconds = float(topic)
        except ValueError:
            continue
        raise UsageError(
            f"-t {topic}: tfx view-frames' -t names a topic of transforms, and {topic} is no topic name",
            f"to listen {seconds:g} s first, as ROS 2's view_frames -t {topic} does: tfx view-frames --duration "
            f"{topic}",
        )
