"""``tfx view-frames``' work: the frame graph view_frames draws, every edge with its statistics and the problems
pinned where they are: ``view_frames(recording)`` (drawn by ``render.graph.to_digraph``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from tftools.analysis.edges import Edge, EdgeStats
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import Scene, findings_of
from tftools.analysis.wtf.fleet import checked_scene
from tftools.core.figures import age
from tftools.core.rejection import RejectionLog
from tftools.sources.timeline import Reference

if TYPE_CHECKING:
    from tftools.sources.recording import Recording

#: Findings that name whole trees: only their roots are marked, not every edge inside.
_TREE_CODES = frozenset({"disconnected"})
#: Findings that name a child frame first, then its parents.
_CHILD_FIRST_CODES = frozenset({"multiple_parents", "mixed_static"})


@dataclass(frozen=True)
class GraphEdge(Edge):
    """One parent -> child edge: its statistics (None when every sample was rejected) and problems."""

    stats: EdgeStats | None
    rejected: tuple[tuple[str, int], ...] = ()  # (tf2 code, samples)
    problems: tuple[int, ...] = ()  # indices into FrameGraph.findings

    @property
    def static(self) -> bool:
        return self.stats is not None and self.stats.static


@dataclass(frozen=True)
class GraphNode:
    """One frame: a root has no parent; ``problems`` are the findings about the frame itself."""

    name: str
    root: bool
    problems: tuple[int, ...] = ()


@dataclass(frozen=True)
class FrameGraph:
    """Frames, edges and findings, each edge and frame pointing at the findings it shows."""

    nodes: tuple[GraphNode, ...]
    edges: tuple[GraphEdge, ...]
    findings: tuple[Finding, ...]
    now: int  # the time ages are measured from (the recording's end)
    clock_ends: Mapping[str, int] = field(default_factory=dict)  # frames on another clock: their own end
    clock: str = "the recording's clock"  # the clock ``now`` is read on, as a sentence names it
    # moving frames stamped on another clock than the one that timed their arrival: no delay (``on_other_clock``)
    other_clock: frozenset[str] = frozenset()

    def now_of(self, edge: Edge) -> int:
        """The time ``edge``'s age is measured from: the recording's end, or for a frame stamped on another
        clock than the rest, that clock at the recording's end (``Timeline.own_clock_ends``)."""
        return self.clock_ends.get(edge.child, self.now)

    def age_of(self, edge: GraphEdge) -> int | None:
        """How old ``edge``'s newest sample is (``core.figures.age``, ns; negative where it is stamped ahead
        of ``clock``); None where no sample was accepted."""
        return None if edge.stats is None else age(self.now_of(edge), edge.stats.last_stamp)

    @property
    def roots(self) -> list[str]:
        return [node.name for node in self.nodes if node.root]

    def severity(self, problems: Sequence[int]) -> Severity | None:
        """The worst severity among ``problems`` (None when there are none)."""
        severities = [self.findings[i].severity for i in problems]
        return min(severities, key=lambda s: s.rank) if severities else None


def view_frames(recording: Recording) -> FrameGraph:
    """``tfx view-frames -b BAG``: the recording's frame graph with ``tfx wtf``'s findings pinned where they are:
    the same checks (``checked_scene``: on its sensor data and robot description too, as read), the same count."""
    return frame_graph(*checked_scene(recording))


def frame_graph(scene: Scene, findings: Sequence[Finding] | None = None) -> FrameGraph:
    """The graph of ``scene``'s frames, its edges with the statistics the checks use (``Scene.stats``), and
    ``findings`` (default: ``tfx wtf``'s, ``findings_of(scene)``) pinned on it.

    A finding marks each drawn edge whose two frames it names, and each frame it names that is
    on none of those edges (for ``disconnected``, only the roots it names).
    """
    buffer, tree = scene.buffer, scene.tree
    found = tuple(findings) if findings is not None else tuple(findings_of(scene))
    rejected = _rejected_edges(buffer.rejections)
    by_key = {s.key: s for s in scene.stats}
    keys = [*by_key, *(key for key in rejected if key not in by_key)]
    names = list(tree.frames) + sorted({f for key in keys for f in key} - set(tree.frames))
    roots = set(tree.roots)
    edge_problems, node_problems = _pin(found, keys, roots)
    edges = tuple(
        GraphEdge(p, c, by_key.get((p, c)), tuple(sorted(rejected.get((p, c), {}).items())), tuple(pinned))
        for (p, c), pinned in edge_problems.items()
    )
    nodes = tuple(GraphNode(name, name in roots, tuple(node_problems.get(name, ()))) for name in names)
    timeline = scene.timeline
    clock = "the listener's clock" if scene.recording.contents.live else "the recording's clock"
    clock = timeline.clock.topic if timeline.reference is Reference.CLOCK else clock
    other_clock = frozenset(timeline.on_other_clock(s.child for s in scene.stats if not s.static))
    return FrameGraph(nodes, edges, found, buffer.now(), timeline.own_clock_ends, clock, other_clock)


def _pin(
    findings: Sequence[Finding], keys: Sequence[tuple[str, str]], roots: set[str]
) -> tuple[dict[tuple[str, str], list[int]], dict[str, list[int]]]:
    """The findings (by index) each edge and each frame shows."""
    edge_problems: dict[tuple[str, str], list[int]] = {key: [] for key in keys}
    node_problems: dict[str, list[int]] = {}
    edges = set(keys)
    touching: dict[str, list[tuple[str, str]]] = {}  # each frame's edges
    for key in keys:
        touching.setdefault(key[0], []).append(key)
        if key[1] != key[0]:
            touching.setdefault(key[1], []).append(key)
    for index, finding in enumerate(findings):
        covered: set[str] = set()
        for key in _edges_named(finding, touching, edges):
            edge_problems[key].append(index)
            covered.update(key)
        for frame in dict.fromkeys(finding.frames):
            if frame not in covered and (finding.code not in _TREE_CODES or frame in roots):
                node_problems.setdefault(frame, []).append(index)
    return edge_problems, node_problems


def _edges_named(
    finding: Finding, touching: dict[str, list[tuple[str, str]]], edges: set[tuple[str, str]]
) -> list[tuple[str, str]]:
    """The edges a finding is about: between two frames it names; for several parents
    (the child named first, then its parents), the edges into that child.

    ``touching`` lists each frame's edges: the cost is that of the frames named (their pairs,
    or their edges, whichever is fewer), never that of the whole graph.
    """
    named = dict.fromkeys(finding.frames)
    if finding.code in _TREE_CODES or not named:
        return []
    if finding.code in _CHILD_FIRST_CODES:
        child = finding.frames[0]
        return [key for key in touching.get(child, []) if key[1] == child and key[0] in named]
    degrees = sum(len(touching.get(frame, [])) for frame in named)
    if len(named) ** 2 <= degrees:
        return [(p, c) for p in named for c in named if (p, c) in edges]
    return list(dict.fromkeys(key for f in named for key in touching.get(f, []) if key[0] in named and key[1] in named))


def _rejected_edges(rejections: RejectionLog) -> dict[tuple[str, str], dict[str, int]]:
    """Rejected samples per edge whose two frames are named (a self-transform is a loop), per tf2 code."""
    result: dict[tuple[str, str], dict[str, int]] = {}
    for (parent, child, code), found in rejections.by_edge().items():
        if parent and child:
            result.setdefault((parent, child), {})[code] = found.rows
    return result
