"""ROS 2's own tf2 tests, ported: the oracle for ``Buffer(semantics="ros2")``.

Each test names the ros2/geometry2 (rolling) test it ports: ``tf2/test/cache_unittest.cpp``,
``static_cache_test.cpp``, ``test_storage.cpp``, ``test_time.cpp``, ``simple_tf2_core.cpp``,
``test_tf2/test/buffer_core_test.cpp`` and ``tf2_py/test/test_buffer_core.py``. A ``TimeCache``
is one child frame's history here: its ``frame_id`` (the parent) is the frame ``p<id>``, its
``getData`` a lookup from ``c`` to its parent at that time, its ``clearList`` a new buffer. What
tftools has no counterpart for is left out (transformable callbacks, ``clear``, velocities, covariance).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from tests.corpus.data import slerp
from tftools.core import (
    BackwardExtrapolationError,
    Buffer,
    ExtrapolationError,
    ForwardExtrapolationError,
    InvalidArgumentError,
    NoDataForExtrapolationError,
    Transform,
    TransformError,
    UnknownFrameError,
)
from tftools.core.rotation import Quat, Vec3, quat_from_rpy
from tftools.core.semantics import ROS2
from tftools.core.time import NS_PER_S, duration_to_sec

S = NS_PER_S
IDENTITY: Quat = (0.0, 0.0, 0.0, 1.0)


def ros2_buffer(cache_time: int | None = 10 * S) -> Buffer:
    """tf2's ``BufferCore()`` / ``TimeCache()``: ROS 2 semantics, a 10 s cache."""
    return Buffer(cache_time=cache_time, semantics="ros2")


def put(buffer: Buffer, parent: str, child: str, stamp: int, translation: Vec3 = (0.0, 0.0, 0.0),
        rotation: Quat = IDENTITY, static: bool = False, authority: str = "authority") -> bool:  # fmt: skip
    return buffer.set_transform(Transform(translation, rotation, stamp, parent, child), authority, static)


def item(buffer: Buffer, nanosec: int, frame_id: int) -> bool:
    """cache_unittest.cpp's ``makeItem(nanosec, frame_id)`` inserted into the child frame ``c``."""
    return put(buffer, f"p{frame_id}", "c", nanosec)


def storage(buffer: Buffer) -> list[tuple[int, str]]:
    """``getAllItems()`` of ``c``, newest first, as (stamp, parent) pairs."""
    hist = buffer.history("c")
    assert hist is not None
    pairs = [(int(t), buffer.frame_name(int(p))) for t, p in zip(hist.stamps, hist.parents, strict=True)]
    return pairs[::-1]


def get_data(buffer: Buffer, time: int) -> tuple[str, list[float]]:
    """``getData`` of ``c`` at ``time``: its parent then, and the edge (tx ty tz qx qy qz qw)."""
    parent = buffer.parent("c", time)
    assert parent is not None
    edge = buffer.lookup(parent, "c", time)
    return parent, [*edge.translation, *edge.rotation]


class PseudoRandom:
    """cache_unittest.cpp's ``seed_rand`` / ``get_rand`` (deterministic)."""

    def __init__(self) -> None:
        self.values = [(math.floor(i * 3.141592653589793) % 100) / 50.0 - 1.0 for i in range(2000)]
        self.step = 0

    def __call__(self) -> float:
        self.step = 0 if self.step >= len(self.values) else self.step + 1
        return self.values[self.step]


# --- tf2/test/cache_unittest.cpp ----------------------------------------------------------


