"""Checks of the tree's shape: loops, several trees, frames with several parents, edges with several publishers."""

from __future__ import annotations

import difflib
from collections import deque
from collections.abc import Iterator

import numpy as np

from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.scene import Scene, duration, edge, listed, transforms
from tftools.core.time import NS_PER_S

#: tf2's words when a lookup meets a loop.
TF2_LOOP = "The tf tree is invalid because it contains a loop."
_ALWAYS = (np.iinfo(np.int64).min, np.iinfo(np.int64).max)


@register("cycle", Severity.error, "a loop in the graph: a frame that is its own ancestor")
def cycles(scene: Scene) -> Iterator[Finding]:
    """Loops among the latest parents (what tf2's buffer holds now), then loops the transforms
    formed at some time (a stamp range every edge of the loop covers)."""
    latest = {child: scene.buffer.frame_name(hist.latest_parent) for child, hist in scene.buffer.histories()}
    reported: set[frozenset[str]] = set()
    order = {name: i for i, name in enumerate(scene.buffer.frames)}
    for loop in _loops({child: {parent} for child, parent in latest.items()}, order):
        reported.add(frozenset(loop))
        yield _loop_finding(scene, loop, "the latest transforms", None)
    spans = _edge_spans(scene)
    graph: dict[str, set[str]] = {}
    for parent, child in spans:
        graph.setdefault(child, set()).add(parent)
    for loop in _loops(graph, order):
        if frozenset(loop) in reported:
            continue
        reported.add(frozenset(loop))
        first = max(spans[(loop[(i + 1) % len(loop)], frame)][0] for i, frame in enumerate(loop))
        last = min(spans[(loop[(i + 1) % len(loop)], frame)][1] for i, frame in enumerate(loop))
        if first <= last:
            yield _loop_finding(scene, loop, "transforms stamped", (first, last))


def _edge_spans(scene: Scene) -> dict[tuple[str, str], tuple[int, int]]:
    """Each edge's stamp range among the usable rows (every time, for a static one)."""
    rows = scene.rows
    spans = {}
    for parent, child, mine in scene.by_edge(rows.usable):
        static = bool(rows.static[mine].all())
        stamps = rows.stamp[mine]
        spans[(rows.names[parent], rows.names[child])] = _ALWAYS if static else (int(stamps.min()), int(stamps.max()))
    return spans


def _loops(parents: dict[str, set[str]], order: dict[str, int]) -> list[list[str]]:
    """Each distinct loop child -> parent -> ... -> child (shortest from each frame), starting at
    its first frame in tf2's order."""
    loops: dict[frozenset[str], list[str]] = {}
    for start in sorted(parents, key=lambda f: order.get(f, len(order))):
        path = _path_back(parents, start)
        if path is not None and frozenset(path) not in loops:
            first = min(range(len(path)), key=lambda i: order.get(path[i], len(order)))
            loops[frozenset(path)] = path[first:] + path[:first]
    return list(loops.values())


def _path_back(parents: dict[str, set[str]], start: str) -> list[str] | None:
    """The shortest walk from ``start`` up through parents back to ``start`` (its frames), if any."""
    came_from: dict[str, str] = {}
    todo = deque([start])
    while todo:
        frame = todo.popleft()
        for parent in sorted(parents.get(frame, ())):
            if parent == start:
                path = [frame]
                while path[-1] != start:
                    path.append(came_from[path[-1]])
                return path[::-1]
            if parent not in came_from:
                came_from[parent] = frame
                todo.append(parent)
    return None


