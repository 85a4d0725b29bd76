"""Compiled lookups (numba): ``walk.py``'s tf2 walk over an ``EdgeTable``, step for step.

``walk.py`` stays the reference: each kernel follows it line by line with the same formulas
(``rotation.py``'s), and reports only success or failure. The buffer falls back to the Python
walk on any failure, so tf2's error messages come from one place. Compiled once per machine
(``cache=True``); warm the cache with ``python3 -c "import tftools.core.kernels"``.
"""

# Kernels are typed by numba (their signatures, and inference inside): no Python annotations.
# ruff: noqa: ANN001, ANN201, ANN202
# mypy: disable-error-code="no-untyped-def"
from __future__ import annotations

import math

import numpy as np
from numba import njit, types
from numba.extending import intrinsic

from tftools.core.kernels_table import END, HAS, PARENTS, STAMPS, START, STATIC, VALUES

OK, FAILED = 0, 1
#: What ``_sample`` found at a frame.
FOUND, GAP, ROOT = 0, 1, 2
MAX_GRAPH_DEPTH = 1000  # walk.MAX_GRAPH_DEPTH
TIME_MAX = np.iinfo(np.int64).max

_TABLE = types.int64[:, ::1]
_jit = njit(cache=True, nogil=True, error_model="numpy")


@intrinsic
def _at(typingctx, address, dtype):
    """A typed pointer to the memory at an integer ``address`` (an ``EdgeTable`` column)."""
    pointer = types.CPointer(dtype.dtype)

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(pointer))

    return pointer(address, dtype), codegen


# --- rotation.py's formulas -----------------------------------------------------------------


@_jit
def _multiply(ax, ay, az, aw, bx, by, bz, bw):
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by + ay * bw + az * bx - ax * bz,
        aw * bz + az * bw + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    )


@_jit
def _rotate(qx, qy, qz, qw, vx, vy, vz):
    px = qw * vx + qy * vz - qz * vy
    py = qw * vy + qz * vx - qx * vz
    pz = qw * vz + qx * vy - qy * vx
    pw = -qx * vx - qy * vy - qz * vz
    return (
        pw * -qx + px * qw + py * -qz - pz * -qy,
        pw * -qy + py * qw + pz * -qx - px * -qz,
        pw * -qz + pz * qw + px * -qy - py * -qx,
    )


@_jit
def _slerp(ax, ay, az, aw, bx, by, bz, bw, t):
    dot = ax * bx + ay * by + az * bz + aw * bw
    norms = math.sqrt((ax * ax + ay * ay + az * az + aw * aw) * (bx * bx + by * by + bz * bz + bw * bw))
    cosine = abs(dot) / norms
    theta = math.acos(1.0 if cosine > 1.0 else cosine)
    if theta == 0.0:
        return ax, ay, az, aw
    d = 1.0 / math.sin(theta)
    s0 = math.sin((1.0 - t) * theta)
    s1 = math.sin(t * theta) if dot >= 0 else -math.sin(t * theta)
    return (ax * s0 + bx * s1) * d, (ay * s0 + by * s1) * d, (az * s0 + bz * s1) * d, (aw * s0 + bw * s1) * d


# --- one edge: EdgeHistory.sample / _row_at ---------------------------------------------------


@_jit
def _row_at(table, frame, time):
    """(kind, row, interpolate): the row to use, or the older of two to interpolate between."""
    if frame >= table.shape[0] or table[frame, HAS] == 0:
        return ROOT, 0, False
    start, end = table[frame, START], table[frame, END]
    if end == start:
        return GAP, 0, False
    if table[frame, STATIC] != 0 or time == 0:
        return FOUND, end - 1, False
    stamps = _at(table[frame, STAMPS], np.int64)
    if end - start == 1:
        return (FOUND, start, False) if stamps[start] == time else (GAP, 0, False)
    latest, earliest = stamps[end - 1], stamps[start]
    if time == latest:
        return FOUND, end - 1, False
    if time == earliest:
        return FOUND, start, False
    if time > latest or time < earliest:
        return GAP, 0, False
    lo, hi = start, end  # bisect_right: the first row stamped after ``time``
    while lo < hi:
        mid = (lo + hi) >> 1
        if time < stamps[mid]:
            hi = mid
        else:
            lo = mid + 1
    return FOUND, lo - 1, True


