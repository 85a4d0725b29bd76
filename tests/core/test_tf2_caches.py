"""The two rules of tf2's caches that ``tfx wtf`` applies to a recording's rows without a live buffer, against
Debian's ROS 1 tf2: which samples ``TimeCache::insertData`` refuses as ``TF_OLD_DATA`` (``history.old_data``),
and which frames live in a ``StaticCache`` that takes every sample whatever its stamp
(``Buffer.in_static_cache``)."""

from __future__ import annotations

import numpy as np

from tests.core import scenarios
from tests.oracle import Row, Scenario, run_tf2
from tftools.core import Buffer, Transform
from tftools.core.buffer import DEFAULT_CACHE_TIME
from tftools.core.history import old_data
from tftools.core.rejection import RejectionCode
from tftools.core.semantics import Semantics
from tftools.core.time import NS_PER_S

CACHE_S = 10


def _row(stamp: int, x: float, static: bool = False) -> Row:
    return ["odom", "base_link", *divmod(stamp, NS_PER_S), x, 0, 0, 0, 0, 0, 1, "me", static]


def _stamps() -> list[int]:
    """One frame's stamps in arrival order (small times: exact through tf2's binding): mostly rising, some back
    by less than the 10 s cache, some by more, some behind a stamp that itself came back, some repeated."""
    rng = np.random.default_rng(39)
    stamps, now = [], 100 * NS_PER_S
    for _ in range(40):
        now += int(rng.integers(1, 4)) * NS_PER_S // 2
        kind = rng.integers(5)
        back = {0: 0, 1: 3 * NS_PER_S, 2: 12 * NS_PER_S, 3: 10 * NS_PER_S, 4: -20 * NS_PER_S}[int(kind)]
        stamps.append(now - back)
    stamps += [stamps[5], stamps[-1], stamps[-1] - CACHE_S * NS_PER_S - 1]
    return stamps


def test_old_data_is_what_tf2_refuses_as_too_old(tf2_available: None) -> None:
    """Each row's verdict from the real tf2: a scenario per prefix of the stream, the row refused as old where
    its prefix logs one more TF_OLD_DATA than the one before. Our own buffer with that cache agrees."""
    stamps = _stamps()
    rows = [_row(s, i / 10) for i, s in enumerate(stamps)]
    prefixes = [Scenario(inserts=rows[: n + 1], cache_time_s=CACHE_S) for n in range(len(rows))]
    logged = [r["rejections"].count("TF_OLD_DATA") for r in run_tf2(prefixes)]
    theirs = np.diff([0, *logged]) == 1
    ours = old_data(np.array(stamps, np.int64), CACHE_S * NS_PER_S)
    assert ours.tolist() == theirs.tolist()
    assert 3 <= int(ours.sum()) < len(stamps) - 10, "the stream should hold old rows and fresh ones"
    buffer = scenarios.load_into_buffer(prefixes[-1])
    refused = {r.sequence for r in buffer.rejections if r.code is RejectionCode.OLD_DATA}
    assert sorted(refused) == np.flatnonzero(ours).tolist()


