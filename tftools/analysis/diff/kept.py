"""Frames that kept their place, or their orientation, above a moved edge: their own edge moved to undo it."""

from __future__ import annotations

import math
from dataclasses import replace

from tftools.analysis.diff.renames import RENAME_DEG, RENAME_MM
from tftools.analysis.differences import Change, Difference, fixed_value, rotation_angle_deg
from tftools.analysis.expected import Tolerances, TreeShape
from tftools.core.transform import Transform


def kept_places(found: list[Difference], a: TreeShape, b: TreeShape, tolerances: Tolerances) -> list[Difference]:
    """``found`` with each fixed edge that moved to undo a fixed edge above it that moved said with that edge once
    (its ``said_with`` and ``folded``, each folded one with ``kept``: how far its frame is from its place in A, in
    that edge's parent): its frame's place there within ``RENAME_MM`` and ``RENAME_DEG`` in both while its own edge
    moved further (the GrandTour box's cam4 under an alphasense_base turned 180 degrees between two calibrations),
    or its orientation there the same within ``tolerances`` while its own edge only turned (Stage's local_map, held
    under robot_0's laser turned opposite the robot's yaw, with the robot standing elsewhere)."""
    moved = {d.frame: d for d in found if d.change is Change.moved and d.part is None and _fixed_in_both(d)}
    kept: dict[str, list[Difference]] = {}
    for name, d in moved.items():
        found_above = _kept_below(name, moved, a, b, tolerances)
        if found_above is not None:
            above, apart = found_above
            kept.setdefault(above, []).append(replace(d, kept=apart))
    if not kept:
        return found
    folded = {d.frame for ds in kept.values() for d in ds}
    return [
        replace(d, said_with=tuple(x.frame for x in kept[d.frame]), folded=tuple(kept[d.frame]))
        if d.frame in kept and d.change is Change.moved
        else d
        for d in found
        if not (d.change is Change.moved and d.frame in folded)
    ]


def _fixed_in_both(d: Difference) -> bool:
    return (
        d.before is not None
        and d.after is not None
        and all(f.held is not None or f.static for f in (d.before, d.after))
    )


def _kept_below(
    name: str, moved: dict[str, Difference], a: TreeShape, b: TreeShape, tolerances: Tolerances
) -> tuple[str, tuple[float, float] | None] | None:
    """The nearest moved edge above ``name`` (its child frame) in whose parent ``name`` kept its place (how far
    from it: mm, degrees) or its orientation (None), on one path of fixed edges; None where there is none."""
    own = moved[name]
    path = [name]
    while len(path) <= len(a.frames):
        parent = a.frames[path[-1]].parent
        if parent is None or parent in path or b.frames.get(path[-1]) is None:
            return None
        if b.frames[path[-1]].parent != parent or parent not in b.frames:
            return None
        path.append(parent)
        if parent in moved:
            was, now = _through(path, a), _through(path, b)
            if was is None or now is None:
                return None
            mm = round(1000.0 * math.dist(was.translation, now.translation), 6)
            deg = round(rotation_angle_deg(was.rotation, now.rotation), 6)
            if (
                mm <= RENAME_MM
                and deg <= RENAME_DEG
                and (own.translation_mm > RENAME_MM or own.rotation_deg > RENAME_DEG)
            ):
                return parent, (mm, deg)
            if own.translation_mm <= tolerances.translation_mm and deg <= tolerances.rotation_deg:
                return parent, None
            return None
    return None


def _through(path: list[str], tree: TreeShape) -> Transform | None:
    """The place of ``path[0]`` in the parent of ``path[-1]``, through the fixed values of the edges on the path."""
    place = Transform()
    for frame in reversed(path):
        t, q = fixed_value(tree.frames[frame])
        if t is None or q is None:
            return None
        place = place * Transform(t, q)
    return place
