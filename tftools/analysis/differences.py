"""Where two tree shapes differ: the one definition of "differs", for ``tfx diff`` and ``tfx wtf --expect``."""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass, replace

from tftools.analysis.expected import FrameShape, StaticValue, Tail, Tolerances, TreeShape
from tftools.core.figures import STOP_FLOOR, silence_limit, stopped
from tftools.core.rotation import Quat, Vec3, rpy_rebuilding
from tftools.core.time import NS_PER_S


class Change(str, enum.Enum):
    """What differs about one frame from the first tree (A) to the second (B)."""

    lost = "lost"  # in A, not in B
    added = "added"  # in B, not in A
    reparented = "reparented"
    static = "static"  # static in one, moving in the other
    moved = "moved"  # a static edge's value (or what of one on /tf never changes in either), beyond the tolerances
    reordered = "reordered"  # the same static values received in another order: tf2 keeps another one
    rate = "rate"  # a moving edge's rate, beyond the tolerance
    clocks = "clocks"  # a moving edge's stamps on more time bases in one, or from the epoch in one only
    publishers = "publishers"
    stopped = "stopped"  # a moving edge that stopped before its recording ended in one, sent to the end in the other
    renamed = "renamed"  # a frame gone from A and one come in B under the same parent, at nearly the same place


class Part(str, enum.Enum):
    """What an edge held still in both recordings is (``FrameShape.joint``), where both say the same."""

    joint = "joint"  # held at another position: the robot's posture
    fixed = "fixed"  # a fixed part's value: a calibration, or another description of the robot


@dataclass(frozen=True)
class Difference:
    """One frame's difference; ``before`` is the frame in A, ``after`` in B (None where absent).
    ``translation_mm``/``rotation_deg`` say how far a static edge (or what of one on /tf stays fixed) moved,
    ``rate_change`` the rate's relative change (B / A - 1, -1 where B has no rate; None where A has none; whether
    it differs is ``rates_apart``'s), of the publisher ``source`` where the edge has several (None: the edge's).
    ``part`` says what an edge held still in both is (a joint, a fixed part; None: not known), ``beneath`` how many
    frames are below it in A: each moved with it, none a difference of its own for that. ``said_with`` names the
    frames whose like difference is said with this one, not each on its own line: a rate's, edges that came in the
    same messages as this one in A, in B or in both (``sent_in``: "a", "b", "both") and changed rate as it did
    (``beneath_all``: every one of them is below it in A); a stop's, edges that stopped early in the same recording
    at the same point. ``mimics`` names the frames of the joints that follow this one (the recorded description's
    ``<mimic>``), held apart with it; ``folded``, the differences of those frames, each as it was before it was
    said with this one (what each says of a damaged side is said too). ``other`` names the frame's other name: a
    rename's in A (``frame`` is its name in B); a frame lost or added beside a rename, the name its namesake has in
    the other recording. ``kept``: of a fixed edge said with a moved one above it (``folded``), how far (mm,
    degrees) its frame is from its place in A, in that edge's parent; None where only its orientation was kept."""

    change: Change
    frame: str
    before: FrameShape | None
    after: FrameShape | None
    translation_mm: float = 0.0
    rotation_deg: float = 0.0
    rate_change: float | None = 0.0
    source: str | None = None
    part: Part | None = None
    beneath: int = 0
    said_with: tuple[str, ...] = ()
    sent_in: str = ""
    beneath_all: bool = False
    mimics: tuple[str, ...] = ()
    folded: tuple[Difference, ...] = ()
    other: str = ""
    kept: tuple[float, float] | None = None


def compare(a: TreeShape, b: TreeShape, tolerances: Tolerances) -> list[Difference]:
    """Every difference from ``a`` to ``b`` beyond ``tolerances``: A's frames in its order, then B's new ones.
    Publishers are compared where both name them; rates where both expect one (``rates_apart``)."""
    found: list[Difference] = []
    for name, before in a.frames.items():
        after = b.frames.get(name)
        if after is None:
            found.append(Difference(Change.lost, name, before, None))
        else:
            found.extend(frame_differences(before, after, tolerances))
    found.extend(Difference(Change.added, name, None, f) for name, f in b.frames.items() if name not in a.frames)
    found = _stopped_together(_changed_together(_mimicked(found, a, b), a, b, tolerances))
    if any(d.part is not None for d in found):
        below = _beneath(a)
        found = [replace(d, beneath=below.get(d.frame, 0)) if d.part is not None else d for d in found]
    return found


