"""Several broadcasters of one edge where the recording does not name publishers (ROS 2 bags, MCAP):
inferred from the edge's own stream, its stamps going back and forth or its values alternating
between two places, sample after sample."""

from __future__ import annotations

import numpy as np

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.scene import Scene, edge, listed
from tftools.core.arrays import FloatArray, Int64Array
from tftools.core.rotation import angle_between_many

#: A sign must show in this many samples, and this share of them, to tell two broadcasters.
TURNS_MIN = 5
TURNS_SHARE = 0.1
#: Two values this far apart (m, degrees) are two places; coming back within a quarter of it, the same one.
APART_M = 0.01
APART_DEG = 1.0


def inferred_broadcasters(scene: Scene) -> list[Finding]:
    """One ``multiple_authorities`` finding per moving edge that looks like several broadcasters
    taking turns, where the recording names no publishers (none elsewhere); computed once per scene."""
    return scene.shared("inferred_broadcasters", lambda: list(_infer(scene)))


def _infer(scene: Scene) -> list[Finding]:
    if scene.publishers_known:
        return []
    rows = scene.rows
    found = []
    for parent, child, mine in rows.by_edge(rows.usable & ~rows.static):
        stamps, values = rows.stamp[mine], rows.values[mine]
        back = _back_and_forth(stamps)
        alternating = _alternating(values)
        signs = [
            f"its stamps went back {back} times" if _enough(back, len(mine)) else "",
            f"its value alternated between two places {alternating} times" if _enough(alternating, len(mine)) else "",
        ]
        if not any(signs):
            continue
        frames = (parent, child)
        found.append(
            scene.finding(
                Severity.warning,
                "multiple_authorities",
                f"{edge(*frames)}{scene.by(scene.authorities_of(mine))} seems to come from several broadcasters "
                f"taking turns: {listed([s for s in signs if s])} in {len(mine)} samples (this recording does not "
                "name publishers)",
                "tf2 takes every sample as it comes, so lookups mix the broadcasters' values: find them "
                "(ros2 topic info /tf --verbose) and turn the transform off in all but one",
                frames,
                mine,
                scene.arrival(mine),
            )
        )
    return found


def _enough(count: int, samples: int) -> bool:
    return count >= TURNS_MIN and count >= TURNS_SHARE * samples


def _back_and_forth(stamps: Int64Array) -> int:
    """Stamps (in arrival order) earlier than the one before them, each followed by a later one again:
    one late message, or a clock jumped back once, is not a turn."""
    steps = np.sign(np.diff(stamps))
    return int(((steps[:-1] < 0) & (steps[1:] > 0)).sum())


def _alternating(values: FloatArray) -> int:
    """Samples (in arrival order) far from the one before and the one after, which are close to each
    other: a value that goes somewhere else and comes back, sample after sample."""
    if len(values) < 3:
        return 0
    out_m, out_deg = apart(values[:-2], values[1:-1])
    back_m, back_deg = apart(values[1:-1], values[2:])
    round_m, round_deg = apart(values[:-2], values[2:])
    moved = ((out_m > APART_M) & (back_m > APART_M) & (round_m < out_m / 4)) | (
        (out_deg > APART_DEG) & (back_deg > APART_DEG) & (round_deg < out_deg / 4)
    )
    return int(moved.sum())


def apart(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """How far each value of ``b`` is from the one of ``a`` (N x 7 each): metres, and degrees of rotation."""
    with np.errstate(over="ignore"):  # values near 1e308 are apart by an infinity of metres
        metres: FloatArray = np.linalg.norm(b[:, :3] - a[:, :3], axis=1)
    return metres, np.degrees(angle_between_many(a[:, 3:], b[:, 3:]))