def test_old_data_of_a_frame_also_sent_static(tf2_available: None) -> None:
    """A frame first sent on /tf, with some samples on /tf_static among them. ROS 1's tf2 puts those into the
    frame's ``TimeCache`` with their stamps, like any (the real tf2_py's logs say which it refuses); ROS 2's
    replaces the frame's cache at each change of kind, so a /tf sample after a /tf_static one starts an empty
    ``TimeCache`` (our ROS 2 buffer, exact to ROS 2's tf2 on its ported tests, says which it refuses)."""
    stamps = _stamps()
    static = np.zeros(len(stamps), np.bool_)
    static[[7, 8, 19, 30]] = True
    rows = [_row(s, i / 10, bool(static[i])) for i, s in enumerate(stamps)]
    prefixes = [Scenario(inserts=rows[: n + 1], cache_time_s=CACHE_S) for n in range(len(rows))]
    logged = [r["rejections"].count("TF_OLD_DATA") for r in run_tf2(prefixes)]
    cache = CACHE_S * NS_PER_S
    ros1 = old_data(np.array(stamps, np.int64), cache, static, keeps_first_cache=True)
    assert ros1.tolist() == (np.diff([0, *logged]) == 1).tolist()
    ros2 = old_data(np.array(stamps, np.int64), cache, static, keeps_first_cache=False)
    judged: list[tuple[Semantics, np.ndarray]] = [("ros1", ros1), ("ros2", ros2)]
    for semantics, ours in judged:
        buffer = scenarios.load_into_buffer(prefixes[-1], semantics)
        refused = {r.sequence for r in buffer.rejections if r.code is RejectionCode.OLD_DATA}
        assert sorted(refused) == np.flatnonzero(ours).tolist(), semantics
    assert (ros1 & ~ros2).any(), "a /tf sample after a /tf_static one should be refused by ROS 1's tf2 alone"
    assert not old_data(np.array(stamps, np.int64), cache, np.ones(len(stamps), np.bool_)).any()  # a StaticCache


def test_old_data_of_no_sample_or_one() -> None:
    assert old_data(np.zeros(0, np.int64), DEFAULT_CACHE_TIME).tolist() == []
    assert old_data(np.array([5], np.int64), DEFAULT_CACHE_TIME).tolist() == [False]


def _put(buffer: Buffer, stamp: int, x: float, static: bool) -> None:
    buffer.set_transform(Transform((x, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), stamp, "odom", "base_link"), "me", static)


def test_a_frame_first_sent_static_takes_every_sample_in_ros1_static_cache(tf2_available: None) -> None:
    """A frame on /tf_static, then on /tf with stamps back by more than the cache and again: ROS 1's tf2 logs
    neither TF_OLD_DATA nor TF_REPEATED_DATA and answers every time with the last value (a ``StaticCache``), so
    the order of its stamps matters to no lookup. The same rows of a frame first sent on /tf are refused."""
    stamps = [500 * NS_PER_S, 480 * NS_PER_S, 496 * NS_PER_S, 496 * NS_PER_S, 450 * NS_PER_S]
    last = float(len(stamps))
    queries = [["lookup", "odom", "base_link", sec, 0] for sec in (0, 1, 450, 500, 900)]
    first = _row(400 * NS_PER_S, 0.5, static=True)
    kept = Scenario([first, *(_row(s, i + 1.0) for i, s in enumerate(stamps))], cache_time_s=CACHE_S)
    moving = Scenario([_row(s, i + 1.0) for i, s in enumerate(stamps)], cache_time_s=CACHE_S)
    kept.queries = moving.queries = queries
    static_result, moving_result = run_tf2([kept, moving])
    assert static_result["rejections"] == []
    assert [a["t"][0] for a in static_result["answers"]] == [last] * len(queries)
    assert sorted(moving_result["rejections"]) == ["TF_OLD_DATA", "TF_OLD_DATA", "TF_REPEATED_DATA"]
    assert old_data(np.array(stamps, np.int64), CACHE_S * NS_PER_S).tolist() == [False, True, False, False, True]

    # ROS 2's tf2 turns the frame dynamic at its first /tf sample, and static again at a last /tf_static one.
    cases: list[tuple[Semantics, bool, bool, bool]] = [
        ("ros1", True, False, True),
        ("ros1", False, False, False),
        ("ros2", True, False, False),
        ("ros2", False, True, False),
    ]
    for semantics, first_static, last_static, expected in cases:
        buffer = Buffer(cache_time=None, semantics=semantics)
        _put(buffer, 400 * NS_PER_S, 0.5, first_static)
        for i, stamp in enumerate(stamps):
            _put(buffer, stamp, i + 1.0, False)
        _put(buffer, 600 * NS_PER_S, 0.5, last_static)
        hist = buffer.history("base_link")
        assert hist is not None and hist.static is (expected or last_static), (semantics, first_static, last_static)
        assert buffer.in_static_cache("base_link") is expected, (semantics, first_static, last_static)
    assert not Buffer().in_static_cache("base_link")  # an unknown frame
