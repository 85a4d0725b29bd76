"""``Buffer(semantics=...)``: what ROS 2 mode does apart from ROS 1 mode, and that every path
(bulk or one-by-one insertion, single or batch lookups) agrees in both."""

from __future__ import annotations

import numpy as np
import pytest

from tests.core import scenarios
from tests.core.test_insert import state
from tftools.core import (
    BackwardExtrapolationError,
    Buffer,
    ExtrapolationError,
    ForwardExtrapolationError,
    NoDataForExtrapolationError,
    Transform,
)
from tftools.core.kernels import lookup_in_parallel
from tftools.core.semantics import Semantics
from tftools.core.stored import stored_rows
from tftools.core.time import format_sec

S = scenarios.S
FEATURES = frozenset({"repeat", "shuffle", "static_then_dynamic", "reparent", "bad"})
CASES = [(seed, features) for seed in range(4) for features in (FEATURES, FEATURES | {"cache"})]


def ros2_scenario(seed: int, features: frozenset[str]) -> scenarios.Built:
    """A random scenario with what ROS 2 treats apart: samples sharing a stamp, exact repeats
    (some in a row, some later), static after dynamic and back, old data."""
    built = scenarios.build(seed, features, 1_700_000_000)
    rng = np.random.default_rng(seed)
    inserts = built.scenario.inserts
    for row in rng.choice(len(inserts), size=min(8, len(inserts)), replace=False).tolist():
        inserts.insert(int(rng.integers(row, len(inserts) + 1)), list(inserts[row]))
    return built


