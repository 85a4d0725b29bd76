"""``tfx filter``: would a tf2 MessageFilter have dropped my sensor data, and why."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import options
from tftools.cli.arguments import positive_seconds
from tftools.cli.common import Exit, TextOrJson, exit_with, stdout, warn
from tftools.cli.errors import UsageError, no_transforms
from tftools.core.time import from_sec

if TYPE_CHECKING:
    from tftools.sources.errors import NoStampedDataError


def command(
    topics: Annotated[
        list[str] | None,
        typer.Argument(
            help="Topics to check (default: every topic whose messages start with a Header, but a gamepad's Joy)."
        ),
    ] = None,
    bags: options.Bags = None,
    target: Annotated[
        str | None,
        typer.Option(
            help="The frame the data is transformed into (default: odom or map, or cf0/odom, else the tree's root).",
        ),
    ] = None,
    cache: Annotated[float, typer.Option(help="The listener's cache length, seconds (tf2's default 10).")] = 10.0,
    wait: Annotated[float | None, typer.Option(help="A filter timeout, seconds: count what it would drop.")] = None,
    queue: Annotated[int | None, typer.Option(min=1, help="A filter queue size: count what it would drop.")] = None,
    fmt: Annotated[TextOrJson, typer.Option("--format", "-f", help="text (a table) or json.")] = TextOrJson.text,
    tf2: options.Tf2 = None,
    duration: options.Listen = 5.0,
    ros1: options.Ros = None,
    use_sim_time: options.SimTime = None,
) -> None:
    """Replay a tf2_ros MessageFilter on every stamped message of a recording.

    For each message, tf2's rule with only the tf that had arrived: transformable into --target
    at header.stamp when it arrived; else dropped at once if already older than the cache; else
    passed after a wait, or never, and why: unknown frame, not connected to the target, tf that
    stopped before its stamp, or older than the cache by the time tf reached it (undecided where
    the recording cannot tell). Per topic: how many went through on arrival, later (wait
    p50/p99/max), never, or undecided; the edge they waited for; the smallest timeout, queue and
    cache that keep 99.9% of them.

    Without -b, listens --duration seconds to the live system: to tf, and to the topics (default:
    every advertised topic whose messages start with a Header), each message's arrival time
    and header; then reports as on a bag.

    Exit codes: 0 every message transformable (at once or after a wait), or no sensor data to check
    (a recording of tf alone: said so, with the topics there are); 1 some never were, or a given
    --wait/--queue drops some; 2 unusable input, or a topic named that holds no stamped message.

    Examples: [cyan]tfx filter -b robot.bag --target odom[/], [cyan]tfx filter /scan -b run.mcap --queue 5 -f json[/],
    [cyan]tfx filter /scan --ros1 -d 10 --target odom[/] (live)
    """
    cache = positive_seconds(cache, "--cache", "10 (tf2's default)")
    if wait is not None and wait != 0:  # a timeout of 0: only what is transformable on arrival goes through
        wait = positive_seconds(wait, "--wait", "0.2")
    from tftools.analysis.filter import FilterQuery, filter_messages
    from tftools.cli.common import frame_arguments
    from tftools.cli.reading import open_recording
    from tftools.render import filter as render
    from tftools.sources.errors import NoStampedDataError, NoTransformsError

    timeout = from_sec(wait) if wait is not None else None
    query = FilterQuery(
        sensor_topics=tuple(topics) if topics else None, cache_time=from_sec(cache), wait=timeout, queue=queue
    )
    try:
        recording = open_recording(bags, None, tf2, ros1, use_sim_time, duration, headers=query.reading().headers)
    except NoTransformsError as error:  # its topics are /tf and /tf_static: no --topic to suggest
        raise no_transforms(error, chosen=False) from None
    read = ", ".join(bags) if bags else recording.paths[0]
    if target is not None:
        (named,) = frame_arguments(recording.buffer.frames, [target], recording.buffer.semantics)
        query = replace(query, target=named)
    try:
        report = filter_messages(recording, query, on_problem=warn)
    except NoStampedDataError as error:
        raise UsageError(str(error), _named_hint(error, bool(bags))) from None
    if fmt is TextOrJson.json:
        render.write_json(report, stdout.file)
    else:
        stdout.print(render.renderable(report, read))
    exit_with(Exit.PROBLEMS if report.lost else Exit.OK)


def _named_hint(error: NoStampedDataError, bags: bool) -> str:
    """What to do where the topics named hold no message to check: not an example naming another topic (``tfx
    filter /scan`` answered 'e.g. tfx filter /scan -b BAG', the command just run), but the command without them."""
    if error.unrecorded:  # the recorder, not the names, is what to look at
        return error.hint
    names = "name topics of sensor data (a Header with a frame_id), or none"
    if bags:
        return f"{names}: tfx filter -b BAG checks every such topic"
    return f"{names}: tfx filter checks every such topic advertised; or listen longer with --duration"