@_jit
def _sample(table, frame, time):
    """(kind, parent, tx, ty, tz, qx, qy, qz, qw) of ``frame``'s edge at ``time``."""
    kind, row, interpolate = _row_at(table, frame, time)
    if kind != FOUND:
        return kind, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    parents = _at(table[frame, PARENTS], np.int32)
    v = _at(table[frame, VALUES], np.float64)
    parent = np.int64(parents[row])
    i = 7 * row
    if not interpolate or parents[row + 1] != parent:
        return FOUND, parent, v[i], v[i + 1], v[i + 2], v[i + 3], v[i + 4], v[i + 5], v[i + 6]
    stamps = _at(table[frame, STAMPS], np.int64)
    t0 = stamps[row]
    r = (time - t0) / (stamps[row + 1] - t0)
    s = 1.0 - r
    j = i + 7
    qx, qy, qz, qw = _slerp(v[i + 3], v[i + 4], v[i + 5], v[i + 6], v[j + 3], v[j + 4], v[j + 5], v[j + 6], r)
    return FOUND, parent, s * v[i] + r * v[j], s * v[i + 1] + r * v[j + 1], s * v[i + 2] + r * v[j + 2], qx, qy, qz, qw


@_jit
def _parent_at(table, frame, time):
    """(kind, parent): ``_sample`` without the values, for ``can_transform``."""
    kind, row, _ = _row_at(table, frame, time)
    if kind != FOUND:
        return kind, 0
    return kind, np.int64(_at(table[frame, PARENTS], np.int32)[row])


# --- the walk: walk.lookup / walk.latest_common_time -----------------------------------------


@_jit
def _latest(table, frame):
    """(has data, latest stamp, latest parent): EdgeHistory.latest_stamp and latest_parent."""
    if frame >= table.shape[0] or table[frame, HAS] == 0 or table[frame, END] == table[frame, START]:
        return False, 0, 0
    end = table[frame, END]
    parent = np.int64(_at(table[frame, PARENTS], np.int32)[end - 1])
    if table[frame, STATIC] != 0:
        return True, 0, parent
    return True, _at(table[frame, STAMPS], np.int64)[end - 1], parent


@_jit
def _latest_common_time(table, target, source):
    """(status, time): walk.latest_common_time."""
    side_stamps = np.empty(MAX_GRAPH_DEPTH + 2, np.int64)
    side_parents = np.empty(MAX_GRAPH_DEPTH + 2, np.int64)
    n = 0
    common = TIME_MAX
    frame = source
    while True:
        has, stamp, parent = _latest(table, frame)
        if not has:
            break
        if stamp:
            common = min(common, stamp)
        side_stamps[n], side_parents[n] = stamp, parent
        n += 1
        frame = parent
        if frame == target:
            return OK, 0 if common == TIME_MAX else common
        if n > MAX_GRAPH_DEPTH:
            return FAILED, 0

    common = TIME_MAX
    common_parent = 0
    frame = target
    depth = 0
    while True:
        has, stamp, parent = _latest(table, frame)
        if not has:
            break
        if stamp:
            common = min(common, stamp)
        if parent in side_parents[:n]:
            common_parent = parent
            break
        frame = parent
        if frame == source:
            return OK, 0 if common == TIME_MAX else common
        depth += 1
        if depth > MAX_GRAPH_DEPTH:
            return FAILED, 0

    if common_parent == 0:
        return FAILED, 0
    for i in range(n):
        if side_stamps[i]:
            common = min(common, side_stamps[i])
        if side_parents[i] == common_parent:
            break
    return OK, 0 if common == TIME_MAX else common


