"""``tfx diff A B``: where two recordings' tf trees differ (or a recording's and a tree file's)."""

from __future__ import annotations

import sys
from typing import Annotated

import typer

from tftools.cli import expected as expected_tree
from tftools.cli import options
from tftools.cli.common import Exit, TextOrJson, exit_with
from tftools.cli.reading import open_recording


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
    (extrinsics) moved, by how much in mm and degrees, or received with the same values in another order
    (reordered: tf2 keeps the last received), edges static in one and moving in the other, rates changed,
    edges stamped on more clocks in one, and each edge's publishers changed.

    A or B may be a tree file ([cyan]tfx wtf --init good.bag > tree.yaml[/]); its tolerances count
    unless given here. A or B may be a URDF file (.urdf): its links, fixed joints as static edges at
    their origins ([cyan]tfx diff robot.urdf run.bag[/]). Publishers are compared where both sides name
    them (ROS 1 bags, tree files written from them); rates where A's edge has one. A recording holding no
    transforms is an empty tree (it says so): it differs from a tree by every frame of that tree.

    Exit codes: 0 no differences beyond the tolerances; 1 differences; 2 unusable input.

    Examples: [cyan]tfx diff monday.bag tuesday.bag[/], [cyan]tfx diff tree.yaml run_db3 --tolerance-mm 2[/],
    [cyan]tfx diff before.mcap after.mcap --format json[/]
    """
    from tftools.analysis.diff import DiffQuery, diff_trees
    from tftools.analysis.expected import Tolerances
    from tftools.render import diff as render

    expected_tree.tolerances(Tolerances(), tolerance_mm, tolerance_deg, tolerance_rate)  # refused before reading
    query = DiffQuery(translation_mm=tolerance_mm, rotation_deg=tolerance_deg, rate_percent=tolerance_rate)
    found = diff_trees(first, second, query, read=lambda paths: open_recording(paths, topics, tf2))
    code = Exit.PROBLEMS if found.differences else Exit.OK
    if fmt is TextOrJson.json:
        render.write_json(
            found.a, found.b, found.differences, found.tolerances, int(code), sys.stdout, found.notes, found.damaged
        )
    else:
        render.write_text(found.a, found.b, found.differences, found.tolerances, sys.stdout, found.notes, found.damaged)
    exit_with(code)
