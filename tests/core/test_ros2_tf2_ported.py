"""ROS 2 mode, exact: issue 29's reproducers (A-G) and more of ROS 2's own tf2 tests, ported.

The expected values were read from ros2/geometry2 (rolling, tf2 0.39.1): its ``BufferCore``
built from its sources and fed the same calls (bits as it printed them with ``%a``), and its
``test_tf2/test/buffer_core_test.cpp``. ROS 2's tf2 holds every rotation as a ``tf2::Transform``'s
matrix: stored and returned rotations come back through ``Matrix3x3::getRotation``.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from tests.bags import BagFormat, TfMessage, write_bag
from tests.core.test_ros2_tf2 import IDENTITY, PseudoRandom, S, position, put, ros2_buffer, setup_tree
from tftools.core import Buffer, InvalidArgumentError, NoDataForExtrapolationError, Transform
from tftools.core.rotation import Quat, Vec3, quat_from_rpy
from tftools.core.semantics import Semantics
from tftools.sources import read_recording

# --- A. the returned rotation: canonical, as getRotation gives it --------------------------------


def test_a_returned_rotation_sign() -> None:
    buffer = ros2_buffer()
    assert put(buffer, "a", "b", S, rotation=(0.0, 0.0, 1.0, 0.0))
    assert buffer.lookup("b", "a", S).rotation == (0.0, 0.0, 1.0, 0.0)  # composed: (0, 0, -1, 0)
    assert buffer.lookup("a", "b", S).rotation == (0.0, 0.0, 1.0, 0.0)
    batch = buffer.lookup_many("b", "a", [S, S])
    assert batch.rotations.tolist() == [[0.0, 0.0, 1.0, 0.0]] * 2


def test_a_ros1_keeps_the_composed_rotation() -> None:
    buffer = Buffer()
    assert put(buffer, "a", "b", S, rotation=(0.0, 0.0, 1.0, 0.0))
    assert buffer.lookup("b", "a", S).rotation == (-0.0, -0.0, -1.0, 0.0)


def _chain(buffer: Buffer) -> None:
    put(buffer, "a", "b", S, (0.5, -1.25, 2.0), (0.1, -0.7, 0.3, -0.64))
    put(buffer, "a", "b", 2 * S, (0.75, -1.0, 2.5), (0.2, -0.6, 0.4, -0.66))
    put(buffer, "b", "c", S, (1.0, 2.0, 3.0), (-0.3, 0.5, 0.6, 0.55))
    put(buffer, "b", "c", 2 * S, (1.0, 2.0, 3.0), (-0.31, 0.52, 0.58, 0.54))


GOLDEN = {  # ROS 2's tf2's answers on _chain, bit for bit
    ("c", "a", 1_300_000_000): (
        "0x1.d5a0b5ba87226p+1 -0x1.1f59b4d0a0ef3p+0 -0x1.28d974530f284p+0",
        "0x1.3271030d79169p-2 0x1.bf93bb8b97bfdp-1 0x1.5decb9c83a954p-2 -0x1.5fb07dad2b85bp-3",
    ),
    ("a", "c", 1_700_000_000): (
        "0x1.0135b333244cep+2 -0x1.30294155f75b2p+0 0x1.599dd1612f8a6p-1",
        "0x1.126d0b6d6e3c1p-2 0x1.cb64cca1fe6dcp-1 0x1.2932d62c341e7p-2 0x1.93d38e24463eep-3",
    ),
    ("a", "b", 0): (
        "0x1.8p-1 -0x1p+0 0x1.4p+1",
        "-0x1.9a810d0075da6p-3 0x1.33e0c9c05863cp-1 -0x1.9a810d0075da6p-2 0x1.52aa7786c7a0fp-1",
    ),
}


def _bits(text: str) -> list[float]:
    return [float.fromhex(x) for x in text.split()]


@pytest.mark.parametrize("query", list(GOLDEN))
def test_a_bit_for_bit(query: tuple[str, str, int]) -> None:
    """Interpolated, composed, inverted (two denormalized-looking inputs normalized on store)."""
    buffer = ros2_buffer()
    _chain(buffer)
    found = buffer.lookup(*query)
    translation, rotation = GOLDEN[query]
    assert list(found.translation) == _bits(translation)
    assert list(found.rotation) == _bits(rotation)
    batch = buffer.lookup_many(query[0], query[1], [query[2]])
    assert batch.translations[0].tolist() == _bits(translation) and batch.rotations[0].tolist() == _bits(rotation)


def test_a_lookup_full_multiplies_the_matrices() -> None:
    """lookupTransform with a fixed frame: tf2::Transform * tf2::Transform, read back."""
    buffer = ros2_buffer()
    _chain(buffer)
    found = buffer.lookup_full("c", 1_500_000_000, "a", 1_200_000_000, "a")
    assert list(found.translation) == _bits("0x1.e895d8422f723p+1 -0x1.1afb83c08b7d7p+0 -0x1.1a518364a7f46p+0")
    assert list(found.rotation) == _bits(
        "0x1.226e8637dedf3p-2 0x1.c5c259193ff5dp-1 0x1.43e2a4209c30bp-2 -0x1.7a11d41ac3898p-3"
    )


# --- B. the stored rotation ----------------------------------------------------------------------


def test_b_stored_rotation_through_the_matrix() -> None:
    """tf2 holds (0, 0, 0, 1.004) as (0, 0, 0, 1): an inverse's translation is not scaled by |q|²
    (the history keeps the sample as it was sent; the walk reads it as tf2 holds it)."""
    buffer = ros2_buffer()
    assert put(buffer, "a", "b", S, rotation=(0.0, 0.0, 0.0, -1.0))
    assert put(buffer, "a", "c", S, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.004))
    assert buffer.lookup("a", "b", S).rotation == IDENTITY
    assert buffer.lookup("c", "a", S).translation == (-1.0, -2.0, -3.0)
    assert buffer.lookup("c", "a", S).rotation == IDENTITY
    history = buffer.history("c")
    assert history is not None and history.values[0, 3:].tolist() == [0.0, 0.0, 0.0, 1.004]  # as sent
    ros1 = Buffer()
    assert put(ros1, "a", "c", S, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.004))
    assert ros1.lookup("a", "c", S).rotation == (0.0, 0.0, 0.0, 1.004)  # ROS 1 keeps it as given
    assert ros1.lookup("c", "a", S).translation != (-1.0, -2.0, -3.0)


# --- C. denormalized, zero and non-finite quaternions --------------------------------------------


def test_c_denormalized_accepted_and_stored_unit() -> None:
    buffer = ros2_buffer()
    assert put(buffer, "a", "b", S, (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 2.0))
    assert buffer.lookup("b", "a", S).translation == (-1.0, -2.0, -3.0)
    assert buffer.lookup("b", "a", S).rotation == IDENTITY
    assert not buffer.rejections
    assert not put(Buffer(), "a", "b", S, rotation=(0.0, 0.0, 0.0, 2.0))  # ROS 1 refuses it


def _log(rotation: Quat, translation: Vec3 = (0.0, 0.0, 0.0)) -> list[str]:
    buffer = ros2_buffer()
    assert not put(buffer, "a", "b", S, translation, rotation)
    return [r.message for r in buffer.rejections]


def test_c_zero_rotation_refused_with_both_codes() -> None:
    source = 'Ignoring transform for child_frame_id "b" from authority "authority" because of'
    assert _log((0.0, 0.0, 0.0, 0.0)) == [
        f"TF_NAN_INPUT: {source} a nan value in the transform (0.000000 0.000000 0.000000) (-nan -nan -nan -nan)",
        f"TF_DENORMALIZED_QUATERNION: {source} an invalid quaternion in the transform (-nan -nan -nan -nan)",
    ]


def test_c_non_finite_rotation_refused_with_both_codes() -> None:
    assert [m.split(":")[0] for m in _log((math.nan, 0.0, 0.0, 1.0))] == ["TF_NAN_INPUT", "TF_DENORMALIZED_QUATERNION"]
    assert "(nan nan nan nan)" in _log((math.nan, 0.0, 0.0, 1.0))[1]
    assert [m.split(":")[0] for m in _log((math.inf, 0.0, 0.0, 1.0))] == ["TF_NAN_INPUT", "TF_DENORMALIZED_QUATERNION"]
    ros1 = Buffer()  # ROS 1's tf2 checks isnan only: an infinite rotation fails the norm check alone
    assert not put(ros1, "a", "b", S, rotation=(math.inf, 0.0, 0.0, 1.0))
    assert [r.code.value for r in ros1.rejections] == ["TF_DENORMALIZED_QUATERNION"]


# --- D. q and -q at one stamp --------------------------------------------------------------------


def test_d_q_and_minus_q_are_one_sample() -> None:
    buffer = ros2_buffer()
    q: Quat = (0.1, -0.7, 0.3, -0.64)
    assert put(buffer, "a", "b", S, (1.0, 2.0, 3.0), q)
    assert put(buffer, "a", "b", S, (1.0, 2.0, 3.0), (-q[0], -q[1], -q[2], -q[3]))
    history = buffer.history("b")
    assert history is not None and len(history) == 1 and len(buffer.duplicates) == 1
    with pytest.raises(NoDataForExtrapolationError):  # still one sample
        buffer.lookup("a", "b", 2 * S)


# --- E. a leading slash --------------------------------------------------------------------------


@pytest.mark.parametrize("semantics", ["ros1", "ros2"])
def test_e_leading_slash(semantics: Semantics) -> None:
    buffer = Buffer(semantics=semantics)
    assert put(buffer, "a", "//b", S)
    assert buffer.frames == ["/b", "a"]
    assert not buffer.can_transform("/b", "a", S)
    assert not buffer.can_transform("a", "/b", 0)
    assert buffer.can_transform("/b", "/b", 0)  # the same name: true before any check
    with pytest.raises(InvalidArgumentError):
        buffer.lookup("/b", "a", S)


# --- F. infinite translation: refused on purpose (tf2 would store it) ----------------------------


@pytest.mark.parametrize("semantics", ["ros1", "ros2"])
def test_f_infinite_translation_refused(semantics: Semantics) -> None:
    buffer = Buffer(semantics=semantics)
    assert not put(buffer, "a", "b", S, (math.inf, 0.0, 0.0))
    assert [r.code.value for r in buffer.rejections] == ["TF_NAN_INPUT"]
    assert "(inf 0.000000 0.000000) (0.000000 0.000000 0.000000 1.000000)" in buffer.rejections[0].message


# --- G. the authority ROS 2's listener gives --------------------------------------------------------


def test_g_authority_undetectable() -> None:
    buffer = ros2_buffer()
    put(buffer, "a", "b", S, authority="/tf")
    assert "  broadcaster: 'Authority undetectable'\n" in buffer.all_frames_as_yaml()
    ros1 = Buffer()
    put(ros1, "a", "b", S, authority="/node")
    assert "  broadcaster: '/node'\n" in ros1.all_frames_as_yaml()


# --- test_tf2/test/buffer_core_test.cpp ------------------------------------------------------------

RING = "abcdefghi"
HALF = math.sqrt(2) / 2


def setup_ring(buffer: Buffer, time: int, space: int) -> None:
    """setupTree's "ring_45": frames a..i, each 45° further on the unit circle; "inverse_" ones the other way."""
    seconds, half = time / S, space / S * 0.5
    stamps = [int((seconds - half) * 1e9), int(seconds * 1e9)] if seconds > half else [0]
    for direction, prefix in ((-1.0, "inverse_"), (1.0, "")):
        for i in range(1, len(RING)):
            parent = RING[i - 1] if i == 1 or not prefix else prefix + RING[i - 1]
            rotation = (0.0, 0.0, math.sin(direction * math.pi / 8), math.cos(direction * math.pi / 8))
            for stamp in stamps:
                translation = (direction * (HALF - 1), direction * HALF, 0.0)
                assert put(buffer, parent, prefix + RING[i], stamp, translation, rotation)