def test_time_cache_get_all_items() -> None:
    """TEST(TimeCache, GetAllItems): order of equal stamps, repeats ignored, prune-then-insert."""
    cache = ros2_buffer(cache_time=10)
    a, b, c, d, e, f, g = (0, 0), (10, 1), (5, 2), (3, 3), (8, 4), (8, 5), (8, 6)
    for stamp, frame in (a, b, c, d, e, f, g):
        assert item(cache, stamp, frame)
    hist = cache.history("c")
    assert hist is not None and hist.latest_stamp - hist.oldest_stamp == 10
    expected = [(t, f"p{i}") for t, i in (b, g, f, e, c, d, a)]
    assert storage(cache) == expected

    for stamp, frame in (g, f, e, d, c, b, a):  # repeated, in reverse: nothing changes
        assert item(cache, stamp, frame)
    assert storage(cache) == expected
    assert len(cache.duplicates) == 7 and not cache.rejections

    h, i, j = (15, 7), (0, 8), (5, 9)
    assert item(cache, *h)
    assert not item(cache, *i)  # dropped: older than the cache time
    assert item(cache, *j)
    assert storage(cache) == [(t, f"p{k}") for t, k in (h, b, g, f, e, j, c)]
    assert [r.code.value for r in cache.rejections] == ["TF_OLD_DATA"]


def test_time_cache_repeatability() -> None:
    """TEST(TimeCache, Repeatability)."""
    cache = ros2_buffer()
    for i in range(1, 100):
        item(cache, i, i)
    assert len(cache.history("c") or ()) == 99
    for i in range(1, 100):
        assert get_data(cache, i)[0] == f"p{i}"


def test_time_cache_repeatability_reverse_insert_order() -> None:
    """TEST(TimeCache, RepeatabilityReverseInsertOrder)."""
    cache = ros2_buffer()
    for i in range(99, -1, -1):
        item(cache, i, i)
    assert len(cache.history("c") or ()) == 100
    for i in range(1, 100):
        assert get_data(cache, i)[0] == f"p{i}"


def test_time_cache_repeated_elements() -> None:
    """TEST(TimeCache, RepeatedElements): the same element 99 times is held once."""
    cache = ros2_buffer()
    for _ in range(1, 100):
        assert item(cache, 0, 0)
    assert len(cache.history("c") or ()) == 1


def test_time_cache_zero_at_front() -> None:
    """TEST(TimeCache, ZeroAtFront): time 0 is the newest sample."""
    cache = ros2_buffer()
    for i in range(1, 100):
        item(cache, i, i)
    item(cache, 100, 100)
    for i in range(1, 100):
        assert get_data(cache, i)[0] == f"p{i}"
    hist = cache.history("c")
    assert hist is not None
    assert get_data(cache, 0)[0] == "p100" and hist.latest_stamp == 100
    item(cache, 101, 100)
    assert get_data(cache, 0)[0] == "p100" and hist.latest_stamp == 101


def test_time_cache_cartesian_interpolation() -> None:
    """TEST(TimeCache, CartesianInterpolation)."""
    rand = PseudoRandom()
    offset = 200
    for _ in range(1, 100):
        cache = ros2_buffer()  # clearList()
        xyz = []
        for step in range(2):
            xyz.append((10.0 * rand(), 10.0 * rand(), 10.0 * rand()))
            put(cache, "p2", "c", step * 100 + offset, xyz[-1])
        for pos in range(100):
            _, v = get_data(cache, offset + pos)
            for k in range(3):
                assert v[k] == pytest.approx(xyz[0][k] + (xyz[1][k] - xyz[0][k]) * pos / 100.0, abs=2e-6)


def test_time_cache_reparenting_interpolation_protection() -> None:
    """TEST(TimeCache, ReparentingInterpolationProtection): no interpolation across parents."""
    rand = PseudoRandom()
    offset = 555
    cache = ros2_buffer()
    xyz = []
    for step in range(2):
        xyz.append((10.0 * rand(), 10.0 * rand(), 10.0 * rand()))
        put(cache, f"p{step + 4}", "c", step * 100 + offset, xyz[-1])
    for pos in range(100):
        _, v = get_data(cache, offset + pos)
        assert v[:3] == pytest.approx(list(xyz[0]), abs=1e-6)


