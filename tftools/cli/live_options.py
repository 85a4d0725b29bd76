"""The options of listening to a live system, apart from ``tftools.cli.live`` so that a command
reading a bag declares them without loading what listening needs."""

from __future__ import annotations

from typing import Annotated

import typer

RosOption = Annotated[
    bool | None,
    typer.Option(
        "--ros1/--ros2",
        help="Live: ROS1 (the master at ROS_MASTER_URI) or ROS2 (DDS domain ROS_DOMAIN_ID). "
        "Default: as the environment says (ROS_VERSION, ROS_MASTER_URI, ROS_DOMAIN_ID).",
    ),
]
UseSimTimeOption = Annotated[
    bool | None,
    typer.Option(
        "--use-sim-time/--wall-time",
        help="Live: follow /clock (e.g. during `rosbag play --clock`), or the wall clock. "
        "Default: the master's /use_sim_time parameter (ROS1), the wall clock (ROS2).",
    ),
]
CacheOption = Annotated[float, typer.Option("--cache", help="Live: seconds of history kept per edge, as tf2's buffer.")]
ListenOption = Annotated[float, typer.Option("--duration", "-d", help="Live: seconds to listen before answering.")]