@_jit
def _walk(table, target, source, time):
    """(status, tx, ty, tz, qx, qy, qz, qw): walk.lookup at a resolved ``time``."""
    # Up from the source, accumulating T_top^source.
    svx, svy, svz, sqx, sqy, sqz, sqw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    frame = top = source
    depth = 0
    while True:
        kind, parent, vx, vy, vz, qx, qy, qz, qw = _sample(table, frame, time)
        if kind != FOUND:
            top = frame
            break
        if frame == target:
            return OK, svx, svy, svz, sqx, sqy, sqz, sqw
        rx, ry, rz = _rotate(qx, qy, qz, qw, svx, svy, svz)
        svx, svy, svz = rx + vx, ry + vy, rz + vz
        sqx, sqy, sqz, sqw = _multiply(qx, qy, qz, qw, sqx, sqy, sqz, sqw)
        top, frame = frame, parent
        depth += 1
        if depth > MAX_GRAPH_DEPTH:
            return FAILED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0

    # Up from the target until the frame the first walk stopped at, accumulating T_top^target.
    tvx, tvy, tvz, tqx, tqy, tqz, tqw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    frame = target
    depth = 0
    while frame != top:
        kind, parent, vx, vy, vz, qx, qy, qz, qw = _sample(table, frame, time)
        if kind == ROOT:
            break
        if kind == GAP:
            return FAILED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
        if frame == source:
            ix, iy, iz = _rotate(-tqx, -tqy, -tqz, tqw, -tvx, -tvy, -tvz)
            return OK, ix, iy, iz, -tqx, -tqy, -tqz, tqw
        rx, ry, rz = _rotate(qx, qy, qz, qw, tvx, tvy, tvz)
        tvx, tvy, tvz = rx + vx, ry + vy, rz + vz
        tqx, tqy, tqz, tqw = _multiply(qx, qy, qz, qw, tqx, tqy, tqz, tqw)
        frame = parent
        depth += 1
        if depth > MAX_GRAPH_DEPTH:
            return FAILED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0

    if frame != top:
        return FAILED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    ix, iy, iz = _rotate(-tqx, -tqy, -tqz, tqw, -tvx, -tvy, -tvz)
    rx, ry, rz = _rotate(-tqx, -tqy, -tqz, tqw, svx, svy, svz)
    qx, qy, qz, qw = _multiply(-tqx, -tqy, -tqz, tqw, sqx, sqy, sqz, sqw)
    return OK, rx + ix, ry + iy, rz + iz, qx, qy, qz, qw


@_jit
def _connected(table, target, source, time):
    """walk.chain's verdict (what can_transform answers) at a resolved ``time``."""
    frame = top = source
    depth = 0
    while True:
        kind, parent = _parent_at(table, frame, time)
        if kind != FOUND:
            top = frame
            break
        if frame == target:
            return True
        top, frame = frame, parent
        depth += 1
        if depth > MAX_GRAPH_DEPTH:
            return False
    frame = target
    depth = 0
    while frame != top:
        kind, parent = _parent_at(table, frame, time)
        if kind == ROOT:
            break
        if kind == GAP:
            return False
        if frame == source:
            return True
        frame = parent
        depth += 1
        if depth > MAX_GRAPH_DEPTH:
            return False
    return frame == top


# --- entry points ---------------------------------------------------------------------------


_LOOKUP = types.int64(_TABLE, types.int64, types.int64, types.int64, types.float64[::1], types.int64[::1])


@njit(_LOOKUP, cache=True, nogil=True)
def lookup(table, target, source, time, values, stamp):
    """walk.lookup into ``values`` (tx ty tz qx qy qz qw) and ``stamp[0]``; OK or FAILED."""
    if time == 0:
        status, time = _latest_common_time(table, target, source)
        if status != OK:
            return FAILED
    status, vx, vy, vz, qx, qy, qz, qw = _walk(table, target, source, time)
    values[0], values[1], values[2], values[3], values[4], values[5], values[6] = vx, vy, vz, qx, qy, qz, qw
    stamp[0] = time
    return status


@njit(types.boolean(_TABLE, types.int64, types.int64, types.int64), cache=True, nogil=True)
def can_transform(table, target, source, time):
    """walk.can_transform."""
    if time == 0:
        status, time = _latest_common_time(table, target, source)
        if status != OK:
            return False
    return _connected(table, target, source, time)
