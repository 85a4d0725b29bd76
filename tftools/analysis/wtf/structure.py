"""Checks of the tree's shape: loops, several trees, frames with several parents, edges with several publishers."""

from __future__ import annotations

import dataclasses
import difflib
import itertools
from collections.abc import Iterator, Sequence

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.frames import FrameTree
from tftools.analysis.wtf.broadcasters import AtOnce, at_once, inferred_broadcasters, resent_notes
from tftools.analysis.wtf.loops import find_loops
from tftools.analysis.wtf.mounts import mount_between, mount_hint
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.robots import prefix_hint, robots_of, robots_said
from tftools.analysis.wtf.rows import split
from tftools.analysis.wtf.scene import Scene, and_joined, base_name, duration, edge, listed, transforms
from tftools.analysis.wtf.sensors import TYPO_CUTOFF, statics_missing
from tftools.analysis.wtf.static_senders import static_senders
from tftools.analysis.wtf.topics import StaticShared, static_shared
from tftools.core.arrays import Int64Array, IntpArray
from tftools.core.time import NS_PER_S
from tftools.sources.codecs.gather import among, distinct

#: tf2's words when a lookup meets a loop.
TF2_LOOP = "The tf tree is invalid because it contains a loop."
_ALWAYS = (np.iinfo(np.int64).min, np.iinfo(np.int64).max)


@register("cycle", Severity.error, "a loop in the graph: a frame that is its own ancestor")
def cycles(scene: Scene) -> Iterator[Finding]:
    """Loops among the latest parents (what tf2's buffer holds now), then loops the transforms
    formed at some time (a stamp range every edge of the loop covers)."""
    latest = {child: [scene.buffer.frame_name(hist.latest_parent)] for child, hist in scene.buffer.histories()}
    order = {name: i for i, name in enumerate(scene.buffer.frames)}
    found: list[tuple[list[str], str, tuple[int, int] | None]]
    found = [(loop, "the latest transforms", None) for loop in find_loops(latest, order)]
    reported = {frozenset(loop) for loop, _, _ in found}
    spans = _edge_spans(scene)
    graph: dict[str, list[str]] = {}
    for parent, child in spans:
        graph.setdefault(child, []).append(parent)
    for loop in find_loops(graph, order):
        first, last = max(spans[p][0] for p in _pairs(loop)), min(spans[p][1] for p in _pairs(loop))
        if frozenset(loop) not in reported and first <= last:
            found.append((loop, "transforms stamped", (first, last)))
    if not found:
        return
    began = _loop_edges(scene, {pair for loop, _, _ in found for pair in _pairs(loop)})
    for loop, what, span in found:
        yield _loop_finding(scene, loop, what, span, began)


def _edge_spans(scene: Scene) -> dict[tuple[str, str], tuple[int, int]]:
    """Each edge's stamp range among the usable rows (every time, for a static one)."""
    rows = scene.rows
    spans: dict[tuple[str, str], tuple[int, int]] = {}
    singles: list[tuple[tuple[str, str], int]] = []  # one-row edges, read at once after (100,000 statics)
    for parent, child, mine in rows.by_edge(rows.usable):
        static = bool(rows.static[mine].all())
        if len(mine) == 1 and not static:
            spans[(parent, child)] = _ALWAYS  # its place in the order; its stamp below
            singles.append(((parent, child), int(mine[0])))
            continue
        if static:
            spans[(parent, child)] = _ALWAYS
            continue
        stamps = rows.stamp[mine]
        spans[(parent, child)] = (int(stamps.min()), int(stamps.max()))
    if singles:
        stamps = rows.stamp[np.array([row for _, row in singles], np.intp)].tolist()
        spans.update(((e, (t, t)) for (e, _), t in zip(singles, stamps, strict=True)))
    return spans


def _pairs(loop: list[str]) -> list[tuple[str, str]]:
    """The (parent, child) edges of ``loop``, which lists frames child first, each the child of the next."""
    return [(loop[(i + 1) % len(loop)], frame) for i, frame in enumerate(loop)]


#: Per loop edge: its rank among the edges (by first row), first arrival and publishers.
_LoopEdges = dict[tuple[str, str], tuple[int, int, tuple[str, ...]]]


