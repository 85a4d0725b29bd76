"""``tfx frames``' work: the frame tree summarised, each frame's parent, publishers, rate and time span:
``frame_tree(recording)``; ``tree_of(buffer)`` for the analyses that hold a buffer."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from tftools.analysis.edges import parents_in_order, publishers
from tftools.core.buffer import Buffer
from tftools.core.figures import held_parts, rate_of, record_span, time_bases
from tftools.core.history import EdgeHistory

if TYPE_CHECKING:
    from tftools.sources.recording import Recording


@dataclass(frozen=True)
class ParentEdge:
    """One parent -> frame edge of a frame that had several parents, counted as ``tfx monitor`` counts an edge
    (``edges.edge_rows``): tf2 keeps one history per frame, a row of it is the edge of the parent it names."""

    parent: str
    count: int
    authorities: tuple[str, ...]
    first_stamp: int
    last_stamp: int
    rate_hz: float  # ``figures.rate_of`` of its stamps; 0 for a static or single-sample edge


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
    #: Mean publishing rate over the samples' span, on each time base apart (``figures.rate_of``); 0 for a
    #: static or single-sample edge.
    rate_hz: float = 0.0
    #: The time bases its stamps are on (``figures.time_bases``): 2 for a replay's samples beside a live
    #: publisher's, a week apart, whose first and last stamps span no time the recording lasted.
    clocks: int = 1
    #: Where it had several parents (``parents``), each one's edge; empty where it had one.
    edges: tuple[ParentEdge, ...] = ()
    #: Sent on /tf with one value throughout (``figures.held_parts``), under its latest parent: a fixed mount sent
    #: as a moving transform (tf1's static_transform_publisher), or a joint that did not move while recorded.
    held: bool = False


@dataclass
class FrameTree:
    """Every frame, and the tree the latest parents make."""

    frames: dict[str, FrameSummary]
    children: dict[str, list[str]] = field(default_factory=dict)

    @property
    def roots(self) -> list[str]:
        """Frames with no parent: one for a healthy tree (a loop has none)."""
        return [name for name, f in self.frames.items() if f.parent is None]

    def trees(self) -> dict[str, list[str]]:
        """Each root (in ``roots``' order) with its tree: the root and every frame under it, breadth first."""
        trees = {}
        for root in self.roots:
            members = [root]
            for frame in members:  # grows as it goes: breadth first
                members.extend(self.children.get(frame, []))
            trees[root] = members
        return trees

    def ancestors(self, frame: str) -> list[str]:
        """``frame``'s parent, that one's parent, and so on up to a root (or until they loop)."""
        found: list[str] = []
        parent = self.frames[frame].parent if frame in self.frames else None
        while parent is not None and parent not in found and parent != frame:
            found.append(parent)
            parent = self.frames[parent].parent if parent in self.frames else None
        return found

    def root_of(self, frame: str) -> str:
        """The root above ``frame`` by latest parents (``frame`` itself where it has none)."""
        ancestors = self.ancestors(frame)
        return ancestors[-1] if ancestors else frame

    def walk(self) -> Iterator[tuple[int, str, bool]]:
        """(depth, frame, last) for each frame under a root, depth first, roots and siblings in name
        order (``last``: no sibling follows): a tree's lines top to bottom. Iterative, so a chain of any
        length is fine; frames in a loop (under no root) are left out."""
        shown: set[str] = set()
        todo = _in_turn(0, self.roots)
        while todo:
            depth, frame, last = todo.pop()
            if frame in shown:
                continue
            shown.add(frame)
            yield depth, frame, last
            todo.extend(_in_turn(depth + 1, self.children.get(frame, [])))


def _in_turn(depth: int, frames: list[str]) -> list[tuple[int, str, bool]]:
    """``frames`` at ``depth`` as a stack pops them: in name order, the last marked."""
    ordered = sorted(frames)
    return [(depth, frame, i == len(ordered) - 1) for i, frame in enumerate(ordered)][::-1]


def frame_tree(recording: Recording) -> FrameTree:
    """``tfx frames -b BAG``: the recording's frames summarised and arranged by their latest parent."""
    return tree_of(recording.buffer)


def tree_of(buffer: Buffer) -> FrameTree:
    """Summarise ``buffer``'s frames and arrange them by their latest parent."""
    frames = {name: FrameSummary(name, None) for name in buffer.frames}
    names = buffer.frame_name
    for name, hist in buffer.histories():
        if len(hist) == 0:
            continue
        stamps, parents = hist.stamps, parents_in_order(hist)
        one = len(stamps) == 1  # a static edge sent once: numpy's reductions cost more than the answer
        first, last = (stamps[0], stamps[-1]) if one or not hist.static else (stamps.min(), stamps.max())
        span = 0 if hist.static else record_span(hist.record_times)  # its time bases' (``figures.across_clocks``)
        frames[name] = FrameSummary(
            frame=name,
            parent=names(hist.latest_parent),
            static=hist.static,
            count=len(hist),
            authorities=publishers(buffer, hist.authorities),
            first_stamp=int(first),
            last_stamp=int(last),
            parents=tuple(names(p) for p in parents),
            rate_hz=0.0 if hist.static else rate_of(stamps, span, hist.record_times),
            clocks=1 if hist.static else time_bases(stamps, span),
            edges=tuple(_parent_edge(buffer, hist, p) for p in parents) if len(parents) > 1 else (),
            held=not hist.static and not one and all(held_parts(hist.values[hist.parents == hist.latest_parent])),
        )
    children: dict[str, list[str]] = {name: [] for name in frames}
    for name, summary in frames.items():
        if summary.parent is not None:
            children[summary.parent].append(name)
    return FrameTree(frames, children)


def _parent_edge(buffer: Buffer, hist: EdgeHistory, parent: int) -> ParentEdge:
    """The edge from ``parent`` (an id) of a frame that had several parents: its rows of ``hist``."""
    mine = hist.parents == parent
    stamps, records = hist.stamps[mine], hist.record_times[mine]
    return ParentEdge(
        parent=buffer.frame_name(parent),
        count=len(stamps),
        authorities=publishers(buffer, hist.authorities[mine]),
        first_stamp=int(stamps.min()),
        last_stamp=int(stamps.max()),
        rate_hz=0.0 if hist.static else rate_of(stamps, record_span(records), records),
    )
