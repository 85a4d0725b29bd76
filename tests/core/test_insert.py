"""A batch inserted in parts leaves the buffer as inserting it whole (or row by row) does."""

from __future__ import annotations

from collections import Counter
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from tests.core import scenarios
from tftools import Buffer, EdgeHistory, RejectionCode, Transform, TransformBatch
from tftools.core.history import ROW_BYTES

S = scenarios.S

CASES = [(seed, frozenset({f}) if f else frozenset()) for seed in range(3) for f in (None, *scenarios.FEATURES)]
CASES += [(100 + seed, frozenset(scenarios.FEATURES) - {"cycle"}) for seed in range(3)]


# A buffer's whole state, comparable: its frames, publishers, each child's history as lists, its rejections.
State = tuple[
    list[str],
    list[str],
    dict[str, tuple[list[Any], list[Any], list[Any], list[Any], list[Any], list[Any], bool]],
    Counter[tuple[RejectionCode, str, str, int, str]],
]


def state(buffer: Buffer) -> State:
    histories = {
        name: (hist.stamps.tolist(), hist.values.tolist(), hist.parents.tolist(), hist.authorities.tolist(),
               hist.sequence.tolist(), hist.flags.tolist(), hist.static)
        for name, hist in buffer.histories()
    }  # fmt: skip
    rejections = Counter((r.code, r.frame_id, r.child_frame_id, r.stamp, r.authority) for r in buffer.rejections)
    return buffer.frames, [buffer.authorities[i] for i in range(len(buffer.authorities))], histories, rejections


@pytest.mark.parametrize(("seed", "features"), CASES)
def test_sliced_insertion_equals_whole_and_one_by_one(seed: int, features: frozenset[str]) -> None:
    built = scenarios.build(seed, features, 1_700_000_000)
    whole = scenarios.load_into_buffer(built.scenario)
    one_by_one = scenarios.load_one_by_one(built.scenario)
    sliced = scenarios.load_into_buffer(built.scenario, rows_per_insert=7)
    assert state(sliced) == state(whole)
    frames, _, histories, rejections = state(one_by_one)
    assert (frames, rejections) == state(whole)[::3]
    assert {k: v[:3] for k, v in histories.items()} == {k: v[:3] for k, v in state(whole)[2].items()}


def test_frames_are_interned_child_first_in_order_of_appearance() -> None:
    from tftools import BatchBuilder, Buffer

    builder = BatchBuilder()
    for parent, child in [("a", "b"), ("c", "d"), ("/b", "e"), ("f", "c")]:
        builder.add(parent, child, 1, (0, 0, 0), (0, 0, 0, 1))
    builder.add("g", "g", 1, (0, 0, 0), (0, 0, 0, 1))  # refused: interns nothing
    buffer = Buffer(cache_time=None)
    buffer.insert(builder.take())
    assert buffer.frames == ["b", "a", "d", "c", "e", "f"]
    hist = buffer.history("e")
    assert hist is not None and np.array_equal(hist.parents, [buffer._core.frame_id("b")])


def test_in_order_samples_of_known_frames_skip_the_batch_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """``set_transform``'s common case stores the sample itself (and prunes, and keeps the compiled
    lookups' view up to date); a frame's first sample, an older stamp, a new publisher take ``insert``."""
    buffer = Buffer(cache_time=3 * S)
    assert buffer.set_transform(Transform((0.0, 0, 0), (0, 0, 0, 1), S, "a", "b"), "pub")
    assert buffer.lookup("a", "b").stamp == S  # the lookups' table exists from here on

    def batch_path(batch: TransformBatch) -> int:
        raise AssertionError("took the batch path")

    monkeypatch.setattr(buffer, "insert", batch_path)
    for k in range(2, 50):
        assert buffer.set_transform(Transform((float(k), 0, 0), (0, 0, 0, 1), k * S, "a", "b"), "pub")
    assert buffer.lookup("a", "b", 0).translation == (49.0, 0.0, 0.0)
    hist = buffer.history("b")
    assert hist is not None
    assert hist.stamps.tolist() == [46 * S, 47 * S, 48 * S, 49 * S]  # pruned as tf2 prunes
    assert hist.sequence.tolist() == [45, 46, 47, 48]
    for refused_here in (
        Transform((0.0, 0, 0), (0, 0, 0, 1), 48 * S, "a", "b"),  # not newer
        Transform((0.0, 0, 0), (0, 0, 0, 1.2), 50 * S, "a", "b"),  # not normalized
        Transform((float("nan"), 0, 0), (0, 0, 0, 1), 50 * S, "a", "b"),
        Transform((0.0, 0, 0), (0, 0, 0, 1), 50 * S, "/a", "b"),
        Transform((0.0, 0, 0), (0, 0, 0, 1), 50 * S, "a", "c"),  # a new frame
    ):
        with pytest.raises(AssertionError, match="batch path"):
            buffer.set_transform(refused_here, "pub")
    with pytest.raises(AssertionError, match="batch path"):
        buffer.set_transform(Transform((0.0, 0, 0), (0, 0, 0, 1), 50 * S, "a", "b"), "another publisher")


def _columns(hist: EdgeHistory) -> list[npt.NDArray[Any]]:
    return [hist.stamps, hist.values, hist.parents, hist.authorities, hist.record_times, hist.sequence, hist.flags]