def _loop_edges(scene: Scene, pairs: set[tuple[str, str]]) -> _LoopEdges:
    """For each edge of ``pairs``: its rank, first arrival and publishers (one pass over the edges,
    whatever the number of loops)."""
    rows = scene.rows
    began: _LoopEdges = {}
    for rank, (parent, child, mine) in enumerate(rows.by_edge(rows.usable)):
        if (parent, child) in pairs:
            began[(parent, child)] = (rank, int(scene.arrival(mine).min()), scene.authorities_of(mine))
    return began


def _loop_finding(
    scene: Scene,
    loop: list[str],
    what: str,
    span: tuple[int, int] | None,
    edges: _LoopEdges,
) -> Finding:
    """``loop`` lists frames child first, each the child of the next; ``edges`` (``_loop_edges``)
    has each loop edge's first arrival and publishers."""
    pairs = _pairs(loop)
    chain = " -> ".join([loop[0], *reversed(loop)])
    ranked = sorted((edges[key] + (key,) for key in pairs if key in edges), key=lambda e: e[0])
    began = {key: (arrival, who) for _, arrival, who, key in ranked}  # each loop edge: first arrival, publishers
    authorities = list(dict.fromkeys(a for _, who in began.values() for a in who))
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


#: Trees the ``disconnected`` finding describes one by one (the largest); the rest are counted.
TREES_DESCRIBED = 20


@register("disconnected", Severity.error, "more than one tree: frames no lookup can join")
def disconnected(scene: Scene) -> Iterator[Finding]:
    members = scene.tree.trees()
    if len(members) < 2:
        return
    roots = sorted(members, key=lambda r: -len(members[r]))
    trees = "; ".join(
        f"{root} ({counted(len(members[root]), 'frame')}: {listed(members[root])})" for root in roots[:TREES_DESCRIBED]
    )
    if len(roots) > TREES_DESCRIBED:
        trees += f"; and {len(roots) - TREES_DESCRIBED} more"
    yield Finding(
        Severity.error,
        "disconnected",
        f"{len(roots)} separate trees, and no lookup between them: {trees}",
        _robots_alike(scene, roots, members)
        or _twin_root(roots, members, scene.tree)
        or _base_unlike_description(scene, roots, members)
        or _misspelt_root(roots, members)
        or _mount_seen(scene, roots, members)
        or statics_missing(scene, "the fixed transforms that would join them")
        or join_hint(roots, members, scene.tree),
        tuple(roots),
        count=len(roots),
    )


def _robots_alike(scene: Scene, roots: list[str], members: dict[str, list[str]]) -> str | None:
    """A tree apart that the same node of several robots sends under frame names without a robot's prefix (two
    drones' MAVROS each sending fcu -> lidarlite_laser): no robot's tree holds it."""
    if not scene.publishers_known:
        return None
    rows = scene.rows
    by_child = dict(rows.by_child(rows.usable))
    for root in roots[1:TREES_DESCRIBED]:
        frames = set(members[root]) - {root}
        mine = [by_child[child] for child in frames if child in by_child]
        if mine:
            child = next(c for c in members[root] if c in frames)
            hint = robots_alike_hint(root, child, scene.authorities_of(np.concatenate(mine)), scene.ros2)
            if hint is not None:
                return hint
    return None


def robots_alike_hint(root: str, child: str, publishers: Sequence[str], ros2: bool) -> str | None:
    """What to do where ``root``'s tree (of which ``root`` -> ``child``) is sent by ``publishers``, if they are the
    same node of several robots (``robots_of``); else None. ``disconnected``'s hint, and echo's between two trees."""
    robots = robots_of(publishers)
    if robots is None:
        return None
    return (
        f"{root}'s tree is sent by {robots_said(robots)}, under frame names without a robot's prefix: "
        f"nothing attaches it to any robot's frames, and {prefix_hint(robots, (root, child), ros2)}"
    )


