"""Walking the frame tree: tf2's ``walkToTopParent`` and ``getLatestCommonTime``.

A lookup walks from the source frame towards the root, accumulating each edge, then from the
target frame until it meets the frame where the first walk stopped; the two halves compose into
the answer. As in tf2, one walk serves every question, an accumulator deciding what it gathers
at each edge: the transform (``lookup``), or the parent only (``can_transform``, ``chain``).
Where a walk stops, which edge failed first and which message is raised follow tf2 step by
step, because users compare our errors with theirs. ``native/`` compiles the same walk (``kernels.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import NamedTuple

from tftools.core.errors import ConnectivityError, ExtrapolationError, TransformError, UnknownFrameError
from tftools.core.frames import NO_PARENT
from tftools.core.history import EdgeHistory, Gap
from tftools.core.rotation import IDENTITY_QUAT, ZERO_VEC, Quat, Vec3, quat_conjugate, quat_multiply, quat_rotate
from tftools.core.semantics import Dialect
from tftools.core.time import duration_to_sec, to_sec

#: tf2's ``MAX_GRAPH_DEPTH``: a walk longer than this is taken for a loop.
MAX_GRAPH_DEPTH = 1000


class Tree(NamedTuple):
    """What a walk reads: each frame's history (None for a root), the frame names, and the tf2
    whose words it reports failures in."""

    histories: Sequence[EdgeHistory | None]
    names: Sequence[str]
    dialect: Dialect


# --- the walk ------------------------------------------------------------------------------

#: How a walk succeeds (tf2's ``WalkEnding``): the target is an ancestor of the source, the
#: source an ancestor of the target, or both meet at one top frame.
TARGET_PARENT_OF_SOURCE, SOURCE_PARENT_OF_TARGET, FULL_PATH = range(3)


class CanTransformAccum:
    """tf2's ``CanTransformAccum``: each edge's parent only."""

    def gather(self, hist: EdgeHistory, time: int) -> int | Gap:
        return hist.parent_at(time)

    def accum(self, source_side: bool) -> None:
        pass

    def finalize(self, ending: int, time: int) -> None:
        pass


class TransformAccum(CanTransformAccum):
    """tf2's ``TransformAccum``: each side's edges composed up to where the walk stopped, then
    ``T_target^source`` and the ``time`` it was looked up at."""

    def __init__(self) -> None:
        self.edge: list[float] = []
        self.source: tuple[Vec3, Quat] = (ZERO_VEC, IDENTITY_QUAT)
        self.target: tuple[Vec3, Quat] = (ZERO_VEC, IDENTITY_QUAT)
        self.result: tuple[Vec3, Quat] = (ZERO_VEC, IDENTITY_QUAT)
        self.time = 0

    def gather(self, hist: EdgeHistory, time: int) -> int | Gap:
        got = hist.sample(time)
        if isinstance(got, Gap):
            return got
        parent, self.edge = got
        return parent

    def accum(self, source_side: bool) -> None:
        v = self.edge
        q = (v[3], v[4], v[5], v[6])
        av, aq = self.source if source_side else self.target
        r = quat_rotate(q, av)
        composed = (r[0] + v[0], r[1] + v[1], r[2] + v[2]), quat_multiply(q, aq)
        if source_side:
            self.source = composed
        else:
            self.target = composed

    def finalize(self, ending: int, time: int) -> None:
        self.time = time
        if ending == TARGET_PARENT_OF_SOURCE:
            self.result = self.source
            return
        tv, tq = self.target
        iq = quat_conjugate(tq)
        iv = quat_rotate(iq, (-tv[0], -tv[1], -tv[2]))
        if ending == SOURCE_PARENT_OF_TARGET:
            self.result = iv, iq
            return
        sv, sq = self.source
        r = quat_rotate(iq, sv)
        self.result = (r[0] + iv[0], r[1] + iv[1], r[2] + iv[2]), quat_multiply(iq, sq)


def walk_to_top_parent(
    tree: Tree,
    target_id: int,
    source_id: int,
    time: int,
    accum: CanTransformAccum,
    frames: list[int] | None = None,
) -> None:
    """tf2's ``walkToTopParent``: up from the source towards the root, then up from the target
    until the frame the first walk stopped at, ``accum`` gathering each edge and composing it
    (time 0: the latest common time). Raises tf2's error where it fails. ``frames`` gets the
    frames from source to target that the answer composes (tf2's frame chain)."""
    if time == 0:
        time = latest_common_time(tree, target_id, source_id)
    histories = tree.histories
    up: list[int] = []
    frame = top = source_id
    source_gap: Gap | None = None
    while True:
        up.append(frame)
        hist = histories[frame]
        if hist is None:
            top = frame
            break
        parent = accum.gather(hist, time)
        if isinstance(parent, Gap):
            top, source_gap = frame, parent
            break
        if frame == target_id:
            accum.finalize(TARGET_PARENT_OF_SOURCE, time)
            if frames is not None:
                frames += up
            return
        accum.accum(True)
        top, frame = frame, parent
        if len(up) > MAX_GRAPH_DEPTH:
            raise UnknownFrameError.loop(frames_as_string(tree))

    down: list[int] = []
    frame = target_id
    while frame != top:
        down.append(frame)
        hist = histories[frame]
        if hist is None:
            break
        parent = accum.gather(hist, time)
        if isinstance(parent, Gap):
            raise _extrapolation(tree, parent, source_id, target_id)
        if frame == source_id:
            accum.finalize(SOURCE_PARENT_OF_TARGET, time)
            if frames is not None:
                frames += down[::-1]
            return
        accum.accum(False)
        frame = parent
        if len(down) > MAX_GRAPH_DEPTH:
            raise UnknownFrameError.loop(frames_as_string(tree))

    if frame != top:
        if source_gap is not None:
            raise _extrapolation(tree, source_gap, source_id, target_id)
        raise ConnectivityError.between(tree.names[target_id], tree.names[source_id])
    accum.finalize(FULL_PATH, time)
    if frames is not None:
        # Both walks reached ``top``; keep the source side up to the first frame they share.
        shared = set(down) | {top}
        meet = next(i for i, f in enumerate(up) if f in shared)
        below_meet = down[: down.index(up[meet])] if up[meet] in down else down
        frames += up[: meet + 1] + below_meet[::-1]


def lookup(tree: Tree, target_id: int, source_id: int, time: int) -> tuple[Vec3, Quat, int]:
    """Translation, rotation and stamp of ``T_target^source`` at ``time`` (0: latest common)."""
    accum = TransformAccum()
    walk_to_top_parent(tree, target_id, source_id, time, accum)
    return (*accum.result, accum.time)


def can_transform(tree: Tree, target_id: int, source_id: int, time: int) -> bool:
    """Whether ``lookup`` succeeds, walking parents only."""
    try:
        walk_to_top_parent(tree, target_id, source_id, time, CanTransformAccum())
    except TransformError:
        return False
    return True


def chain(tree: Tree, target_id: int, source_id: int, time: int) -> list[int]:
    """The frame ids from source to target that a lookup at ``time`` composes."""
    frames: list[int] = []
    walk_to_top_parent(tree, target_id, source_id, time, CanTransformAccum(), frames)
    return frames


def latest_common_time(tree: Tree, target_id: int, source_id: int) -> int:
    """tf2's ``getLatestCommonTime``: the newest stamp every dynamic edge of the chain has."""
    if source_id == target_id:
        hist = tree.histories[source_id]
        return hist.latest_stamp if hist is not None else 0
    source_side = _edges_up(tree, source_id, lambda parent: parent == target_id)
    if source_side and source_side[-1][1] == target_id:
        return _newest_common(source_side)
    source_parents = [parent for _, parent in source_side]
    target_side = _edges_up(tree, target_id, lambda parent: parent == source_id or parent in source_parents)
    meet = target_side[-1][1] if target_side else NO_PARENT
    if meet == source_id:
        return _newest_common(target_side)
    if meet not in source_parents:
        raise ConnectivityError.between(tree.names[target_id], tree.names[source_id])
    return _newest_common(target_side + source_side[: source_parents.index(meet) + 1])


def _edges_up(tree: Tree, frame: int, stop: Callable[[int], bool]) -> list[tuple[int, int]]:
    """The latest stamp and parent of each edge up from ``frame``, to the first whose parent is a
    ``stop``, or to a frame without samples."""
    edges: list[tuple[int, int]] = []
    while (hist := tree.histories[frame]) is not None and len(hist):
        edges.append((hist.latest_stamp, hist.latest_parent))
        frame = hist.latest_parent
        if stop(frame):
            break
        if len(edges) > MAX_GRAPH_DEPTH:
            raise UnknownFrameError.loop(frames_as_string(tree))
    return edges


def _newest_common(edges: list[tuple[int, int]]) -> int:
    """The oldest of the edges' latest stamps, static edges (stamp 0) aside; 0 if all are static."""
    return min((stamp for stamp, _ in edges if stamp), default=0)


def frames_as_string(tree: Tree) -> str:
    """tf2's ``allFramesAsString``."""
    lines = []
    for frame_id, hist in enumerate(tree.histories):
        if hist is not None:
            lines.append(f"Frame {tree.names[frame_id]} exists with parent {tree.names[hist.latest_parent]}.\n")
    return "".join(lines)


def frames_as_yaml(tree: Tree, broadcasters: Mapping[int, str]) -> str:
    """tf2's ``allFramesAsYAML``: parent, latest broadcaster (``broadcasters``: per frame id, who sent
    its last accepted sample), rate and time span per child frame."""
    ros2 = tree.dialect.ros2
    if len(tree.names) == 1:  # no frame at all
        return "[]" if ros2 else "{}"
    lines = []
    for frame_id, hist in enumerate(tree.histories):
        if hist is None or not len(hist):
            continue
        latest, oldest = (0, 0) if hist.static else (hist.latest_stamp, hist.oldest_stamp)
        count = 1 if hist.static else len(hist)
        if ros2:
            rate = count * 1e9 / max(latest - oldest, 100_000)
            newest_text, oldest_text = tree.dialect.seconds(latest), tree.dialect.seconds(oldest)
            length = duration_to_sec(latest - oldest)
        else:
            rate = count / max(to_sec(latest) - to_sec(oldest), 0.0001)
            newest_text, oldest_text = f"{to_sec(latest):.3f}", f"{to_sec(oldest):.3f}"
            length = to_sec(latest - oldest)
        lines += [
            f"{tree.names[frame_id]}: ",
            f"  parent: '{tree.names[hist.latest_parent]}'",
            f"  broadcaster: '{broadcasters.get(frame_id, 'no recorded authority')}'",
            f"  rate: {rate:.3f}",
            f"  most_recent_transform: {newest_text}",
            f"  oldest_transform: {oldest_text}",
            f"  buffer_length: {length:.3f}",
        ]
    return "\n".join(lines) + "\n" if lines else ""


def _extrapolation(tree: Tree, gap: Gap, source_id: int, target_id: int) -> ExtrapolationError:
    return tree.dialect.extrapolation(gap, tree.names[source_id], tree.names[target_id])