def _mimicked(found: list[Difference], a: TreeShape, b: TreeShape) -> list[Difference]:
    """``found`` with each mimic joint held apart (``moved``, held in both) said with the joint it follows, where
    that one is held apart too (``Difference.mimics``): the PR2's fingers follow its gripper's one joint. Which
    joint mimics which is the recorded descriptions' (``TreeShape.mimics``; where both hold one, what both say);
    a recording without one is left as it was, nothing guessed."""
    leaders = _agreed(a.mimics, b.mimics)
    held = {d.frame for d in found if d.change is Change.moved and _held_both(d)}
    followers: dict[str, list[str]] = {}
    for frame in held:
        leader, seen = leaders.get(frame), {frame}
        while leader is not None and leader in leaders and leader not in seen:  # the joint a chain follows
            seen.add(leader)
            leader = leaders[leader]
        if leader is not None and leader in held and leader != frame:
            followers.setdefault(leader, []).append(frame)
    if not followers:
        return found
    folded = {f for names in followers.values() for f in names}
    order = {d.frame: i for i, d in enumerate(found)}
    moved = {d.frame: d for d in found if d.change is Change.moved}

    def said(d: Difference) -> Difference:
        names = tuple(sorted(followers[d.frame], key=order.__getitem__))
        return replace(d, mimics=names, folded=tuple(moved[f] for f in names))

    return [
        said(d) if d.frame in followers and d.change is Change.moved else d
        for d in found
        if not (d.frame in folded and d.change is Change.moved)
    ]


def _agreed(mine: dict[str, str], theirs: dict[str, str]) -> dict[str, str]:
    """The mimic joints both descriptions say alike; one side's where only one recording holds a description."""
    if not mine or not theirs:
        return mine or theirs
    return {frame: leader for frame, leader in mine.items() if theirs.get(frame) == leader}


def _held_both(d: Difference) -> bool:
    return d.before is not None and d.after is not None and d.before.held is not None and d.after.held is not None


def _changed_together(found: list[Difference], a: TreeShape, b: TreeShape, tolerances: Tolerances) -> list[Difference]:
    """``found`` with the edges that came together and changed alike said once, with the first of them in A's order
    (``Difference.said_with``): their rates (within the tolerance of each other's in A, and in B), or their
    publishers (the same in A, and in B). Together: in the same messages (``TreeShape.together``, in A or in B),
    else each in its own message but stamped alike in both (``TreeShape.stamped``: one publisher's). The Kinect's
    five edges in one robot_state_publisher's messages at 50 Hz in one recording, at 10 Hz from
    static_transform_publishers in the other, are one change; so are a Neato driver's odometry and its two wheels,
    each in its own message with the same stamps, slower in 2024 than in 2023."""
    found = _grouped(found, a, b, Change.rate, lambda one, other: _alike(one, other, tolerances))
    return _grouped(found, a, b, Change.publishers, _same_publishers)


def _grouped(
    found: list[Difference], a: TreeShape, b: TreeShape, kind: Change, alike: Callable[[Difference, Difference], bool]
) -> list[Difference]:
    """``found`` with the differences of ``kind`` of edges that came together and are ``alike`` said once
    (``_changed_together``); each said with another is kept in its ``folded``."""
    chosen = [d for d in found if d.change is kind and d.source is None and d.before and d.after]
    if len(chosen) < 2:
        return found
    evidence = (
        [_group_of(a.together), _group_of(b.together)],  # the same messages, in A or in B
        [_group_of(a.stamped), _group_of(b.stamped)],  # stamped alike, in A and in B
    )
    taken: set[str] = set()
    said: dict[str, Difference] = {}
    below = _below(a)
    for i, first in enumerate(chosen):
        if first.frame in taken:
            continue
        others = [d for d in chosen[i + 1 :] if d.frame not in taken and alike(first, d)]
        mates, sent_in = _mates(first, others, *evidence)
        if mates:
            taken.update(d.frame for d in mates)
            names = tuple(d.frame for d in mates)
            beneath = set(names) <= below.get(first.frame, set())
            said[first.frame] = replace(
                first, said_with=names, sent_in=sent_in, beneath_all=beneath, folded=tuple(mates)
            )

    def folded(d: Difference) -> bool:
        return d.change is kind and d.source is None and d.frame in taken

    def leads(d: Difference) -> bool:
        return d.change is kind and d.source is None and d.frame in said

    return [said[d.frame] if leads(d) else d for d in found if not folded(d)]


def _mates(
    first: Difference, others: list[Difference], messages: list[dict[str, int]], stamps: list[dict[str, int]]
) -> tuple[list[Difference], str]:
    """Which of ``others`` came with ``first`` and where (``Difference.sent_in``): in the same messages, in A ("a"),
    in B ("b") or in both; else, none of them so, each in its own message stamped alike in A and in B
    ("stamped")."""
    mates: list[Difference] = []
    sides: set[int] = set()
    for other in others:
        shared = {k for k in (0, 1) if _same_group(messages[k], first.frame, other.frame)}
        if shared:
            mates.append(other)
            sides |= shared
    if mates:
        return mates, "both" if sides == {0, 1} else "a" if sides == {0} else "b"
    mates = [d for d in others if all(_same_group(stamps[k], first.frame, d.frame) for k in (0, 1))]
    return mates, "stamped" if mates else ""


def _same_publishers(one: Difference, other: Difference) -> bool:
    """Whether two edges were published by the same nodes in A, and by the same in B."""
    assert one.before is not None and one.after is not None and other.before is not None and other.after is not None
    return set(one.before.publishers or ()) == set(other.before.publishers or ()) and set(
        one.after.publishers or ()
    ) == set(other.after.publishers or ())