def _base_unlike_description(scene: Scene, roots: list[str], members: dict[str, list[str]]) -> str | None:
    """Odometry's base apart from the description's root (Gazebo's planar move publishing its default
    base_footprint beside a URDF rooted at footprint_link): the two names to make one, or None."""
    robot = scene.robot
    if robot is None:
        return None
    description = robot.description
    heads = [r for r in roots if r in description.links and description.joint_of(r) is None]
    for root in roots if heads else ():
        if heads[0] in members[root]:
            continue
        for frame in members[root]:
            parent = scene.tree.frames[frame].parent
            if parent is None or base_name(parent) != "odom" or frame in description.links:
                continue
            return (
                f"{parent} -> {frame} names a base that {description.source} lacks, while the robot's links hang "
                f"from {heads[0]}, which nothing joins to {parent}: make the odometry publish {parent} -> "
                f"{heads[0]} (Gazebo's diff drive and planar move: robot_base_frame), or name the description's "
                f"root {frame}"
            )
    return None


def _mount_seen(scene: Scene, roots: list[str], members: dict[str, list[str]]) -> str | None:
    """The join a detector's markers show (``mounts.mount_between``: each sent in two of the trees), or None."""
    if not scene.siblings:
        return None
    mount = mount_between(scene, {frame: root for root in roots for frame in members[root]})
    return None if mount is None else mount_hint(mount, scene.ros2)


#: The typo search of ``join_hint`` looks at most at this many roots, against at most this many
#: frames of the other trees, of names at most this long (difflib is quadratic in a name's length).
TYPO_ROOTS, TYPO_FRAMES, TYPO_NAME_LENGTH = 10, 10_000, 200


def _misspelt_root(roots: list[str], members: dict[str, list[str]]) -> str | None:
    """A root whose name is close to a frame of another tree is likely a typo: how to fix it, or None."""
    for root in roots[1:TYPO_ROOTS]:
        if len(root) > TYPO_NAME_LENGTH:
            continue
        apart = (f for r in roots if r != root for f in members[r] if len(f) <= TYPO_NAME_LENGTH)
        others = list(itertools.islice(apart, TYPO_FRAMES))
        close = difflib.get_close_matches(root, others, n=1, cutoff=TYPO_CUTOFF)
        if close:
            return f"'{root}' looks like a misspelling of '{close[0]}': fix the frame name where it is published"
    return None


def _twin_root(roots: list[str], members: dict[str, list[str]], tree: FrameTree) -> str | None:
    """A root whose tree has the same frames as a tree under another namespace prefix (three robots in Stage,
    robot_2/odom's tree the same as robot_0's and robot_1's, which world holds): the transform that joins the
    others, missing for it; None where no tree repeats another so."""
    for root in roots[:TYPO_ROOTS]:
        prefix, _, local = root.rpartition("/")
        if not prefix or not local or not all(f.startswith(prefix + "/") for f in members[root]):
            continue
        names = [f[len(prefix) + 1 :] for f in members[root]]
        if len(names) < 2:  # a lone frame is as likely a namespace misspelt
            continue
        twins = [
            frame
            for other in roots
            if other != root
            for frame in members[other]
            if frame != root and tree.frames[frame].parent is not None and _heads_alike(frame, local, names, tree)
        ]
        if not twins:
            if alike := _root_twins(root, local, names, roots, tree):
                return _fleet_hint([root, *alike], names)
            continue
        parent = tree.frames[twins[0]].parent
        owners = and_joined([f"{twin[: -len(local) - 1]}'s" for twin in twins])
        joins = and_joined([edge(str(tree.frames[twin].parent), twin) for twin in twins])
        return (
            f"{root}'s tree has the same frames as {owners} under '{prefix}/' ({listed(names)}); they are joined "
            f"to the rest by {joins}: publish {parent} -> {root} as they do (a transform missing, not a typo)"
        )
    return None


def _root_twins(root: str, local: str, names: list[str], roots: list[str], tree: FrameTree) -> list[str]:
    """The other roots heading the same frames under their own prefix (robot_0/odom beside robot_1/odom)."""
    return [other for other in roots if other != root and _heads_alike(other, local, names, tree)]


