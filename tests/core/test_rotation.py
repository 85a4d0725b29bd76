"""Transform math: tf2's conventions, scalar and vectorized forms agreeing."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from tftools import Transform
from tftools.core import rotation as r

rng = np.random.default_rng(42)
QUATS = [tuple(q / np.linalg.norm(q)) for q in rng.normal(size=(50, 4))]


def angle_between(a: npt.ArrayLike, b: npt.ArrayLike) -> float:
    """The rotation angle from a to b, well conditioned near zero (unlike acos of the dot)."""
    a, b = np.asarray(a), np.asarray(b)
    if np.dot(a, b) < 0:
        b = -b
    return 4 * math.atan2(np.linalg.norm(a - b), np.linalg.norm(a + b))


def same_rotation(a: npt.ArrayLike, b: npt.ArrayLike, tol: float = 1e-12) -> bool:
    return angle_between(a, b) < 1e-6 or np.allclose(a, b, atol=tol) or np.allclose(a, np.negative(b), atol=tol)


def test_rpy_round_trip_and_known_values() -> None:
    assert r.rpy_from_quat(r.quat_from_rpy(0, 0, math.pi / 2)) == pytest.approx((0, 0, math.pi / 2))
    assert r.quat_from_rpy(math.pi, 0, 0) == pytest.approx((1, 0, 0, 0), abs=1e-15)
    for roll, pitch, yaw in rng.uniform([-3, -1.5, -3], [3, 1.5, 3], (50, 3)):
        assert r.rpy_from_quat(r.quat_from_rpy(roll, pitch, yaw)) == pytest.approx((roll, pitch, yaw), abs=1e-9)


def test_rpy_at_gimbal_lock_puts_everything_in_roll() -> None:
    _roll, pitch, yaw = r.rpy_from_quat(r.quat_from_rpy(0.3, math.pi / 2, 0.0))
    assert pitch == pytest.approx(math.pi / 2)
    assert yaw == 0.0


#: Rotations at a pitch of +-90 degrees, where tf2's getRPY loses part of the rotation: the UR flange's
#: (ur_wrist_3_link -> ur_flange, rpy "0 -pi/2 -pi/2" in its URDF), and a half turn about y and x together.
LOCKED = [(-0.5, -0.5, -0.5, 0.5), (0.5, -0.5, 0.5, 0.5), (math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0)]


@pytest.mark.parametrize("q", LOCKED)
def test_rpy_rebuilding_makes_the_rotation_again_where_tf2s_rpy_does_not(q: r.Quat) -> None:
    assert angle_between(q, r.quat_from_rpy(*r.rpy_from_quat(q))) > math.radians(89)  # tf2's (tf_echo's) angles
    assert angle_between(q, r.quat_from_rpy(*r.rpy_rebuilding(q))) < 1e-12
    assert abs(r.rpy_rebuilding(q)[1]) == pytest.approx(math.pi / 2)


def test_rpy_rebuilding_is_tf2s_rpy_away_from_the_lock_and_exact_near_it() -> None:
    for q in QUATS:
        assert r.rpy_rebuilding(q) == pytest.approx(r.rpy_from_quat(q), abs=1e-12)
    for roll, yaw in rng.uniform(-3.1, 3.1, (200, 2)):
        for pitch in (math.pi / 2, -math.pi / 2, math.pi / 2 - 1e-9, -math.pi / 2 + 1e-7):
            q = r.quat_from_rpy(roll, pitch, yaw)
            assert angle_between(q, r.quat_from_rpy(*r.rpy_rebuilding(q))) < 1e-7


def test_vectorized_forms_equal_the_rotation_matrices() -> None:
    a, b = np.array(QUATS[:-1]), np.array(QUATS[1:])
    v = rng.normal(size=(len(a), 3))
    matrix = [np.array(r.matrix_from_quat(tuple(q))) for q in a]
    products = [np.array(r.matrix_from_quat(tuple(q))) for q in r.quat_multiply_many(a, b)]
    for m_a, q_b, m_ab in zip(matrix, b, products, strict=True):
        np.testing.assert_allclose(m_ab, m_a @ np.array(r.matrix_from_quat(tuple(q_b))), atol=1e-12)
    np.testing.assert_allclose(r.quat_rotate_many(a, v), [m @ x for m, x in zip(matrix, v, strict=True)], atol=1e-12)
    np.testing.assert_allclose(r.rpy_from_quat_many(a), [r.rpy_from_quat(tuple(x)) for x in a], atol=1e-12)


def test_composition_applies_right_to_left() -> None:
    a = Transform.from_rpy((1, 2, 3), (0.1, 0.2, 0.3), frame_id="a", child_frame_id="b")
    b = Transform.from_rpy((-1, 0.5, 2), (-0.4, 0.1, 1.2), frame_id="b", child_frame_id="c")
    ab = a * b
    assert (ab.frame_id, ab.child_frame_id) == ("a", "c")
    point = np.array([0.3, -0.7, 1.1])
    np.testing.assert_allclose(ab.apply(point), a.apply(b.apply(point)), atol=1e-12)
    np.testing.assert_allclose(ab.as_matrix(), a.as_matrix() @ b.as_matrix(), atol=1e-12)


def test_inverse_undoes_the_transform() -> None:
    t = Transform.from_rpy((1, -2, 0.5), (0.3, -0.2, 2.0), stamp=7, frame_id="a", child_frame_id="b")
    back = t.inverse()
    assert (back.frame_id, back.child_frame_id, back.stamp) == ("b", "a", 7)
    identity = t * back
    np.testing.assert_allclose(identity.translation, (0, 0, 0), atol=1e-12)
    assert same_rotation(identity.rotation, (0, 0, 0, 1))


def test_matrix_round_trip() -> None:
    for q in QUATS[:20]:
        t = Transform((1.0, 2.0, 3.0), q)
        back = Transform.from_matrix(t.as_matrix())
        np.testing.assert_allclose(back.translation, t.translation)
        assert same_rotation(back.rotation, q)
    with pytest.raises(ValueError, match="4x4"):
        Transform.from_matrix(np.eye(3))


def test_rpy_degrees() -> None:
    t = Transform.from_rpy((0, 0, 0), (0, 0, math.pi / 2))
    assert t.rpy_degrees() == pytest.approx((0, 0, 90))
