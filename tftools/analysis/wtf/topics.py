"""Checks of /tf against /tf_static: fixed transforms sent as moving ones, moving ones sent as fixed, and both;
and publishers of /tf_static that disagree."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from tftools.analysis.findings import Finding, Severity, counted
from tftools.analysis.listed import listed_publishers
from tftools.analysis.wtf.registry import register
from tftools.analysis.wtf.rows import Rows, split
from tftools.analysis.wtf.scene import Scene, and_joined, base_name, duration, edge, listed, transforms
from tftools.analysis.wtf.static_senders import Sender, StaticSenders, static_senders
from tftools.core.arrays import IntpArray
from tftools.core.figures import HELD_DEG, HELD_M, apart, held_groups, held_parts, rate_hz
from tftools.core.time import NS_PER_S
from tftools.sources.codecs.gather import distinct

#: A /tf edge is "static" only when it repeats one value this many times, this often, this long.
STATIC_MIN_SAMPLES = 10
STATIC_MIN_RATE_HZ = 1.0
STATIC_MIN_SPAN_S = 1.0
#: A constant edge sent in the same messages as moving ones this often is a joint at rest, not a fixed transform.
JOINT_SHARE = 0.9
#: Frames whose children move by nature (REP 105), though a robot standing still sends them constant.
WORLD_FRAMES = frozenset({"map", "odom", "world", "earth"})


def _by(scene: Scene, who: Sequence[str]) -> str:
    """ " by /node" where ROS1 names publishers; nothing where the authority is only the topic."""
    return f" by {', '.join(a for a in who if a)}" if scene.publishers_known and any(who) else ""


@register("static_on_dynamic", Severity.warning, "a constant transform sent on /tf at a high rate")
def static_on_dynamic(scene: Scene) -> Iterator[Finding]:
    """Not for edges moving by nature (REP 105's map -> odom -> base: a robot standing still), nor
    for edges another finding accounts for (a second parent or publisher, a loop), nor for joints
    that did not move: constant edges from robot_state_publisher (whose /tf joints are movable ones),
    sent in the same messages as moving ones (a gripper finger at rest among the arm's joints), or
    movable joints of the robot's description (a wheel its /joint_states hold at 0)."""
    rows = scene.rows
    contested = _contested(scene)
    joints = _movable_joints(scene)
    constant: list[tuple[str, str, np.ndarray]] = []
    moving = np.zeros(len(rows), bool)
    for parent, child, mine in rows.by_edge(rows.usable & ~rows.static):
        if _mark_moving(rows, mine, moving):
            constant.append((parent, child, mine))
    # the rate and stamps as monitor counts them (the samples tf2 stores: a stamp sent again is one)
    stored = {(s.parent, s.child): s for s in scene.stats}
    for parent, child, mine in constant:
        if len(mine) < STATIC_MIN_SAMPLES or child in contested or child in joints:
            continue
        if _moving_by_nature(parent) or child in (parent, *scene.tree.ancestors(parent)):
            continue  # moving by nature, or in a loop
        if (parent, child) in scene.detections:
            continue  # a detector sends what it sees while it sees it: an object at rest is no fixed transform
        stamps = rows.stamp[mine]
        span = int(stamps.max()) - int(stamps.min())
        own = stored.get((parent, child))
        samples = own.count if own else len(mine)
        hz = own.rate_hz if own else rate_hz(len(mine), span)
        if span < STATIC_MIN_SPAN_S * NS_PER_S or hz < STATIC_MIN_RATE_HZ or _joint_at_rest(rows, mine, moving):
            continue
        sent = transforms(len(mine)) if samples == len(mine) else f"{samples} stamps in {transforms(len(mine))}"
        yield scene.finding(
            Severity.warning,
            "static_on_dynamic",
            f"{edge(parent, child)} never changes, yet it is sent on /tf{_by(scene, scene.authorities_of(mine))} "
            f"{hz:.1f} times a second ({sent} over {duration(span / NS_PER_S)})",
            "publish it once on /tf_static (static_transform_publisher, or a fixed joint for robot_state_publisher): "
            "it then holds at every time and /tf carries less; ignore this if it is a joint that did not move "
            "during this recording",
            (parent, child),
            mine,
        )


def _movable_joints(scene: Scene) -> set[str]:
    """Child links of the description's movable joints: where ROS 2 names no publisher, the description
    says what robot_state_publisher's name would (a continuous wheel is no fixed transform)."""
    robot = scene.robot
    return set() if robot is None else {j.child for j in robot.description.joints if j.moving}


def _mark_moving(rows: Rows, mine: np.ndarray, moving: np.ndarray) -> bool:
    """Whether the ``mine`` rows (one edge's) never change; if they do, ``moving`` marked where one publisher's
    own samples change: two publishers that disagree (Stage's base_footprint -> base_link at z 0 beside
    robot_state_publisher's at 0.0102 m) move nothing. One edge's values held at a time, copied once. Exactly
    equal, not within ``figures.HELD_M``: a fixed transform re-sent is the same doubles each time, while a joint
    at rest computed again from its state jitters at rounding (a JetAcker's link1 in Gazebo, 8e-8°), which is no
    fixed transform to publish on /tf_static."""
    values = rows.values[mine]
    if (values == values[0]).all():
        return True
    authority = rows.authority[mine]
    publishers = distinct(authority.astype(np.int64))
    for who in publishers:
        own = values if len(publishers) == 1 else values[authority == who]
        if not (own == own[0]).all():
            moving[mine[authority == who]] = True
    return False


def _joint_at_rest(rows: Rows, mine: np.ndarray, moving: np.ndarray) -> bool:
    """Whether the ``mine`` rows are a movable joint that did not move: sent by robot_state_publisher
    (which sends fixed joints on /tf_static), or mostly in messages that also carried moving edges
    (transforms of one publisher with the same record time and stamp: one message)."""
    publishers = distinct(rows.authority[mine].astype(np.int64))
    if any(rows.authorities[int(a)].endswith("robot_state_publisher") for a in publishers):
        return True
    if not (rows.record_time[mine] > 0).all():
        return False
    together = np.zeros(len(mine), bool)
    for authority in publishers:
        theirs = rows.authority[mine] == authority
        others = np.flatnonzero(moving & (rows.authority.whole() == authority))
        keys = _message_keys(rows, mine[theirs])
        together[theirs] = np.isin(keys, _message_keys(rows, others))
    return bool(together.mean() >= JOINT_SHARE)


def _message_keys(rows: Rows, which: np.ndarray) -> np.ndarray:
    """One value per (record time, stamp) pair: the transforms of one message share it."""
    pairs = np.stack([rows.record_time[which], rows.stamp[which]], axis=1)
    return pairs.view(np.dtype((np.void, pairs.dtype.itemsize * 2))).ravel()


def _contested(scene: Scene) -> set[str]:
    """Child frames with more than one parent or publisher, or sent on both /tf_static and /tf (``mixed_static``'s:
    a recording replayed through rosbag play names one publisher for both, frand08/ramon_slam's cartographer bag)."""
    rows = scene.rows
    found = set()
    for child, mine in rows.by_child(rows.usable):
        if len(mine) < 2:  # one row: one parent, one publisher
            continue
        parents, publishers, static = rows.parent[mine], rows.authority[mine], rows.static[mine]
        if parents.min() != parents.max() or publishers.min() != publishers.max() or static.min() != static.max():
            found.add(child)
    return found


def _moving_by_nature(parent: str) -> bool:
    """map, odom, world, earth (REP 105): what is under them moves even when it stands still."""
    return base_name(parent) in WORLD_FRAMES or base_name(parent).startswith("odom")


@register("dynamic_on_static", Severity.error, "a changing transform on /tf_static")
def dynamic_on_static(scene: Scene) -> Iterator[Finding]:
    """Static edges whose value one publisher changed (publishers that disagree: ``static_conflict``; where
    the recording names none, ``static_senders`` tells them apart)."""
    rows = scene.rows
    senders = static_senders(scene)
    for parent, child, mine in rows.by_edge(rows.usable & rows.static):
        if len(mine) < 2:  # one value never changes
            continue
        values = rows.values[mine]
        group = held_groups(values)
        changed = np.flatnonzero(group[1:] != group[:-1]) + 1
        if not len(changed) or not _changes_its_own(rows, senders, mine):
            continue
        distinct = int(group.max()) + 1
        when = scene.arrival(mine[changed])
        who = scene.authorities_of(mine)
        evidence, hint = "", ""
        if senders.inferred:
            most = max((c for a in who if (c := listed_publishers(scene.recording.qos, a)) is not None), default=None)
            listed_said = f"; {most.said()}" if most is not None else ""
            evidence = (
                " (each /tf_static message holds every transform of the one before it, as one "
                f"StaticTransformBroadcaster sends them{listed_said}: one publisher, it seems; this recording does "
                "not name publishers)"
            )
            hint = f"; if two nodes send it ({scene.list_publishers('/tf_static')} lists them), publish it from one"
        finding = Finding(
            Severity.error,
            "dynamic_on_static",
            f"{edge(parent, child)} takes {distinct} different values on /tf_static"
            f"{_by(scene, who)}: it changed {counted(len(changed), 'time')}, first at "
            f"{scene.at_row(int(mine[changed[0]]))}{evidence}",
            "a static transform holds at every time, so tf2 applies its latest value to the past too: send a "
            "moving transform on /tf with current stamps (a TransformBroadcaster), and on /tf_static only what "
            f"never moves{hint}",
            (parent, child),
            who,
            int(when[0]),
            int(when[-1]),
            len(changed),
        )
        yield dataclasses.replace(finding, figures={"values": distinct, "changes": len(changed)})


def _changes_its_own(rows: Rows, senders: StaticSenders, mine: np.ndarray) -> bool:
    """Whether a publisher of the static edge ``mine`` sent it with more than one value."""
    return any(not all(held_parts(rows.values[theirs])) for _, theirs in split(mine, senders.sender[mine]))


@dataclass(frozen=True)
class StaticShared:
    """Static edges sent by the same several publishers (``static_senders``): those on which their values
    differ (with how far the other publishers' latest value is from the one tf2 keeps: metres, degrees),
    and the others."""

    senders: tuple[int, ...]
    names: list[str]  # the publishers as findings name them
    authorities: tuple[str, ...]  # as the recording names them (the topic, where it names none)
    differ: list[tuple[str, str, float, float]]
    agree: list[tuple[str, str]]
    rows: IntpArray  # every row of these edges


def static_shared(scene: Scene) -> list[StaticShared]:
    """Per set of publishers sending the same static edges: where they agree and where they differ."""
    return scene.shared("static_shared", lambda: _static_shared(scene))


def _static_shared(scene: Scene) -> list[StaticShared]:
    rows = scene.rows
    senders = static_senders(scene)
    groups: dict[tuple[int, ...], tuple[list[tuple[str, str, float, float]], list[tuple[str, str]], list[IntpArray]]]
    groups = {}
    for parent, child, mine in rows.by_edge(rows.usable & rows.static):
        ids = senders.sender[mine]
        if ids.min() == ids.max() or _changes_its_own(rows, senders, mine):
            continue
        differ, agree, members = groups.setdefault(senders.of(mine), ([], [], []))
        members.append(mine)
        values = rows.values[mine]
        metres, degrees = apart(values, np.broadcast_to(values[-1], values.shape))  # from the one tf2 keeps
        if metres.max() > HELD_M or degrees.max() > HELD_DEG:
            differ.append((parent, child, float(metres.max()), float(degrees.max())))
        else:
            agree.append((parent, child))
    shared = []
    for who, (d, a, m) in groups.items():
        every = np.sort(np.concatenate(m))
        shared.append(StaticShared(who, senders.names(who), scene.authorities_of(every), d, a, every))
    return shared


@register("static_conflict", Severity.error, "publishers of /tf_static that disagree on frames")
def static_conflict(scene: Scene) -> Iterator[Finding]:
    """Two robot descriptions or calibrations latched at once: one finding per set of publishers,
    with the frames they disagree on and by how much."""
    senders = static_senders(scene)
    for group in static_shared(scene):
        if group.differ:
            yield _conflict(scene, senders, group)


def _conflict(scene: Scene, senders: StaticSenders, group: StaticShared) -> Finding:
    worst = max(group.differ, key=lambda d: (d[2], d[3]))
    turned = max(group.differ, key=lambda d: (d[3], d[2]))
    kept = senders.senders[int(senders.sender[group.rows[-1]])]
    described = [f"{edge(p, c)} ({_apart(m, d)})" for p, c, m, d in group.differ]
    agree = f"; they agree on {counted(len(group.agree), 'other')}" if group.agree else ""
    most = (
        f"; up to {worst[2] * 1000:.1f} mm ({edge(worst[0], worst[1])}) and {turned[3]:.2f}° "
        f"({edge(turned[0], turned[1])})"
        if len(group.differ) > 1
        else ""  # one transform: its figures are said with it
    )
    arrivals = scene.arrival(group.rows)
    figures: dict[str, float | int | str] = {
        "publishers": len(group.senders),
        "transforms_differing": len(group.differ),
        "transforms_agreeing": len(group.agree),
        "apart_m_max": worst[2],
        "apart_deg_max": turned[3],
    }
    if senders.inferred:
        who = [senders.senders[k] for k in group.senders]
        sent = "; ".join(
            f"publisher {s.number}: {counted(s.transforms, 'transform')} at {scene.at(s.first)}{_times(s)}"
            + (f", which {s.evidence}" if s.evidence else "")
            for s in who
        )
        message = (
            f"/tf_static came from {len(who)} publishers, told apart by their messages (this recording does not "
            f"name them): {sent}. They send different values for "
            f"{counted(len(group.differ), 'static transform')}: {listed(described)}{most}{agree}. tf2 keeps the "
            f"values last received for every time: publisher {kept.number}'s"
        )
        hint = (
            "two descriptions of one robot are published at once (a driver's own static transforms and "
            "robot_state_publisher's URDF, two robot_state_publishers, two calibration files): publish each frame "
            f"from one of them ({scene.list_publishers('/tf_static')} lists the publishers); tfx diff compares two "
            "recordings' calibrations"
        )
        for i, s in enumerate(who, 1):
            figures |= {f"publisher_{i}_transforms": s.transforms, f"publisher_{i}_at_s": s.first / NS_PER_S}
    else:
        message = (
            f"{and_joined(group.names)} send different values for "
            f"{counted(len(group.differ), 'static transform')}: {listed(described)}; the largest "
            f"{edge(worst[0], worst[1])}, {_apart(worst[2], worst[3])}{agree}. tf2 keeps the values last received "
            f"for every time: {kept.name}'s, at {scene.at(int(arrivals.max()))}"
        )
        hint = (
            "two descriptions of one robot are published at once (two calibration files, two "
            "robot_state_publishers with different URDFs): publish each frame from one of them; "
            "tfx diff compares two recordings' calibrations"
        )
    finding = Finding(
        Severity.error,
        "static_conflict",
        message,
        hint,
        tuple(dict.fromkeys(f for p, c, _, _ in group.differ for f in (p, c))),
        group.authorities,
        int(arrivals.min()),
        int(arrivals.max()),
        len(group.differ),
    )
    return dataclasses.replace(finding, figures=figures)


def _times(sender: Sender) -> str:
    """How often a publisher told apart sent, true of what it sent again: its first message, or later ones
    holding more transforms or other values (a copy ``tfx static --repair`` wrote of the real Create 3's two
    descriptions re-sends the merged 35 every 5 s after publisher 2's first 23)."""
    if sender.messages <= 1:
        return ""
    if sender.alike == sender.messages:
        return f" (the same {sender.messages} times)"
    held = [f"up to {sender.most} transforms"] if sender.most > sender.transforms else []
    held += ["other values of them"] if sender.revalued else []
    same = f"the same {sender.alike} times; " if sender.alike > 1 else ""
    more = sender.messages - sender.alike
    return f" ({same}{more} more {'message' if more == 1 else 'messages'} with {' and '.join(held) or 'other stamps'})"


def _apart(metres: float, degrees: float) -> str:
    return f"{metres * 1000:.1f} mm and {degrees:.2f}° apart"


@register("mixed_static", Severity.error, "one frame sent both on /tf_static and on /tf")
def mixed_static(scene: Scene) -> Iterator[Finding]:
    rows = scene.rows
    for name, mine in rows.by_child(rows.usable):
        static = rows.static[mine]
        if static.all() or not static.any():
            continue
        fixed, moving = mine[static], mine[~static]
        effect = _mixed_effect(scene, name, mine, static)
        parents = sorted({rows.names[p] for p in rows.parent[mine].tolist()})
        yield scene.finding(
            Severity.error,
            "mixed_static",
            f"{name} (under {listed(parents)}) is sent on /tf_static{_by(scene, scene.authorities_of(fixed))} "
            f"({transforms(len(fixed))}) and on /tf{_by(scene, scene.authorities_of(moving))} "
            f"({transforms(len(moving))}, {_from(scene, moving)}){_two_values(rows, fixed, moving)}: "
            f"{effect}",
            "send each frame on one topic: /tf_static if it never moves, /tf otherwise",
            (name, *parents),
            mine,
            scene.arrival(mine),
        )


def _from(scene: Scene, moving: IntpArray) -> str:
    """When the first /tf transform came; one stamped 0 with no time of arrival (an MCAP's log time 0: a
    Franka's JSON MCAP) has none: its stamp was never set, no moment to say as "from 0.000"."""
    arrivals = scene.arrival(moving)
    first = int(np.argmin(arrivals))
    if arrivals[first] == 0 and scene.rows.stamp[moving[first : first + 1]][0] == 0:
        return "the first stamped 0 (unset)"
    return f"from {scene.at(int(arrivals[first]))}"


def _two_values(rows: Rows, fixed: IntpArray, moving: IntpArray) -> str:
    """Where the /tf transforms of a frame hold one value under the parent of its /tf_static one, and the
    two differ (a tf1 static_transform_publisher beside robot_state_publisher's URDF): by how much."""
    values = rows.values[moving]
    same_parent = bool((rows.parent[moving] == rows.parent[fixed[-1:]][0]).all())
    if not same_parent or bool((values != values[0]).any()):
        return ""
    metres, degrees = apart(rows.values[fixed[-1:]], values[:1])
    if float(metres[0]) == 0 and float(degrees[0]) == 0:
        return ""
    return f", one value on each, {_apart(float(metres[0]), float(degrees[0]))}"


def _mixed_effect(scene: Scene, child: str, mine: IntpArray, static: np.ndarray) -> str:
    """What the recording's tf2 made of a frame sent on both topics (``static``: which of ``mine`` came on
    /tf_static): ROS 1's keeps the cache its first sample made; ROS 2's replaces it at each switch."""
    if scene.buffer.semantics == "ros2":
        switches = np.flatnonzero(static[1:] != static[:-1]) + 1
        last = scene.at(int(scene.arrival(mine[switches[-1:]])[0]))
        held = (
            "the last /tf_static value, for every time, and none of the /tf transforms"
            if static[-1]
            else "only the /tf transforms since then"
        )
        return (
            "ROS 2's tf2 replaces a frame's cache when it switches between /tf_static and /tf, dropping what it "
            f"held: it switched {counted(len(switches), 'time')}, the last at {last} to "
            f"{'/tf_static' if static[-1] else '/tf'}, so tf2 holds {held}"
        )
    if scene.buffer.in_static_cache(child):
        return (
            "tf2 made it a static frame (its first transform came on /tf_static), so each /tf transform "
            "replaces its value for every time"
        )
    return (
        "tf2 made it a moving frame (its first transform came on /tf), so the /tf_static one counts only at its stamp"
    )