def _heads_alike(frame: str, local: str, names: list[str], tree: FrameTree) -> bool:
    """Whether ``frame`` is ``local`` under a prefix of its own, with every one of ``names`` under that prefix."""
    return frame.endswith("/" + local) and all(frame[: -len(local)] + name in tree.frames for name in names)


def _fleet_hint(heads: list[str], names: list[str]) -> str:
    """Robots each in a tree of its own, none joined to a common frame (a PFMS assignment's three robots in
    Stage, no world recorded): a transform missing for each, not a misspelt name."""
    heads = sorted(heads)
    return (
        f"{and_joined(heads)} head trees of the same frames under their own prefixes ({listed(names)}), and "
        f"nothing joins them (transforms missing, not a typo): if they are looked up together, publish a common "
        f"parent for each (a static_transform_publisher world -> {heads[0]} and likewise for the others, or "
        "map -> odom from each robot's localization)"
    )


def join_hint(roots: list[str], members: dict[str, list[str]], tree: FrameTree) -> str:
    """How to join the trees: the transform a tree like another under another namespace lacks; a root whose name
    is close to a frame of another tree is likely a typo."""
    if (hint := _twin_root(roots, members, tree) or _misspelt_root(roots, members)) is not None:
        return hint
    main, other = roots[0], roots[1]
    # localization's map -> odom only where there is an odom to hang a map on (a real UR5's laser tracker under
    # 'map' beside the arm's world tree has none)
    localized = ", localization for map -> odom" if any(base_name(f) == "odom" for f in tree.frames) else ""
    return (
        f"publish the transform that attaches {other} to the {main} tree (a static_transform_publisher for a "
        f"fixed mount{localized}), or check the frame names for typos"
    )


@register("multiple_parents", Severity.error, "a frame re-parented: two parents for one frame")
def multiple_parents(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    for child, mine in rows.by_child(rows.usable):
        if len(mine) < 2:  # one row, one parent (a tree of 100,000 statics has little else)
            continue
        parents = rows.parent[mine]
        if parents.min() == parents.max():
            continue
        switches = mine[1:][parents[1:] != parents[:-1]]
        yield _parents_finding(scene, child, mine, switches)


def _parents_finding(scene: Scene, child: str, mine: np.ndarray, switches: np.ndarray) -> Finding:
    rows = scene.rows
    described, publishers, names = [], [], []
    for parent_id, theirs in split(mine, rows.parent[mine]):
        times = scene.arrival(theirs)
        who = scene.authorities_of(theirs)
        publishers.append(who)
        by = scene.by(who)
        names.append(rows.names[parent_id])
        described.append(f"{names[-1]} ({by.strip() + ', ' if by else ''}{_during(scene, theirs, times)})")
    hist = scene.buffer.history(child)
    now = scene.buffer.frame_name(hist.latest_parent) if hist is not None else rows.names[rows.parent[mine[-1:]][0]]
    switch_times = scene.arrival(switches)
    message = (
        f"{child} has {len(names)} parents: {'; '.join(described)}; it changed parent {counted(len(switches), 'time')}"
        f", first at {scene.at_row(int(switches[0]))}, and is now under {now}"
    )
    all_publishers = tuple(dict.fromkeys(a for group in publishers for a in group))
    figures: dict[str, float | int | str] = {"parents": len(names)}
    if rows.static[mine].all():
        hint = _static_parents_hint(scene, child, mine, names, now)
        figures["parents_each_from_other_static_publishers"] = int(_each_from_others(scene, mine))
    elif (split_by_topic := _parents_by_topic(scene, mine)) is not None:
        hint = _mount_twice_hint(scene, child, mine, *split_by_topic)
    elif (shared := _stamped_under_both(scene, mine)) is not None:
        hint = _at_once_hint(scene, child, names, shared)
        figures["stamps_under_both"] = shared
        message += f"; {counted(shared, 'stamp')} came under both"
    elif scene.publishers_known and not set.intersection(*map(set, publishers)):
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
        figures=figures,
    )