def _loop_finding(scene: Scene, loop: list[str], what: str, span: tuple[int, int] | None) -> Finding:
    """``loop`` lists frames child first, each the child of the next."""
    pairs = [(loop[(i + 1) % len(loop)], frame) for i, frame in enumerate(loop)]
    chain = " -> ".join([loop[0], *reversed(loop)])
    rows = scene.rows
    authorities: list[str] = []
    began: dict[tuple[str, str], tuple[int, tuple[str, ...]]] = {}  # each loop edge: first arrival, publishers
    for parent, child, mine in scene.by_edge(rows.usable):
        key = (rows.names[parent], rows.names[child])
        if key in pairs:
            who = scene.authorities_of(mine)
            authorities.extend(a for a in who if a not in authorities)
            began[key] = (int(scene.arrival(mine).min()), who)
    publishers = f" ({scene.by(authorities).strip()})" if authorities else ""
    closing = max(began, key=lambda k: began[k][0])
    if span is None:
        stamps = [h.latest_stamp for f in loop if (h := scene.buffer.history(f)) is not None]
        first, last = min(stamps), max(stamps)
        when = f"lookups through these frames fail (since {scene.at(began[closing][0])})"
    else:
        first, last = (0, 0) if span == _ALWAYS else span
        when = "always" if span == _ALWAYS else f"from {scene.at(first)} to {scene.at(last)}"
        when = f"lookups at those times fail ({when})"
    starts = sorted(t for t, _ in began.values())
    suspect = ""
    if len(starts) > 1 and starts[-1] - starts[-2] > NS_PER_S:  # one came well after the rest: it closed the loop
        suspect = f"; {edge(*closing)}{scene.by(began[closing][1])} closed it, at {scene.at(began[closing][0])}"
    return Finding(
        Severity.error,
        "cycle",
        f"{what} form a loop {chain}{publishers}: {when} with tf2's error '{TF2_LOOP}'",
        "each frame has one parent and cannot be its own ancestor: of the loop's transforms "
        f"({listed([edge(p, c) for p, c in pairs])}) stop the one that does not belong, or send it the other "
        f"way round (header.frame_id is the parent, child_frame_id the child){suspect}",
        tuple(loop),
        tuple(authorities),
        first,
        last,
        len(loop),
    )


@register("disconnected", Severity.error, "more than one tree: frames no lookup can join")
def disconnected(scene: Scene) -> Iterator[Finding]:
    tree = scene.tree
    roots = tree.roots
    if len(roots) < 2:
        return
    members = {root: _descendants(tree.children, root) for root in roots}
    roots.sort(key=lambda r: -len(members[r]))
    trees = "; ".join(
        f"{root} ({len(members[root])} frame{'s' if len(members[root]) > 1 else ''}: {listed(members[root])})"
        for root in roots
    )
    yield Finding(
        Severity.error,
        "disconnected",
        f"{len(roots)} separate trees, and no lookup between them: {trees}",
        _join_hint(roots, members),
        tuple(roots),
        (),
        0,
        0,
        len(roots),
    )


def _descendants(children: dict[str, list[str]], root: str) -> list[str]:
    found, todo = [], [root]
    while todo:
        frame = todo.pop(0)
        found.append(frame)
        todo.extend(children.get(frame, []))
    return found


def _join_hint(roots: list[str], members: dict[str, list[str]]) -> str:
    """How to join the trees; a root whose name is close to a frame of another tree is likely a typo."""
    for root in roots[1:]:
        others = [f for r in roots if r != root for f in members[r]]
        close = difflib.get_close_matches(root, others, n=1, cutoff=0.8)
        if close:
            return f"'{root}' looks like a misspelling of '{close[0]}': fix the frame name where it is published"
    main, other = roots[0], roots[1]
    return (
        f"publish the transform that attaches {other} to the {main} tree (a static_transform_publisher for a "
        "fixed mount, localization for map -> odom), or check the frame names for typos"
    )