def put(buffer: Buffer, parent: str, child: str, stamp: int, x: float = 0.0, static: bool = False) -> bool:
    return buffer.set_transform(Transform((x, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, parent, child), "me", static)


def test_semantics_is_checked_and_kept() -> None:
    with pytest.raises(ValueError, match="ros1, ros2"):
        Buffer(semantics="ros3")  # type: ignore[arg-type]  # the wrong call is the test
    assert Buffer().semantics == "ros1"
    buffer = Buffer(semantics="ros2")
    put(buffer, "a", "b", S)
    assert buffer.semantics == "ros2"
    with pytest.raises(NoDataForExtrapolationError):
        buffer.lookup("a", "b", 2 * S)


@pytest.mark.parametrize(("seed", "features"), CASES)
def test_ros2_insertion_paths_agree(seed: int, features: frozenset[str]) -> None:
    built = ros2_scenario(seed, features)
    whole = scenarios.load_into_buffer(built.scenario, "ros2")
    one_by_one = scenarios.load_one_by_one(built.scenario, "ros2")
    assert state(one_by_one) == state(whole)
    assert sorted(one_by_one.duplicates) == sorted(whole.duplicates)
    sliced = scenarios.load_into_buffer(built.scenario, "ros2", rows_per_insert=5)
    assert state(sliced) == state(whole) and sorted(sliced.duplicates) == sorted(whole.duplicates)
    assert whole.all_frames_as_yaml() == one_by_one.all_frames_as_yaml()
    assert not any(r.code.value == "TF_REPEATED_DATA" for r in whole.rejections)


@pytest.mark.parametrize("semantics", ["ros1", "ros2"])
@pytest.mark.parametrize(("seed", "features"), CASES)
def test_batch_lookups_answer_as_single_ones(seed: int, features: frozenset[str], semantics: Semantics) -> None:
    """``lookup_many`` (the compiled lookups, in parallel) equals the single lookup at every time."""
    built = ros2_scenario(seed, features)
    buffer = scenarios.load_into_buffer(built.scenario, semantics)
    stamps = sorted({r[2] * S + r[3] for r in built.scenario.inserts})
    times = np.array([0, *stamps, *(t + 1 for t in stamps), *(t - 1 for t in stamps)], np.int64)
    pairs = [(a, b) for a in buffer.frames for b in buffer.frames if a != b][:40]
    for target, source in pairs:
        ids = buffer._core.frame_id(target), buffer._core.frame_id(source)
        expected = []
        for t in times.tolist():
            found, _ = buffer._core.lookup(*ids, t)
            expected.append(None if found is None else (found[2], [*found[0], *found[1]]))
        resolved, values, valid = lookup_in_parallel(buffer._core, *ids, times)
        for i, want in enumerate(expected):
            where = (target, source, int(times[i]))
            assert bool(valid[i]) == (want is not None), where
            if want is not None:
                assert int(resolved[i]) == want[0], where
                np.testing.assert_allclose(values[i], want[1], atol=1e-12, err_msg=str(where))


def test_several_samples_at_one_stamp() -> None:
    """ROS 2 stores them in arrival order; the last counts, but at the oldest stamp the first."""
    buffer = Buffer(semantics="ros2")
    for stamp, x in ((S, 1.0), (S, 2.0), (2 * S, 3.0), (2 * S, 4.0), (3 * S, 5.0), (3 * S, 6.0)):
        assert put(buffer, "a", "b", stamp, x)
    history = buffer.history("b")
    assert history is not None and history.values[:, 0].tolist() == [1, 2, 3, 4, 5, 6]
    assert buffer.lookup("a", "b", S).translation[0] == 1.0  # the oldest stamp: the first
    assert buffer.lookup("a", "b", 2 * S).translation[0] == 4.0  # interpolated from the last, r = 0
    assert buffer.lookup("a", "b", 3 * S).translation[0] == 6.0
    assert buffer.lookup("a", "b", 0).translation[0] == 6.0
    assert buffer.lookup("a", "b", 3 * S // 2).translation[0] == pytest.approx(2.5)
    assert buffer.lookup("a", "b", 5 * S // 2).translation[0] == pytest.approx(4.5)  # last at 2 s, first at 3 s
    batch = buffer.lookup_many("a", "b", [S, 2 * S, 3 * S, 0])
    assert batch.translations[:, 0].tolist() == [1.0, 4.0, 6.0, 6.0]
    ros1 = Buffer()
    assert put(ros1, "a", "b", S, 1.0) and not put(ros1, "a", "b", S, 2.0)
    assert [r.code.value for r in ros1.rejections] == ["TF_REPEATED_DATA"]


def test_identical_samples_are_accepted_once() -> None:
    buffer = Buffer(semantics="ros2")
    assert put(buffer, "a", "b", S) and put(buffer, "a", "b", S) and put(buffer, "a", "b", S, 1.0)
    assert len(buffer.history("b") or ()) == 2 and buffer.duplicates == [1] and not buffer.rejections


def test_static_after_dynamic_and_back_replace_the_cache() -> None:
    for cache_time in (None, 10 * S):
        buffer = Buffer(cache_time=cache_time, semantics="ros2")
        put(buffer, "a", "b", S, 1.0)
        put(buffer, "a", "b", 2 * S, 2.0)
        put(buffer, "a", "b", 5 * S, 3.0, static=True)
        hist = buffer.history("b")
        assert hist is not None and hist.static and len(hist) == 1
        assert buffer.lookup("a", "b", 100 * S).translation[0] == 3.0
        put(buffer, "a", "b", 7 * S, 4.0)
        hist = buffer.history("b")
        assert hist is not None and not hist.static
        with pytest.raises(NoDataForExtrapolationError):
            buffer.lookup("a", "b", 5 * S)
        _, sequence = stored_rows(buffer)
        assert sequence.tolist() == ([0, 1, 2, 3] if cache_time is None else [3])  # kept only when all is
    ros1 = Buffer()
    put(ros1, "a", "b", S, 1.0)
    put(ros1, "a", "b", 5 * S, 3.0, static=True)
    hist = ros1.history("b")
    assert hist is not None and not hist.static and len(hist) == 2


def test_ros2_prunes_before_inserting() -> None:
    """ROS 2's cache keeps a too-old sample until the next insertion (ROS 1's drops it at once)."""
    cases: tuple[tuple[Semantics, list[int]], ...] = (("ros1", [3]), ("ros2", [0, 3]))
    for semantics, kept in cases:
        buffer = Buffer(cache_time=2 * S, semantics=semantics)
        put(buffer, "a", "b", 0)
        put(buffer, "a", "b", 3 * S)
        history = buffer.history("b")
        assert history is not None and (history.stamps // S).tolist() == kept
    put(buffer, "a", "b", 4 * S)
    history = buffer.history("b")
    assert history is not None and (history.stamps // S).tolist() == [3, 4]


def test_ros2_messages() -> None:
    buffer = Buffer(semantics="ros2")
    put(buffer, "a", "b", 1_700_000_007_990_000_001)
    put(buffer, "a", "b", 1_700_000_008_000_000_123)
    with pytest.raises(ForwardExtrapolationError) as future:
        buffer.lookup("a", "b", 1_700_000_009 * S)
    assert str(future.value) == (
        "Lookup would require extrapolation into the future.  Requested time 1700000009.000000 but the "
        "latest data is at time 1700000008.000000, when looking up transform from frame [b] to frame [a]"
    )
    with pytest.raises(BackwardExtrapolationError, match=r"into the past.  Requested time 1700000006\.000000 but"):
        buffer.lookup("a", "b", 1_700_000_006 * S)
    assert not put(buffer, "a", "b", 1_699_999_990 * S)
    assert buffer.rejections[0].message == (
        "TF_OLD_DATA ignoring data from the past for frame b at time 1699999990.000000 according to authority me\n"
        "Possible reasons are listed at http://wiki.ros.org/tf/Errors%20explained"
    )
    assert buffer.all_frames_as_yaml() == (
        # ROS 2's listener gives its BufferCore no publisher: "Authority undetectable".
        "b: \n  parent: 'a'\n  broadcaster: 'Authority undetectable'\n  rate: 199.998\n"  # 2e9 / 10000122 ns
        "  most_recent_transform: 1700000008.000000\n  oldest_transform: 1700000007.990000\n  buffer_length: 0.010\n"
    )
    assert Buffer(semantics="ros2").all_frames_as_yaml() == "[]"
    assert Buffer().all_frames_as_yaml() == "{}"
    with pytest.raises(ExtrapolationError) as ros1:
        buffer_ros1 = Buffer()
        put(buffer_ros1, "a", "b", S)
        buffer_ros1.lookup("a", "b", 2 * S)
    assert type(ros1.value) is ExtrapolationError


def test_chain_and_fixed_frame_can_transform_of_one_frame() -> None:
    for semantics in ("ros1", "ros2"):
        buffer = Buffer(semantics=semantics)
        put(buffer, "a", "b", S)
        assert buffer.chain("b", "b") == [] and buffer.chain("ghost", "ghost") == []
        assert buffer.chain("a", "b", S) == ["b", "a"]
        assert buffer.can_transform_full("b", 0, "b", 0, "b")
        for frame in ("ghost", "", "/b"):
            assert not buffer.can_transform_full(frame, 0, frame, 0, frame)
            assert buffer.can_transform(frame, frame)


@pytest.mark.parametrize(
    ("ns", "precision", "text"),
    [
        (1_700_000_007_990_000_001, 9, "1700000007.990000001"),
        (1_700_000_007_990_000_123, 9, "1700000007.990000123"),
        (1_700_000_007_990_000_123, 3, "1700000007.990"),
        (1_500_000, 3, "0.002"),  # a tie: to even
        (2_500_000, 3, "0.002"),
        (2_500_001, 3, "0.003"),
        (999_999_999, 3, "1.000"),
        (-1, 9, "-0.000000001"),
        (1_234_000_000, 0, "1"),
        (1, 12, "0.000000001000"),
    ],
)
def test_format_sec_is_exact(ns: int, precision: int, text: str) -> None:
    assert format_sec(ns, precision) == text
