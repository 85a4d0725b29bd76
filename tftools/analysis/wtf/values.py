"""Checks of what each transform says: numbers tf2 refuses, frames it cannot use, names it rewrites."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.rows import VALUE_REFUSALS, split
from tftools.analysis.wtf.scene import Scene, edge, listed, transforms
from tftools.core.arrays import FloatArray, IntpArray
from tftools.core.rejection import RejectionCode

#: roswtf's limit on | |q| - 1 | for a rotation to count as normalised.
ROSWTF_NORM_TOLERANCE = 1e-6
#: Above this, a rotation tf2 accepts still visibly scales what goes through it.
VISIBLE_NORM_ERROR = 1e-3


@register("invalid_values", Severity.error, "NaN, infinity, or a rotation that is not a unit quaternion")
def invalid_values(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    refused = rows.refused_for(*VALUE_REFUSALS)  # the buffer's verdicts; what was wrong, told from the values
    nan = refused & rows.of_values(lambda v: np.asarray(np.isnan(v).any(axis=1), bool))
    inf = refused & ~nan & rows.of_values(lambda v: np.asarray(~np.isfinite(v).all(axis=1), bool))
    for parent, child, mine in rows.by_edge(refused):
        yield _refused(scene, parent, child, mine, nan, inf)
    slightly = ~refused & rows.of_values(lambda v: _length_error(v) > ROSWTF_NORM_TOLERANCE)
    accepted = (
        "ROS 2's tf2 accepts them and normalises each (through its rotation matrix), but readers that take them "
        "as sent scale points through this edge"
        if scene.buffer.semantics == "ros2"
        else "tf2 accepts them, but points through this edge get scaled"
    )
    roswtf = "ROS 1's roswtf" if scene.ros2 else "roswtf"  # a ROS 1 tool: ROS 2 has none
    for parent, child, mine in rows.by_edge(slightly):
        worst = float(_length_error(rows.values[mine]).max())
        yield scene.finding(
            Severity.warning if worst > VISIBLE_NORM_ERROR else Severity.info,
            "invalid_values",
            f"rotations of {edge(parent, child)}{scene.by(scene.authorities_of(mine))} "
            f"are not unit length in {transforms(len(mine))} (| |q| - 1 | up to {worst:.2g}): {accepted}",
            "normalise the quaternion before publishing (tf2::Quaternion::normalize()); "
            f"{roswtf} flags rotations off by more than {ROSWTF_NORM_TOLERANCE:g}",
            (parent, child),
            mine,
        )


def _length_error(values: FloatArray) -> FloatArray:
    """| |q| - 1 | of ``values``' rotations (0 where a value is not finite)."""
    finite = np.isfinite(values).all(axis=1)
    with np.errstate(over="ignore"):  # a rotation too long to square: an infinite error
        error: FloatArray = np.abs(np.sqrt(np.where(finite, (values[:, 3:] ** 2).sum(axis=1), 1.0)) - 1.0)
    return error


def _refused(scene: Scene, parent: str, child: str, mine: IntpArray, nan: np.ndarray, inf: np.ndarray) -> Finding:
    rows = scene.rows
    kinds, hints = [], []
    n_nan, n_inf = int(nan[mine].sum()), int(inf[mine].sum())
    n_quat = len(mine) - n_nan - n_inf
    if n_nan:
        kinds.append(f"NaN in {n_nan}")
    if n_inf:
        kinds.append(f"infinity in {n_inf}")
    if n_nan or n_inf:
        hints.append(
            "guard the publisher's math (a division by zero, an uninitialised pose, a failed sensor read) and "
            "publish nothing until the values are valid"
        )
    if n_quat:
        rotations = rows.values[mine[~nan[mine] & ~inf[mine]]][:, 3:]
        zero = int((np.abs(rotations).sum(axis=1) == 0).sum())
        with np.errstate(over="ignore", invalid="ignore"):  # rotations too long to square: of length inf
            lengths = np.sqrt((rotations**2).sum(axis=1))
            spread = lengths.max() - lengths.min()
        kinds.append(
            f"a rotation of length {lengths.min():.3g}"
            + (f" to {lengths.max():.3g}" if spread > 5e-4 else "")
            + f" in {n_quat}"
        )
        hint = "normalise the quaternion before publishing (tf2::Quaternion::normalize())"
        if zero:
            hint += "; for no rotation send x=y=z=0, w=1, not all zeros"
        hints.append(hint)
    by = scene.by(scene.authorities_of(mine))
    return scene.finding(
        Severity.error,
        "invalid_values",
        f"{transforms(len(mine))} {edge(parent or '(empty)', child or '(empty)')}{by} "
        f"refused by tf2 ({', '.join(kinds)}), first at {scene.first_at(mine)}",
        "tf2 drops them (TF_NAN_INPUT, TF_DENORMALIZED_QUATERNION), so lookups miss these updates: " + "; ".join(hints),
        tuple(f for f in (parent, child) if f),
        mine,
    )