def _stamped_under_both(scene: Scene, mine: IntpArray) -> int | None:
    """How many stamps a frame was sent with under each of its two moving parents, where that is most of each
    parent's: two sources placing it at once, taking turns in tf2's cache (aerostack2's Crazyflie: Gazebo's pose
    bridge under cf0 and the estimator under cf0/odom at each of the same 194 stamps); None otherwise (a frame
    moved from one parent to another, an object picked up)."""
    rows = scene.rows
    if rows.static[mine].any():
        return None
    stamps = [distinct(rows.stamp[theirs]) for _, theirs in split(mine, rows.parent[mine])]
    if len(stamps) != 2:
        return None
    shared = int(among(stamps[0], stamps[1]).sum())
    return shared if shared * 2 > min(len(stamps[0]), len(stamps[1])) else None


def _at_once_hint(scene: Scene, child: str, parents: list[str], shared: int) -> str:
    """Two sources placing ``child`` under ``parents`` at the same stamps: a parent that is a root no transform
    places (a simulator's model frame, a description's root) is where the other's odometry should end."""
    roots = [p for p in parents if (summary := scene.tree.frames.get(p)) is not None and summary.parent is None]
    at_once = (
        f"two sources place {child} at once, so what tf2 answers flips with whichever came last (not an object "
        "moved between parents)"
    )
    if len(roots) == 1:
        root, other = roots[0], next(p for p in parents if p != roots[0])
        return (
            f"{at_once}. {root} is a root no transform places (a simulator's model frame or a description's root, "
            f"with its own frames beneath): the odometry should end at it ({edge(other, root)}), or one source "
            f"stop sending {child}"
        )
    return f"{at_once}: let one of them send {child}, the other attach elsewhere"


def _parents_by_topic(scene: Scene, mine: IntpArray) -> tuple[list[str], list[str]] | None:
    """The parents a frame has on /tf_static and those it has on /tf, where no parent is on both: two
    descriptions of one mount (frand08/ramon_slam's cartographer bag: each laser under laser_link on /tf_static,
    under base_link from a static_transform_publisher on /tf); None where the topics do not split them."""
    rows = scene.rows
    static = rows.static[mine]
    if static.all() or not static.any():
        return None
    on_static = list(dict.fromkeys(rows.names[p] for p in rows.parent[mine[static]]))
    on_tf = list(dict.fromkeys(rows.names[p] for p in rows.parent[mine[~static]]))
    return None if set(on_static) & set(on_tf) else (on_static, on_tf)


def _mount_twice_hint(scene: Scene, child: str, mine: IntpArray, on_static: list[str], on_tf: list[str]) -> str:
    """A frame under one parent on /tf_static and another on /tf: two descriptions of one mount where its /tf
    samples are constant; where they move, odometry (or localization) ends at a link the robot's description
    puts under another frame (a real Neato's driver sending odom -> base_link beside a URDF rooted at
    base_footprint), and keeping "one description" of it would drop one of two different things."""
    kept = _kept_on_switch(scene, child)
    on_tf_values = scene.rows.values[mine[~scene.rows.static[mine]]]
    if not (on_tf_values == on_tf_values[0]).all():
        root = scene.tree.root_of(on_static[0])
        return (
            f"{child} is under {and_joined(on_static)} on /tf_static (a fixed joint of the robot's description) and "
            f"moves under {and_joined(on_tf)} on /tf (odometry or localization): a frame has one parent, so the "
            f"moving transform should end at the description's root ({edge(on_tf[0], root)}: e.g. the driver's "
            f"odometry child frame set to {root}), or the description start at {child}; {kept}"
        )
    return (
        f"{child} is under {and_joined(on_static)} on /tf_static and under {and_joined(on_tf)} on /tf: two "
        f"descriptions of one mount (e.g. a static_transform_publisher on /tf beside robot_state_publisher's "
        f"/tf_static); {kept}. Keep one description of it"
    )


def _kept_on_switch(scene: Scene, child: str) -> str:
    """What tf2 keeps of a frame sent on /tf_static and on /tf, in the words of the recording's ROS."""
    if scene.ros2:
        return "ROS 2's tf2 replaces the frame's cache each time it switches between the two topics"
    if scene.buffer.in_static_cache(child):
        return "ROS 1's tf2 keeps it a static frame, so whichever came last places it, under its parent, for every time"
    return (
        "ROS 1's tf2 keeps it a moving frame (its first transform came on /tf): the static one holds at its stamp only"
    )


