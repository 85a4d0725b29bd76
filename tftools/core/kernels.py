"""Compiled lookups (numba): ``walk.py``'s tf2 walk over an ``EdgeTable``, step for step.

``walk.py`` stays the reference: ``_walk`` is its ``walk_to_top_parent``, recording the edges it
takes (each one's row) instead of composing them as it goes; ``_side_at`` and ``_end`` then do
what its ``TransformAccum`` does, with the same formulas (``rotation.py``'s). The kernels report
only success or failure; the buffer falls back to the Python walk on any failure, so tf2's error
messages come from one place. Compiled once per machine (``cache=True``); warm the cache with
``python3 -c "import tftools.core.kernels"``. (One module: numba's cache of a function is
refreshed when its own file changes, not when a file it inlines from does.)

``lookup_many``: many lookups along one chain of edges, walked once, then composed edge by edge.

Over a span of time where no frame of the chain changes parent and every time falls strictly
inside every dynamic edge's history, ``_walk`` takes the same steps at each time: the
same frames, each sampled by interpolation, composed in the same order. Such a span is composed
here edge-major: the chain is walked once, at the block's first time, then for a block of times
each edge in turn is sampled at every time of the block and composed into per-time accumulators
(``_edge_block``), with exactly ``_side_at``'s operations in its order, so the answers are
bit-identical. Per time, a one-time walk is a long chain of dependent multiplications (each
edge waits for the previous one); across the times of a block they are independent, which lets
the processor overlap them, and the per-time frame lookups, parent checks and branches go away.

Whatever does not fit (a time of 0, a time on or outside a history's first or last stamp, a
parent that changes, an unconnected chain, a gap) makes its whole block fall back to
``_lookup_at`` at each time, which answers everything.
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
#: What ``_row_at`` found at a frame.
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
def _edge_at(table, frame, row, interpolate, time, memo, arcs):
    """(tx, ty, tz, qx, qy, qz, qw): ``frame``'s edge at ``time`` from the row ``_row_at`` found
    (EdgeHistory.sample)."""
    parents = _at(table[frame, PARENTS], np.int32)
    v = _at(table[frame, VALUES], np.float64)
    i = 7 * row
    if not interpolate or parents[row + 1] != parents[row]:
        return v[i], v[i + 1], v[i + 2], v[i + 3], v[i + 4], v[i + 5], v[i + 6]
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
    return s * v[i] + r * v[j], s * v[i + 1] + r * v[j + 1], s * v[i + 2] + r * v[j + 2], qx, qy, qz, qw


# --- the walk: walk.walk_to_top_parent / walk.latest_common_time -----------------------------------------


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


#: How a walk ends: walk.py's TARGET_PARENT_OF_SOURCE, SOURCE_PARENT_OF_TARGET, FULL_PATH, or
#: NO_PATH where it fails.
AT_TARGET, AT_SOURCE, AT_TOP, NO_PATH = 0, 1, 2, -1
#: Columns of a walked chain's rows (one per edge): the frame, its parent, whether it is composed
#: (an edge the walk only samples, for its verdict, is not), the row ``_row_at`` found and
#: whether to interpolate from it.
FRAME, PARENT, COMPOSED, ROW, INTERPOLATE = range(5)


@_jit
def _new_chain():
    return np.empty((2, MAX_GRAPH_DEPTH + 2, 5), np.int64)


@_jit
def _walk(table, target, source, time, chain, memo):
    """walk.walk_to_top_parent at a resolved ``time``: (ending, edges up from the source, edges up
    from the target, whether the source side stopped at a frame without history rather than at
    a gap). The edges go to ``chain[0]`` (source side) and ``chain[1]`` (target side), for
    ``_side_at`` to compose as walk.TransformAccum does."""
    frame, top, n_source, rooted = source, source, 0, True
    while True:
        kind, row, interpolate = _row_at(table, frame, time, memo)
        if kind != FOUND:
            top, rooted = frame, kind == ROOT
            break
        parent = np.int64(_at(table[frame, PARENTS], np.int32)[row])
        _put(chain, 0, n_source, frame, parent, frame != target, row, interpolate)
        n_source += 1
        if frame == target:
            return AT_TARGET, n_source, 0, rooted
        frame = parent
        if n_source > MAX_GRAPH_DEPTH:
            return NO_PATH, 0, 0, rooted
    frame, n_target = target, 0
    while frame != top:
        kind, row, interpolate = _row_at(table, frame, time, memo)
        if kind != FOUND:  # a gap, or a root that is not where the source side stopped
            return NO_PATH, 0, 0, rooted
        parent = np.int64(_at(table[frame, PARENTS], np.int32)[row])
        _put(chain, 1, n_target, frame, parent, frame != source, row, interpolate)
        n_target += 1
        if frame == source:  # the inverse of T_source^target: the source side is not used
            chain[0, :n_source, COMPOSED] = 0
            return AT_SOURCE, n_source, n_target, rooted
        frame = parent
        if n_target > MAX_GRAPH_DEPTH:
            return NO_PATH, 0, 0, rooted
    return AT_TOP, n_source, n_target, rooted


@_inline
def _put(chain, side, i, frame, parent, composed, row, interpolate):
    chain[side, i, FRAME], chain[side, i, PARENT], chain[side, i, COMPOSED] = frame, parent, composed
    chain[side, i, ROW], chain[side, i, INTERPOLATE] = row, interpolate


@_inline
def _side_at(table, chain, side, n_edges, time, memo, arcs):
    """One side of ``_walk``'s chain composed at ``time``, edge by edge (walk.TransformAccum.accum)."""
    vx, vy, vz, qx, qy, qz, qw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    for e in range(n_edges):
        if chain[side, e, COMPOSED] == 0:
            continue
        frame, row, interpolate = chain[side, e, FRAME], chain[side, e, ROW], chain[side, e, INTERPOLATE] != 0
        ex, ey, ez, eqx, eqy, eqz, eqw = _edge_at(table, frame, row, interpolate, time, memo, arcs)
        rx, ry, rz = _rotate(eqx, eqy, eqz, eqw, vx, vy, vz)
        vx, vy, vz = rx + ex, ry + ey, rz + ez
        qx, qy, qz, qw = _multiply(eqx, eqy, eqz, eqw, qx, qy, qz, qw)
    return vx, vy, vz, qx, qy, qz, qw