def _stopped_together(found: list[Difference]) -> list[Difference]:
    """``found`` with the edges that stopped early in the same recording, sent to the end in the other, at one
    point (their last arrivals no further apart than ``_stopped_apart`` allows one edge's) said once, with the first
    of them in A's order (``Difference.said_with``): a simulation paused before its recording ended stops its
    odometry and its wheels at once."""
    stops = [d for d in found if d.change is Change.stopped and _one_stopped(d)]
    taken: set[str] = set()
    said: dict[str, Difference] = {}
    for i, first in enumerate(stops):
        if first.frame in taken:
            continue
        mates = [d for d in stops[i + 1 :] if d.frame not in taken and _at_one_point(first, d)]
        if mates:
            taken.update(d.frame for d in mates)
            said[first.frame] = replace(first, said_with=tuple(d.frame for d in mates), folded=tuple(mates))
    if not said:
        return found
    return [said.get(d.frame, d) if d.change is Change.stopped else d for d in found if not _stop_taken(d, taken)]


def _one_stopped(d: Difference) -> bool:
    """Whether a ``stopped`` difference is an edge stopped early in one recording, sent to the end in the other."""
    tails = (d.before.tail, d.after.tail) if d.before is not None and d.after is not None else (None, None)
    return tails[0] is not None and tails[1] is not None and tails[0].stopped != tails[1].stopped


def _at_one_point(one: Difference, other: Difference) -> bool:
    """Whether two edges stopped early in the same recording at one point: their last arrivals there no further
    apart than the slower one's own rate explains (``figures.stopped`` at ``STOP_FLOOR``)."""
    sides = []
    for d in (one, other):
        assert d.before is not None and d.after is not None and d.before.tail is not None and d.after.tail is not None
        early = d.before if d.before.tail.stopped else d.after
        assert early.tail is not None
        sides.append((early is d.before, early.tail.arrived, early.rate_hz or 0.0))
    (side, arrived, rate), (other_side, other_arrived, other_rate) = sides
    return side == other_side and not stopped(abs(arrived - other_arrived), min(rate, other_rate), STOP_FLOOR)


def _stop_taken(d: Difference, taken: set[str]) -> bool:
    return d.change is Change.stopped and d.frame in taken


def _group_of(together: tuple[tuple[str, ...], ...]) -> dict[str, int]:
    return {name: k for k, names in enumerate(together) for name in names}


def _same_group(group: dict[str, int], one: str, other: str) -> bool:
    return one in group and group.get(other) == group[one]


def _alike(one: Difference, other: Difference, tolerances: Tolerances) -> bool:
    """Whether two edges' rates are within the tolerance of each other in A and in B."""
    assert one.before is not None and one.after is not None and other.before is not None and other.after is not None
    return all(
        rates_apart(x or 0.0, y or 0.0) * 100 <= tolerances.rate_percent
        for x, y in ((one.before.rate_hz, other.before.rate_hz), (one.after.rate_hz, other.after.rate_hz))
    )


def _beneath(tree: TreeShape) -> dict[str, int]:
    """How many frames are below each frame of ``tree`` (0 for a leaf; a loop's frames count none)."""
    return {name: len(names) for name, names in _below(tree).items()}


def _below(tree: TreeShape) -> dict[str, set[str]]:
    """The frames below each frame of ``tree`` (none for a leaf; a loop's frames have none)."""
    children: dict[str, list[str]] = {}
    for f in tree.frames.values():
        if f.parent is not None:
            children.setdefault(f.parent, []).append(f.frame)
    found: dict[str, set[str]] = {}
    for root in (name for name, f in tree.frames.items() if f.parent is None):
        order, stack = [], [root]
        while stack:
            order.append(stack.pop())
            stack.extend(children.get(order[-1], ()))
        for name in reversed(order):
            found[name] = {c for child in children.get(name, ()) for c in (child, *found[child])}
    return found