def test_time_cache_angular_interpolation() -> None:
    """TEST(TimeCache, AngularInterpolation): the cache's rotation is slerp's."""
    rand = PseudoRandom()
    offset = 200
    for _ in range(1, 100):
        cache = ros2_buffer()
        quats = []
        for step in range(2):
            quats.append(quat_from_rpy(10.0 * rand() / 100.0, 0.0, 0.0))
            put(cache, "p3", "c", offset + step * 100, rotation=quats[-1])
        for pos in range(100):
            _, v = get_data(cache, offset + pos)
            truth = slerp(np.array(quats[0]), np.array(quats[1]), pos / 100.0)
            dot = abs(sum(a * b for a, b in zip(truth, v[3:], strict=True)))
            assert 2 * math.acos(min(1.0, dot)) == pytest.approx(0, abs=1e-6)


def test_time_cache_duplicate_entries() -> None:
    """TEST(TimeCache, DuplicateEntries)."""
    cache = ros2_buffer()
    item(cache, 1, 3)
    assert len(cache.history("c") or ()) == 1
    item(cache, 1, 3)
    assert len(cache.history("c") or ()) == 1
    assert not any(math.isnan(x) for x in get_data(cache, 1)[1])


# --- tf2/test/static_cache_test.cpp --------------------------------------------------------


def test_static_cache_repeatability() -> None:
    """TEST(StaticCache, Repeatability): the last sample holds at every time."""
    cache = ros2_buffer()
    for i in range(1, 100):
        put(cache, f"p{i}", "c", i, static=True)
        assert get_data(cache, i)[0] == f"p{i}"
        assert cache.lookup(f"p{i}", "c", i).stamp == i


def test_static_cache_duplicate_entries() -> None:
    """TEST(StaticCache, DuplicateEntries)."""
    cache = ros2_buffer()
    put(cache, "p3", "c", 1, static=True)
    put(cache, "p3", "c", 1, static=True)
    assert not any(math.isnan(x) for x in get_data(cache, 1)[1])


# --- tf2/test/test_storage.cpp -------------------------------------------------------------


@pytest.mark.parametrize(
    ("field", "other"),
    [("rotation", (1.0, 0.0, 0.0, 0.0)), ("translation", (1.0, 0.0, 0.0)), ("stamp", S), ("parent", "p55")],
)
def test_transform_storage_equality(field: str, other: object) -> None:
    """TEST_F(TransformStorageTest, EqualityOperator / InequalityOperator), as the cache uses
    it: a sample equal in every field is held once, one differing in any field is stored."""
    sample = {"parent": "p0", "stamp": 0, "translation": (0.0, 0.0, 0.0), "rotation": IDENTITY}
    for changed, count in (({}, 1), ({field: other}, 2)):
        cache = ros2_buffer()
        for s in (sample, {**sample, **changed}):
            put(cache, str(s["parent"]), "c", int(s["stamp"]), s["translation"], s["rotation"])  # type: ignore[call-overload, arg-type]  # a dict of mixed fields
        assert len(cache.history("c") or ()) == count


def test_transform_storage_equality_compares_doubles() -> None:
    """``TransformStorage ==`` compares doubles: -0.0 equals 0.0."""
    cache = ros2_buffer()
    put(cache, "p0", "c", 5, (0.0, 0.0, 0.0))
    put(cache, "p0", "c", 5, (-0.0, 0.0, 0.0))
    assert len(cache.history("c") or ()) == 1


# --- tf2/test/test_time.cpp ----------------------------------------------------------------


def test_duration_to_sec() -> None:
    """TEST(TestTime, durationToSec) and timeToSec."""
    ms, ns = 1_000_000, 1
    cases = {0: 0.0, S: 1.0, -S: -1.0, ns: 1e-9, -ns: -1e-9, S + ns: 1.000000001, S - ns: 0.999999999}
    cases |= {500 * ms: 0.5, S + 500 * ms: 1.5, 2 * S + 500 * ms: 2.5}
    cases |= {-500 * ms: -0.5, -S - 500 * ms: -1.5, -2 * S - 500 * ms: -2.5}
    for duration, seconds in cases.items():
        assert duration_to_sec(duration) == seconds, duration