@_inline
def _end(ending, svx, svy, svz, sqx, sqy, sqz, sqw, tvx, tvy, tvz, tqx, tqy, tqz, tqw):
    """T_target^source from the source and target sides (walk.TransformAccum.finalize)."""
    if ending == AT_TARGET:
        return svx, svy, svz, sqx, sqy, sqz, sqw
    ix, iy, iz = _rotate(-tqx, -tqy, -tqz, tqw, -tvx, -tvy, -tvz)
    if ending == AT_SOURCE:
        return ix, iy, iz, -tqx, -tqy, -tqz, tqw
    rx, ry, rz = _rotate(-tqx, -tqy, -tqz, tqw, svx, svy, svz)
    qx, qy, qz, qw = _multiply(-tqx, -tqy, -tqz, tqw, sqx, sqy, sqz, sqw)
    return rx + ix, ry + iy, rz + iz, qx, qy, qz, qw


@_jit
def _lookup_at(table, target, source, time, chain, memo, arcs):
    """(status, tx, ty, tz, qx, qy, qz, qw): walk.lookup at a resolved ``time``."""
    ending, n_source, n_target, _ = _walk(table, target, source, time, chain, memo)
    if ending == NO_PATH:
        return FAILED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
    svx, svy, svz, sqx, sqy, sqz, sqw = _side_at(table, chain, 0, n_source, time, memo, arcs)
    tvx, tvy, tvz, tqx, tqy, tqz, tqw = _side_at(table, chain, 1, n_target, time, memo, arcs)
    vx, vy, vz, qx, qy, qz, qw = _end(ending, svx, svy, svz, sqx, sqy, sqz, sqw, tvx, tvy, tvz, tqx, tqy, tqz, tqw)
    return OK, vx, vy, vz, qx, qy, qz, qw


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
    status, vx, vy, vz, qx, qy, qz, qw = _lookup_at(table, target, source, time, _new_chain(), memo, arcs)
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
    return _walk(table, target, source, time, _new_chain(), _no_memo()[0])[0] != NO_PATH


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


