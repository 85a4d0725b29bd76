"""Frames lost or added whole with a frame above them: said once, with the highest of them."""

from __future__ import annotations

from dataclasses import replace

from tftools.analysis.differences import Change, Difference


def whole_subtrees(found: list[Difference]) -> list[Difference]:
    """``found`` with each frame lost (or added) whose parent is lost (or added) too said with the highest frame
    lost (or added) above it (``said_with``, ``folded``): a TurtleBot3 waffle's camera_link and the two frames
    beneath it, absent from a burger, were three lines; the GrandTour box's zed2i_* chain seven."""
    for change in (Change.lost, Change.added):
        found = _detections(_folded(found, change), change)
    return found


def _detections(found: list[Difference], change: Change) -> list[Difference]:
    """``found`` with the detections lost (or added) under one parent said with the first of them: a detector's
    objects named by their place in a list (Agri Bot's obj2 to obj43 in one run, obj0 and obj1 in another) were a
    line each."""
    first: dict[str, str] = {}  # each such detection's first sibling
    for d in found:
        shape = d.before if change is Change.lost else d.after
        if d.change is change and not d.other and not d.said_with and shape is not None and shape.detection:
            first.setdefault(str(shape.parent), d.frame)
    firsts = set(first.values())
    beneath: dict[str, list[Difference]] = {}
    for d in found:
        top = first.get(str(_parent(d))) if d.change is change and not d.said_with else None
        shape = d.before if change is Change.lost else d.after
        if top is not None and top != d.frame and shape is not None and shape.detection and not d.other:
            beneath.setdefault(top, []).append(d)
    folded = {x.frame for xs in beneath.values() for x in xs}
    return [
        replace(d, said_with=tuple(x.frame for x in beneath[d.frame]), folded=tuple(beneath[d.frame]))
        if d.change is change and d.frame in firsts and d.frame in beneath
        else d
        for d in found
        if not (d.change is change and d.frame in folded)
    ]


def _folded(found: list[Difference], change: Change) -> list[Difference]:
    gone = {d.frame: d for d in found if d.change is change and not d.other and not d.said_with}
    parent = {name: _parent(d) for name, d in gone.items()}
    top: dict[str, str] = {}
    for name in gone:
        above, seen = name, {name}
        while parent[above] in gone and parent[above] not in seen:
            above = str(parent[above])
            seen.add(above)
        if above != name:
            top[name] = above
    if not top:
        return found
    beneath: dict[str, list[Difference]] = {}
    for d in found:
        if d.change is change and d.frame in top:
            beneath.setdefault(top[d.frame], []).append(d)
    return [
        replace(d, said_with=tuple(x.frame for x in beneath[d.frame]), folded=tuple(beneath[d.frame]))
        if d.change is change and d.frame in beneath
        else d
        for d in found
        if not (d.change is change and d.frame in top)
    ]


def _parent(d: Difference) -> str | None:
    shape = d.before if d.change is Change.lost else d.after
    return shape.parent if shape is not None else None
