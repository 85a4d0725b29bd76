"""``lookup_many`` (numba): many lookups along one chain of edges, resolved once, edge by edge.

Over a span of time where no frame of the chain changes parent and every time falls strictly
inside every dynamic edge's history, ``kernels._walk`` takes the same steps at each time: the
same frames, each sampled by interpolation, composed in the same order. Such a span is walked
here edge-major: the chain is resolved once (``_resolve``), then for a block of times each edge
in turn is sampled at every time of the block and composed into per-time accumulators
(``_edge_block``), with exactly ``_walk``'s operations in ``_walk``'s order, so the answers are
bit-identical. Per time, a one-time walk is a long chain of dependent multiplications (each
edge waits for the previous one); across the times of a block they are independent, which lets
the processor overlap them, and the per-time frame lookups, parent checks and branches go away.

Whatever does not fit (a time of 0, a time on or outside a history's first or last stamp, a
parent that changes, an unconnected chain, a gap) makes its whole block fall back to
``_walk`` at each time, which answers everything. This module is what ``kernels_table.compiled``
loads: it also passes on ``kernels``' single lookups.
"""

# Kernels are typed by numba (their signatures, and inference inside), which mypy cannot follow.
# ruff: noqa: ANN001, ANN201, ANN202
# mypy: ignore-errors
from __future__ import annotations

import numpy as np
from numba import njit

from tftools.core.kernels import (
    _LOOKUP_MANY,
    FOUND,
    MAX_GRAPH_DEPTH,
    OK,
    ROOT,
    SMALL_ANGLE,
    _arc,
    _at,
    _find,
    _inline,
    _jit,
    _latest_common_time,
    _multiply,
    _new_memo,
    _no_memo,
    _parent_at,
    _rotate,
    _slerp,
    _small_sin,
    _walk,
    _weigh,
    can_transform,
    lookup,
    lookup_each,
)
from tftools.core.kernels_table import END, PARENTS, STAMPS, START, STATIC, VALUES

__all__ = ["OK", "can_transform", "lookup", "lookup_each", "lookup_many"]

#: Times per block: the accumulators (2 x 8 x BLOCK doubles) stay in the L1 cache.
BLOCK = 256
#: A side's accumulator ``acc`` is flat: component ``c`` (tx ty tz qx qy qz qw) of the k-th time
#: at ``acc[c * BLOCK + k]``, then scratch (``LAG + k``). All at constant distances from each
#: other, so that the compiler sees that the loops over k have no dependence between times
#: (with separate arrays, or strides known only at run time, it would not vectorize them).
LAG = 7 * BLOCK
B = BLOCK
#: Indices are made unsigned in the loops meant to vectorize: numba checks a signed index for
#: being negative (to count from the end), a branch that keeps the compiler from vectorizing.
_U = np.uint64
#: How the walk ends (``_walk``'s three returns that succeed).
AT_TARGET, AT_SOURCE, AT_TOP = 0, 1, 2
#: ``_resolve``'s answer when the walk is not one this module can repeat.
IRREGULAR = -1
#: Columns of a resolved chain's rows: the frame, its parent, whether it is composed (an edge
#: the walk only samples, for its verdict, is checked but not composed).
FRAME, PARENT, COMPOSED = range(3)


# --- the chain ------------------------------------------------------------------------------


@_jit
def _resolve(table, target, source, time, chain):
    """(ending, edges up from the source, edges up from the target) of ``_walk`` at ``time``.

    ``chain[0]`` and ``chain[1]`` get the source and target sides' edges (FRAME, PARENT,
    COMPOSED). IRREGULAR where the walk fails, or stops at anything but a frame without
    history, which could change with time.
    """
    no_memo = _no_memo()[0]
    frame, top, n_source = source, source, 0
    while True:
        kind, parent = _parent_at(table, frame, time, no_memo)
        if kind == ROOT:
            top = frame
            break
        if kind != FOUND or n_source > MAX_GRAPH_DEPTH:
            return IRREGULAR, 0, 0
        _put(chain, 0, n_source, frame, parent, frame != target)
        n_source += 1
        if frame == target:  # _walk returns T_target^source itself
            return AT_TARGET, n_source, 0
        frame = parent
    frame, n_target = target, 0
    while frame != top:
        kind, parent = _parent_at(table, frame, time, no_memo)
        if kind != FOUND or n_target > MAX_GRAPH_DEPTH:
            return IRREGULAR, 0, 0
        _put(chain, 1, n_target, frame, parent, frame != source)
        n_target += 1
        if frame == source:  # _walk returns the inverse of T_source^target; the source side is unused
            chain[0, :n_source, COMPOSED] = 0
            return AT_SOURCE, n_source, n_target
        frame = parent
    return AT_TOP, n_source, n_target