def test_display_time_point() -> None:
    """TEST(TestTime, displayTimePoint): how ROS 2's tf2 prints times in its messages."""
    cases = {0: "0.000000", S: "1.000000", 10 * S: "10.000000", -S: "-1.000000", -10 * S: "-10.000000"}
    cases |= {1: "0.000000", -1: "-0.000000", 1000: "0.000001", -1000: "-0.000001"}
    for stamp, text in cases.items():
        assert ROS2.seconds(stamp) == text


# --- tf2/test/simple_tf2_core.cpp ----------------------------------------------------------


def test_set_transform_fail() -> None:
    """TEST(tf2, setTransformFail): an empty message is refused."""
    assert not put(ros2_buffer(), "", "", 0, rotation=(0.0, 0.0, 0.0, 0.0))


def test_set_transform_valid() -> None:
    """TEST(tf2, setTransformValid)."""
    assert put(ros2_buffer(), "foo", "child", S)


def test_set_transform_invalid_quaternion() -> None:
    """TEST(tf2, setTransformInvalidQuaternion)."""
    buffer = ros2_buffer()
    assert not put(buffer, "foo", "child", S, rotation=(0.0, 0.0, 0.0, 0.0))
    # Its matrix makes the zero quaternion NaNs, which both checks refuse.
    assert [r.code.value for r in buffer.rejections] == ["TF_NAN_INPUT", "TF_DENORMALIZED_QUATERNION"]


def test_lookup_exception_nothing_exists() -> None:
    """TEST(tf2_lookupTransform, LookupException_Nothing_Exists) and TEST(tf2_canTransform, Nothing_Exists)."""
    buffer = ros2_buffer()
    with pytest.raises(UnknownFrameError):
        buffer.lookup("a", "b", S)
    assert not buffer.can_transform("a", "b", S)


def test_lookup_exception_one_exists() -> None:
    """TEST(tf2_lookupTransform, LookupException_One_Exists) and TEST(tf2_canTransform, One_Exists)."""
    buffer = ros2_buffer()
    assert put(buffer, "foo", "child", S)
    with pytest.raises(UnknownFrameError):
        buffer.lookup("foo", "bar", S)
    assert not buffer.can_transform("foo", "bar", S)


def test_transform_exception_backward_forward() -> None:
    """TEST(tf2_lookupTransform, TransformException_Backward_Forward) (Jazzy and later)."""
    buffer = ros2_buffer()
    assert put(buffer, "foo", "bar", 2 * S)
    buffer.lookup("foo", "bar", 2 * S)
    with pytest.raises(NoDataForExtrapolationError) as one:
        buffer.lookup("foo", "bar", 4 * S)
    assert isinstance(one.value, ExtrapolationError) and isinstance(one.value, TransformError)
    assert put(buffer, "foo", "bar", 3 * S)
    with pytest.raises(BackwardExtrapolationError):
        buffer.lookup("foo", "bar", S)
    with pytest.raises(ForwardExtrapolationError):
        buffer.lookup("foo", "bar", 4 * S)


@pytest.mark.parametrize("dynamic_first", [False, True])
def test_lookup_static_transform(dynamic_first: bool) -> None:
    """TEST(tf2_clear, LookUp_Static_Transfrom_Succeed / _Fail): a static sample makes the frame
    static, also after dynamic ones (tftools has no ``clear``: the static sample comes after)."""
    buffer = ros2_buffer()
    if dynamic_first:
        assert put(buffer, "foo", "bar", S)
    assert put(buffer, "foo", "bar", S, static=True)
    assert buffer.lookup("foo", "bar", 2 * S).stamp == 2 * S


# --- test_tf2/test/buffer_core_test.cpp ----------------------------------------------------


def test_no_insert_on_self_transform() -> None:
    """TEST(BufferCore_setTransform, NoInsertOnSelfTransform)."""
    buffer = ros2_buffer()
    assert not put(buffer, "same_frame", "same_frame", 10 * S)
    assert buffer.rejections[0].message == (
        'TF_SELF_TRANSFORM: Ignoring transform from authority "authority" with frame_id and  '
        'child_frame_id "same_frame" because they are the same'
    )


