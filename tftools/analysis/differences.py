"""Where two tree shapes differ: the one definition of "differs", for ``tfx diff`` and ``tfx wtf --expect``."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from tftools.analysis.expected import FrameShape, StaticValue, Tolerances, TreeShape
from tftools.core.rotation import Quat, Vec3, rpy_rebuilding


class Change(str, enum.Enum):
    """What differs about one frame from the first tree (A) to the second (B)."""

    lost = "lost"  # in A, not in B
    added = "added"  # in B, not in A
    reparented = "reparented"
    static = "static"  # static in one, moving in the other
    moved = "moved"  # a static edge's value (or a never changing one's on /tf), beyond the tolerances
    reordered = "reordered"  # the same static values received in another order: tf2 keeps another one
    rate = "rate"  # a moving edge's rate, beyond the tolerance
    clocks = "clocks"  # a moving edge's stamps on more time bases in one than in the other
    publishers = "publishers"


@dataclass(frozen=True)
class Difference:
    """One frame's difference; ``before`` is the frame in A, ``after`` in B (None where absent).
    ``translation_mm``/``rotation_deg`` say how far a static edge (or one held on /tf) moved, ``rate_change`` the
    rate's relative change (B / A - 1, -1 where B has no rate; None where A has none; whether it differs is
    ``rates_apart``'s)."""

    change: Change
    frame: str
    before: FrameShape | None
    after: FrameShape | None
    translation_mm: float = 0.0
    rotation_deg: float = 0.0
    rate_change: float | None = 0.0


def compare(a: TreeShape, b: TreeShape, tolerances: Tolerances) -> list[Difference]:
    """Every difference from ``a`` to ``b`` beyond ``tolerances``: A's frames in its order, then B's new ones.
    Publishers are compared where both name them; rates where both expect one (``rates_apart``)."""
    found: list[Difference] = []
    for name, before in a.frames.items():
        after = b.frames.get(name)
        if after is None:
            found.append(Difference(Change.lost, name, before, None))
        else:
            found.extend(_frame(before, after, tolerances))
    found.extend(Difference(Change.added, name, None, f) for name, f in b.frames.items() if name not in a.frames)
    return found


def _frame(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> list[Difference]:
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
        if rates_apart(before.rate_hz, after.rate_hz) * 100 > tolerances.rate_percent:
            a, b = before.rate_hz or 0.0, after.rate_hz or 0.0
            change = b / a - 1.0 if a > 0 else None
            found.append(Difference(Change.rate, name, before, after, rate_change=change))
        if before.clocks is not None and after.clocks is not None and before.clocks != after.clocks:
            found.append(Difference(Change.clocks, name, before, after))
    if not (before.static and after.static):
        found.extend(_held_moved(before, after, tolerances))
    known = before.publishers is not None and after.publishers is not None
    if known and set(before.publishers or ()) != set(after.publishers or ()):
        found.append(Difference(Change.publishers, name, before, after))
    return found


def _held_moved(before: FrameShape, after: FrameShape, tolerances: Tolerances) -> list[Difference]:
    """A mount held on /tf moved as much as one on /tf_static: compared where one side or both send it on /tf
    never changing (``held``), the other on /tf_static (a simulator's laser at 50 Hz beside the real robot's
    static_transform_publisher) or on /tf too."""
    a, b = _fixed(before), _fixed(after)
    if a is None or b is None:
        return []
    mm, deg = _apart(*a, *b)
    if mm > tolerances.translation_mm or deg > tolerances.rotation_deg:
        return [Difference(Change.moved, before.frame, before, after, translation_mm=mm, rotation_deg=deg)]
    return []


def _fixed(f: FrameShape) -> tuple[Vec3, Quat] | None:
    """An edge's one value: held on /tf, or static; None where it moves or its value is not known."""
    if f.held is not None:
        return f.held.translation, f.held.rotation
    if f.static and f.translation is not None and f.rotation is not None:
        return f.translation, f.rotation
    return None


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
    mm = 1000.0 * math.dist(t1, t2)
    # To a nanometre and a micro-degree: 0.122 - 0.121 is 1.0000000000000009 mm in floats, beyond a 1 mm tolerance.
    return round(mm, 6), round(rotation_angle_deg(q1, q2), 6)


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
    if d.change is Change.lost and before is not None:
        return f"{d.frame} is in {a} ({_place(before)}), not in {b}"
    if d.change is Change.added and after is not None:
        return f"{d.frame} is in {b} ({_place(after)}), not in {a}"
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
    if d.change is Change.moved and before.held is not None and after.held is not None:
        return (
            f"{edge} (on /tf, never changing in either) moved by {d.translation_mm:.1f} mm and "
            f"{d.rotation_deg:.2f}°: {_value(before.held)} in {a}, {_value(after.held)} in {b}"
        )
    if d.change is Change.moved and (before.held is not None or after.held is not None):
        return (
            f"{edge} moved by {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}°: {_value(before.held or before)} "
            f"in {a} ({_sent(before)}), {_value(after.held or after)} in {b} ({_sent(after)})"
        )
    if d.change is Change.moved:
        several = "".join(
            f"; {side} received {len(f.received)} values of it on /tf_static ({_received(f)}), tf2 keeps the last"
            for side, f in ((a, before), (b, after))
            if f.received
        )
        return (
            f"{edge} (static) moved by {d.translation_mm:.1f} mm and {d.rotation_deg:.2f}°: "
            f"{_value(before)} in {a}, {_value(after)} in {b}{several}"
        )
    if d.change is Change.rate:
        was, now = before.rate_hz or 0.0, after.rate_hz or 0.0
        if not was or not now:
            return f"{edge} at {_rate(now)} in {b}, {_rate(was)} in {a}"
        slower = b if now < was else a
        apart = rates_apart(was, now)
        return f"{edge} at {now:.1f} Hz in {b}, {was:.1f} Hz in {a} ({slower} {apart:.0%} slower)"
    if d.change is Change.clocks:
        return (
            f"{edge} is stamped on {_clocks(after)} in {b}, on {_clocks(before)} in {a} (stamps further apart than "
            "the transforms took to arrive: publishers on different clocks, as a recording replayed with its own tf "
            "beside live nodes; tfx wtf says which)"
        )
    return (
        f"{edge} published by {', '.join(after.publishers or ()) or 'nobody'} in {b}, "
        f"by {', '.join(before.publishers or ()) or 'nobody'} in {a}"
    )


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
    xyz = ", ".join(f"{v:.4f}" for v in f.translation)
    rpy = ", ".join(f"{round(math.degrees(v), 2) + 0.0:.2f}" for v in rpy_rebuilding(f.rotation))  # no -0.00
    return f"xyz [{xyz}] m rpy [{rpy}]°"


def _received(f: FrameShape) -> str:
    """A static edge's values in the order they first came: each with when, and how often where more than once."""
    return " then ".join(f"{_value(v)}{_when(v)}" for v in f.received)


def _when(v: StaticValue) -> str:
    said = [f"at {v.at_s:.3f} s"] if v.at_s is not None else []
    said += [f"{v.times} times"] if v.times > 1 else []
    return f" ({', '.join(said)})" if said else ""
