"""Compiled lookups (numba): ``walk.py``'s tf2 walk over an ``EdgeTable``, step for step.

``walk.py`` stays the reference: each kernel follows it line by line with the same formulas
(``rotation.py``'s), and reports only success or failure. The buffer falls back to the Python
walk on any failure, so tf2's error messages come from one place. Compiled once per machine
(``cache=True``); warm the cache with ``python3 -c "import tftools.core.kernels_chain"``.
"""

# Kernels are typed by numba (their signatures, and inference inside), which mypy cannot follow.
# ruff: noqa: ANN001, ANN201, ANN202
# mypy: ignore-errors
from __future__ import annotations

import math

import numpy as np
from numba import njit, types
from numba.extending import intrinsic

from tftools.core import rotation
from tftools.core.kernels_table import END, HAS, PARENTS, STAMPS, START, STATIC, VALUES

OK, FAILED = 0, 1
#: What ``_sample`` found at a frame.
FOUND, GAP, ROOT = 0, 1, 2
MAX_GRAPH_DEPTH = 1000  # walk.MAX_GRAPH_DEPTH
TIME_MAX = np.iinfo(np.int64).max

_TABLE = types.int64[:, ::1]
_jit = njit(cache=True, nogil=True, error_model="numpy")
_inline = njit(cache=True, nogil=True, error_model="numpy", inline="always")


@intrinsic
def _at(typingctx, address, dtype):
    """A typed pointer to the memory at an integer ``address`` (an ``EdgeTable`` column)."""
    pointer = types.CPointer(dtype.dtype)

    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(pointer))

    return pointer(address, dtype), codegen


# --- rotation.py's formulas -----------------------------------------------------------------


# rotation.py's functions themselves, compiled; the kernels pass scalars, as they keep them.
_quat_multiply = _inline(rotation.quat_multiply)
_quat_rotate = _inline(rotation.quat_rotate)


@_inline
def _multiply(ax, ay, az, aw, bx, by, bz, bw):
    return _quat_multiply((ax, ay, az, aw), (bx, by, bz, bw))


@_inline
def _rotate(qx, qy, qz, qw, vx, vy, vz):
    return _quat_rotate((qx, qy, qz, qw), (vx, vy, vz))


@_inline
def _arc(ax, ay, az, aw, bx, by, bz, bw):
    """(theta, 1 / sin(theta), sign of the dot product): what slerp needs of two samples."""
    dot = ax * bx + ay * by + az * bz + aw * bw
    norms = math.sqrt((ax * ax + ay * ay + az * az + aw * aw) * (bx * bx + by * by + bz * bz + bw * bw))
    cosine = abs(dot) / norms
    theta = math.acos(1.0 if cosine > 1.0 else cosine)
    if theta == 0.0:
        return theta, 0.0, 1.0
    return theta, 1.0 / math.sin(theta), 1.0 if dot >= 0 else -1.0


@_inline
def _slerp(ax, ay, az, aw, bx, by, bz, bw, t, theta, d, sign, batch):
    """rotation.slerp, given ``_arc``'s constants; ``batch`` takes ``_sin`` for ``math.sin``."""
    if theta == 0.0:
        return ax, ay, az, aw
    return _weigh(ax, ay, az, aw, bx, by, bz, bw, _sin((1.0 - t) * theta, batch), _sin(t * theta, batch) * sign, d)


@_inline
def _weigh(ax, ay, az, aw, bx, by, bz, bw, s0, s1, d):
    """Slerp's last step: (a s0 + b s1) d."""
    return (ax * s0 + bx * s1) * d, (ay * s0 + by * s1) * d, (az * s0 + bz * s1) * d, (aw * s0 + bw * s1) * d


@_inline
def _sin(x, batch):
    """math.sin; for batches, small angles (the usual arc between two samples) by their Taylor
    series, within an ulp of it and several times faster (terms past x**9 are below 1e-20 x)."""
    if not batch or abs(x) > SMALL_ANGLE:
        return math.sin(x)
    return _small_sin(x)


#: Up to this angle, ``_sin`` takes ``_small_sin``.
SMALL_ANGLE = 0.0625


@_inline
def _small_sin(x):
    """sin(x) for ``|x| <= SMALL_ANGLE``, by its Taylor series."""
    x2 = x * x
    return x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880))))


# --- one edge: EdgeHistory.sample / _row_at ---------------------------------------------------
#
# ``memo`` (int64, one row per frame: the last row used, the row ``arcs`` holds) and ``arcs``
# (float64: ``_arc`` of that row and the next) let a walk over ascending times move a cursor
# instead of bisecting, and compute each interval's slerp constants once. Empty: no memo.


@_jit
def _new_memo(frames):
    return np.full((frames, 2), -1, np.int64), np.zeros((frames, 3))


@_jit
def _no_memo():
    return np.empty((0, 2), np.int64), np.empty((0, 3))


