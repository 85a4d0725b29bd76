"""The frame tree summarised: each frame's parent, publishers, rate and time span."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tftools.core.buffer import Buffer
from tftools.core.time import NS_PER_S


@dataclass(frozen=True)
class FrameSummary:
    """One frame as the tree shows it; a root has no parent and no samples."""

    frame: str
    parent: str | None  # the latest parent
    static: bool = False
    count: int = 0
    authorities: tuple[str, ...] = ()
    first_stamp: int = 0
    last_stamp: int = 0
    parents: tuple[str, ...] = ()  # every parent it ever had, first seen first

    @property
    def rate_hz(self) -> float:
        """Mean publishing rate over the samples' span; 0 for a static or single-sample edge."""
        span = self.last_stamp - self.first_stamp
        if self.static or self.count < 2 or span <= 0:
            return 0.0
        return (self.count - 1) * NS_PER_S / span


@dataclass
class FrameTree:
    """Every frame, and the tree the latest parents make."""

    frames: dict[str, FrameSummary]
    children: dict[str, list[str]] = field(default_factory=dict)

    @property
    def roots(self) -> list[str]:
        """Frames with no parent: one for a healthy tree (a loop has none)."""
        return [name for name, f in self.frames.items() if f.parent is None]


def frame_tree(buffer: Buffer) -> FrameTree:
    """Summarise ``buffer``'s frames and arrange them by their latest parent."""
    frames = {name: FrameSummary(name, None) for name in buffer.frames}
    for name, hist in buffer.histories():
        parent_ids, first_seen = np.unique(hist.parents[np.argsort(hist.sequence, kind="stable")], return_index=True)
        parents = tuple(buffer.frame_name(int(p)) for p in parent_ids[np.argsort(first_seen)])
        authority_ids = np.unique(hist.authorities)
        frames[name] = FrameSummary(
            frame=name,
            parent=buffer.frame_name(hist.latest_parent),
            static=hist.static,
            count=len(hist),
            authorities=tuple(buffer.authorities[int(a)] for a in authority_ids),
            first_stamp=int(hist.stamps.min()),
            last_stamp=int(hist.stamps.max()),
            parents=parents,
        )
    children: dict[str, list[str]] = {name: [] for name in frames}
    for name, summary in frames.items():
        if summary.parent is not None:
            children[summary.parent].append(name)
    return FrameTree(frames, children)
