"""Extreme but well-formed recordings, built in memory: deep chains, rings, stars, long names."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

from tftools.core.batch import TransformBatch
from tftools.core.time import NS_PER_S
from tftools.sources.bag.contents import BagContents, BagFileInfo
from tftools.sources.contents import DEFAULT_TOPICS
from tftools.sources.recording import Recording, recording_of

START = 1_700_000_000 * NS_PER_S


Indices = Sequence[int] | np.ndarray


def batch(names: Sequence[str], parent: Indices, child: Indices, stamps: Indices | None = None) -> TransformBatch:
    """Identity-rotation transforms parent[i] -> child[i] (indices into ``names``), on /tf, from /pub."""
    n = len(parent)
    stamp = np.full(n, START, np.int64) if stamps is None else np.asarray(stamps, np.int64)
    rotation = np.zeros((n, 4))
    rotation[:, 3] = 1.0
    return TransformBatch(
        list(names),
        ["/pub"],
        np.asarray(parent, np.int32),
        np.asarray(child, np.int32),
        stamp,
        np.full((n, 3), 0.1),
        rotation,
        np.zeros(n, bool),
        stamp + 1000,
    )


def chain(frames: int, samples: int = 2) -> TransformBatch:
    """f0 -> f1 -> ... -> f{frames}, each edge sent ``samples`` times 0.1 s apart."""
    names = [f"f{i}" for i in range(frames + 1)]
    edges = np.arange(frames)
    parent = np.tile(edges, samples)
    stamps = START + np.repeat(np.arange(samples), frames) * NS_PER_S // 10
    return batch(names, parent, parent + 1, stamps)


def ring(frames: int) -> TransformBatch:
    """f0 -> f1 -> ... -> f{frames - 1} -> f0: one loop through every frame."""
    edges = np.arange(frames)
    return batch([f"f{i}" for i in range(frames)], edges, (edges + 1) % frames)


def recording(part: TransformBatch) -> Recording:
    info = BagFileInfo("memory.bag", "ros1", START, START + NS_PER_S, 1, {"/tf": "tf2_msgs/msg/TFMessage"}, len(part))
    return recording_of(BagContents([part], [info], DEFAULT_TOPICS))


def seconds(run: Callable[[], object]) -> float:
    """The best of two runs' CPU times (this process's: the time it waited for a busy machine's cores
    is not counted, so a loaded machine does not make a linear step look quadratic)."""
    best = float("inf")
    for _ in range(2):
        began = time.process_time()
        run()
        best = min(best, time.process_time() - began)
    return best


def grows_linearly(small: float, large: float, factor: int) -> bool:
    """Whether a ``factor`` times larger input took well under ``factor`` squared as long as the
    baseline ``small``, measured in the same test (with a floor for timer noise on tiny runs)."""
    return large <= max(small, 0.01) * factor * 3