@register("self_transform", Severity.error, "a transform from a frame to itself")
def self_transform(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    same = rows.refused_for(RejectionCode.SELF_TRANSFORM) & ~rows.refused_for(RejectionCode.NO_CHILD_FRAME_ID)
    for _, frame, mine in rows.by_edge(same):
        raw_pairs = zip(rows.raw_parent[mine].tolist(), rows.raw_child[mine].tolist(), strict=True)
        spelled = sorted({f"{rows.raw_names[p]} -> {rows.raw_names[c]}" for p, c in raw_pairs})
        sent = f", sent as {listed(spelled)}: one frame to tf2" if any(n.startswith("/") for n in spelled) else ""
        yield scene.finding(
            Severity.error,
            "self_transform",
            f"{transforms(len(mine))} from {frame} to itself{scene.by(scene.authorities_of(mine))}{sent}, "
            f"first at {scene.first_at(mine)}: tf2 ignores them (TF_SELF_TRANSFORM)",
            "header.frame_id must name the parent and child_frame_id the frame that moves: set them to two "
            "different frames (a name with and without a leading '/' is the same frame)",
            (frame,),
            mine,
        )


@register("empty_frame_id", Severity.error, "a transform without frame_id or child_frame_id")
def empty_frame_id(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    parent, child = rows.parent.whole(), rows.child.whole()
    no_parent, no_child = rows.refused_for(RejectionCode.NO_FRAME_ID), rows.refused_for(RejectionCode.NO_CHILD_FRAME_ID)
    hint = (
        "set both header.frame_id and child_frame_id (an empty frame parameter in a launch file or config is "
        "the usual cause)"
    )
    # Both empty is one fault, said once: foxglove-wizard's drone.mcap sends 17 default TransformStampeds
    # (no frames, stamp 0) before its flight's world -> drone
    if (both := np.flatnonzero(no_parent & no_child)).size:
        yield scene.finding(
            Severity.error,
            "empty_frame_id",
            f"{transforms(len(both))}{scene.by(scene.authorities_of(both))} with both frame_id and child_frame_id "
            f"empty, first {_arrived(scene, both)}: tf2 ignores them (TF_NO_CHILD_FRAME_ID, TF_NO_FRAME_ID)",
            hint,
            (),
            both,
        )
    for field, other_field, missing, other in (
        ("frame_id", "child_frame_id", no_parent & ~no_child, child),
        ("child_frame_id", "frame_id", no_child & ~no_parent, parent),
    ):
        empty = np.flatnonzero(missing)
        for other_id, mine in split(empty, other[empty]):
            named = rows.names[other_id]
            yield scene.finding(
                Severity.error,
                "empty_frame_id",
                f"{transforms(len(mine))}{scene.by(scene.authorities_of(mine))} with an empty {field} "
                f"({other_field} {named}), first {_arrived(scene, mine)}: "
                f"tf2 ignores them (TF_NO_{'CHILD_' if field == 'child_frame_id' else ''}FRAME_ID)",
                hint,
                (named,),
                mine,
            )


def _arrived(scene: Scene, rows: IntpArray) -> str:
    """When the first of ``rows`` arrived: as ``first_at``, but on the record clock where they are all stamped
    0 (a default-made message: its stamp says no time)."""
    if scene.rows.stamp[rows].any() or not scene.rows.record_time[rows].any():
        return f"at {scene.first_at(rows)}"
    return f"received at {scene.at_arrival(int(scene.rows.record_time[rows].min()))}"


@register("leading_slash", Severity.warning, "frame ids starting with '/' (tf_prefix style)")
def leading_slash(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    slashed = np.array([n.startswith("/") for n in rows.raw_names] or [False])
    uses = np.flatnonzero(slashed[rows.raw_parent.whole()] | slashed[rows.raw_child.whole()])
    for authority, mine in split(uses, rows.authority[uses]):
        names = sorted(
            {rows.raw_names[i] for i in (*rows.raw_parent[mine].tolist(), *rows.raw_child[mine].tolist())}
            & {n for n in rows.raw_names if n.startswith("/")}
        )
        yield scene.finding(
            Severity.warning,
            "leading_slash",
            f"frame ids with a leading '/'{scene.by([rows.authorities[authority]])}: {listed(names)} "
            f"(in {transforms(len(mine))}, first at {scene.first_at(mine)})",
            "tf2 drops the '/' when it stores them, but lookups by those names fail ('frame_ids cannot start with "
            "a /') and tools comparing names see two frames: remove the '/' from the publisher's frame names "
            + (
                "(robot_state_publisher's frame_prefix, the URDF's link names, a driver's frame_id parameter)"
                if scene.ros2
                else "(tf_prefix is gone since ROS Hydro)"
            ),
            tuple(n[1:] for n in names),
            mine,
            scene.arrival(mine),  # when they arrived, as the message says: a static's stamp can lie hours away
        )
