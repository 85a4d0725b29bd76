"""A history whose rows have more than one parent is walked through each row's own parent, however its rows
came in (the walk takes a history's sole parent without reading its rows where it has one)."""

from __future__ import annotations

import pickle
from collections.abc import Callable

import numpy as np
import pytest

from tftools import Buffer, Transform, TransformError
from tftools.core.batch import BatchBuilder

S = 1_000_000_000
IDENTITY = (0.0, 0.0, 0.0, 1.0)
#: c under a at 1..10 s (x = the second), and one sample under b at 5.5 s (x = 55).
UNDER_A = [(k * S, float(k)) for k in range(1, 11)]
UNDER_B = (5 * S + S // 2, 55.0)


def sample(parent: str, stamp: int, x: float) -> Transform:
    return Transform((x, 0.0, 0.0), IDENTITY, stamp, parent, "c")


def one_by_one(buffer: Buffer) -> None:
    """a's samples in order, then b's, older than the newest (merged in by stamp)."""
    for stamp, x in UNDER_A:
        assert buffer.set_transform(sample("a", stamp, x), "p")
    assert buffer.set_transform(sample("b", *UNDER_B), "p")


def b_first(buffer: Buffer) -> None:
    """b's sample first, then a's around it."""
    assert buffer.set_transform(sample("b", *UNDER_B), "p")
    for stamp, x in UNDER_A:
        assert buffer.set_transform(sample("a", stamp, x), "p")


def in_one_batch(buffer: Buffer) -> None:
    builder = BatchBuilder()
    for stamp, x in UNDER_A:
        builder.add("a", "c", stamp, (x, 0.0, 0.0), IDENTITY, authority="p")
    builder.add("b", "c", UNDER_B[0], (UNDER_B[1], 0.0, 0.0), IDENTITY, authority="p")
    assert buffer.insert(builder.take()) == len(UNDER_A) + 1


def restored(buffer: Buffer) -> Buffer:
    """A copy of ``one_by_one``'s (``__getstate__``, ``__setstate__``: the histories rebuilt from their columns)."""
    one_by_one(buffer)
    state = buffer.__getstate__()
    state["_core"] = pickle.loads(pickle.dumps(state["_core"]))
    copy = Buffer.__new__(Buffer)
    copy.__setstate__(state)
    return copy


def filled(how: Callable[[Buffer], object]) -> Buffer:
    buffer = Buffer(cache_time=None)
    out = how(buffer)
    return out if isinstance(out, Buffer) else buffer


@pytest.mark.parametrize("how", [one_by_one, b_first, in_one_batch, restored], ids=lambda f: f.__name__)
def test_each_row_its_own_parent(how: Callable[[Buffer], object]) -> None:
    buffer = filled(how)
    b_stamp, b_x = UNDER_B
    # At b's stamp, and between it and a's next sample (tf2 does not interpolate across a change of
    # parent: the older sample, under b, answers), c is under b only.
    for time in (b_stamp, b_stamp + S // 4):
        assert buffer.lookup("b", "c", time).translation[0] == b_x
        assert not buffer.can_transform("a", "c", time)
        with pytest.raises(TransformError):
            buffer.lookup("a", "c", time)
    # Elsewhere under a, interpolated.
    assert buffer.lookup("a", "c", 3 * S + S // 2).translation[0] == 3.5
    assert not buffer.can_transform("b", "c", 3 * S + S // 2)
    batch = buffer.lookup_many("a", "c", np.array([3 * S + S // 2, b_stamp, b_stamp + S // 4, 8 * S]))
    assert batch.valid.tolist() == [True, False, False, True]
    assert buffer.lookup_many("b", "c", np.array([b_stamp])).valid.tolist() == [True]


def test_one_parent_again_after_pruning() -> None:
    """A live buffer that pruned its history's last sample under another parent walks it as before."""
    buffer = Buffer(cache_time=3 * S)
    assert buffer.set_transform(sample("b", S, 1.0), "p")
    for k in range(2, 20):
        assert buffer.set_transform(sample("a", k * S, float(k)), "p")
    assert buffer.lookup("a", "c", 18 * S + S // 2).translation[0] == 18.5
    assert not buffer.can_transform("b", "c", 18 * S)
