"""Extreme but well-formed recordings: deep chains, big loops, many roots, long and odd names, in linear time."""

from __future__ import annotations

import difflib
from collections import deque
from collections.abc import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.analysis.scale_scenes import START, batch, chain, grows_linearly, recording, ring, seconds
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.frames import tree_of
from tftools.analysis.graph import frame_graph
from tftools.analysis.wtf import structure
from tftools.analysis.wtf.fleet import check
from tftools.analysis.wtf.loops import find_loops
from tftools.analysis.wtf.scene import Scene
from tftools.core.batch import TransformBatch
from tftools.core.errors import UnknownFrameError


def _cycle_check(frames: int, make: Callable[[int], TransformBatch] = chain) -> float:
    scene_of = recording(make(frames))
    return seconds(lambda: list(structure.cycles(Scene(scene_of))))


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_the_loop_check_is_linear_in_a_chains_frames() -> None:
    # Quadratic before: 10k frames took 20 s, 100k more than 150 s.
    small, large = _cycle_check(2_000), _cycle_check(20_000)
    assert grows_linearly(small, large, 10), (small, large)


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_a_ring_of_20000_frames_is_one_loop_found_in_linear_time() -> None:
    small, large = _cycle_check(2_000, ring), _cycle_check(20_000, ring)
    assert grows_linearly(small, large, 10), (small, large)
    (finding,) = structure.cycles(Scene(recording(ring(20_000))))
    assert finding.count == 20_000 and finding.frames[0] == "f1"  # tf2 interns each child first


def test_a_deep_chain_is_a_tree_walked_without_recursion() -> None:
    buffer = recording(chain(5_000)).buffer
    lines = list(tree_of(buffer).walk())
    assert lines[0] == (0, "f0", True) and lines[-1] == (5_000, "f5000", True) and len(lines) == 5_001
    assert "f5000:" in buffer.all_frames_as_yaml()


def test_lookups_along_a_deep_chain_answer_as_tf2_up_to_its_depth_limit() -> None:
    buffer = recording(chain(5_000)).buffer
    assert buffer.lookup("f0", "f900", START).translation[0] == pytest.approx(90.0)
    with pytest.raises(UnknownFrameError, match="contains a loop"):  # tf2's MAX_GRAPH_DEPTH, not a RecursionError
        buffer.lookup("f0", "f5000", START)


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_wtf_and_the_graph_on_a_deep_chain_find_nothing_wrong() -> None:
    deep = recording(chain(5_000))
    assert [f.code for f in check(deep).findings if f.severity.rank == 0] == []
    graph = frame_graph(Scene(deep), [])
    assert len(graph.edges) == 5_000 and graph.roots == ["f0"]


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_many_trees_are_listed_in_bounded_words_and_found_in_linear_time() -> None:
    def pairs(n: int) -> Scene:
        names = [f"{kind}{i}" for i in range(n) for kind in ("a", "b")]
        return Scene(recording(batch(names, range(0, 2 * n, 2), range(1, 2 * n, 2))))

    def run(n: int) -> float:
        return seconds(lambda: list(structure.disconnected(pairs(n))))

    assert grows_linearly(run(1_000), run(10_000), 10)
    (finding,) = structure.disconnected(pairs(10_000))
    assert finding.count == 10_000 and len(finding.message) < 5_000 and "and 9980 more" in finding.message


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_pinning_many_findings_on_a_big_graph_is_linear() -> None:
    def run(n: int) -> float:
        star = recording(batch(["root", *(f"c{i}" for i in range(n))], [0] * n, range(1, n + 1)))
        findings = [f for f in check(star).findings]
        stale = [Finding(Severity.warning, "stale", "", "", ("root", f"c{i}")) for i in range(n)]
        return seconds(lambda: frame_graph(Scene(star), findings + stale))

    assert grows_linearly(run(1_000), run(10_000), 10)


