"""``Transform``: a rigid transform with its stamp and frames, as a lookup returns it."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
import numpy.typing as npt

from tftools.core.arrays import FloatArray
from tftools.core.rotation import (
    IDENTITY_QUAT,
    ZERO_VEC,
    Quat,
    Vec3,
    matrix_apply,
    matrix_from_quat,
    matrix_multiply,
    matrix_transpose,
    quat_from_matrix,
    quat_from_rpy,
    rpy_from_quat,
)


@dataclass(frozen=True, slots=True, init=False)
class Transform:
    """``T_frame^child``: takes points in ``child_frame_id`` to ``frame_id``.

    As in ``geometry_msgs/TransformStamped``: ``translation`` is the child's origin in the parent
    frame, ``rotation`` (x, y, z, w) the child's orientation, ``stamp`` integer nanoseconds.
    ``a * b`` composes ``T_a^b * T_b^c = T_a^c``. Composition and inverse go through rotation
    matrices as ``tf2::Transform`` does, so results (the quaternion's sign included) match it.
    """

    translation: Vec3 = ZERO_VEC
    rotation: Quat = IDENTITY_QUAT
    stamp: int = 0
    frame_id: str = ""
    child_frame_id: str = ""

    def __init__(
        self,
        translation: Vec3 = ZERO_VEC,
        rotation: Quat = IDENTITY_QUAT,
        stamp: int = 0,
        frame_id: str = "",
        child_frame_id: str = "",
    ) -> None:
        # The slots' own setters: a frozen dataclass's __init__ calls object.__setattr__ per
        # field, which made building a lookup's answer cost as much as the compiled lookup.
        _set_translation(self, translation)
        _set_rotation(self, rotation)
        _set_stamp(self, stamp)
        _set_frame_id(self, frame_id)
        _set_child_frame_id(self, child_frame_id)

    @classmethod
    def identity(cls, stamp: int = 0, frame_id: str = "", child_frame_id: str = "") -> Transform:
        return cls(ZERO_VEC, IDENTITY_QUAT, stamp, frame_id, child_frame_id)

    @classmethod
    def from_rpy(cls, xyz: Vec3, rpy: Vec3, stamp: int = 0, frame_id: str = "", child_frame_id: str = "") -> Transform:
        """From a translation and fixed-axis roll, pitch, yaw in radians (tf2's ``setRPY``)."""
        return cls(_vec(xyz), quat_from_rpy(*rpy), stamp, frame_id, child_frame_id)

    @classmethod
    def from_matrix(
        cls, matrix: npt.ArrayLike, stamp: int = 0, frame_id: str = "", child_frame_id: str = ""
    ) -> Transform:
        """From a 4x4 homogeneous matrix."""
        m = np.asarray(matrix, dtype=float)
        if m.shape != (4, 4):
            raise ValueError(f"expected a 4x4 matrix, got shape {m.shape}")
        rows = m[:3, :3].tolist()
        basis = (tuple(rows[0]), tuple(rows[1]), tuple(rows[2]))
        return cls(_vec(m[:3, 3]), quat_from_matrix(basis), stamp, frame_id, child_frame_id)

    def __mul__(self, other: Transform) -> Transform:
        """``self * other``: the transform from ``other``'s child frame to ``self``'s frame."""
        if not isinstance(other, Transform):
            return NotImplemented
        basis = matrix_from_quat(self.rotation)
        moved = matrix_apply(basis, other.translation)
        translation = (moved[0] + self.translation[0], moved[1] + self.translation[1], moved[2] + self.translation[2])
        rotation = quat_from_matrix(matrix_multiply(basis, matrix_from_quat(other.rotation)))
        return Transform(translation, rotation, self.stamp, self.frame_id, other.child_frame_id)

    def inverse(self) -> Transform:
        """The transform back: ``T_child^frame``."""
        inv = matrix_transpose(matrix_from_quat(self.rotation))
        x, y, z = self.translation
        return Transform(
            matrix_apply(inv, (-x, -y, -z)), quat_from_matrix(inv), self.stamp, self.child_frame_id, self.frame_id
        )

    def rpy(self) -> Vec3:
        """Roll, pitch, yaw in radians, as tf_echo prints them."""
        return rpy_from_quat(self.rotation)

    def rpy_degrees(self) -> Vec3:
        r, p, y = self.rpy()
        return (math.degrees(r), math.degrees(p), math.degrees(y))

    def as_matrix(self) -> FloatArray:
        """The 4x4 homogeneous matrix."""
        m = np.eye(4)
        m[:3, :3] = matrix_from_quat(self.rotation)
        m[:3, 3] = self.translation
        return m

    def apply(self, points: npt.ArrayLike) -> FloatArray:
        """Points (3,) or (N, 3) in ``child_frame_id`` expressed in ``frame_id``."""
        p = np.asarray(points, dtype=float)
        m = self.as_matrix()
        moved: FloatArray = p @ m[:3, :3].T + m[:3, 3]
        return moved


# The fields' slot descriptors' setters (what object.__setattr__ looks up on every call).
_set_translation, _set_rotation, _set_stamp, _set_frame_id, _set_child_frame_id = (
    vars(Transform)[field.name].__set__ for field in fields(Transform)
)


def _vec(values: npt.ArrayLike) -> Vec3:
    x, y, z = (float(v) for v in np.asarray(values, dtype=float).reshape(3))
    return (x, y, z)
