"""The options and arguments several commands take, each declared once (``bags: options.Bags = None``)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Annotated

import typer

from tftools.cli.common import warn
from tftools.cli.errors import UsageError
from tftools.core.semantics import Semantics
from tftools.sources.errors import BagNotFoundError
from tftools.sources.storage import expand
from tftools.sources.storage.locations import METADATA, is_url


def _bags(bags: list[str] | None) -> list[str] | None:
    """``-b``: each bag once, and a folder of bags refused with the way to give them."""
    for bag in bags or []:
        found = _recordings_in_folder(bag)
        if found:
            raise UsageError(
                f"-b {bag} is a folder of {len(found)} recordings, not a bag",
                f"give one, e.g. -b {found[0]} (-b again for each part of a split recording); "
                f"tfx wtf {bag.rstrip('/')}/ checks each on its own",
            )
    return _each_once(bags) if bags else bags


Bags = Annotated[
    list[str] | None,
    typer.Option(
        "--bag",
        "-b",
        help="A bag: ROS1 .bag, ROS2 .db3/.mcap or bag directory, or a URL (s3://, gs://, az://, http(s)://; "
        "needs tftools\\[fleet]). Repeat for a split recording. Without -b: the live system.",
        callback=_bags,
    ),
]
Topics = Annotated[
    list[str] | None,
    typer.Option("--topic", "-t", help="Topics carrying transforms (default /tf and /tf_static)."),
]
Start = Annotated[
    str | None,
    typer.Option(
        help="Begin at TIME: absolute seconds, +S after the first tf stamp or -S before the last, on the clock of "
        "the frames asked about (a device on the wall clock beside a simulation: its own stamps); without frames, "
        "on the clock of the recording's tf span."
    ),
]
Tf2 = Annotated[
    Semantics | None,
    typer.Option(
        "--tf2",
        help="Answer as ROS 1's or ROS 2's tf2 (default: the recording's own, or the live system's).",
    ),
]
End = Annotated[str | None, typer.Option(help="Stop at TIME (same forms as --start).")]
Ros = Annotated[
    bool | None,
    typer.Option(
        "--ros1/--ros2",
        help="Live: ROS1 (ROS_MASTER_URI) or ROS2 (ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE or "
        "ROS_LOCALHOST_ONLY); default: ROS_VERSION.",
    ),
]
SimTime = Annotated[
    bool | None,
    typer.Option(
        "--use-sim-time/--wall-time",
        help="Live: follow /clock (as during rosbag play --clock) or the wall clock; default: the master's "
        "/use_sim_time (ROS1), the wall clock (ROS2).",
    ),
]
Listen = Annotated[float, typer.Option("--duration", "-d", help="Live: seconds to listen before answering.")]
Paths = Annotated[
    list[str] | None,
    typer.Argument(
        help="Bags, each on its own (a fleet: logs/*.bag), as -b takes them; a URL prefix (s3://bucket/fleet/) "
        "means every recording below it.",
        metavar="BAG",
    ),
]
Target = Annotated[
    str | None,
    typer.Option(
        help="Check sensor data (messages with a header) against tf in this frame (default: odom or map, or "
        "cf0/odom, else the tree's root).",
    ),
]
Force = Annotated[
    bool,
    typer.Option(
        "--force", help="Replace an output file that exists (a regular file only: never an input, a FIFO or a device)."
    ),
]
Sensors = Annotated[
    list[str] | None,
    typer.Option(
        "--sensor",
        help="Check this topic's data against tf (repeat for more; default: a bag's every topic with a Header "
        "but a gamepad's Joy, live none).",
    ),
]


def recordings_given(paths: Sequence[str] | None, bags: Sequence[str] | None) -> list[list[str]]:
    """A fleet command's recordings: each BAG argument on its own (globs, URL prefixes and local folders
    of bags expanded; each recording once), the -b bags together as one more."""
    found = expand([p + "/" if _recordings_in_folder(p) else p for p in paths or []])
    return [[p] for p in _each_once(found)] + ([list(bags)] if bags else [])


def _recordings_in_folder(location: str) -> list[str]:
    """The recordings below a local folder that is not itself a bag (``sample_bags``, with or without
    its final slash); none for anything else."""
    if is_url(location) or not os.path.isdir(location):
        return []
    folder = location.rstrip("/" + os.sep) + "/"
    try:
        found = expand([folder])
    except BagNotFoundError:  # nothing below it: reading it says what it is not
        return []
    return [] if found == [folder] else found


def _each_once(locations: Sequence[str]) -> list[str]:
    """``locations`` without repeats, a note for each: a bag given twice would be read twice, each
    transform seen twice (tf2's repeated data), as if two bags had recorded the same."""
    seen: dict[str, str] = {}
    for location in locations:
        key = _identity(location)
        if key in seen:
            again = "" if seen[key] == location else f" (as {seen[key]})"
            warn(f"{location} is given twice{again}: read once")
            continue
        seen[key] = location
    return list(seen.values())


def _identity(location: str) -> str:
    """What a location is: a URL as written; a local path resolved, a rosbag2 directory's file as the
    directory."""
    if is_url(location):
        return location
    path = os.path.realpath(location)
    folder = os.path.dirname(path)
    return folder if os.path.isfile(path) and os.path.isfile(os.path.join(folder, METADATA)) else path