def test_no_insert_with_nan() -> None:
    """TEST(BufferCore_setTransform, NoInsertWithNan)."""
    buffer = ros2_buffer()
    assert put(buffer, "same_frame", "other_frame", 10 * S)
    assert not put(buffer, "same_frame", "other_frame", 10 * S, (math.nan, 0.0, 0.0))
    assert buffer.rejections[0].message == (
        'TF_NAN_INPUT: Ignoring transform for child_frame_id "other_frame" from authority "authority" '
        "because of a nan value in the transform (nan 0.000000 0.000000) (0.000000 0.000000 0.000000 1.000000)"
    )


@pytest.mark.parametrize("empty", ["", "/"])
def test_no_insert_with_no_frame_id(empty: str) -> None:
    """TEST(BufferCore_setTransform, NoInsertWithNoFrameID / NoInsertWithNoParentID)."""
    buffer = ros2_buffer()
    assert not put(buffer, "same_frame", empty, 10 * S)
    assert not put(buffer, empty, "some_frame", 10 * S)
    assert [r.code.value for r in buffer.rejections] == ["TF_NO_CHILD_FRAME_ID", "TF_NO_FRAME_ID"]


TREES = {  # setupTree's trees: (parent, child, dx, dy)
    "i": [("a", "b", 1, 0), ("b", "c", 1, 0)],
    "1": [("1", "2", 1, 0)],
    "v": [("a", "b", 1, 0), ("b", "c", 1, 0), ("a", "f", 0, 1), ("f", "g", 0, 1)],
    "y": [("a", "b", 1, 0), ("b", "c", 1, 0), ("b", "d", 0, 1), ("d", "e", 0, 1)],
}


def setup_tree(buffer: Buffer, mode: str, time: int, interpolation_space: int = 0) -> None:
    """buffer_core_test.cpp's ``setupTree``: each edge at ``time - space / 2`` (0 if that is
    not after 0), then again at ``time`` where there is a space. At time 0 the second
    sample repeats the first: ROS 2's tf2 accepts it (``EXPECT_TRUE``)."""
    for parent, child, dx, dy in TREES[mode]:
        half = duration_to_sec(interpolation_space) * 0.5
        seconds = time / S
        first = int((seconds - half) * 1e9) if seconds > half else 0
        assert put(buffer, parent, child, first, (float(dx), float(dy), 0.0))
        if interpolation_space > 0:
            assert put(buffer, parent, child, int(seconds * 1e9), (float(dx), float(dy), 0.0))


def position(mode: str, frame: str) -> np.ndarray:
    edges = {child: (parent, dx, dy) for parent, child, dx, dy in TREES[mode]}
    at = np.zeros(3)
    while frame in edges:
        frame, dx, dy = edges[frame]
        at += (dx, dy, 0)
    return at