@register("multiple_parents", Severity.error, "a frame re-parented: two parents for one frame")
def multiple_parents(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    for child, mine in scene.by_child(rows.usable):
        parents = rows.parent[mine]
        if parents.min() == parents.max():
            continue
        switches = mine[1:][parents[1:] != parents[:-1]]
        yield _parents_finding(scene, child, mine, switches)


def _parents_finding(scene: Scene, child_id: int, mine: np.ndarray, switches: np.ndarray) -> Finding:
    rows = scene.rows
    child = rows.names[child_id]
    parents = rows.parent[mine]
    _, first = np.unique(parents, return_index=True)
    described, publishers = [], []
    for parent_id in parents[np.sort(first)]:
        theirs = mine[parents == parent_id]
        times = scene.arrival(theirs)
        who = scene.authorities_of(theirs)
        publishers.append(set(who))
        by = scene.by(who)
        described.append(
            f"{rows.names[parent_id]} ({by.strip() + ', ' if by else ''}{transforms(len(theirs))} "
            f"from {scene.rel(int(times.min()))} to {scene.rel(int(times.max()))})"
        )
    hist = scene.buffer.history(child)
    now = scene.buffer.frame_name(hist.latest_parent) if hist is not None else rows.names[parents[-1]]
    names = [rows.names[p] for p in parents[np.sort(first)]]
    switch_times = scene.arrival(switches)
    message = (
        f"{child} has {len(names)} parents: {'; '.join(described)}; it changed parent {len(switches)} "
        f"time{'s' if len(switches) > 1 else ''}, first at {scene.at(int(switch_times[0]))}, and is now under {now}"
    )
    all_publishers = tuple(dict.fromkeys(a for group in publishers for a in group))
    if scene.publishers_known and not set.intersection(*publishers):
        hint = (
            f"{child} can have one parent only, and these publishers fight over it: lookups jump between trees. "
            f"Let one of them publish {child}; the others attach elsewhere (a localizer publishes map -> odom, "
            f"not map -> {child})"
        )
    else:
        hint = (
            f"{child} can have one parent at a time: if it moves between parents on purpose (an object picked "
            "up), lookups across the switch fail; otherwise fix the frame_id its publisher sends"
        )
    return Finding(
        Severity.error,
        "multiple_parents",
        message,
        hint,
        (child, *names),
        all_publishers,
        int(switch_times[0]),
        int(switch_times[-1]),
        len(switches),
    )


@register("multiple_authorities", Severity.warning, "two publishers of one edge")
def multiple_authorities(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    for static in (False, True):
        for parent, child, mine in scene.by_edge(rows.usable & (rows.static == static)):
            ids = rows.authority[mine]
            if ids.min() == ids.max():
                continue
            yield _authorities_finding(scene, rows.names[parent], rows.names[child], mine)


def _authorities_finding(scene: Scene, parent: str, child: str, mine: np.ndarray) -> Finding:
    rows = scene.rows
    who = scene.authorities_of(mine)
    ids = rows.authority[mine]
    _, first_rows = np.unique(ids, return_index=True)
    spans = []
    for authority in ids[np.sort(first_rows)]:
        theirs = mine[ids == authority]
        times = scene.arrival(theirs)
        spans.append((rows.authorities[int(authority)], len(theirs), int(times.min()), int(times.max())))
    together = any(a[2] <= b[3] and b[2] <= a[3] for i, a in enumerate(spans) for b in spans[i + 1 :])
    parts = "; ".join(f"{n} ({transforms(c)} from {scene.rel(s)} to {scene.rel(e)})" for n, c, s, e in spans)
    first, last = min(s[2] for s in spans), max(s[3] for s in spans)
    source = "nodes" if scene.publishers_known else "topics"
    if together:
        return Finding(
            Severity.warning,
            "multiple_authorities",
            f"{edge(parent, child)} comes from {len(who)} {source} at once: {parts}",
            "tf2 takes every sample as it comes, so lookups mix both publishers' values: turn the transform off "
            "in all but one (robot_localization's publish_tf, a driver's publish_tf or enable_odom_tf parameter)",
            (parent, child),
            who,
            first,
            last,
            len(mine),
        )
    handover = spans[1][2]
    return Finding(
        Severity.info,
        "multiple_authorities",
        f"{edge(parent, child)} was handed over between {source}, one after the other: {parts}",
        f"fine if intended (a node restarted under another name at {scene.at(handover)}); "
        f"the silence between them lasted {duration((handover - spans[0][3]) / 1e9)}",
        (parent, child),
        who,
        first,
        last,
        len(mine),
    )
