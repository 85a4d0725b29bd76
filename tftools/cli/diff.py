"""``tfx diff A B``: where two recordings' tf trees differ (or a recording's and a tree file's)."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from tftools.cli import expected as expected_tree
from tftools.cli import options
from tftools.cli.common import Exit, TextOrJson, exit_with
from tftools.cli.reading import open_recording
from tftools.core.semantics import Semantics
from tftools.sources.storage.locations import METADATA, is_url

if TYPE_CHECKING:
    from tftools.analysis.expected import TreeShape


def command(
    first: Annotated[
        str, typer.Argument(help="A: a recording (.bag, .db3, .mcap, bag directory, or a URL) or a tree file (.yaml).")
    ],
    second: Annotated[str, typer.Argument(help="B: the same, compared with A.")],
    fmt: Annotated[TextOrJson, typer.Option("--format", "-f", help="text, or json (one document).")] = TextOrJson.text,
    tolerance_mm: expected_tree.ToleranceMmOption = None,
    tolerance_deg: expected_tree.ToleranceDegOption = None,
    tolerance_rate: expected_tree.ToleranceRateOption = None,
    topics: options.Topics = None,
    tf2: options.Tf2 = None,
) -> None:
    """Where the tf trees of A and B differ: frames added and lost, re-parented frames, static edges
    (extrinsics) moved, by how much in mm and degrees, rates and publishers changed.

    A or B may be a tree file ([cyan]tfx wtf --init good.bag > tree.yaml[/]); its tolerances count
    unless given here. A or B may be a URDF file (.urdf): its links, fixed joints as static edges at
    their origins ([cyan]tfx diff robot.urdf run.bag[/]). Publishers are compared where both sides name
    them (ROS 1 bags, tree files written from them); rates where A's edge has one.

    Exit codes: 0 no differences beyond the tolerances; 1 differences; 2 unusable input.

    Examples: [cyan]tfx diff monday.bag tuesday.bag[/], [cyan]tfx diff tree.yaml run_db3 --tolerance-mm 2[/],
    [cyan]tfx diff before.mcap after.mcap --format json[/]
    """
    from tftools.analysis.description import described_differences, description_shape
    from tftools.analysis.diff import compare
    from tftools.render import diff as render
    from tftools.sources.urdf import read_urdf

    robots = {location: read_urdf(location) for location in (first, second) if _is_urdf(location)}
    a, b = (
        description_shape(robots[location]) if location in robots else _read(location, topics, tf2)
        for location in (first, second)
    )
    base = a.tolerances if _is_tree_file(first) else b.tolerances  # a recording's are the defaults
    tolerances = expected_tree.tolerances(base, tolerance_mm, tolerance_deg, tolerance_rate)
    differences = compare(a, b, tolerances)
    for location, other in ((first, b), (second, a)):
        if location in robots:  # the frames above a robot (odom, map) are no difference from its URDF
            differences = described_differences(differences, robots[location], other)
    code = Exit.PROBLEMS if differences else Exit.OK
    if fmt is TextOrJson.json:
        render.write_json(a, b, differences, tolerances, int(code), sys.stdout)
    else:
        render.write_text(a, b, differences, tolerances, sys.stdout)
    exit_with(code)


def _is_tree_file(location: str) -> bool:
    """A local YAML file other than a rosbag2 bag's own ``metadata.yaml``."""
    path = Path(location)
    return not is_url(location) and path.suffix in (".yaml", ".yml") and path.name != METADATA


def _is_urdf(location: str) -> bool:
    return not is_url(location) and Path(location).suffix in (".urdf", ".xacro")


def _read(location: str, topics: list[str] | None, semantics: Semantics | None) -> TreeShape:
    from tftools.analysis.expected import shape_of
    from tftools.analysis.tree_file import read_tree

    if _is_tree_file(location):
        return read_tree(Path(location))
    return shape_of(open_recording([location], topics, semantics))
