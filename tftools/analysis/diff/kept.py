"""Frames that kept their orientation above a moved edge: their own edge turned only to undo it, said with it once."""

from __future__ import annotations

from dataclasses import replace

from tftools.analysis.differences import Change, Difference, fixed_value, rotation_angle_deg
from tftools.analysis.expected import Tolerances, TreeShape
from tftools.core.transform import Transform


def kept_places(found: list[Difference], a: TreeShape, b: TreeShape, tolerances: Tolerances) -> list[Difference]:
    """``found`` with each fixed edge that only turned, to undo a fixed edge above it that moved (the frame's
    orientation in the parent of that edge the same in both, within ``tolerances``), said with that edge once (its
    ``said_with`` and ``folded``): Stage's local_map, held under robot_0's laser turned opposite the robot's yaw,
    kept its orientation in robot_0/odom while the robot stood elsewhere, turned otherwise: two lines said one
    thing."""
    moved = {d.frame: d for d in found if d.change is Change.moved and d.part is None and _fixed_in_both(d)}
    kept: dict[str, list[Difference]] = {}
    for name, d in moved.items():
        above = _kept_below(name, moved, a, b, tolerances)
        if above is not None:
            kept.setdefault(above, []).append(d)
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
) -> str | None:
    """The nearest moved edge above ``name`` (its child frame, its own edge only turned) in whose parent ``name`` is
    turned alike in both, on one path of fixed edges; None where there is none."""
    if moved[name].translation_mm > tolerances.translation_mm:
        return None
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
            if rotation_angle_deg(was.rotation, now.rotation) <= tolerances.rotation_deg:
                return parent
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
