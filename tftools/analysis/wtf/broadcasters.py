"""Several broadcasters of one edge where the recording does not name publishers (ROS 2 bags, MCAP):
inferred from the edge's own stream. Three patterns are told apart: most stamps sent twice (two
identical broadcasters, such as two robot_state_publishers); one publisher sending an old stamp
again among its own (not two broadcasters: ``time_backwards`` says so); and, among the samples not
sent before, stamps going back and forth or values alternating between two places, sample after
sample (broadcasters taking turns)."""

from __future__ import annotations

import numpy as np

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.scene import Scene, edge, listed
from tftools.core.arrays import BoolArray, FloatArray, Int64Array, IntpArray
from tftools.core.rotation import angle_between_many

#: A sign must show in this many samples, and this share of them, to tell two broadcasters.
TURNS_MIN = 5
TURNS_SHARE = 0.1
#: Two values this far apart (m, degrees) are two places; coming back within a quarter of it, the same one.
APART_M = 0.01
APART_DEG = 1.0
#: Two identical broadcasters: at least this share of an edge's stamps sent twice (or more).
TWINS_SHARE = 0.5


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
        stamps = rows.stamp[mine]
        again = sent_before(stamps)
        frames = (parent, child)
        if _enough(twice := _stamps_sent_twice(stamps, again), len(np.unique(stamps)), TWINS_SHARE):
            found.append(_twins(scene, frames, mine, twice, again))
            continue
        new = mine[~again]  # a publisher re-sending an old stamp is one publisher, not a turn
        back = _back_and_forth(rows.stamp[new])
        alternating = _alternating(rows.values[new])
        signs = [
            f"its stamps went back {back} times" if _enough(back, len(new)) else "",
            f"its value alternated between two places {alternating} times" if _enough(alternating, len(new)) else "",
        ]
        if not any(signs):
            continue
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


def _enough(count: int, samples: int, share: float = TURNS_SHARE) -> bool:
    return count >= TURNS_MIN and count >= share * samples


def sent_before(stamps: Int64Array, values: FloatArray | None = None) -> BoolArray:
    """Which samples (in arrival order) carry a stamp an earlier one of the same stream carried (and its
    value too, if ``values`` are given: a clock reset that replays old stamps elsewhere is new data)."""
    keys: np.ndarray = stamps
    if values is not None:
        table = np.empty(len(stamps), [("stamp", np.int64), ("value", np.float64, (7,))])
        table["stamp"], table["value"] = stamps, values
        keys = table.view(np.dtype((np.void, table.dtype.itemsize)))
    first = np.zeros(len(stamps), bool)
    first[np.unique(keys, return_index=True)[1]] = True
    return ~first


def _stamps_sent_twice(stamps: Int64Array, again: BoolArray) -> int:
    return len(np.unique(stamps[again]))


def _twins(scene: Scene, frames: tuple[str, str], mine: IntpArray, twice: int, again: BoolArray) -> Finding:
    """Most stamps sent twice: two broadcasters of the same transform, each sending every sample."""
    rows = scene.rows
    stamps, values = rows.stamp[mine], rows.values[mine]
    first = np.unique(stamps, return_index=True)
    originals = values[first[1][np.searchsorted(first[0], stamps[again])]]
    metres, degrees = apart(originals, values[again])
    if metres.max() == 0 and degrees.max() == 0:
        values_said = "the same values"
        effect = "tf2 drops the exact copies, so lookups are right, but every sample costs twice"
    else:
        values_said = f"values up to {metres.max() * 1000:.1f} mm and {degrees.max():.2f}° apart"
        effect = "tf2 keeps both where they differ, so lookups mix the two publishers' values"
    distinct = len(first[0])
    return scene.finding(
        Severity.warning,
        "multiple_authorities",
        f"{edge(*frames)}{scene.by(scene.authorities_of(mine))} arrives twice: {twice} of its {distinct} stamps "
        f"came again, with {values_said}: two identical publishers, it seems (two robot_state_publishers, or one "
        "launched twice; this recording does not name publishers)",
        f"{effect}: find them (ros2 node list, ros2 topic info /tf --verbose) and stop the one that should not run",
        frames,
        mine,
        scene.arrival(mine),
    )


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
