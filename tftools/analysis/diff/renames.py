"""Frames renamed between two recordings: one gone and another come under the same parent at nearly one place."""

from __future__ import annotations

import math
from dataclasses import replace

from tftools.analysis.differences import Change, Difference, fixed_value, frame_differences, rotation_angle_deg
from tftools.analysis.expected import FrameShape, Tolerances

#: How near two fixed frames of one parent are to be one frame renamed (a description's revision moving a wheel a
#: few mm), and how far from their parent's origin: at the origin every frame is at one place, which tells nothing.
RENAME_MM = 20.0
RENAME_DEG = 5.0
PLACE_MM = 50.0


def renamed(found: list[Difference], tolerances: Tolerances) -> list[Difference]:
    """``found`` with each frame renamed said so (``Change.renamed``: its name in B, its name in A as ``other``,
    how far it moved): a frame of A (lost, or moved away) and one of B (added, or a frame of A's moved there) under
    the same parent (itself in both and not moved, so that a place under it is one place), each fixed (static, or
    held on /tf) at least ``PLACE_MM`` from it, within ``RENAME_MM`` and ``RENAME_DEG`` of each other and of no
    other such frame. A frame moved whose two places are both renames is
    said by them; one whose one place is a rename is said lost (or added) at the other, its namesake named.
    The hologlyph robot's wheels renamed across two URDF versions, left_wheel's name given to the rear wheel, read
    'left_wheel moved 1168.9 mm' and a wheel lost and one added: they are two wheels renamed, each moved 8.9 mm."""
    moved = {d.frame: pair for d in found if (pair := _moved_away(d)) is not None}
    was = {d.frame: d.before for d in found if d.change is Change.lost and d.before and _placed(d.before)}
    now = {d.frame: d.after for d in found if d.change is Change.added and d.after and _placed(d.after)}
    was.update((name, before) for name, (before, _) in moved.items())
    now.update((name, after) for name, (_, after) in moved.items())
    unsettled = {d.frame for d in found if _unsettled(d)}  # a place under such a parent tells nothing
    was = {name: f for name, f in was.items() if f.parent not in unsettled}
    now = {name: f for name, f in now.items() if f.parent not in unsettled}
    near = {x: [y for y in now if y != x and _near(was[x], now[y])] for x in was}
    into = {y: [x for x in was if y in near[x]] for y in now}
    to = {x: ys[0] for x, ys in near.items() if len(ys) == 1 and len(into[ys[0]]) == 1}
    if not to:
        return _parents_renamed(found, tolerances)
    came = {y: x for x, y in to.items()}
    said: list[Difference] = []
    for d in found:
        x = d.frame
        if d.change not in (Change.lost, Change.added, Change.moved) or not (x in to or x in came):
            said.append(d)
            continue
        if d.change is Change.moved and x not in moved:
            said.append(d)
            continue
        if d.change is not Change.added and x in to and not _swapped_later(x, to, said):
            said.append(
                _renamed(was[x], now[to[x]], was.get(to[x]), now.get(x))
                if to.get(to[x]) == x
                else _renamed(was[x], now[to[x]])
            )
        if d.change is Change.moved and x not in to:
            said.append(Difference(Change.lost, x, d.before, None, other=came[x]))
        if d.change is Change.moved and x not in came:
            said.append(Difference(Change.added, x, None, d.after, other=to[x]))
    return _parents_renamed(said, tolerances)


#: The differences of a parent under which its children's places are not compared for a rename: the GrandTour
#: box's alphasense_base turned 180 degrees between two calibrations, its cameras' places under it with it.
_UNSETTLED = (Change.moved, Change.reparented, Change.static, Change.reordered, Change.lost, Change.added)


def _unsettled(d: Difference) -> bool:
    """Whether ``d`` leaves its frame's children's places uncompared (``_UNSETTLED``); not a root of A that B hangs
    under a parent (a mapping robot's base_link under the odom its EKF added, robo_lape's two bags: its mounts,
    renamed, were read lost and added): its place under that new parent tells nothing of theirs under it."""
    joined = d.change is Change.reparented and d.before is not None and d.before.parent is None
    return d.change in _UNSETTLED and not joined


def _swapped_later(x: str, to: dict[str, str], said: list[Difference]) -> bool:
    """Whether ``x`` swapped names with a frame already said with it (one line for a swap)."""
    return to.get(to[x]) == x and any(d.change is Change.renamed and d.frame == x for d in said)


def _renamed(
    before: FrameShape, after: FrameShape, back: FrameShape | None = None, to: FrameShape | None = None
) -> Difference:
    """A frame renamed from ``before``'s name in A to ``after``'s in B, and how far it moved; where the two swapped
    names (``back``, A's frame of ``after``'s name, is B's ``to``), the other one's rename said with it."""
    (t1, q1), (t2, q2) = _place(before), _place(after)
    mm, deg = round(1000.0 * math.dist(t1, t2), 6), round(rotation_angle_deg(q1, q2), 6)
    d = Difference(Change.renamed, after.frame, before, after, translation_mm=mm, rotation_deg=deg, other=before.frame)
    if back is None or to is None:
        return d
    return replace(d, said_with=(to.frame,), folded=(_renamed(back, to),))