def _each_from_others(scene: Scene, mine: IntpArray) -> bool:
    """Whether each parent of a frame sent on /tf_static came from publishers none of its other parents came
    from: two descriptions that place it differently (``causes``: their ``static_conflict`` explains it), not
    one publisher sending it under two parents (a mistake of that description alone)."""
    senders, rows = static_senders(scene), scene.rows
    groups = [set(senders.of(theirs)) for _, theirs in split(mine, rows.parent[mine])]
    return all(not (a & b) for a, b in itertools.combinations(groups, 2))


def _static_parents_hint(scene: Scene, child: str, mine: IntpArray, names: list[str], now: str) -> str:
    """A frame sent on /tf_static under several parents: by several publishers (two descriptions of the
    robot), or by one that changed its mind; tf2 keeps the last for every time either way."""
    senders = static_senders(scene)
    lost = listed([n for n in names if n != now])
    kept = (
        f"tf2 keeps the last static transform received for every time: {child} is under {now} at every time, and "
        f"its transform from {lost} is lost"
    )
    if len(senders.of(mine)) > 1:
        return (
            f"{kept}. {and_joined(senders.names(senders.of(mine)))} publish {child} on /tf_static under different "
            "parents (two descriptions of the robot): publish it from one of them"
        )
    return f"{kept}: fix the frame_id its publisher sends on /tf_static"


@register(
    "multiple_authorities",
    Severity.error,
    "two publishers of one edge (an error where at once they contradict each other, a warning where they agree)",
)
def multiple_authorities(scene: Scene) -> Iterator[Finding]:
    """Per moving edge; static edges per set of publishers (where they differ, ``static_conflict``). Where the
    recording names no publishers (ROS 2 bags), several are inferred from each edge's stream. Publishers at once
    further apart than the edge's own step and noise contradict each other (``broadcasters.AtOnce``): an error."""
    yield from inferred_broadcasters(scene)
    rows = scene.rows
    for parent, child, mine in rows.by_edge(rows.usable & ~rows.static):
        ids = rows.authority[mine]
        if ids.min() == ids.max():
            continue
        yield _authorities_finding(scene, parent, child, mine)
    for group in static_shared(scene):
        if not group.differ:  # else ``static_conflict`` says where they differ, and that they agree elsewhere
            yield _same_statics(scene, group)


@register("resent", Severity.info, "one publisher sending a sample again: a stamp and value it sent before")
def resent(scene: Scene) -> Iterator[Finding]:
    """Where the recording names no publishers (ROS 2 bags): edges whose stream repeats samples on the
    publisher's own timer, told apart from a second publisher (``multiple_authorities``)."""
    yield from resent_notes(scene)


def _same_statics(scene: Scene, group: StaticShared) -> Finding:
    """Several publishers of the same static transforms, with the same values: harmless, one finding for them all."""
    agree = [edge(p, c) for p, c in group.agree]
    senders = static_senders(scene)
    told = next((s.evidence for s in (senders.senders[k] for k in group.senders) if s.evidence), "")
    inferred = senders.inferred and told
    apart = f". Told apart by their messages (the recording names none): one {told}" if inferred else ""
    many = senders.inferred and len(group.names) > 2
    who = f"{len(group.names)} /tf_static publishers (unnamed)" if many else and_joined(group.names)
    hint = "fine: tf2 keeps one value per static transform, and here they are equal; one publisher is enough"
    robots = None if senders.inferred else robots_of(group.names)
    if robots is not None:  # three drones' MAVROS, each sending its local_origin -> local_origin_ned
        who = f"{who} ({robots_said(robots)})"
        hint = f"equal values, so no lookup differs today; but {prefix_hint(robots, group.agree[0], scene.ros2)}"
    return scene.finding(
        Severity.info,
        "multiple_authorities",
        f"{who} {'both' if len(group.names) == 2 else 'all'} send {counted(len(agree), 'static transform')}, with "
        f"the same values: {listed(agree)}{apart}",
        hint,
        tuple(dict.fromkeys(f for p, c in group.agree for f in (p, c))),
        group.rows,
        scene.arrival(group.rows),
    )


