"""Quaternion and vector math with tf2's formulas and conventions.

Quaternions are (x, y, z, w). Rotations are active: ``quat_rotate_many(q, v)`` turns ``v`` by ``q``.
The formulas are tf2's own (``tf2/LinearMath``), not normalised ones, so that results agree with
tf2 to the last bits even for the slightly non-unit quaternions tf2 accepts (it tolerates
``|q|^2`` within 0.01 of 1). A formula is written once for numbers and arrays: the scalar forms
on tuples serve single transforms, where numpy's per-call cost dominates, the ``_many`` forms
``(N, 4)`` / ``(N, 3)`` arrays.
"""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

from tftools.core.arrays import FloatArray

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]
Matrix3 = tuple[Vec3, Vec3, Vec3]
#: A number, or an array of them: the formulas written once serve both forms.
S = TypeVar("S", float, FloatArray)

IDENTITY_QUAT: Quat = (0.0, 0.0, 0.0, 1.0)
ZERO_VEC: Vec3 = (0.0, 0.0, 0.0)


def _hamilton(ax: S, ay: S, az: S, aw: S, bx: S, by: S, bz: S, bw: S) -> tuple[S, S, S, S]:
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by + ay * bw + az * bx - ax * bz,
        aw * bz + az * bw + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def _rotated(qx: S, qy: S, qz: S, qw: S, vx: S, vy: S, vz: S) -> tuple[S, S, S]:
    # q * (v, 0)
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    # ... * conj(q)
    return (
        pw * -qx + px * qw + py * -qz - pz * -qy,
        pw * -qy + py * qw + pz * -qx - px * -qz,
        pw * -qz + pz * qw + px * -qy - py * -qx,
    )


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """Fixed-axis roll (X), pitch (Y), yaw (Z): tf2's ``Quaternion::setRPY``."""
    cy, sy = math.cos(yaw * 0.5), math.sin(yaw * 0.5)
    cp, sp = math.cos(pitch * 0.5), math.sin(pitch * 0.5)
    cr, sr = math.cos(roll * 0.5), math.sin(roll * 0.5)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def matrix_from_quat(q: Quat) -> Matrix3:
    """The 3x3 rotation matrix of ``q``, rows first: tf2's ``Matrix3x3::setRotation``."""
    return _matrix(*q)


def _matrix(x: S, y: S, z: S, w: S) -> tuple[tuple[S, S, S], tuple[S, S, S], tuple[S, S, S]]:
    s = 2.0 / (x * x + y * y + z * z + w * w)
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return (
        (1.0 - (yy + zz), xy - wz, xz + wy),
        (xy + wz, 1.0 - (xx + zz), yz - wx),
        (xz - wy, yz + wx, 1.0 - (xx + yy)),
    )


def rpy_from_quat(q: Quat) -> Vec3:
    """Roll, pitch, yaw of ``q``: tf2's ``Matrix3x3::getRPY`` (first solution), as tf_echo prints."""
    m = matrix_from_quat(q)
    m20 = m[2][0]
    if abs(m20) >= 1.0:
        delta = math.atan2(m[2][1], m[2][2])
        pitch = math.pi / 2 if m20 < 0 else -math.pi / 2
        return (delta, pitch, 0.0)
    pitch = -math.asin(m20)
    c = math.cos(pitch)
    roll = math.atan2(m[2][1] / c, m[2][2] / c)
    yaw = math.atan2(m[1][0] / c, m[0][0] / c)
    return (roll, pitch, yaw)


#: Below this cosine of the pitch, roll and yaw are rounding noise apart (a pitch of 90 degrees in floats).
_LOCKED = 1e-8


def rpy_rebuilding(q: Quat) -> Vec3:
    """Roll, pitch, yaw from which ``quat_from_rpy`` (a URDF ``<origin rpy>``, setRPY) makes ``q`` again. tf2's
    getRPY (``rpy_from_quat``, as tf_echo prints) takes a pitch of +-90 degrees from a matrix term rounded to 1
    and a roll from two terms that are then noise, losing the rest of the rotation: a UR flange's (-0.5, -0.5,
    -0.5, 0.5) said (0, -90, 0), a rotation 90 degrees away. Here the pitch's cosine decides, and at +-90 yaw is
    0 and the roll carries what roll and yaw share there."""
    m = matrix_from_quat(q)
    cosine = math.hypot(m[0][0], m[1][0])
    if cosine >= _LOCKED:
        return (math.atan2(m[2][1], m[2][2]), math.atan2(-m[2][0], cosine), math.atan2(m[1][0], m[0][0]))
    if m[2][0] < 0:  # pitch +90: the matrix holds roll - yaw
        return (math.atan2(m[0][1], m[1][1]), math.pi / 2, 0.0)
    return (math.atan2(-m[0][1], m[1][1]), -math.pi / 2, 0.0)  # pitch -90: roll + yaw


