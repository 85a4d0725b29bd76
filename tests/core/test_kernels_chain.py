"""``lookup_many`` along a resolved chain against the walk at each time (what it falls back to): the
very same bits, on the blocks it takes and on every kind of block it must leave to the walk."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt
import pytest

from tftools import Buffer, Transform, TransformError
from tftools.core.rotation import _hamilton, _rotated

S = 1_000_000_000
T0 = 1_700_000_000 * S
SPAN = 20 * S
#: tool changes parent (arm2 -> base) here.
REPARENT = T0 + 12 * S


def _quat(axis: int, angle: float) -> tuple[float, float, float, float]:
    q = [0.0, 0.0, 0.0, math.cos(angle / 2)]
    q[axis] = math.sin(angle / 2)
    return q[0], q[1], q[2], q[3]


def _edge(
    buffer: Buffer,
    parent: str,
    child: str,
    hz: int,
    axis: int,
    angle: Callable[[int, float], float],
    start: int = T0,
    end: int = T0 + SPAN,
) -> None:
    period = S // hz
    for k, stamp in enumerate(range(start + period // 3, end, period)):
        s = (stamp - T0) / S
        buffer.set_transform(Transform((0.1 * k, 0.01 * s, 0.2), _quat(axis, angle(k, s)), stamp, parent, child))


@functools.cache
def robot() -> Buffer:
    """map -> odom -> base -> arm0 -> arm1 (static) -> arm2 -> tool (re-parented to base), base ->
    wheel, and an island; built once (the tests only read it). arm2's rotation holds still at
    times (equal samples: no arc) and jumps at others (arcs too wide for the Taylor sine)."""
    buffer = Buffer(cache_time=None)
    _edge(buffer, "map", "odom", 10, 2, lambda k, s: 0.3 * math.sin(s))
    _edge(buffer, "odom", "base", 50, 2, lambda k, s: 0.6 * math.sin(0.5 * s))
    for parent, child, axis in (("base", "arm0", 0), ("arm0", "arm1", 1)):
        buffer.set_transform(Transform((0.1, 0.2, 0.3), _quat(axis, 0.4), T0, parent, child), static=True)
    _edge(buffer, "arm1", "arm2", 100, 1, lambda k, s: 0.0 if (k // 50) % 3 == 1 else 0.7 * k + 0.3)
    _edge(buffer, "base", "wheel", 100, 0, lambda k, s: 3.0 * s)
    _edge(buffer, "arm2", "tool", 100, 2, lambda k, s: 0.2 * s, end=REPARENT)
    _edge(buffer, "base", "tool", 100, 2, lambda k, s: 0.2 * s, start=REPARENT)
    _edge(buffer, "island_root", "island", 20, 0, lambda k, s: s)
    return buffer


def _ids(buffer: Buffer, target: str, source: str) -> tuple[int, int]:
    return buffer._core.frame_id(target), buffer._core.frame_id(source)


def _run(
    buffer: Buffer, target: str, source: str, times: npt.NDArray[np.int64], rows: npt.NDArray[np.int64], chained: bool
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """``lookup_many`` along the chain where it can, or (not ``chained``) the walk at each time."""
    n = len(times)
    stamps, values, valid = np.zeros(n, np.int64), np.zeros((n, 7)), np.zeros(n, bool)
    buffer._core.lookup_many(*_ids(buffer, target, source), times, rows, stamps, values, valid, chained=chained)
    return stamps, values, valid


def assert_same_bits(buffer: Buffer, target: str, source: str, times: npt.ArrayLike) -> npt.NDArray[np.bool_]:
    """lookup_many and the walk at each of ``times`` (in their order, answers to shuffled rows)."""
    at = np.ascontiguousarray(times, np.int64)
    rows = np.random.default_rng(0).permutation(len(at))
    fast = _run(buffer, target, source, at, rows, chained=True)
    each = _run(buffer, target, source, at, rows, chained=False)
    np.testing.assert_array_equal(fast[0], each[0])
    np.testing.assert_array_equal(fast[2], each[2])
    np.testing.assert_array_equal(fast[1].view(np.int64), each[1].view(np.int64))  # -0.0 and NaN too
    return fast[2][np.argsort(rows)]


def times_of(kind: str) -> np.ndarray:
    rng = np.random.default_rng(7)
    inside = rng.integers(T0 + S, T0 + SPAN - S, 20_000)
    if kind == "sorted":
        return np.sort(inside)
    if kind == "random":
        return inside
    if kind == "sparse":  # about one time per interval or fewer
        return np.sort(rng.integers(T0 + S, T0 + SPAN - S, 300))
    if kind == "stamps":  # exactly on samples: interior ones interpolate at 0, first and last do not
        arm2, odom = np.arange(T0 + S // 300, T0 + SPAN, S // 100), np.arange(T0 + S // 30, T0 + SPAN, S // 10)
        return np.sort(np.concatenate([arm2, arm2 + 1, arm2 - 1, odom, odom + 1, inside[:2000]]))
    if kind == "outside":  # before and after every history, and around their ends
        return np.sort(np.concatenate([inside[:5000], T0 - S + inside[:300] % S, T0 + SPAN + inside[:300] % S]))
    if kind == "first_stamp_later":  # arm2's first stamp after a later time of its first interval
        first = T0 + S // 300
        return np.array([first + 5, first, first + 1, first + S // 100 + 7])
    if kind == "reparent":  # blocks that end between tool's last sample on arm2 and first on base
        return np.sort(rng.integers(REPARENT - S // 50, REPARENT + S // 500, 1000))
    if kind == "zeros":
        return np.concatenate([np.zeros(300, np.int64), np.sort(inside[:3000]), np.zeros(3, np.int64)])
    raise AssertionError(kind)


PAIRS = [
    ("map", "arm2"),  # the source walk reaches the root: target side empty
    ("wheel", "arm2"),  # two sides meeting at the root
    ("base", "arm2"),  # the source walk reaches the target
    ("arm0", "arm2"),  # ... through one dynamic edge: its first and last stamps decide
    ("arm2", "base"),  # the target walk reaches the source
    ("odom", "tool"),  # tool changes parent part way
    ("base", "arm1"),  # static edges only
    ("arm0", "map"),
    ("island", "arm2"),  # unconnected: every time fails
]
KINDS = ["sorted", "random", "sparse", "stamps", "first_stamp_later", "outside", "reparent", "zeros"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(("target", "source"), PAIRS)
def test_lookup_many_is_the_walk_at_each_time_bit_for_bit(target: str, source: str, kind: str) -> None:
    buffer = robot()
    valid = assert_same_bits(buffer, target, source, times_of(kind))
    if target == "island":
        assert not valid.any()
    elif kind in ("sorted", "random", "sparse"):
        assert valid.all()


def test_the_answers_are_single_lookups() -> None:
    buffer = robot()
    times = np.concatenate([times_of("random")[:800], times_of("outside")[-50:], [0, REPARENT]])
    for target, source in PAIRS:
        got = buffer.lookup_many(target, source, times)
        for i, time in enumerate(times.tolist()):
            try:
                expected = buffer.lookup(target, source, time)
            except TransformError:
                assert not got.valid[i], (target, source, time)
                continue
            assert got.valid[i] and got.stamps[i] == expected.stamp, (target, source, time)
            np.testing.assert_allclose(got.translations[i], expected.translation, rtol=0, atol=1e-12)
            np.testing.assert_allclose(got.rotations[i], expected.rotation, rtol=0, atol=1e-12)


def test_runs_of_every_length_compose_as_the_walk() -> None:
    """A block composes each run of times (those in one interval of an edge) in whole vectors, the last
    running past the run into the next run's lanes: runs of 1 to 17 times in each 100 Hz interval, and
    blocks ending part way through a vector, give the walk's bits."""
    period = S // 100
    times = [
        T0 + period // 3 + k * period + 1 + j * (period // 40) for k in range(100, 1900) for j in range(k % 17 + 1)
    ]
    for target, source in (("map", "arm2"), ("wheel", "arm2"), ("arm2", "base"), ("odom", "tool")):
        for count in (len(times), 1000 + 3):
            assert assert_same_bits(robot(), target, source, times[:count]).all()