def frame_differences(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> list[Difference]:
    """What differs about one frame present in both trees (A's ``before``, B's ``after``), beyond ``tolerances``."""
    name = before.frame
    if before.parent != after.parent:
        return [Difference(Change.reparented, name, before, after)]
    if before.parent is None:
        return []
    found = []
    if before.static != after.static:
        found.append(Difference(Change.static, name, before, after))
    elif before.static:
        mm, deg = _moved(before, after)
        if mm > tolerances.translation_mm or deg > tolerances.rotation_deg:
            kind = Change.reordered if _same_values(before, after, tolerances) else Change.moved
            found.append(Difference(kind, name, before, after, translation_mm=mm, rotation_deg=deg))
    else:
        # a detection's rate is how often it was seen, its end when last seen, its fixed parts the detector's
        # (a rotation it never estimates): what the camera saw in each recording, not how the tree differs
        detection = before.detection or after.detection
        found.extend(_rates(before, after, tolerances) if not detection else [])
        counted = before.clocks is not None and after.clocks is not None and before.clocks != after.clocks
        if counted and not any(d.change is Change.clocks for d in found):
            found.append(Difference(Change.clocks, name, before, after))
        if not detection and _stopped_apart(before, after):
            found.append(Difference(Change.stopped, name, before, after))
    if not (before.static and after.static) and not (before.detection or after.detection):
        found.extend(_fixed_parts(before, after, tolerances))
    known = before.publishers is not None and after.publishers is not None
    if known and set(before.publishers or ()) != set(after.publishers or ()):
        found.append(Difference(Change.publishers, name, before, after))
    return found


def _stopped_apart(before: FrameShape, after: FrameShape) -> bool:
    """Whether a moving edge stopped early in one recording and was sent to the end in the other, or stopped in
    both at points (its last arrival, seconds into each recording) further apart than its own rate explains: more
    than ``figures.silence_limit`` of the slower of its two rates. Sent to the end in both: no difference."""
    was, now = before.tail, after.tail
    if was is None or now is None or not (was.stopped or now.stopped):
        return False
    if was.stopped != now.stopped:
        return True
    return stopped(abs(was.arrived - now.arrived), min(before.rate_hz or 0.0, after.rate_hz or 0.0), STOP_FLOOR)


def _rates(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> list[Difference]:
    """A moving edge's rates beyond the tolerance, like with like: each publisher's where either side has several
    (``FrameShape.rates``) and both name them (okoslam's odom -> base_link: cartographer's 198 Hz and a bridge's
    20 Hz, not their sum over spans that differ); else the edge's. Rates counted on clocks of different kinds
    (``FrameShape.epoch``: 33.3 Hz of a slow simulation's time against 3.9 Hz of a wall clock) are no rate
    difference: where they are apart, a ``clocks`` one says the clocks differ."""
    name = before.frame
    apart = [
        (source, was, now)
        for source, was, now in _rate_pairs(before, after)
        if rates_apart(was, now) * 100 > tolerances.rate_percent
    ]
    if apart and _other_seconds(before, after, tolerances):
        return [Difference(Change.clocks, name, before, after)]
    return [
        Difference(
            Change.rate, name, before, after, rate_change=(now or 0.0) / was - 1.0 if was else None, source=source
        )
        for source, was, now in apart
    ]


def _other_seconds(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> bool:
    """Whether an edge's rates in two recordings count seconds of different lengths: stamped from the epoch in
    one, from a start in the other (``epoch``), and in one of them the stamps advance at another pace than the
    recording's clock (``pace``: a simulation slower than real time). A simulation at real time, or recorded on
    its own clock, counts seconds as a wall clock does; two simulations count the same simulated seconds."""
    return _kinds_apart(before, after) and any(
        f.pace is not None and rates_apart(f.pace, 1.0) * 100 > tolerances.rate_percent for f in (before, after)
    )


def _kinds_apart(before: FrameShape, after: FrameShape) -> bool:
    """Whether an edge is stamped from the epoch in one recording and from a start in the other."""
    return before.epoch is not None and after.epoch is not None and before.epoch != after.epoch


def _rate_pairs(before: FrameShape, after: FrameShape) -> list[tuple[str | None, float | None, float | None]]:
    """The rates of an edge to compare (source, A's, B's): by source where either side has several and both
    sides say each source's (their common ones); else the edge's own (a tree file's, of all its publishers)."""
    if before.rates or after.rates:
        mine, theirs = _by_source(before), _by_source(after)
        if mine is not None and theirs is not None:
            return [(source, rate, theirs[source]) for source, rate in mine.items() if source in theirs]
    return [(None, before.rate_hz, after.rate_hz)]


def _by_source(f: FrameShape) -> dict[str, float | None] | None:
    """A moving edge's rate by source: its several (``rates``), or its one named publisher's; None where it says
    neither (one unnamed publisher, or a tree file naming several without their rates)."""
    if f.rates:
        return {r.source: r.rate_hz for r in f.rates}
    if f.publishers is not None and len(f.publishers) == 1:
        return {f.publishers[0]: f.rate_hz}
    return None


def _fixed_parts(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> list[Difference]:
    """What of an edge stays fixed in both recordings, where one or both send it on /tf (``_fixed``), compared as a
    static edge's value is: a wheel held still in one recording and turning in the other moved by as far as its
    origins are apart; a simulator's laser held on /tf at 50 Hz as far from the real robot's static mount."""
    (t1, q1), (t2, q2) = fixed_value(before), fixed_value(after)
    mm = _mm_apart(t1, t2) if t1 is not None and t2 is not None else 0.0
    deg = _deg_apart(q1, q2) if q1 is not None and q2 is not None else 0.0
    if mm > tolerances.translation_mm or deg > tolerances.rotation_deg:
        held = before.held is not None and after.held is not None and before.joint == after.joint
        part = None if not held or before.joint is None else Part.joint if before.joint else Part.fixed
        return [Difference(Change.moved, before.frame, before, after, mm, deg, part=part)]
    return []


def fixed_value(f: FrameShape) -> tuple[Vec3 | None, Quat | None]:
    """What of an edge's value stays fixed: all of it where it is static or held on /tf (``held``), a turning
    joint's origin or a sliding joint's rotation (``Motion``); None where nothing does or it is not known."""
    if f.held is not None:
        return f.held.translation, f.held.rotation
    if f.static:
        return f.translation, f.rotation
    if f.motion is not None:
        return f.motion.translation, f.motion.rotation
    return None, None


def rates_apart(a: float | None, b: float | None) -> float:
    """How far two rates (Hz) are apart, the same whichever comes first: the slower's shortfall from the faster
    (10 and 12.1 Hz: 0.17 either way; B / A - 1 said +21% one way, -17% the other, flagged at 20% one way only).
    From an expected tree's rate, a fall is measured as before (4 Hz against 10: 0.60). 0 where either expects
    any rate (None: a tree file without ``rate_hz``, a URDF) or neither has one; 1 where one has no rate (0: fewer
    than two samples stamped apart) beside the other's: an edge seen once did not keep a rate of 10 Hz."""
    if a is None or b is None or (a <= 0 and b <= 0):
        return 0.0
    if a <= 0 or b <= 0:
        return 1.0
    return 1.0 - min(a, b) / max(a, b)


def _moved(before: FrameShape, after: FrameShape) -> tuple[float, float]:
    """How far a static edge moved: the translation's distance (mm) and the rotation's angle (degrees)."""
    if before.translation is None or after.translation is None or before.rotation is None or after.rotation is None:
        return 0.0, 0.0
    return _apart(before.translation, before.rotation, after.translation, after.rotation)


def _apart(t1: Vec3, q1: Quat, t2: Vec3, q2: Quat) -> tuple[float, float]:
    return _mm_apart(t1, t2), _deg_apart(q1, q2)


# To a nanometre and a micro-degree: 0.122 - 0.121 is 1.0000000000000009 mm in floats, beyond a 1 mm tolerance.
def _mm_apart(t1: Vec3, t2: Vec3) -> float:
    return round(1000.0 * math.dist(t1, t2), 6)


def _deg_apart(q1: Quat, q2: Quat) -> float:
    return round(rotation_angle_deg(q1, q2), 6)


def _same_values(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> bool:
    """Whether both sides received a static edge with the same several values (each within the tolerances
    of one of the other side's), so that only their order tells which one tf2 keeps."""

    def within(a: StaticValue, b: StaticValue) -> bool:
        mm, deg = _apart(a.translation, a.rotation, b.translation, b.rotation)
        return mm <= tolerances.translation_mm and deg <= tolerances.rotation_deg

    mine, theirs = before.received, after.received
    return (
        bool(mine and theirs)
        and all(any(within(a, b) for b in theirs) for a in mine)
        and all(any(within(a, b) for a in mine) for b in theirs)
    )


def rotation_angle_deg(a: Quat, b: Quat) -> float:
    """The angle of the rotation from ``a`` to ``b`` (degrees, 0 to 180), for quaternions of any norm."""
    norms = math.hypot(*a) * math.hypot(*b)
    cosine = min(1.0, abs(sum(x * y for x, y in zip(a, b, strict=True))) / norms) if norms > 0 else 1.0
    return math.degrees(2.0 * math.acos(cosine))


def describe(d: Difference, a: str = "A", b: str = "B") -> str:
    """One line saying what differs, the first tree called ``a``, the second ``b``."""
    before, after = d.before, d.after
    if d.change is Change.lost and before is not None and d.other:
        return (
            f"{d.frame} of {a} ({_place(before)}, {_moving(before)}) is at no place of {b}'s frames: {b}'s "
            f"{d.frame} is {a}'s {d.other}, renamed"
        )
    if d.change is Change.added and after is not None and d.other:
        return (
            f"{d.frame} of {b} ({_place(after)}, {_moving(after)}) is at no place of {a}'s frames: {a}'s "
            f"{d.frame} is {d.other} in {b}, renamed"
        )
    if d.change is Change.renamed and before is not None and after is not None and d.folded:
        back = d.folded[0]
        return (
            f"{d.other} and {d.frame} swapped names, each the one frame of {after.parent} near the other's place in "
            f"{a}: {a}'s {d.other} is {b}'s {d.frame}, {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}° apart; "
            f"{a}'s {back.other} is {b}'s {back.frame}, {back.translation_mm:.1f} mm and {back.rotation_deg:.2f}° "
            f"apart"
        )
    if d.change is Change.renamed and before is not None and after is not None and not _whole(before):
        return (
            f"{d.other} in {a} is {d.frame} in {b}, renamed: {_place(before)} in both, with "
            f"{'its child' if len(d.said_with) == 1 else f'its {len(d.said_with)} children'} beneath it in both: "
            f"{', '.join(d.said_with)}"
        )
    if d.change is Change.renamed and before is not None and after is not None:
        return (
            f"{d.other} in {a} is {d.frame} in {b}, renamed: the one frame of {after.parent} in each near that place, "
            f"{d.translation_mm:.1f} mm and {d.rotation_deg:.2f}° apart ({_moving(before)} in {a}, {_moving(after)} "
            f"in {b})"
        )
    if d.change is Change.lost and before is not None:
        return f"{d.frame} is in {a} ({_place(before)}), not in {b}{_beneath_it(d, b, a)}"
    if d.change is Change.added and after is not None:
        return f"{d.frame} is in {b} ({_place(after)}), not in {a}{_beneath_it(d, a, b)}"
    assert before is not None and after is not None
    edge = f"{before.parent} -> {d.frame}"
    if d.change is Change.reparented:
        return f"{d.frame} is {_place(before)} in {a}, {_place(after)} in {b}"
    if d.change is Change.static:
        return f"{edge} is {_kind(before)} in {a}, {_kind(after)} in {b}"
    if d.change is Change.reordered:
        return (
            f"{edge} (static): {a} and {b} each received the same {len(before.received)} values of it on "
            f"/tf_static, in another order (at: seconds into each recording): {a} {_received(before)}; {b} "
            f"{_received(after)}. tf2 keeps the last received, so the order alone makes the kept values "
            f"{d.translation_mm:.1f} mm and {d.rotation_deg:.2f}° apart"
        )
    if d.change is Change.moved and d.part is not None and before.held is not None and after.held is not None:
        what, why = _PARTS[d.part]
        return (
            f"{edge}, {what} {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}° apart{why}: "
            f"{_value(before.held)} in {a}, {_value(after.held)} in {b}{_with_it(d.beneath)}{_mimics(d.mimics)}"
            f"{_kept(d)}"
        )
    if d.change is Change.moved and before.held is not None and after.held is not None:
        return (
            f"{edge} (on /tf, never changing in either) moved by {d.translation_mm:.1f} mm and "
            f"{d.rotation_deg:.2f}°: {_value(before.held)} in {a}, {_value(after.held)} in {b}{_kept(d)}"
        )
    if d.change is Change.moved and before.static != after.static and _whole(before) and _whole(after):
        return (
            f"{edge} moved by {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}°: {_value(before.held or before)} "
            f"in {a} ({_sent(before)}), {_value(after.held or after)} in {b} ({_sent(after)})"
        )
    if d.change is Change.moved and not (before.static and after.static):
        (t1, q1), (t2, q2) = fixed_value(before), fixed_value(after)
        fixed = [(f"{d.translation_mm:.1f} mm", "translation")] if t1 and t2 else []
        fixed += [(f"{d.rotation_deg:.2f}°", "rotation")] if q1 and q2 else []
        on_tf = "" if before.static or after.static else " (on /tf)"
        return (
            f"{edge}{on_tf} moved by {' and '.join(f for f, _ in fixed)} (its {' and '.join(p for _, p in fixed)}, "
            f"fixed in both): {_moving(before)} in {a}, {_moving(after)} in {b}"
        )
    if d.change is Change.moved:
        several = "".join(
            f"; {side} received {len(f.received)} values of it on /tf_static ({_received(f)}), tf2 keeps the last"
            for side, f in ((a, before), (b, after))
            if f.received
        )
        return (
            f"{edge} (static) moved by {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}°: "
            f"{_value(before)} in {a}, {_value(after)} in {b}{several}{_kept(d)}"
        )
    if d.change is Change.rate:
        was, now = _source_rate(before, d.source), _source_rate(after, d.source)
        edge = f"{edge} from {d.source}" if d.source is not None else edge
        sums = "".join(_sum(side, f) for side, f in ((a, before), (b, after)) if d.source is None)
        if not was or not now:
            return f"{edge} at {_rate(now)} in {b}, {_rate(was)} in {a}{sums}"
        slower = b if now < was else a
        apart = rates_apart(was, now)
        return (
            f"{edge} at {now:.1f} Hz in {b}, {was:.1f} Hz in {a} ({slower} {apart:.0%} slower){sums}"
            f"{_sent_with(d, a, b)}"
        )
    if d.change is Change.stopped and before.tail is not None and after.tail is not None:
        if before.tail.stopped and after.tail.stopped:
            rate = min(before.rate_hz or 0.0, after.rate_hz or 0.0)
            return (
                f"{edge} stopped early in both, at points {_s(abs(before.tail.arrived - after.tail.arrived))} apart "
                f"(more than its {_rate(rate)} explains: {_s(int(silence_limit(rate, STOP_FLOOR)))}): in {a} its last "
                f"sample {_last(before.tail, a)}; in {b} {_last(after.tail, b)}"
            )
        (early, tail), (other, sent) = sorted(((a, before.tail), (b, after.tail)), key=lambda side: not side[1].stopped)
        return (
            f"{edge} stopped early in {early}: its last sample (stamped {_stamp(tail.stamp)}) arrived "
            f"{_s(tail.arrived)} into {early}'s {_s(tail.length)}, silent for its last {_s(tail.silent)}; in {other} "
            f"it was sent to the end ({_s(sent.arrived)} of {_s(sent.length)}){_stopped_with(d, early, other)}"
        )
    if d.change is Change.clocks and _kinds_apart(before, after):
        return (
            f"{edge} is stamped on {_base(after)} in {b}, on {_base(before)} in {a}: "
            f"{_rate(after.rate_hz or 0.0)}{_paced(after, b)} in {b} and {_rate(before.rate_hz or 0.0)}"
            f"{_paced(before, a)} in {a} count seconds of different lengths, not compared as rates"
        )
    if d.change is Change.clocks:
        return (
            f"{edge} is stamped on {_clocks(after)}{_by_clock(after)} in {b}, "
            f"on {_clocks(before)}{_by_clock(before)} in {a} "
            "(stamps further apart than the transforms took to arrive: publishers on different clocks, as a "
            "recording replayed with its own tf beside live nodes; tfx wtf says which)"
        )
    return (
        f"{edge} published by {_publishers(after)} in {b}, by {_publishers(before)} in {a}"
        f"{_sent_with(d, a, b, 'changed publishers')}"
    )


#: What an edge held still in both recordings is, by ``Part``.
_PARTS = {
    Part.joint: ("a joint (it came with the joints that move), held at positions", ""),
    Part.fixed: (
        "a fixed part (it came with the fixed transforms, apart from the joints), set",
        " (a calibration, or another description of the robot)",
    ),
}


def _sent_with(d: Difference, a: str, b: str, changed: str = "changed rate") -> str:
    """The edges said with a rate's or publishers' change (``said_with``): how they came with it, and their
    frames."""
    if not d.said_with:
        return ""
    n = len(d.said_with)
    which = f"the {n} frames beneath it" if d.beneath_all and n > 1 else "the frame beneath it" if d.beneath_all else ""
    which = which or (f"{n} more frames" if n > 1 else "one more frame")
    if d.sent_in == "stamped":
        how = f"each in messages of its own but stamped as it was, sample for sample, in {a} and in {b} (one source)"
    else:
        side = {"a": f"in {a}", "b": f"in {b}", "both": f"in {a} and in {b}"}[d.sent_in]
        how = f"sent in the same messages {side}"
    return f"; the edges of {which}, {how}, {changed} with it: {', '.join(d.said_with)}"


def _stopped_with(d: Difference, early: str, other: str) -> str:
    """The edges said with a stop (``said_with``): they stopped at the same point, sent to the end in the other."""
    if not d.said_with:
        return ""
    n = len(d.said_with)
    which = f"the edges of {n} more frames" if n > 1 else "the edge of one more frame"
    return f"; {which} stopped in {early} at the same point, each sent to the end in {other}: {', '.join(d.said_with)}"


def _beneath_it(d: Difference, without: str, within: str) -> str:
    """What is said with a frame lost or added: the frames beneath it, absent with it (``folded``), the detections
    of its parent absent with it (``subtrees.whole_subtrees``), or its children that are roots where it is absent
    (``said_with`` alone)."""
    children = d.said_with
    if not children:
        return ""
    shape = d.before or d.after
    if d.folded and shape is not None and shape.detection and all(f.before or f.after for f in d.folded):
        parent = shape.parent
        which = "one more detection" if len(children) == 1 else f"{len(children)} more detections"
        return f", nor {which} of {parent} (a detector's, named as it names what it sees): {', '.join(children)}"
    if d.folded:
        which = "the frame" if len(children) == 1 else f"the {len(children)} frames"
        return f", nor {which} beneath it: {', '.join(children)}"
    which = "its child" if len(children) == 1 else f"its {len(children)} children"
    roots = "is a root" if len(children) == 1 else "are roots"
    return f"; {which} in {within} {roots} in {without}: {', '.join(children)}"


def _kept(d: Difference) -> str:
    """The frames beneath a moved fixed edge that kept their place or orientation in its parent (``said_with`` of a
    ``moved``, each ``kept``): each one's own edge moved to undo it."""

    if d.change is not Change.moved or not d.said_with or d.before is None:
        return ""
    return "".join(
        f"; beneath it, {x.frame} kept its place in {d.before.parent} (within {x.kept[0]:.1f} mm and "
        f"{x.kept[1]:.2f}°): its own edge ({x.before.parent} -> {x.frame}) moved by {x.translation_mm:.1f} mm and "
        f"{x.rotation_deg:.2f}° to undo it"
        if x.kept is not None
        else f"; beneath it, {x.frame} kept its orientation in {d.before.parent}: its own edge ({x.before.parent} -> "
        f"{x.frame}) turned by {x.rotation_deg:.2f}° only to undo it"
        for x in d.folded
        if x.before is not None
    )


def _mimics(mimics: tuple[str, ...]) -> str:
    """The mimic joints said with the joint they follow (``Difference.mimics``), by their frames."""
    if not mimics:
        return ""
    joints = "its mimic joint's frame" if len(mimics) == 1 else f"its {len(mimics)} mimic joints' frames"
    return f"; {joints} (the recorded /robot_description's <mimic>) followed it: {', '.join(mimics)}"


def _with_it(beneath: int) -> str:
    if not beneath:
        return ""
    return f"; the {beneath} frames beneath it moved with it" if beneath > 1 else "; the frame beneath it moved with it"


def _last(tail: Tail, side: str) -> str:
    """Where an edge's last sample came in a recording it stopped early in."""
    return (
        f"(stamped {_stamp(tail.stamp)}) arrived {_s(tail.arrived)} into {side}'s {_s(tail.length)}, silent for its "
        f"last {_s(tail.silent)}"
    )


def _s(ns: int) -> str:
    return f"{ns / NS_PER_S:.1f} s"


def _stamp(ns: int) -> str:
    return f"{ns / NS_PER_S:.3f}"


def _publishers(f: FrameShape) -> str:
    """Who published an edge, each at its rate where it had several (``rates``)."""
    rates = {r.source: r.rate_hz for r in f.rates}
    named = [f"{p} ({_rate(rates[p])})" if p in rates else p for p in f.publishers or ()]
    return ", ".join(named) or "nobody"


def _source_rate(f: FrameShape, source: str | None) -> float:
    """The rate of ``source``'s samples of an edge (``_by_source``), or the edge's (None)."""
    if source is None:
        return f.rate_hz or 0.0
    return (_by_source(f) or {}).get(source) or 0.0


def _sum(side: str, f: FrameShape) -> str:
    """Where an edge's rate is the sum of several sources' (``rates``), each of them."""
    return f"; {side}'s is the sum of its {len(f.rates)} sources'{_by(f)}" if f.rates else ""


def _by(f: FrameShape) -> str:
    """Each of an edge's several sources (``rates``) at its rate, in brackets; "" where it has one."""
    return f" ({', '.join(f'{r.source} {_rate(r.rate_hz)}' for r in f.rates)})" if f.rates else ""


#: A clock's pace (``FrameShape.pace``) is said where it is this far from 1 (a robot's clock against its recorder's
#: ticks within it).
_PACE_SAID = 0.05


def _by_clock(f: FrameShape) -> str:
    """Each clock's rate (``_by``) where an edge's sources are its clocks (no node named), else ""."""
    return _by(f) if all(r.source.startswith("clock ") for r in f.rates) else ""


def _base(f: FrameShape) -> str:
    kind = "a wall clock (from the epoch)" if f.epoch else "a clock from a start (simulated time, or a boot's)"
    return f"{kind} advancing {f.pace:.3f} s a second of its recording" if _paced_apart(f) and f.pace else kind


def _paced(f: FrameShape, side: str) -> str:
    """An edge's rate on its recording's clock, where its stamps' clock runs at another pace (``pace``)."""
    if not (_paced_apart(f) and f.pace and f.rate_hz):
        return ""
    return f" of {side}'s clock ({f.rate_hz * f.pace:.1f} Hz of its recording's)"


def _paced_apart(f: FrameShape) -> bool:
    return f.pace is not None and abs(f.pace - 1.0) > _PACE_SAID


def _moving(f: FrameShape) -> str:
    """What of a moving edge on /tf stays fixed and how far the rest moves (``Motion``), or its ``held`` value."""
    if f.held is not None:
        return f"held at {_value(f.held)}"
    if f.static:
        return f"static at {_value(f)}"
    motion = f.motion
    if motion is None or (motion.translation is None and motion.rotation is None):
        return "moving"
    if motion.translation is not None:
        return f"at xyz [{_xyz(motion.translation)}] m, turning by up to {motion.turn_deg:.2f}°"
    assert motion.rotation is not None
    return f"at rpy [{_rpy(motion.rotation)}]°, moving by up to {motion.spread_mm:.1f} mm"


def _whole(f: FrameShape) -> bool:
    """Whether all of an edge's value stays fixed: static, or held on /tf."""
    return f.static or f.held is not None


def _sent(f: FrameShape) -> str:
    return "on /tf, never changing" if f.held is not None else "static"


def _rate(hz: float) -> str:
    return f"{hz:.1f} Hz" if hz > 0 else "no rate (one sample, or none stamped apart)"


def _clocks(f: FrameShape) -> str:
    return "one clock" if f.clocks == 1 else f"{f.clocks} clocks"


def _place(f: FrameShape) -> str:
    return f"a child of {f.parent}" if f.parent is not None else "a root"


def _kind(f: FrameShape) -> str:
    if not f.static:
        return f"moving at {f.rate_hz:.1f} Hz" if f.rate_hz else "moving"
    if f.on_tf_hz > 0:
        return (
            f"static to tf2 though sent at {f.on_tf_hz:.1f} Hz on /tf ({f.frame}'s first transform came on "
            "/tf_static: ROS 1's tf2 keeps the frame static, each transform replacing its value for every time)"
        )
    return "static"


def _value(f: FrameShape | StaticValue) -> str:
    if f.translation is None or f.rotation is None:
        return "unknown"
    return f"xyz [{_xyz(f.translation)}] m rpy [{_rpy(f.rotation)}]°"


def _xyz(t: Vec3) -> str:
    return ", ".join(f"{v:.4f}" for v in t)


def _rpy(q: Quat) -> str:
    return ", ".join(f"{round(math.degrees(v), 2) + 0.0:.2f}" for v in rpy_rebuilding(q))  # no -0.00


def _received(f: FrameShape) -> str:
    """A static edge's values in the order they first came: each with when, and how often where more than once."""
    return " then ".join(f"{_value(v)}{_when(v)}" for v in f.received)


def _when(v: StaticValue) -> str:
    said = [f"at {v.at_s:.3f} s"] if v.at_s is not None else []
    said += [f"{v.times} times"] if v.times > 1 else []
    return f" ({', '.join(said)})" if said else ""
