"""The buffer under extreme but well-formed input: a million refusals, many frames, one huge message."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from tests.analysis.scale_scenes import START, batch, grows_linearly, seconds
from tftools.core.batch import TransformBatch
from tftools.core.buffer import Buffer
from tftools.core.rejection import LIVE_REJECTIONS_KEPT, RejectionCode, code_bits


def _repeated(n: int) -> tuple[list[str], list[int], list[int]]:
    return ["odom", "base"], [0] * n, [1] * n


def test_a_million_samples_at_one_stamp_are_refused_in_columns_not_objects() -> None:
    n = 1_000_000
    rows = batch(*_repeated(n))  # ROS 1's tf2: TF_REPEATED_DATA for all but the first
    buffer = Buffer(cache_time=None)
    tracemalloc.start()
    buffer.insert(rows)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert len(buffer.rejections) == buffer.rejections.total == n - 1
    assert peak < 200 * n  # bytes: was a Rejection object per row, ~0.3 GB more
    last = buffer.rejections[-1]
    assert last.code is RejectionCode.REPEATED_DATA and last.sequence == n - 1 and last.child_frame_id == "base"
    assert buffer.rejections.sequences(n - 3).tolist() == [n - 2, n - 1]
    (edge,) = buffer.rejections.by_edge().values()
    assert edge.rows == n - 1 and edge.samples == 1 and edge.codes == (RejectionCode.REPEATED_DATA,)


def test_a_live_buffer_keeps_its_latest_rejections_and_counts_them_all() -> None:
    buffer = Buffer()  # a finite cache time: a live buffer
    n = 3 * LIVE_REJECTIONS_KEPT
    for part in range(3):
        buffer.insert(batch(*_repeated(LIVE_REJECTIONS_KEPT)))
        assert len(buffer.rejections) <= 2 * LIVE_REJECTIONS_KEPT, part
    assert buffer.rejections.total == n - 1
    assert buffer.rejections[-1].sequence == n - 1  # the latest kept


def test_rejections_read_as_the_rejection_objects_they_stand_for() -> None:
    rows = batch(["a", "b", "a"], [0, 0, 2], [1, 1, 0], [START, START, START])
    rows.rotation[1] = (0.0, 0.0, 0.0, 2.0)  # a bad quaternion
    buffer = Buffer(cache_time=None)
    buffer.insert(rows)
    self_tf, bad = buffer.rejections  # by code, in tf2's order of checks, as before
    assert (bad.code, bad.values, bad.sequence) == (RejectionCode.DENORMALIZED_QUATERNION, (0.0, 0.0, 0.0, 2.0), 1)
    assert (self_tf.code, self_tf.frame_id, self_tf.child_frame_id) == (RejectionCode.SELF_TRANSFORM, "a", "a")
    assert buffer.rejections == [self_tf, bad] and buffer.rejections[1:] == [bad]


def test_each_samples_verdict_holds_every_code_it_was_refused_for() -> None:
    rows = batch(["a", "b", ""], [0, 0, 2, 0, 2], [1, 0, 1, 1, 2], [START, START, START, START - 1, START])
    rows.translation[1, 0] = np.nan  # a self transform with a NaN: two codes
    rows.rotation[4] = (0.0, 0.0, 0.0, 0.0)  # "" -> "" with no rotation: four
    buffer = Buffer(cache_time=None)
    buffer.insert(rows)
    verdicts = buffer.rejections.verdicts(np.array([4, 0, 1, 2, 3, 9], np.int64))
    self_nan = code_bits(RejectionCode.SELF_TRANSFORM, RejectionCode.NAN_INPUT)
    frames = (RejectionCode.SELF_TRANSFORM, RejectionCode.NO_FRAME_ID, RejectionCode.NO_CHILD_FRAME_ID)
    everything = code_bits(*frames, RejectionCode.DENORMALIZED_QUATERNION)
    assert code_bits(RejectionCode.SELF_TRANSFORM) | code_bits(RejectionCode.NAN_INPUT) == self_nan
    assert verdicts.tolist() == [everything, 0, self_nan, code_bits(RejectionCode.NO_FRAME_ID), 0, 0]
    assert {r.code for r in buffer.rejections if r.sequence == 4} == {
        c for c in RejectionCode if verdicts[0] & code_bits(c)
    }


@pytest.mark.slow  # seconds of CPU at full size: CI runs it
def test_many_frames_seen_once_are_inserted_in_linear_time() -> None:
    def run(n: int) -> float:
        names = ["root", *(f"c{i}" for i in range(n))]
        rows = batch(names, [0] * n, range(1, n + 1))
        return seconds(lambda: Buffer(cache_time=None).insert(rows))

    assert grows_linearly(run(5_000), run(50_000), 10)


def test_one_message_of_a_million_samples_of_one_frame_inserts_in_linear_time() -> None:
    def samples(n: int) -> TransformBatch:
        return batch(["odom", "base"], [0] * n, [1] * n, START + np.arange(n, dtype=np.int64) * 1_000_000)

    small, large = samples(100_000), samples(1_000_000)
    assert grows_linearly(
        seconds(lambda: Buffer(cache_time=None).insert(small)),
        seconds(lambda: Buffer(cache_time=None).insert(large)),
        10,
    )
    buffer = Buffer(cache_time=None)
    buffer.insert(large)
    history = buffer.history("base")
    assert history is not None and len(history) == 1_000_000 and not buffer.rejections


def test_a_live_ros2_buffer_keeps_its_latest_duplicates() -> None:
    """ROS 2's tf2 takes a sample identical to one it holds without storing it: a live buffer that
    hears one again and again keeps only the latest arrival numbers of them."""
    buffer = Buffer(semantics="ros2")  # a finite cache time: a live buffer
    n = 3 * LIVE_REJECTIONS_KEPT
    for part in range(3):
        buffer.insert(batch(*_repeated(LIVE_REJECTIONS_KEPT)))
        assert len(buffer.duplicates) <= 2 * LIVE_REJECTIONS_KEPT, part
    assert buffer.duplicates[-1] == n - 1 and len(buffer.rejections) == 0
    whole = Buffer(cache_time=None, semantics="ros2")
    whole.insert(batch(*_repeated(n)))
    assert len(whole.duplicates) == n - 1  # a whole recording's are all kept