def quat_from_matrix(m: Matrix3) -> Quat:
    """The quaternion of a rotation matrix (rows first): tf2's ``Matrix3x3::getRotation``."""
    trace = m[0][0] + m[1][1] + m[2][2]
    if trace > 0.0:
        s = math.sqrt(trace + 1.0)
        w = s * 0.5
        s = 0.5 / s
        return ((m[2][1] - m[1][2]) * s, (m[0][2] - m[2][0]) * s, (m[1][0] - m[0][1]) * s, w)
    i = max(range(3), key=lambda d: m[d][d])  # tf2's choice: the largest diagonal term, the first of equals
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0)
    out = [0.0, 0.0, 0.0, 0.0]
    out[i] = s * 0.5
    s = 0.5 / s
    out[3] = (m[k][j] - m[j][k]) * s
    out[j] = (m[j][i] + m[i][j]) * s
    out[k] = (m[k][i] + m[i][k]) * s
    return (out[0], out[1], out[2], out[3])


def matrix_multiply(a: Matrix3, b: Matrix3) -> Matrix3:
    """``a @ b`` for 3x3 matrices given as row tuples."""
    columns = matrix_transpose(b)
    return (matrix_apply(columns, a[0]), matrix_apply(columns, a[1]), matrix_apply(columns, a[2]))


def matrix_apply(m: Matrix3, v: Vec3) -> Vec3:
    """``m @ v``."""
    return (
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    )


def matrix_transpose(m: Matrix3) -> Matrix3:
    return ((m[0][0], m[1][0], m[2][0]), (m[0][1], m[1][1], m[2][1]), (m[0][2], m[1][2], m[2][2]))


# --- vectorized forms: the same formulas over rows ----------------------------------------


def quat_multiply_many(a: FloatArray, b: FloatArray) -> FloatArray:
    """The Hamilton products ``a * b``: rotate by ``b``, then by ``a``."""
    return np.stack(_hamilton(*_columns(a), *_columns(b)), axis=-1)


def quat_rotate_many(q: FloatArray, v: FloatArray) -> FloatArray:
    """``q * v * conj(q)``, tf2's ``quatRotate``."""
    return np.stack(_rotated(*_columns(q), *_columns(v)), axis=-1)


def rpy_from_quat_many(q: FloatArray) -> FloatArray:
    m = _matrix(*_columns(q))
    m20 = m[2][0]
    locked = np.abs(m20) >= 1.0
    pitch = np.where(locked, np.where(m20 < 0, np.pi / 2, -np.pi / 2), -np.arcsin(np.clip(m20, -1, 1)))
    c = np.where(locked, 1.0, np.cos(pitch))
    roll = np.where(locked, np.arctan2(m[2][1], m[2][2]), np.arctan2(m[2][1] / c, m[2][2] / c))
    yaw = np.where(locked, 0.0, np.arctan2(m[1][0] / c, m[0][0] / c))
    return np.stack((roll, pitch, yaw), axis=-1)


def _columns(a: FloatArray) -> list[FloatArray]:
    """The components of vectors or quaternions along the last axis (indexing them: the fastest)."""
    return [a[..., i] for i in range(a.shape[-1])]


def angle_between_many(a: FloatArray, b: FloatArray) -> FloatArray:
    """The rotation (radians, 0 to pi) taking each quaternion of ``a`` to the one of ``b``, by their
    chord (exact near zero, where an arccos of the dot product is not); q and -q are one rotation."""
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    b = np.where(((a * b).sum(axis=-1) < 0)[..., None], -b, b)
    chord = np.minimum(np.linalg.norm(a - b, axis=-1) / 2, 1.0)
    angles: FloatArray = 4 * np.arcsin(chord)
    return angles
