"""What the buffer records beyond tf2: rejections, provenance of samples, clocks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tftools import (
    BatchBuilder,
    Buffer,
    ExtrapolationError,
    RejectionCode,
    SimClock,
    Transform,
    UnknownFrameError,
)
from tftools.core.history import CHILD_HAD_SLASH, FROM_STATIC_TOPIC, PARENT_HAD_SLASH
from tftools.core.rotation import Quat

S = 1_000_000_000


def tf(parent: str, child: str, stamp: int, x: float = 0.0, q: Quat = (0.0, 0.0, 0.0, 1.0)) -> Transform:
    return Transform((x, 0.0, 0.0), q, stamp, parent, child)


def test_rejections_are_recorded_not_printed(capsys: pytest.CaptureFixture[str]) -> None:
    buffer = Buffer(cache_time=None)
    assert not buffer.set_transform(tf("a", "b", 5 * S, x=math.nan), "/nav", record_time=6 * S)
    assert not buffer.set_transform(tf("a", "a", 5 * S), "/self")
    assert capsys.readouterr() == ("", "")
    nan, self_tf = buffer.rejections
    assert (nan.code, nan.frame_id, nan.child_frame_id, nan.stamp, nan.authority, nan.record_time) == (
        RejectionCode.NAN_INPUT,
        "a",
        "b",
        5 * S,
        "/nav",
        6 * S,
    )
    assert "TF_NAN_INPUT" in nan.message and '"b"' in nan.message
    assert self_tf.code is RejectionCode.SELF_TRANSFORM
    assert buffer.frames == []  # refused samples intern no frame, as in tf2


def test_infinite_translation_is_refused_unlike_tf2() -> None:
    buffer = Buffer(cache_time=None)
    assert not buffer.set_transform(tf("a", "b", S, x=math.inf))
    assert [r.code for r in buffer.rejections] == [RejectionCode.NAN_INPUT]


def test_repeated_stamp_keeps_the_first_sample() -> None:
    buffer = Buffer(cache_time=None)
    buffer.set_transform(tf("a", "b", S, x=1.0))
    buffer.set_transform(tf("a", "b", 2 * S, x=2.0))
    assert not buffer.set_transform(tf("a", "b", S, x=9.0), "/late")
    assert buffer.lookup("a", "b", S).translation[0] == 1.0
    assert buffer.rejections[0].code is RejectionCode.REPEATED_DATA
    assert buffer.rejections[0].authority == "/late"


def test_finite_cache_prunes_and_refuses_old_data() -> None:
    buffer = Buffer(cache_time=2 * S)
    for k in range(10):
        buffer.set_transform(tf("a", "b", k * S, x=k))
    history = buffer.history("b")
    assert history is not None and history.stamps.tolist() == [7 * S, 8 * S, 9 * S]
    with pytest.raises(ExtrapolationError, match="into the past"):
        buffer.lookup("a", "b", 6 * S)
    assert not buffer.set_transform(tf("a", "b", 6 * S))
    assert buffer.rejections[-1].code is RejectionCode.OLD_DATA


def test_samples_keep_their_provenance() -> None:
    buffer = Buffer(cache_time=None)
    builder = BatchBuilder()
    builder.add("/odom", "base", 3 * S, (1, 0, 0), (0, 0, 0, 1), record_time=31, authority="/ekf")
    builder.add("odom", "base", 1 * S, (2, 0, 0), (0, 0, 0, 1), record_time=32, authority="/other")
    builder.add("odom", "/laser", 1 * S, (0, 0, 0), (0, 0, 0, 1), static=True, record_time=33, authority="/rsp")
    assert buffer.insert(builder.take()) == 3
    base = buffer.history("base")
    assert base is not None
    assert base.stamps.tolist() == [1 * S, 3 * S]  # sorted by stamp ...
    assert base.sequence.tolist() == [1, 0]  # ... but arrival order is kept
    assert base.record_times.tolist() == [32, 31]
    assert [buffer.authorities[a] for a in base.authorities] == ["/other", "/ekf"]
    assert base.flags.tolist() == [0, PARENT_HAD_SLASH]
    laser = buffer.history("laser")
    assert laser is not None and laser.static and laser.flags[0] == FROM_STATIC_TOPIC | CHILD_HAD_SLASH
    assert buffer.frames == ["base", "odom", "laser"]  # child before parent, as tf2 interns


def test_static_edges_hold_at_every_time_and_keep_their_history() -> None:
    buffer = Buffer(cache_time=None)
    buffer.set_transform(tf("base", "laser", 5 * S, x=1.0), static=True)
    buffer.set_transform(tf("base", "laser", 6 * S, x=2.0), static=True)  # replaces the first
    assert buffer.lookup("base", "laser", 1).translation[0] == 2.0
    assert buffer.lookup("base", "laser", 10**12).stamp == 10**12
    assert buffer.lookup("base", "laser").stamp == 0
    assert len(buffer.history("laser") or ()) == 2


def test_a_frame_can_change_parent_over_time() -> None:
    buffer = Buffer(cache_time=None)
    for k in range(3):
        buffer.set_transform(tf("a", "x", k * S))
    for k in range(3, 6):
        buffer.set_transform(tf("b", "x", k * S))
    assert buffer.parent("x", 1 * S) == "a"
    assert buffer.parent("x", 4 * S) == "b"
    assert buffer.parent("x") == "b"
    assert buffer.parent("nowhere") is None


def test_lookup_many_agrees_with_lookup_on_a_moving_chain() -> None:
    buffer = Buffer(cache_time=None)
    rng = np.random.default_rng(1)
    for k in range(50):
        for parent, child in (("map", "odom"), ("odom", "base"), ("base", "arm")):
            q = rng.normal(size=4)
            buffer.set_transform(
                Transform(tuple(rng.normal(size=3)), tuple(q / np.linalg.norm(q)), k * S // 10 + 1, parent, child)
            )
    times = rng.integers(0, 6 * S, 300)
    got = buffer.lookup_many("arm", "map", times)
    for i, t in enumerate(times):
        try:
            one = buffer.lookup("arm", "map", int(t))
        except ExtrapolationError:
            assert not got.valid[i]
            continue
        assert got.valid[i]
        np.testing.assert_allclose(got.translations[i], one.translation, atol=1e-12)
        np.testing.assert_allclose(got.rotations[i], one.rotation, atol=1e-12)


def test_lookup_many_identity_and_unknown_frames() -> None:
    buffer = Buffer(cache_time=None)
    buffer.set_transform(tf("a", "b", S))
    same = buffer.lookup_many("b", "b", [0, 5])
    assert same.valid.all() and same.stamps.tolist() == [S, 5]
    np.testing.assert_array_equal(same.rotations, [[0, 0, 0, 1]] * 2)
    with pytest.raises(UnknownFrameError, match='"c" passed to lookupTransform argument source_frame'):
        buffer.lookup_many("a", "c", [S])


def test_chain_lists_frames_from_source_to_target() -> None:
    buffer = Buffer(cache_time=None)
    for parent, child in (("map", "odom"), ("odom", "base"), ("base", "laser"), ("base", "arm"), ("arm", "hand")):
        buffer.set_transform(tf(parent, child, S))
    assert buffer.chain("laser", "hand", S) == ["hand", "arm", "base", "laser"]
    assert buffer.chain("map", "hand", S) == ["hand", "arm", "base", "odom", "map"]
    assert buffer.chain("hand", "map", S) == ["map", "odom", "base", "arm", "hand"]


def test_sim_clock_drives_now() -> None:
    clock = SimClock()
    buffer = Buffer(clock=clock)
    assert buffer.now() == 0
    clock.set(5 * S)
    clock.set(4 * S)  # never backwards
    assert buffer.now() == 5 * S
    assert clock.wait_until(5 * S, timeout_s=0)
    assert not clock.wait_until(6 * S, timeout_s=0.01)