def test_names_of_10000_characters_and_control_characters_go_through_every_check() -> None:
    long = ["x" * 10_000 + str(i) for i in range(200)]
    odd = ["a\x1b[31mred", "b\nnew line", "c\x00nul", "d\x07bell\r", 'e"quote', "f<html>&"]
    names = ["root", *long, *odd]
    children = range(1, len(names))
    scene = recording(batch(names, [0] * len(children), children))
    assert set(scene.buffer.frames) == set(names)
    assert [f.code for f in check(scene).findings if f.severity.rank == 0] == []
    graph = frame_graph(Scene(scene))
    assert {n.name for n in graph.nodes} == set(names)


def test_many_roots_with_long_names_keep_the_typo_hint_cheap(monkeypatch: pytest.MonkeyPatch) -> None:
    """difflib is quadratic in a name's length: the typo search gives it no long name, and a bounded
    number of candidates (counted, not timed)."""
    compared: list[tuple[str, list[str]]] = []
    close_matches = difflib.get_close_matches

    def counted(word: str, possibilities: list[str], n: int = 3, cutoff: float = 0.6) -> list[str]:
        compared.append((word, list(possibilities)))
        return close_matches(word, possibilities, n, cutoff)

    monkeypatch.setattr(difflib, "get_close_matches", counted)
    names = [f"short{i}" for i in range(10)] + [("y" * 5_000) + str(i) for i in range(400)]
    scene = Scene(recording(batch(names, range(0, 410, 2), range(1, 410, 2))))
    (finding,) = structure.disconnected(scene)
    assert finding.count == 205 and compared  # the short roots were searched, against the short frames
    assert len(compared) <= structure.TYPO_ROOTS
    for word, possibilities in compared:
        assert len(possibilities) <= structure.TYPO_FRAMES
        assert max(map(len, [word, *possibilities])) <= structure.TYPO_NAME_LENGTH


# --- find_loops against the plain search it replaces (a search from every frame) ------------------


def _reference(parents: dict[str, set[str]], order: dict[str, int]) -> list[list[str]]:
    loops: dict[frozenset[str], list[str]] = {}
    for start in sorted(parents, key=lambda f: order.get(f, len(order))):
        came_from: dict[str, str] = {}
        todo, path = deque([start]), None
        while todo and path is None:
            frame = todo.popleft()
            for parent in sorted(parents.get(frame, ())):
                if parent == start:
                    path = [frame]
                    while path[-1] != start:
                        path.append(came_from[path[-1]])
                    path.reverse()
                    break
                if parent not in came_from:
                    came_from[parent] = frame
                    todo.append(parent)
        if path is not None and frozenset(path) not in loops:
            first = min(range(len(path)), key=lambda i: order.get(path[i], len(order)))
            loops[frozenset(path)] = path[first:] + path[:first]
    return list(loops.values())


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 7), st.integers(0, 7)), max_size=20))
def test_find_loops_finds_what_a_search_from_every_frame_finds(edges: list[tuple[int, int]]) -> None:
    parents: dict[str, set[str]] = {}
    for child, parent in edges:
        if child != parent:
            parents.setdefault(f"n{child}", set()).add(f"n{parent}")
    order = {f"n{i}": (i * 5) % 8 for i in range(8)}
    found = find_loops(parents, order)
    assert sorted(map(tuple, found)) == sorted(map(tuple, _reference(parents, order)))
    assert [order[loop[0]] for loop in found] == sorted(order[loop[0]] for loop in found)


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_find_loops_on_a_loop_of_100000_frames_and_a_chain_into_it() -> None:
    n = 100_000
    parents = {f"r{i}": [f"r{(i + 1) % n}"] for i in range(n)}
    parents.update({f"t{i}": [f"t{i + 1}"] for i in range(n)} | {f"t{n}": ["r0"]})
    order = {name: i for i, name in enumerate(parents)}
    (loop,) = find_loops(parents, order)
    assert len(loop) == n and loop[0] == "r0"


@pytest.mark.slow
def test_wtf_on_a_chain_of_100000_frames_grows_linearly() -> None:
    small, large = _cycle_check(10_000), _cycle_check(100_000)
    assert grows_linearly(small, large, 10), (small, large)
