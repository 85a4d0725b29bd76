"""Loops among frames (a frame its own ancestor), found in time linear in the frames and edges."""

from __future__ import annotations

from collections import deque
from collections.abc import Collection, Mapping

#: Frames a loop search may visit in all (beyond the first loop of each tangle): a tangle of
#: thousands of frames, each with several parents, would otherwise take a search per frame.
LOOP_SEARCH_BUDGET = 2_000_000


def find_loops(parents: Mapping[str, Collection[str]], order: Mapping[str, int]) -> list[list[str]]:
    """Each distinct loop child -> parent -> ... -> child: from each frame on a loop, the shortest
    one back to it (parents tried in name order), started at its first frame in ``order`` (tf2's);
    loops in the order of those first frames.

    Only frames of a strongly connected tangle can be on a loop, and a search from one of them
    never leaves its tangle; a tangle where each frame has one parent inside it is one loop.
    """
    last = len(order)

    def rank(frame: str) -> int:
        return order.get(frame, last)

    graph = {child: sorted(ps) for child, ps in parents.items()}
    loops: dict[frozenset[str], list[str]] = {}
    budget = LOOP_SEARCH_BUDGET
    for tangle in _tangles(graph):
        inside = {frame: [p for p in graph.get(frame, ()) if p in tangle] for frame in tangle}
        starts = sorted(tangle, key=rank)
        if all(len(ps) == 1 for ps in inside.values()):
            starts = starts[:1]  # one loop through every frame of the tangle
        for start in starts:
            path, visited = _path_back(inside, start)
            budget -= visited
            if path is not None and frozenset(path) not in loops:
                first = min(range(len(path)), key=lambda i: rank(path[i]))
                loops[frozenset(path)] = path[first:] + path[:first]
            if budget < 0:
                break
    return sorted(loops.values(), key=lambda loop: rank(loop[0]))


def _path_back(parents: Mapping[str, list[str]], start: str) -> tuple[list[str] | None, int]:
    """The shortest walk from ``start`` up through parents back to ``start`` (its frames), if
    any, and how many frames the search visited."""
    came_from: dict[str, str] = {}
    todo = deque([start])
    while todo:
        frame = todo.popleft()
        for parent in parents.get(frame, ()):
            if parent == start:
                path = [frame]
                while path[-1] != start:
                    path.append(came_from[path[-1]])
                return path[::-1], len(came_from)
            if parent not in came_from:
                came_from[parent] = frame
                todo.append(parent)
    return None, len(came_from)


def _tangles(graph: Mapping[str, list[str]]) -> list[set[str]]:
    """The strongly connected sets of frames that hold a loop (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    tangles: list[set[str]] = []
    for root in graph:
        if root in index:
            continue
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        work = [(root, iter(graph.get(root, ())))]
        while work:
            frame, edges = work[-1]
            for parent in edges:
                if parent not in index:
                    index[parent] = low[parent] = len(index)
                    stack.append(parent)
                    on_stack.add(parent)
                    work.append((parent, iter(graph.get(parent, ()))))
                    break
                if parent in on_stack:
                    low[frame] = min(low[frame], index[parent])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[frame])
                if low[frame] == index[frame]:
                    members = set()
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        members.add(member)
                        if member == frame:
                            break
                    if len(members) > 1 or frame in graph.get(frame, ()):
                        tangles.append(members)
    return tangles