@_inline
def _find(stamps, start, end, time, memo, frame):
    """bisect_right(stamps, time, start, end): from the memo's cursor when it has one."""
    lo, hi = start, end
    if memo.shape[0]:
        cursor = memo[frame, 0]
        if start <= cursor < end and stamps[cursor] <= time:
            lo, step = cursor + 1, 1  # gallop forward from the cursor
            while lo + step < end and stamps[lo + step] <= time:
                lo += step
                step *= 2
            hi = min(lo + step, end)
    while lo < hi:
        mid = (lo + hi) >> 1
        if time < stamps[mid]:
            hi = mid
        else:
            lo = mid + 1
    if memo.shape[0]:
        memo[frame, 0] = lo - 1
    return lo


@_inline
def _row_at(table, frame, time, memo):
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
    return FOUND, _find(stamps, start, end, time, memo, frame) - 1, True


@_inline
def _sample(table, frame, time, memo, arcs):
    """(kind, parent, tx, ty, tz, qx, qy, qz, qw) of ``frame``'s edge at ``time``."""
    kind, row, interpolate = _row_at(table, frame, time, memo)
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
    ax, ay, az, aw, bx, by, bz, bw = v[i + 3], v[i + 4], v[i + 5], v[i + 6], v[j + 3], v[j + 4], v[j + 5], v[j + 6]
    if memo.shape[0] == 0:
        theta, d, sign = _arc(ax, ay, az, aw, bx, by, bz, bw)
    elif memo[frame, 1] == row:
        theta, d, sign = arcs[frame, 0], arcs[frame, 1], arcs[frame, 2]
    else:
        theta, d, sign = _arc(ax, ay, az, aw, bx, by, bz, bw)
        memo[frame, 1] = row
        arcs[frame, 0], arcs[frame, 1], arcs[frame, 2] = theta, d, sign
    qx, qy, qz, qw = _slerp(ax, ay, az, aw, bx, by, bz, bw, r, theta, d, sign, memo.shape[0] > 0)
    return FOUND, parent, s * v[i] + r * v[j], s * v[i + 1] + r * v[j + 1], s * v[i + 2] + r * v[j + 2], qx, qy, qz, qw


@_inline
def _parent_at(table, frame, time, memo):
    """(kind, parent): ``_sample`` without the values, for ``can_transform``."""
    kind, row, _ = _row_at(table, frame, time, memo)
    if kind != FOUND:
        return kind, 0
    return kind, np.int64(_at(table[frame, PARENTS], np.int32)[row])


# --- the walk: walk.lookup / walk.latest_common_time -----------------------------------------


@_inline
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
def _walk(table, target, source, time, memo, arcs):
    """(status, tx, ty, tz, qx, qy, qz, qw): walk.lookup at a resolved ``time``."""
    # Up from the source, accumulating T_top^source.
    svx, svy, svz, sqx, sqy, sqz, sqw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    frame = top = source
    depth = 0
    while True:
        kind, parent, vx, vy, vz, qx, qy, qz, qw = _sample(table, frame, time, memo, arcs)
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
        kind, parent, vx, vy, vz, qx, qy, qz, qw = _sample(table, frame, time, memo, arcs)
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
def _connected(table, target, source, time, memo):
    """walk.chain's verdict (what can_transform answers) at a resolved ``time``."""
    frame = top = source
    depth = 0
    while True:
        kind, parent = _parent_at(table, frame, time, memo)
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
        kind, parent = _parent_at(table, frame, time, memo)
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
    memo, arcs = _no_memo()
    status, vx, vy, vz, qx, qy, qz, qw = _walk(table, target, source, time, memo, arcs)
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
    return _connected(table, target, source, time, _no_memo()[0])


_LOOKUP_MANY = types.void(
    _TABLE,
    types.int64,
    types.int64,
    types.int64[::1],
    types.int64[::1],
    types.int64[::1],
    types.float64[:, ::1],
    types.boolean[::1],
)


@njit(_LOOKUP_MANY, cache=True, nogil=True)
def lookup_each(table, target, source, times, rows, stamps, values, valid):
    """``lookup`` at each of ``times`` (fastest in ascending order), into row ``rows[i]`` of the
    outputs (threads that split the times write their answers in place): the walk at each time,
    which ``kernels_chain.lookup_many`` answers as, bit for bit, and falls back to.

    ``stamps`` gets each time used (0 resolved to the latest common time), ``values`` the
    transform (identity where it failed), ``valid`` whether tf2 would have succeeded.
    """
    memo, arcs = _new_memo(table.shape[0])
    common_status, common = _latest_common_time(table, target, source)
    for i in range(times.shape[0]):
        time = times[i]
        if time == 0:
            time = common
        status, vx, vy, vz, qx, qy, qz, qw = _walk(table, target, source, time, memo, arcs)
        ok = status == OK and (times[i] != 0 or common_status == OK)
        if not ok:
            vx, vy, vz, qx, qy, qz, qw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
        row = rows[i]
        stamps[row], valid[row] = time, ok
        values[row, 0], values[row, 1], values[row, 2] = vx, vy, vz
        values[row, 3], values[row, 4], values[row, 5], values[row, 6] = qx, qy, qz, qw
