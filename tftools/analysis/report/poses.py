"""Every frame's pose in one fixed frame over a recording, at a bounded number of times: what the report's 3D
view draws. Looked up with the buffer's batch lookups (``Buffer.lookup_many``), so each pose is tf2's."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from tftools.analysis.edges import chain_moving_edges
from tftools.analysis.frames import FrameTree
from tftools.core.arrays import BoolArray, FloatArray, Int64Array
from tftools.core.buffer import Buffer

if TYPE_CHECKING:
    from tftools.sources.timeline import Timeline

#: Times at which every frame is placed, at most: enough for a slider to move smoothly.
MAX_TIMES = 120
#: Frames placed at most, the nearest the fixed frame first (a page of thousands of frames would be megabytes
#: of poses, and a picture no one could read).
MAX_FRAMES = 300
#: Roots preferred as the fixed frame, when several trees have as many frames (REP 105's order).
PREFERRED = ("map", "world", "odom")


@dataclass(frozen=True)
class FramePoses:
    """Frames' poses in ``fixed`` at ``times`` (ns): ``translations`` (F, T, 3), ``rotations`` (F, T, 4,
    x y z w), ``valid`` (F, T) where tf2 could look the frame up; ``parents`` each frame's latest parent."""

    fixed: str
    times: Int64Array
    frames: tuple[str, ...]
    parents: tuple[str | None, ...]
    translations: FloatArray
    rotations: FloatArray
    valid: BoolArray
    unplaced: tuple[str, ...]  # frames in another tree than ``fixed``'s, or beyond ``MAX_FRAMES``: not drawn
    #: Frames whose chain is stamped on another clock than the recording's (``Timeline.span_of``): placed as far
    #: into their own stamps as each of ``times`` is into the recording's, as ``+S`` counts for them.
    own_clock: tuple[str, ...] = ()


def choose_fixed(tree: FrameTree) -> str | None:
    """The root of the tree with the most frames (map, world or odom before others of as many)."""
    if not tree.roots:
        return None

    def size(root: str) -> int:
        count, todo = 0, [root]
        while todo:
            frame = todo.pop()
            count += 1
            todo += tree.children.get(frame, [])
        return count

    return max(
        sorted(tree.roots), key=lambda r: (size(r), r in PREFERRED, -PREFERRED.index(r) if r in PREFERRED else -9)
    )


def frame_poses(
    buffer: Buffer,
    tree: FrameTree,
    start: int,
    end: int,
    fixed: str | None = None,
    timeline: Timeline | None = None,
) -> FramePoses | None:
    """Every frame of ``fixed``'s tree (default ``choose_fixed``) placed in it at up to ``MAX_TIMES``
    times spread evenly from ``start`` to ``end`` (ns, stamps' clock); a frame whose chain is on another clock
    than ``timeline``'s tf span (an arm on simulated time among detections on wall time), at the same times
    into its own stamps (``FramePoses.own_clock``). None for a buffer without frames."""
    fixed = fixed if fixed is not None else choose_fixed(tree)
    if fixed is None:
        return None
    count = MAX_TIMES if end > start else 1
    # Offsets, not epoch nanoseconds, through floats: 1.7e18 in a double is 256 ns coarse, and a last time past
    # the last stamp was looked up in nothing (every frame missing at the slider's end).
    times = np.unique(start + np.linspace(0, end - start, count).round().astype(np.int64))
    in_tree: list[str] = []
    todo = [fixed]
    while todo and len(in_tree) < MAX_FRAMES:
        frame = todo.pop(0)
        in_tree.append(frame)
        todo += sorted(tree.children.get(frame, []))
    translations = np.zeros((len(in_tree), len(times), 3))
    rotations = np.tile([0.0, 0.0, 0.0, 1.0], (len(in_tree), len(times), 1))
    valid = np.ones((len(in_tree), len(times)), bool)
    own_clock = []
    for k, frame in enumerate(in_tree[1:], start=1):
        at = times
        moving = list(chain_moving_edges(buffer, fixed, frame)) if timeline is not None else []
        if timeline is not None and moving and (own_start := timeline.span_of(moving)[0]) != timeline.tf_start:
            at = times - timeline.tf_start + own_start
            own_clock.append(frame)
        looked = buffer.lookup_many(fixed, frame, at)
        translations[k], rotations[k], valid[k] = looked.translations, looked.rotations, looked.valid
    parents = tuple(tree.frames[f].parent if f in tree.frames else None for f in in_tree)
    unplaced = tuple(sorted(set(tree.frames) - set(in_tree)))
    return FramePoses(
        fixed, times, tuple(in_tree), parents, translations, rotations, valid, unplaced, tuple(sorted(own_clock))
    )