# --- which blocks the chain takes ------------------------------------------------------------


def _block(buffer: Buffer, target: str, source: str, times: npt.ArrayLike) -> bool | None:
    """Whether ``lookup_many`` takes ``times`` as one block (None: the chain does not resolve at the first)."""
    taken = buffer._core.chain_takes(*_ids(buffer, target, source), np.ascontiguousarray(times, np.int64))
    return None if taken < 0 else bool(taken)


def test_the_chain_takes_healthy_blocks_and_leaves_the_others_to_the_walk() -> None:
    buffer = robot()
    inside = np.sort(np.random.default_rng(3).integers(T0 + S, T0 + 3 * S, 200))
    for target, source in PAIRS[:6]:
        assert _block(buffer, target, source, inside), (target, source)
    assert _block(buffer, "arm0", "arm1", [-5, 1, T0 + 100 * SPAN])  # static only: any time but 0
    first, last, step = T0 + S // 300, T0 + S // 300 + SPAN - S // 100, S // 100  # arm2's stamps
    assert _block(buffer, "arm1", "arm2", [first + 1, first + step, last - 1])  # interior stamps interpolate
    assert not _block(buffer, "arm1", "arm2", [first, *inside[:10]])  # on the first stamp
    assert not _block(buffer, "arm1", "arm2", [first + 5, first])  # ... after a time of the first interval
    assert not _block(buffer, "arm1", "arm2", [*inside[:10], last])  # on the last stamp
    assert not _block(buffer, "map", "arm2", [*inside[:10], T0 + SPAN + S])  # past the end
    assert not _block(buffer, "map", "arm2", [T0 + S // 50, *inside[:10]])  # before odom's first stamp
    assert not _block(buffer, "odom", "tool", [REPARENT - S, REPARENT + S])  # re-parented between
    assert not _block(buffer, "odom", "tool", [REPARENT - S, REPARENT + 1])  # between its samples on each parent
    assert _block(buffer, "odom", "tool", [REPARENT + S, REPARENT + 2 * S])  # after: the other chain
    assert _block(buffer, "island", "arm2", inside) is None


def test_intervals_of_more_than_52_days_too() -> None:
    """An interval longer than 2**52 ns, whose times' lags the chain converts one by one (shorter ones from
    their bits): the walk's bits in both, sorted blocks that the chain takes."""
    buffer = Buffer(cache_time=None)
    day = 86_400 * S
    for stamp, angle in ((T0, 0.1), (T0 + 60 * day, 0.4), (T0 + 60 * day + S, 0.5)):
        buffer.set_transform(Transform((stamp / S % 7, 1.0, 2.0), _quat(2, angle), stamp, "a", "b"))
    rng = np.random.default_rng(5)
    for low, high in ((T0 + 1, T0 + 60 * day), (T0 + 60 * day + 1, T0 + 60 * day + S)):
        times = np.sort(rng.integers(low, high, 600))
        assert _block(buffer, "a", "b", times[:256])
        assert assert_same_bits(buffer, "a", "b", times).all()


#: Pose: translation, rotation (x y z w).
Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]


def _compose(edge: Pose, acc: Pose) -> Pose:
    """``edge`` applied after ``acc``, as tf2's TransformAccum composes (rotation.py's operations)."""
    r = _rotated(*edge[1], *acc[0])
    return (r[0] + edge[0][0], r[1] + edge[0][1], r[2] + edge[0][2]), _hamilton(*edge[1], *acc[1])


def _into_root(upper: Pose, lower: Pose) -> Pose:
    """tf2's answer root <- leaf through root -> mid (``upper``) and mid -> leaf (``lower``): both edges composed
    onto the identity, then finished against the target side's identity (its conjugate, (-0, -0, -0, 1))."""
    up = _compose(upper, _compose(lower, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))))
    iq = (-0.0, -0.0, -0.0, 1.0)
    iv, r = _rotated(*iq, -0.0, -0.0, -0.0), _rotated(*iq, *up[0])
    return (r[0] + iv[0], r[1] + iv[1], r[2] + iv[2]), _hamilton(*iq, *up[1])


