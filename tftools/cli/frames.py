"""``tfx frames``: the frame tree in the terminal, or as JSON/YAML for scripts."""

from __future__ import annotations

import enum
from typing import Annotated

import typer

from tftools.cli import options
from tftools.cli.common import stdout
from tftools.cli.reading import open_recording


class FramesFormat(str, enum.Enum):
    text = "text"
    json = "json"
    yaml = "yaml"


def command(
    bags: options.Bags = None,
    fmt: Annotated[
        FramesFormat,
        typer.Option(
            "--format",
            "-f",
            help="text (a tree), json, or yaml (exactly tf2's allFramesAsYAML, whose rate is tf2's: samples over "
            "the span, where tfx counts intervals, samples - 1).",
        ),
    ] = FramesFormat.text,
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
    duration: options.Listen = 5.0,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
) -> None:
    """Show every frame as a tree: its parent, publishers, rate, samples and time span.

    Static frames are marked; a frame with several parents or publishers is flagged.

    Without -b, listens --duration seconds to the live system first, as view_frames does.

    Example: [cyan]tfx frames -b robot.bag --format yaml[/]
    """
    from tftools.analysis.frames import frame_tree
    from tftools.render import frames as render

    recording = open_recording(bags, topics, tf2, ros1, use_sim_time, duration)
    tree = frame_tree(recording)
    if fmt is FramesFormat.json:
        render.write_json(tree, stdout.file)
    elif fmt is FramesFormat.yaml:
        render.write_yaml(recording.buffer.all_frames_as_yaml(), stdout.file)
    else:
        render.write_tree(tree, stdout)
