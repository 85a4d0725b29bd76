"""ROS 2's round trip of a rotation through tf2::Transform's matrix, as the compiled core makes it a block of
rows at a time (the positive traces in vector lanes, the others one by one): the bits of tf2's own
operations (rotation.py's ``matrix_from_quat`` then ``quat_from_matrix``) for every row, whatever the
block's length or where a row with no positive trace falls in it."""

from __future__ import annotations

import numpy as np
import pytest

from tftools.core import rotation
from tftools.core._kernels import through_matrix
from tftools.core.rejection import through_matrix as one_through_matrix


def tf2_round_trip(q: np.ndarray) -> np.ndarray:
    rows = [(float(x), float(y), float(z), float(w)) for x, y, z, w in q]
    return np.array([rotation.quat_from_matrix(rotation.matrix_from_quat(row)) for row in rows])


def quaternions(count: int, seed: int) -> np.ndarray:
    """Unit and unnormalized rotations; about a third turn by more than 120 degrees (no positive trace)."""
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(count, 4))
    q[::3] /= np.linalg.norm(q[::3], axis=1)[:, None]
    q[1::7] *= 1e-3
    q[2::11, 3] = 0.0  # a half turn: trace -1
    return q


@pytest.mark.parametrize("count", [1, 2, 63, 64, 65, 130, 1000])
def test_rows_through_the_matrix_have_tf2s_bits(count: int) -> None:
    q = quaternions(count, seed=count)
    turned = q.copy()
    through_matrix(turned)
    expected = tf2_round_trip(q)
    assert turned.tobytes() == expected.tobytes()
    no_positive_trace = 4 * q[:, 3] ** 2 <= np.sum(q * q, axis=1)  # the trace is 4 w^2 / |q|^2 - 1
    assert no_positive_trace.any() or count < 3  # row 2 is a half turn
    assert [one_through_matrix(row) for row in q[:5]] == expected[:5].tolist()


def test_rows_that_are_no_rotation_come_back_as_nan() -> None:
    q = quaternions(200, seed=1)
    q[[0, 70, 199]] = [[0.0, 0.0, 0.0, 0.0], [np.nan, 0.0, 0.0, 1.0], [0.0, 0.0, np.inf, 1.0]]
    turned = q.copy()
    through_matrix(turned)
    assert np.isnan(turned[[0, 70, 199]]).all()
    fine = np.ones(200, bool)
    fine[[0, 70, 199]] = False
    assert turned[fine].tobytes() == tf2_round_trip(q[fine]).tobytes()