C, SN = math.cos(0.2), math.sin(0.2)
#: (upper, lower) static edges whose answer into the root has a negative zero (finish makes it +0), subnormals,
#: infinities (finish makes NaNs of them), or only normal numbers (finish changes no bit).
INTO_ROOT: dict[str, tuple[Pose, Pose]] = {
    "negative_zero": (((-0.0, 1.0, 2.0), (-0.0, 0.0, SN, -C)), ((0.0, -0.0, 1.0), (0.0, 0.0, SN, C))),
    "subnormal": (((5e-324, 1.0, -2.0), (0.0, 0.0, SN, C)), ((1.0, -1e-310, 3.0), _quat(0, 0.4))),
    "infinite": (((1e308, 1.0, 2.0), (0.0, 0.0, SN, C)), ((1e308, 3.0, 4.0), (0.0, 0.0, SN, C))),
    "normal": (((0.5, 1.0, 2.0), _quat(1, 0.3)), ((1.5, -3.0, 4.0), _quat(0, 0.4))),
}


@pytest.mark.parametrize("case", INTO_ROOT)
def test_into_the_root_finish_is_left_out_only_where_it_changes_no_bit(case: str) -> None:
    """A lookup into the tree's root leaves out ``finish`` where each of the answer's components is a finite
    normal number: a lookup, the chain's blocks and the walk at each time all give tf2's bits, zeros' signs
    and NaNs included, where the answer has a negative zero, subnormals or infinities too."""
    upper, lower = INTO_ROOT[case]
    buffer = Buffer(cache_time=None)
    buffer.set_transform(Transform(*upper, T0, "root", "mid"), static=True)
    buffer.set_transform(Transform(*lower, T0, "mid", "leaf"), static=True)
    translation, rotation = _into_root(upper, lower)
    expected = np.array([*translation, *rotation])
    got = buffer.lookup("root", "leaf", T0 + S)
    np.testing.assert_array_equal(np.array([*got.translation, *got.rotation]).view(np.int64), expected.view(np.int64))
    times = np.arange(T0, T0 + 600 * S, S)
    assert _block(buffer, "root", "leaf", times[:256])
    assert assert_same_bits(buffer, "root", "leaf", times).all()
    values = _run(buffer, "root", "leaf", times, np.arange(len(times)), chained=True)[1]
    np.testing.assert_array_equal(values.view(np.int64), np.tile(expected, (len(times), 1)).view(np.int64))
