"""``edges_jumps`` checks many edges in one pass (issue 44: a tree of 20,000 moving edges spent 27 s of a
76 s report in numpy's per-call overhead, one edge at a time): each edge's answer is what it is alone."""

from __future__ import annotations

import numpy as np
import pytest

from tftools.analysis.wtf import jumps


def _edge(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    stamps = np.sort(rng.integers(0, 10**10, n)).astype(np.int64)
    if n > 2 and rng.random() < 0.2:
        stamps[n // 2 :] = stamps[n // 2]  # steps of no time
    angle = np.cumsum(rng.normal(0, 0.02, n))
    values = np.zeros((n, 7))
    values[:, 0] = np.cumsum(rng.normal(0, 0.01, n)) + (rng.random(n) < 0.05) * rng.normal(0, 3, n)
    values[:, 5], values[:, 6] = np.sin(angle / 2), np.cos(angle / 2)
    if n and rng.random() < 0.05:
        values[0, 1] = 1e308
    if n and rng.random() < 0.05:
        values[-1, 2] = np.nan
    return stamps, values


def test_edges_checked_together_are_answered_as_each_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(44)
    edges = [_edge(rng, int(rng.choice([0, 1, 2, 3, 5, 8, 50, 300]))) for _ in range(1500)]
    monkeypatch.setattr(jumps, "SAMPLES_AT_ONCE", 5000)  # several passes, edges split between them
    together = jumps.edges_jumps(edges)
    with np.errstate(all="ignore"):
        alone = [jumps.edges_jumps([e])[0] for e in edges]
    assert sum(len(j) for j in together) > 1000  # the edges do jump
    for a, b in zip(together, alone, strict=True):
        assert a.at.tolist() == b.at.tolist()
        np.testing.assert_array_equal(a.metres, b.metres)
        np.testing.assert_array_equal(a.degrees, b.degrees)


def test_a_jump_next_to_another_edge_is_judged_on_its_own_edge_s_motion() -> None:
    """A still edge's first step after a fast one's last: the fast one's speed is not its neighbour's."""
    stamps = np.arange(10, dtype=np.int64) * 100_000_000
    fast, still = np.zeros((10, 7)), np.zeros((10, 7))
    fast[:, 6] = still[:, 6] = 1.0
    fast[:, 0] = np.arange(10) * 1.0  # 10 m/s, steady: no jump
    still[1:, 0] = 0.5  # a 0.5 m step at the still edge's start: a jump, whatever the fast edge before it
    found = jumps.edges_jumps([(stamps, fast), (stamps, still)])
    assert [j.at.tolist() for j in found] == [[], [1]]


def test_steps_measured_a_block_at_a_time_are_those_measured_at_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """A pass measures its steps' distances (``_steps_apart``) a block at a time: bounded memory, same answer."""
    rng = np.random.default_rng(45)
    edges = [_edge(rng, int(rng.choice([2, 3, 50, 300]))) for _ in range(200)]
    with np.errstate(all="ignore"):
        at_once = jumps.edges_jumps(edges)
        monkeypatch.setattr(jumps, "WINDOWS_AT_ONCE", 7)
        blocked = jumps.edges_jumps(edges)
    assert sum(len(j) for j in at_once) > 100
    for a, b in zip(at_once, blocked, strict=True):
        assert a.at.tolist() == b.at.tolist()
        np.testing.assert_array_equal(a.metres, b.metres)
        np.testing.assert_array_equal(a.degrees, b.degrees)