def test_a_reserved_bulk_load_lays_its_histories_in_one_block_from_a_large_page() -> None:
    """``reserve`` then ``insert``: every history's columns lie in one block starting on a 2 MiB page
    (so the kernel brings it in large pages), sized for the reserved rows."""
    from tftools import BatchBuilder

    builder = BatchBuilder()
    for k in range(1, 301):
        for child in ("b", "c", "d"):
            builder.add("a", child, k * S, (0, 0, 0), (0, 0, 0, 1))
    batch = builder.take()
    buffer = Buffer(cache_time=None)
    buffer.reserve([batch])
    buffer.insert(batch)
    columns = [column for _, hist in buffer.histories() for column in _columns(hist)]
    starts = [column.ctypes.data for column in columns]
    ends = [column.ctypes.data + column.nbytes for column in columns]
    assert min(starts) % (2 << 20) == 0
    assert max(ends) - min(starts) <= 3 * (300 * ROW_BYTES + 64)  # the rows, each history's block aligned
    assert [len(hist) for _, hist in buffer.histories()] == [300, 300, 300]


def test_a_bulk_load_too_large_for_large_pages_takes_small_ones(monkeypatch: pytest.MonkeyPatch) -> None:
    """Past ``LARGE_PAGES_UP_TO`` the block is anonymous memory the system keeps in small pages (a large
    page a column, resident before its rows come, would grow with the load); the histories are the same."""
    from tftools import BatchBuilder
    from tftools.core import history

    builder = BatchBuilder()
    for k in range(1, 301):
        builder.add("a", "b", k * S, (k, 0, 0), (0, 0, 0, 1))
    batch = builder.take()
    loaded = {}
    for limit in (1 << 30, 0):
        monkeypatch.setattr(history, "LARGE_PAGES_UP_TO", limit)
        buffer = Buffer(cache_time=None)
        buffer.reserve([batch])
        buffer.insert(batch)
        loaded[limit] = state(buffer)
        if limit:
            hist = buffer.history("b")
            assert hist is not None and hist.stamps.ctypes.data % (2 << 20) == 0
    assert loaded[0] == loaded[1 << 30]


def test_a_bulk_load_takes_the_memory_brought_in_for_it_while_it_was_read() -> None:
    """A ``Spare`` brought in ahead of the rows (on a thread of its own) is the reserved block's memory: the
    histories start on a large page and are those of a load without it; the spare holds nothing after."""
    from tftools import BatchBuilder
    from tftools.core._kernels import Spare

    builder = BatchBuilder()
    for k in range(1, 15_001):
        for child in ("b", "c"):
            builder.add("a", child, k * S, (k, 0, 0), (0, 0, 0, 1), record_time=k)
    batch = builder.take()  # 30,000 rows: a block of 2.7 MB, on large pages
    loaded = []
    for spare in (None, Spare()):
        if spare is not None:
            spare.ahead(len(batch) // 2)  # a part read, more to come
            spare.ahead(len(batch))
        buffer = Buffer(cache_time=None)
        buffer.reserve([batch], spare)
        buffer.insert(batch)
        loaded.append(state(buffer))
        hist = buffer.history("b")
        assert hist is not None and hist.stamps.ctypes.data % (2 << 20) == 0
        assert spare is None or spare.brought == 0
    assert loaded[0] == loaded[1]


def test_a_spare_past_the_largest_block_on_large_pages_is_given_back_at_once() -> None:
    """Rows past ``LARGE_PAGES_UP_TO``'s block (laid on small pages): the spare lets its memory go as soon as
    it is told of them, and a buffer reserving with it makes its block itself."""
    from tftools import BatchBuilder
    from tftools.core._kernels import Spare
    from tftools.core.history import LARGE_PAGES_UP_TO

    spare = Spare()
    spare.ahead(1)
    spare.ahead(LARGE_PAGES_UP_TO // ROW_BYTES + 1)
    assert spare.brought == 0
    builder = BatchBuilder()
    for k in range(1, 101):
        builder.add("a", "b", k * S, (k, 0, 0), (0, 0, 0, 1))
    batch = builder.take()
    buffer = Buffer(cache_time=None)
    buffer.reserve([batch], spare)
    buffer.insert(batch)
    hist = buffer.history("b")
    assert hist is not None and hist.stamps.tolist() == [k * S for k in range(1, 101)]


def test_views_outlive_the_columns_they_were_taken_of() -> None:
    """A history's columns move when it grows or is pruned: a view taken before keeps the old ones."""
    buffer = Buffer(cache_time=2 * S)
    buffer.set_transform(Transform((1.0, 0, 0), (0, 0, 0, 1), S, "a", "b"))
    hist = buffer.history("b")
    assert hist is not None
    before = hist.values
    for k in range(2, 400):
        buffer.set_transform(Transform((float(k), 0, 0), (0, 0, 0, 1), k * S, "a", "b"))
    assert before.tolist() == [[1.0, 0, 0, 0, 0, 0, 1]]
    assert not before.flags.writeable
    hist = buffer.history("b")
    assert hist is not None and hist.stamps.tolist() == [397 * S, 398 * S, 399 * S]


def test_rows_reserved_for_a_frame_that_has_a_history_size_it_once() -> None:
    """``reserve`` for frames already held (a bulk load in several reserved parts): each history is sized
    for the rows to come once, and they are stored as without the reservation (the Python history this
    replaced had no such method: the insert raised)."""
    from tftools import BatchBuilder

    def batch(first: int, count: int) -> TransformBatch:
        builder = BatchBuilder()
        for k in range(first, first + count):
            builder.add("a", "b", k * S, (k, 0, 0), (0, 0, 0, 1))
        return builder.take()

    buffer, plain = Buffer(cache_time=None), Buffer(cache_time=None)
    for target in (buffer, plain):
        target.insert(batch(1, 3))
    more = batch(4, 500)
    buffer.reserve([more])
    assert buffer.insert(more) == plain.insert(more) == 500
    assert state(buffer) == state(plain)