# --- many lookups along a walked chain (see the module docstring) ---------------------------

#: Times per block: the accumulators (2 SIDE doubles) stay in the L1 cache.
BLOCK = 256
#: A side's accumulator ``acc`` is flat: component ``c`` (tx ty tz qx qy qz qw) of the k-th time
#: at ``acc[c * BLOCK + k]``, then scratch (``LAG + k``). All at constant distances from each
#: other, so that the compiler sees that the loops over k have no dependence between times
#: (with separate arrays, or strides known only at run time, it would not vectorize them).
LAG = 7 * BLOCK
#: Where the target side's accumulator begins, after the source side's.
SIDE = 8 * BLOCK
B = BLOCK
#: Indices are made unsigned in the loops meant to vectorize: numba checks a signed index for
#: being negative (to count from the end), a branch that keeps the compiler from vectorizing.
_U = np.uint64
# --- one edge over a block ------------------------------------------------------------------


@_inline
def _compose(acc, k, vx, vy, vz, qx, qy, qz, qw):
    """The k-th time's accumulator = edge * it, as ``_walk`` accumulates."""
    sx, sy, sz, sqx, sqy, sqz, sqw = _get(acc, k)
    rx, ry, rz = _rotate(qx, qy, qz, qw, sx, sy, sz)
    mx, my, mz, mw = _multiply(qx, qy, qz, qw, sqx, sqy, sqz, sqw)
    _set(acc, k, rx + vx, ry + vy, rz + vz, mx, my, mz, mw)


@_inline
def _get(acc, k):
    """The k-th time's accumulator (its 7 components)."""
    return (
        acc[_U(k)],
        acc[_U(k + B)],
        acc[_U(k + 2 * B)],
        acc[_U(k + 3 * B)],
        acc[_U(k + 4 * B)],
        acc[_U(k + 5 * B)],
        acc[_U(k + 6 * B)],
    )


@_inline
def _set(acc, k, vx, vy, vz, qx, qy, qz, qw):
    acc[_U(k)], acc[_U(k + B)], acc[_U(k + 2 * B)] = vx, vy, vz
    acc[_U(k + 3 * B)], acc[_U(k + 4 * B)], acc[_U(k + 5 * B)], acc[_U(k + 6 * B)] = qx, qy, qz, qw


@_jit
def _static_block(table, frame, parent, n, acc, composed):
    """A static edge: its last sample at every time (``_row_at``). False if it has none."""
    end = table[frame, END]
    if end == table[frame, START] or _at(table[frame, PARENTS], np.int32)[end - 1] != parent:
        return False
    if composed:
        v = _at(table[frame, VALUES], np.float64)
        i = 7 * (end - 1)
        vx, vy, vz, qx, qy, qz, qw = v[i], v[i + 1], v[i + 2], v[i + 3], v[i + 4], v[i + 5], v[i + 6]
        for k in range(n):
            _compose(acc, k, vx, vy, vz, qx, qy, qz, qw)
    return True