def _authorities_finding(scene: Scene, parent: str, child: str, mine: np.ndarray) -> Finding:
    rows = scene.rows
    who = scene.authorities_of(mine)
    spans, described = [], []
    for authority, theirs in split(mine, rows.authority[mine]):
        times = scene.arrival(theirs)
        spans.append((int(times.min()), int(times.max())))
        described.append(f"{rows.authorities[authority]} ({_during(scene, theirs, times)})")
    together = any(a[0] <= b[1] and b[0] <= a[1] for i, a in enumerate(spans) for b in spans[i + 1 :])
    parts = "; ".join(described)
    source = "nodes" if scene.publishers_known else "topics"
    figures: dict[str, float | int | str] = {}
    if together:
        apart = _at_once(scene, mine)
        severity, message = Severity.warning, f"{edge(parent, child)} comes from {len(who)} {source} at once: {parts}"
        if apart is not None:
            severity, message = apart.severity, f"{message}; {apart.said(scene)}{apart.follows()}"
            figures = apart.figures()
        hint = (
            "tf2 takes every sample as it comes, so lookups mix both publishers' values: turn the transform off "
            f"in all but one ({_turned_off_by(parent, child)})"
        )
        robots = robots_of(who) if scene.publishers_known else None
        if robots is not None:  # two drones' MAVROS: each robot's frame, not a second publisher of one
            message = f"{message} ({robots_said(robots)})"
            hint = prefix_hint(robots, (parent, child), scene.ros2)
        figures["at_once"] = 1
    else:
        severity = Severity.info
        message = f"{edge(parent, child)} was handed over between {source}, one after the other: {parts}"
        handover = spans[1][0]
        hint = (
            f"fine if intended (a node restarted under another name at {scene.at(handover)}); "
            f"the silence between them lasted {duration((handover - spans[0][1]) / 1e9)}"
        )
    found = scene.finding(severity, "multiple_authorities", message, hint, (parent, child), mine, scene.arrival(mine))
    return dataclasses.replace(found, figures=figures) if figures else found


#: Frames of localization and odometry (REP 105's, by their name without a namespace prefix), whose publishers
#: are turned off by a parameter of their own; a robot's links come from a state publisher.
_LOCALIZED = frozenset({"map", "odom", "base_link", "base_footprint"})


def _turned_off_by(parent: str, child: str) -> str:
    """How a second publisher of ``parent -> child`` is usually turned off: an odometry or localization node's
    parameter, or, for a robot's links (a humanoid's force sensors from two state publishers), one description."""
    if {base_name(parent), base_name(child)} & _LOCALIZED:
        return (
            "robot_localization's publish_tf, a driver's publish_tf or enable_odom_tf parameter, cartographer's "
            "provide_odom_frame"
        )
    return "two state publishers of one robot's links: keep the joint in one's description only, or run one of them"


def _at_once(scene: Scene, mine: IntpArray) -> AtOnce | None:
    """How far the publishers of one edge are apart at the same times, against the edge's own step (``at_once``)."""
    rows = scene.rows
    streams = []
    for _, theirs in split(mine, rows.authority[mine]):
        order = np.argsort(rows.stamp[theirs], kind="stable")
        streams.append((rows.stamp[theirs][order], rows.values[theirs][order]))
    return at_once(streams)


def _during(scene: Scene, rows: IntpArray, arrivals: Int64Array) -> str:
    """ "413 transforms from +0.0 s to +88.2 s"; where the first and last read the same (one transform, or
    several within a rounding), one moment: "1 transform 0.1 s before the first tf stamp", "2 transforms at
    +3.0 s"."""
    first, last = scene.rel(int(arrivals.min())), scene.rel(int(arrivals.max()))
    if first != last:
        return f"{transforms(len(rows))} from {first} to {last}"
    if first.startswith("-"):  # what was observed, not a negative offset that reads as an error
        return f"{transforms(len(rows))} {first[1:]} before the first tf stamp"
    return f"{transforms(len(rows))} {first if first.startswith('at ') else 'at ' + first}"