@pytest.mark.parametrize(
    ("mode", "spaces"),
    [("i", (S, S // 1000, S // 10)), ("1", (0,)), ("v", (0,)), ("y", (0,))],
)
def test_lookup_transform_configurations(mode: str, spaces: tuple[int, ...]) -> None:
    """TEST(BufferCore_lookupTransform, i_configuration / one_link / v / y_configuration)."""
    frames = sorted({f for edge in TREES[mode] for f in edge[:2]})
    for time, space, source, target in itertools.product((S, 10 * S, 0), spaces, frames, frames):
        buffer = ros2_buffer()
        setup_tree(buffer, mode, time, space)
        out = buffer.lookup(source, target, time)
        assert (out.stamp, out.frame_id, out.child_frame_id) == (time, source, target)
        expected = position(mode, target) - position(mode, source)
        np.testing.assert_allclose(out.translation, expected, atol=1e-6)
        np.testing.assert_allclose(out.rotation, IDENTITY, atol=1e-6)


def test_lookup_transform_invalid_arguments() -> None:
    """TEST(BufferCore_lookupTransform, invalid_arguments), with ROS 2's wording."""
    buffer = ros2_buffer()
    setup_tree(buffer, "i", S)
    buffer.lookup("b", "a", 0)
    for target, source in (("", "a"), ("b", ""), ("/b", "a"), ("b", "/a")):
        with pytest.raises(InvalidArgumentError):
            buffer.lookup(target, source, 0)
    with pytest.raises(InvalidArgumentError) as empty:
        buffer.lookup("", "a", 0)
    assert str(empty.value) == (
        'Invalid argument "" passed to lookupTransform argument target_frame - in tf2 frame_ids cannot be empty'
    )
    with pytest.raises(InvalidArgumentError) as slash:
        buffer.lookup("b", "/a", 0)
    assert str(slash.value) == (
        'Invalid argument "/a" passed to lookupTransform argument source_frame - '
        "in tf2 frame_ids cannot start with a '/'"
    )


def test_can_transform_invalid_arguments() -> None:
    """TEST(BufferCore_canTransform, invalid_arguments)."""
    buffer = ros2_buffer()
    setup_tree(buffer, "i", S)
    assert buffer.can_transform("b", "a", 0)
    for target, source in (("", "a"), ("b", ""), ("/b", "a"), ("b", "/a")):
        assert not buffer.can_transform(target, source, 0)


# --- tf2_py/test/test_buffer_core.py -------------------------------------------------------


def build_transform(buffer: Buffer, target: str, source: str, stamp: int, static: bool = False) -> bool:
    return put(buffer, target, source, stamp, (2.0, 0.0, 0.0), static=static, authority="unittest")


def test_py_all_frames_as_yaml_and_string() -> None:
    """test_all_frames_as_yaml, test_all_frames_as_string."""
    buffer = ros2_buffer()
    build_transform(buffer, "bar", "foo", 0)
    for text in (buffer.all_frames_as_yaml(), buffer.all_frames_as_string()):
        assert isinstance(text, str) and "foo" in text and "bar" in text


@pytest.mark.parametrize(("static", "can"), [(False, False), (True, True)])
def test_py_set_transform(static: bool, can: bool) -> None:
    """test_set_transform, test_set_transform_static."""
    buffer = ros2_buffer()
    assert build_transform(buffer, "bar", "foo", 0, static)
    assert buffer.can_transform("bar", "foo", S // 2) is can


def test_py_can_transform_core() -> None:
    """test_can_transform_core_pass, test_can_transform_core_fail."""
    buffer = ros2_buffer()
    build_transform(buffer, "bar", "foo", 0)
    build_transform(buffer, "bar", "foo", S)
    assert buffer.can_transform("foo", "bar", S // 2)
    buffer = ros2_buffer()
    build_transform(buffer, "bar", "foo", S)
    build_transform(buffer, "bar", "foo", 2 * S)
    for time, words in ((5 * S // 2, "extrapolation into the future"), (S // 2, "extrapolation into the past")):
        assert not buffer.can_transform("foo", "bar", time)
        with pytest.raises(ExtrapolationError, match=words):
            buffer.lookup("foo", "bar", time)


def test_py_can_transform_full_core() -> None:
    """test_can_transform_full_core."""
    buffer = ros2_buffer()
    build_transform(buffer, "bar", "foo", 0)
    build_transform(buffer, "foo", "baz", 0)
    assert buffer.can_transform_full("foo", 0, "baz", 0, "bar")


def test_py_get_latest_common_time() -> None:
    """test_get_latest_common_time."""
    buffer = ros2_buffer()
    for stamp in (0, S, S // 2):
        build_transform(buffer, "bar", "foo", stamp)
    assert buffer.latest_common_time("bar", "foo") == S


def test_py_lookup_transform_core() -> None:
    """test_lookup_transform_core_pass, test_lookup_transform_core_fail."""
    buffer = ros2_buffer()
    build_transform(buffer, "bar", "foo", 0)
    out = buffer.lookup("bar", "foo", 0)
    assert (out.translation, out.rotation, out.stamp) == ((2.0, 0.0, 0.0), IDENTITY, 0)
    with pytest.raises(UnknownFrameError):
        buffer.lookup("bar", "baz", 0)