def _parents_renamed(found: list[Difference], tolerances: Tolerances) -> list[Difference]:
    """``found`` with each frame renamed as a parent said so: one lost from A and one added in B, under one parent
    (or roots both), every child of the lost frame that is in B a child of the added one (one or more); each child's
    own differences then compared under it. IAS0220's IMU bags: world in one is map in the other, imu_link beneath."""
    lost = {d.frame: d for d in found if d.change is Change.lost and d.before is not None and not d.other}
    added = {d.frame: d for d in found if d.change is Change.added and d.after is not None and not d.other}
    moved: dict[str, set[str]] = {}
    for d in found:
        if d.change is Change.reparented and d.before is not None and d.after is not None:
            moved.setdefault(str(d.before.parent), set()).add(str(d.after.parent))
    to = {x: next(iter(moved[x])) for x in lost if len(moved.get(x, ())) == 1 and next(iter(moved[x])) in added}
    to = {x: y for x, y in to.items() if _same_parent(lost[x], added[y]) and list(to.values()).count(y) == 1}
    if not to:
        return _orphans(found)
    came = set(to.values())
    children = {x: tuple(d.frame for d in found if d.change is Change.reparented and _under(d, x)) for x in to}
    said: list[Difference] = []
    for d in found:
        if d.change is Change.lost and d.frame in to:
            y = to[d.frame]
            said.append(
                replace(
                    d, change=Change.renamed, after=added[y].after, other=d.frame, frame=y, said_with=children[d.frame]
                )
            )
        elif d.change is Change.reparented and d.before is not None and d.after is not None and d.before.parent in to:
            said.extend(frame_differences(replace(d.before, parent=d.after.parent), d.after, tolerances))
        elif not (d.change is Change.added and d.frame in came):
            said.append(d)
    return _orphans(said)


def _orphans(found: list[Difference]) -> list[Difference]:
    """``found`` with the children of a frame lost from A that are roots in B said with it (``said_with``), and
    those of a frame added in B that were roots in A with it: the PFMS Stage bags' world, whose three robots' odom
    frames are roots where it is absent, were four lines."""
    lost = {d.frame for d in found if d.change is Change.lost and not d.other}
    added = {d.frame for d in found if d.change is Change.added and not d.other}
    kids: dict[str, list[str]] = {}
    for d in found:
        if d.change is Change.reparented and d.before is not None and d.after is not None:
            if d.after.parent is None and d.before.parent in lost:
                kids.setdefault(d.before.parent, []).append(d.frame)
            if d.before.parent is None and d.after.parent in added:
                kids.setdefault(d.after.parent, []).append(d.frame)
    if not kids:
        return found
    folded = {name for names in kids.values() for name in names}
    return [
        replace(d, said_with=tuple(kids[d.frame])) if d.change in (Change.lost, Change.added) and d.frame in kids else d
        for d in found
        if not (d.change is Change.reparented and d.frame in folded)
    ]


def _under(d: Difference, parent: str) -> bool:
    return d.before is not None and d.before.parent == parent


def _same_parent(lost: Difference, added: Difference) -> bool:
    assert lost.before is not None and added.after is not None
    return lost.before.parent == added.after.parent


def _moved_away(d: Difference) -> tuple[FrameShape, FrameShape] | None:
    """A frame fixed in both, moved further than a rename may move one (else it is itself, a little moved)."""
    if d.change is not Change.moved or d.mimics or d.before is None or d.after is None:
        return None
    if not (_placed(d.before) and _placed(d.after)) or _near(d.before, d.after):
        return None
    return d.before, d.after


def _placed(f: FrameShape) -> bool:
    """Whether a frame is fixed under its parent, away from its origin (``PLACE_MM``)."""
    if f.parent is None:
        return False
    t, q = fixed_value(f)
    return t is not None and q is not None and (f.static or f.held is not None) and 1000.0 * math.hypot(*t) >= PLACE_MM


def _near(one: FrameShape, other: FrameShape) -> bool:
    """Whether two fixed frames are under one parent, within ``RENAME_MM`` and ``RENAME_DEG`` of each other."""
    (t1, q1), (t2, q2) = _place(one), _place(other)
    return (
        one.parent == other.parent
        and 1000.0 * math.dist(t1, t2) <= RENAME_MM
        and rotation_angle_deg(q1, q2) <= RENAME_DEG
    )


def _place(f: FrameShape) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    t, q = fixed_value(f)
    assert t is not None and q is not None
    return t, q