@_inline
def _put(chain, side, i, frame, parent, composed):
    chain[side, i, FRAME], chain[side, i, PARENT], chain[side, i, COMPOSED] = frame, parent, composed


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
    """Compose ``frame``'s edge at ``times[:n]`` into ``acc`` as ``_sample`` and ``_walk``
    do. False (``acc`` then half done) unless each time lies strictly between the history's first
    and last stamps and both rows it interpolates between have ``parent``: then ``_sample``
    interpolates at every time, which is all this does.

    The hot loop: for each run of times within one interval of the history, the row is found
    (``_find``, galloping from the cursor), its parents checked and its slerp constants taken
    (memoized per row in ``arcs``, as ``_sample`` does) once; ``_interval`` then composes the run.
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
        low = t0 if row > start else t0 + 1  # at the first stamp itself, _sample does not interpolate
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
    edge interpolated between the samples at ``v[i:i + 7]`` and ``v[i + 7:i + 14]``: ``_sample``'s
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
    """``_walk`` at ``times[:n]`` along the resolved chain, the answers in ``acc[0]``;
    False where any time does not fit it (``acc`` is then of no use)."""
    if not _side_block(table, chain, 0, n_source, times, n, acc[0], memo, arcs):
        return False
    if not _side_block(table, chain, 1, n_target, times, n, acc[1], memo, arcs):
        return False
    out, t = acc[0], acc[1]
    if ending == AT_TARGET:
        return True
    for k in range(n):
        tvx, tvy, tvz, tqx, tqy, tqz, tqw = _get(t, k)
        ix, iy, iz = _rotate(-tqx, -tqy, -tqz, tqw, -tvx, -tvy, -tvz)
        if ending == AT_SOURCE:
            _set(out, k, ix, iy, iz, -tqx, -tqy, -tqz, tqw)
            continue
        svx, svy, svz, sqx, sqy, sqz, sqw = _get(out, k)
        rx, ry, rz = _rotate(-tqx, -tqy, -tqz, tqw, svx, svy, svz)
        qx, qy, qz, qw = _multiply(-tqx, -tqy, -tqz, tqw, sqx, sqy, sqz, sqw)
        _set(out, k, rx + ix, ry + iy, rz + iz, qx, qy, qz, qw)
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
def _each_block(table, target, source, times, rows, n, common_status, common, stamps, values, valid, memo, arcs):
    """``_walk`` at each time of a block, as ``kernels.lookup_each``: what answers any time."""
    for k in range(n):
        time = times[k]
        if time == 0:
            time = common
        status, vx, vy, vz, qx, qy, qz, qw = _walk(table, target, source, time, memo, arcs)
        ok = status == OK and (times[k] != 0 or common_status == OK)
        if not ok:
            vx, vy, vz, qx, qy, qz, qw = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0
        row = rows[k]
        stamps[row], valid[row] = time, ok
        values[row, 0], values[row, 1], values[row, 2] = vx, vy, vz
        values[row, 3], values[row, 4], values[row, 5], values[row, 6] = qx, qy, qz, qw


# --- entry point ----------------------------------------------------------------------------


@njit(_LOOKUP_MANY, cache=True, nogil=True)
def lookup_many(table, target, source, times, rows, stamps, values, valid):
    """``lookup`` at each of ``times`` (fastest in ascending order), into row ``rows[i]`` of the
    outputs (threads that split the times write their answers in place); as ``lookup_each``,
    bit for bit, along a resolved chain where it can (see the module docstring).

    ``stamps`` gets each time used (0 resolved to the latest common time), ``values`` the
    transform (identity where it failed), ``valid`` whether tf2 would have succeeded.
    """
    memo, arcs = _new_memo(table.shape[0])
    common_status, common = _latest_common_time(table, target, source)
    chain = np.zeros((2, MAX_GRAPH_DEPTH + 2, 3), np.int64)
    acc = np.empty((2, 8 * BLOCK))
    ending, n_source, n_target = IRREGULAR, 0, 0
    resolve = True  # at the next block's first time: at first, and after a block did not fit
    for lo in range(0, times.shape[0], BLOCK):
        n = min(BLOCK, times.shape[0] - lo)
        block, block_rows = times[lo : lo + n], rows[lo : lo + n]
        if resolve and block[0] != 0:
            ending, n_source, n_target = _resolve(table, target, source, block[0], chain)
            resolve = False
        fits = ending != IRREGULAR and np.count_nonzero(block) == n
        if fits and _chain_block(table, chain, ending, n_source, n_target, block, n, acc, memo, arcs):
            _scatter(acc[0], block, block_rows, n, stamps, values, valid)
            continue
        resolve = True
        _each_block(
            table, target, source, block, block_rows, n, common_status, common, stamps, values, valid, memo, arcs
        )