@_jit
def _edge_block(table, frame, parent, times, n, acc, memo, arcs, composed):
    """Compose ``frame``'s edge at ``times[:n]`` into ``acc`` as ``_row_at``, ``_edge_at`` and ``_side_at``
    do. False (``acc`` then half done) unless each time lies strictly between the history's first
    and last stamps and both rows it interpolates between have ``parent``: then ``_edge_at``
    interpolates at every time, which is all this does.

    The hot loop: for each run of times within one interval of the history, the row is found
    (``_find``, galloping from the cursor), its parents checked and its slerp constants taken
    (memoized per row in ``arcs``, as ``_edge_at`` does) once; ``_interval`` then composes the run.
    """
    if table[frame, STATIC] != 0:
        return _static_block(table, frame, parent, n, acc, composed)
    start, end = table[frame, START], table[frame, END]
    if end - start < 2:
        return False
    stamps = _at(table[frame, STAMPS], np.int64)
    parents = _at(table[frame, PARENTS], np.int32)
    v = _at(table[frame, VALUES], np.float64)
    earliest, latest = stamps[start], stamps[end - 1]
    k = 0
    while k < n:
        time = times[k]
        if time <= earliest or time >= latest:
            return False
        row = _find(stamps, start, end, time, memo, frame) - 1
        if parents[row] != parent or parents[row + 1] != parent:
            return False
        t0, t1 = stamps[row], stamps[row + 1]
        low = t0 if row > start else t0 + 1  # at the first stamp itself, _row_at does not interpolate
        last = k + 1  # the run: times[k:last], all within [low, t1)
        acc[LAG + k] = time - t0
        while last < n and low <= times[last] < t1:
            acc[LAG + last] = times[last] - t0
            last += 1
        if composed:
            if memo[frame, 1] != row:
                memo[frame, 1] = row
                i, j = 7 * row + 3, 7 * row + 10
                arcs[frame, 0], arcs[frame, 1], arcs[frame, 2] = _arc(
                    v[i], v[i + 1], v[i + 2], v[i + 3], v[j], v[j + 1], v[j + 2], v[j + 3]
                )
            _interval(acc, k, last, v, 7 * row, float(t1 - t0), arcs[frame, 0], arcs[frame, 1], arcs[frame, 2])
        k = last
    return True


@_inline
def _interval(acc, k0, k1, v, i, span, theta, d, sign):
    """Compose, at the times ``k0:k1`` (at ``LAG``: each less the older sample's stamp), the
    edge interpolated between the samples at ``v[i:i + 7]`` and ``v[i + 7:i + 14]``: ``_edge_at``'s
    lerp and ``_slerp``. Where every angle is small enough for ``_small_sin`` (the arc is), the
    loop has no branch, and compiles to vector instructions."""
    j = i + 7
    x0, y0, z0, x1, y1, z1 = v[i], v[i + 1], v[i + 2], v[j], v[j + 1], v[j + 2]
    ax, ay, az, aw, bx, by, bz, bw = v[i + 3], v[i + 4], v[i + 5], v[i + 6], v[j + 3], v[j + 4], v[j + 5], v[j + 6]
    if theta == 0.0 or theta > SMALL_ANGLE:
        for k in range(k0, k1):
            r = acc[_U(LAG + k)] / span
            s = 1.0 - r
            qx, qy, qz, qw = _slerp(ax, ay, az, aw, bx, by, bz, bw, r, theta, d, sign, True)
            _compose(acc, k, s * x0 + r * x1, s * y0 + r * y1, s * z0 + r * z1, qx, qy, qz, qw)
        return
    for k in range(k0, k1):  # _slerp where both _sin are _small_sin: (1 - r) * theta <= theta
        r = acc[_U(LAG + k)] / span
        s = 1.0 - r
        s0, s1 = _small_sin((1.0 - r) * theta), _small_sin(r * theta) * sign
        qx, qy, qz, qw = _weigh(ax, ay, az, aw, bx, by, bz, bw, s0, s1, d)
        _compose(acc, k, s * x0 + r * x1, s * y0 + r * y1, s * z0 + r * z1, qx, qy, qz, qw)


@_jit
def _side_block(table, chain, side, n_edges, times, n, acc, memo, arcs):
    """Identity into ``acc``, then each edge of one side of the chain, in walk order."""
    acc[:LAG] = 0.0
    acc[6 * BLOCK : LAG] = 1.0
    for e in range(n_edges):
        frame, parent, composed = chain[side, e, FRAME], chain[side, e, PARENT], chain[side, e, COMPOSED]
        if not _edge_block(table, frame, parent, times, n, acc, memo, arcs, composed != 0):
            return False
    return True


# --- a block of times -----------------------------------------------------------------------