def ring_pose(k: int) -> tuple[np.ndarray, float]:
    """Frame ``RING[k]``'s origin and heading (radians) in frame a: k edges of setupTree's ring."""
    at, heading = np.zeros(2), 0.0
    for _ in range(k):
        c, s = math.cos(heading), math.sin(heading)
        at = at + np.array([c * (HALF - 1) - s * HALF, s * (HALF - 1) + c * HALF])
        heading += math.pi / 4
    return at, heading


@pytest.mark.parametrize(("time", "space"), list(itertools.product((S, 10 * S, 0), (S, S // 1000, S // 10))))
def test_ring_45_configuration(time: int, space: int) -> None:
    """TEST(BufferCore_lookupTransform, ring_45_configuration). Its table's rotations carry the sign
    getRotation gives, which ROS 2's tf2 returns: w > 0 where the matrix's trace (1 + 2 cos angle)
    is positive, else z > 0 (its "inverse chaining 3" is (0, 0, 0.92, -0.38))."""
    buffer = ros2_buffer()
    setup_ring(buffer, time, space)
    for source, target in itertools.product(RING, RING):
        out = buffer.lookup(source, target, time)
        assert (out.stamp, out.frame_id, out.child_frame_id) == (time, source, target)
        (ps, hs), (pt, ht) = ring_pose(RING.index(source)), ring_pose(RING.index(target))
        angle = ht - hs
        c, s = math.cos(hs), math.sin(hs)
        d = pt - ps
        np.testing.assert_allclose(out.translation, (c * d[0] + s * d[1], -s * d[0] + c * d[1], 0.0), atol=1e-6)
        q = np.array([0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2)])
        trace = 1 + 2 * math.cos(angle)
        if (trace > 1e-9 and q[3] < 0) or (trace <= 1e-9 and q[2] < 0):
            q = -q
        np.testing.assert_allclose(out.rotation, q, atol=1e-6)


@pytest.mark.parametrize("time", [S, 10 * S, 0])
def test_multi_configuration(time: int) -> None:
    """TEST(BufferCore_lookupTransform, multi_configuration): trees "1" and "v" side by side."""
    frames = ["1", "2", "a", "b", "c", "f", "g"]
    buffer = ros2_buffer()
    for mode in ("1", "v"):
        setup_tree(buffer, mode, time)
    for source, target in itertools.product(frames, frames):
        same_tree = (source in "12") == (target in "12")
        assert buffer.can_transform(source, target, time) is same_tree
        if same_tree:
            out = buffer.lookup(source, target, time)
            mode = "1" if source in "12" else "v"
            np.testing.assert_allclose(out.translation, position(mode, target) - position(mode, source), atol=1e-6)
            np.testing.assert_allclose(out.rotation, IDENTITY, atol=1e-6)


# --- tf2/test/cache_unittest.cpp -------------------------------------------------------------------


def test_bullet_slerp() -> None:
    """TEST(Bullet, Slerp): halfway between identity and q2, as the cache interpolates."""
    rand = PseudoRandom()
    for _ in range(100):
        yaw, pitch, roll = rand(), rand(), rand()  # setEuler(yaw, pitch, roll)
        q2 = np.array(quat_from_rpy(roll, pitch, yaw))
        buffer = ros2_buffer()
        put(buffer, "p", "c", S)
        put(buffer, "p", "c", 3 * S, rotation=tuple(q2))
        q3 = np.array(buffer.lookup("p", "c", 2 * S).rotation)

        def angle(a: np.ndarray, b: np.ndarray) -> float:  # tf2::Quaternion::angle: half the arc
            return math.acos(max(-1.0, min(1.0, float(a @ b) / math.sqrt(float(a @ a) * float(b @ b)))))

        assert angle(q3, np.array(IDENTITY)) == pytest.approx(angle(q2, q3), abs=1e-5)


# --- a recording of such samples ---------------------------------------------------------------------


@pytest.mark.parametrize("fmt", [BagFormat.ros1, BagFormat.rosbag2_sqlite3])
def test_recording_keeps_each_refused_sample_once_and_as_sent(tmp_path: Path, fmt: BagFormat) -> None:
    """A sample refused for two reasons (a zero rotation in ROS 2, a NaN one in both) is one row of
    ``transforms``; kept rows are as recorded (q = (0, 0, 0, -1) stays so, though ROS 2 holds (0, 0, 0, 1))."""
    sent = [
        Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, -1.0), S, "a", "b"),
        Transform((0.0, 0.0, 0.0), (math.nan, 0.0, 0.0, 1.0), 2 * S, "a", "b"),
        Transform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), 3 * S, "a", "b"),
    ]
    bag = write_bag(tmp_path / "q.bag", [TfMessage("/tf", t.stamp, [t]) for t in sent], fmt)
    recording = read_recording([bag])
    rows = recording.transforms
    assert rows.stamp.tolist() == [S, 2 * S, 3 * S]
    np.testing.assert_array_equal(rows.rotation, [t.rotation for t in sent])
    held = (0.0, 0.0, 0.0, -1.0) if fmt is BagFormat.ros1 else IDENTITY
    assert recording.buffer.lookup("a", "b", S).rotation == held