@_jit
def _chain_block(table, chain, ending, n_source, n_target, times, n, acc, memo, arcs):
    """``_lookup_at`` at ``times[:n]`` along the walked chain, the answers in the source side of
    ``acc`` (the target side's follows at ``SIDE``); False where any time does not fit it (``acc``
    is then of no use). The last loop indexes ``acc`` whole, so that it vectorizes too."""
    if not _side_block(table, chain, 0, n_source, times, n, acc[:SIDE], memo, arcs):
        return False
    if not _side_block(table, chain, 1, n_target, times, n, acc[SIDE:], memo, arcs):
        return False
    if ending != AT_TARGET:
        for k in range(n):
            svx, svy, svz, sqx, sqy, sqz, sqw = _get(acc, k)
            tvx, tvy, tvz, tqx, tqy, tqz, tqw = _get(acc, k + SIDE)
            vx, vy, vz, qx, qy, qz, qw = _end(
                ending, svx, svy, svz, sqx, sqy, sqz, sqw, tvx, tvy, tvz, tqx, tqy, tqz, tqw
            )
            _set(acc, k, vx, vy, vz, qx, qy, qz, qw)
    return True


@_jit
def _scatter(acc, times, rows, n, stamps, values, valid):
    """A block's answers (all valid) to their rows: a tight loop, so that the cache misses of
    rows spread over a large output overlap (interleaved with the walk, they would not)."""
    for k in range(n):
        row = rows[k]
        stamps[row], valid[row] = times[k], True
        for c in range(7):
            values[row, c] = acc[c * BLOCK + k]


@_jit
def _each_block(table, target, source, times, rows, n, common, stamps, values, valid, chain, memo, arcs):
    """``_lookup_at`` at each time of a block: what answers any time. ``common`` is
    ``_latest_common_time``'s answer, for the times of 0."""
    common_status, common_time = common
    for k in range(n):
        time = times[k]
        if time == 0:
            time = common_time
        status, vx, vy, vz, qx, qy, qz, qw = _lookup_at(table, target, source, time, chain, memo, arcs)
        ok = status == OK and (times[k] != 0 or common_status == OK)
        if not ok:
            vx, vy, vz, qx, qy, qz, qw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
        row = rows[k]
        stamps[row], valid[row] = time, ok
        values[row, 0], values[row, 1], values[row, 2] = vx, vy, vz
        values[row, 3], values[row, 4], values[row, 5], values[row, 6] = qx, qy, qz, qw


# --- entry point: many lookups --------------------------------------------------------------


@njit(_LOOKUP_MANY, cache=True, nogil=True)
def lookup_many(table, target, source, times, rows, stamps, values, valid):
    """``lookup`` at each of ``times`` (fastest in ascending order), into row ``rows[i]`` of the
    outputs (threads that split the times write their answers in place): along a walked chain
    where it can (see the module docstring), else ``_lookup_at`` at each time.

    ``stamps`` gets each time used (0 resolved to the latest common time), ``values`` the
    transform (identity where it failed), ``valid`` whether tf2 would have succeeded.
    """
    memo, arcs = _new_memo(table.shape[0])
    common = _latest_common_time(table, target, source)
    chain, scratch = _new_chain(), _new_chain()
    acc = np.empty(2 * SIDE)
    ending, n_source, n_target, rooted = NO_PATH, 0, 0, False
    resolve = True  # at the next block's first time: at first, and after a block did not fit
    for lo in range(0, times.shape[0], BLOCK):
        n = min(BLOCK, times.shape[0] - lo)
        block, block_rows = times[lo : lo + n], rows[lo : lo + n]
        if resolve and block[0] != 0:
            ending, n_source, n_target, rooted = _walk(table, target, source, block[0], chain, memo)
            resolve = False
        # A walk stopped at a gap may take another way at another time: blocks need a root.
        fits = ending != NO_PATH and rooted and np.count_nonzero(block) == n
        if fits and _chain_block(table, chain, ending, n_source, n_target, block, n, acc, memo, arcs):
            _scatter(acc, block, block_rows, n, stamps, values, valid)
            continue
        resolve = True
        _each_block(table, target, source, block, block_rows, n, common, stamps, values, valid, scratch, memo, arcs)
