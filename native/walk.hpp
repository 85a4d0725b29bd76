// tf2's walk over the edge histories, the only one: every lookup, can_transform,
// chain and latest common time takes it.
//
// `walk` is tf2's walkToTopParent, recording the edges it takes (each one's row) instead of
// composing them as it goes; `edges_at`, `compose_all` and `finish` then do what tf2's
// TransformAccum does, with rotation.py's formulas in their order (compiled without contraction
// into fused multiply-adds or fast math, so that every build answers the same bits). A failure is
// reported (`Failure`, with the `Extrapolation` of an extrapolation), not worded: tftools/core/walk.py makes
// tf2's error messages from it, in one place.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <vector>

namespace tfcore {

// The hot kernels (a lookup's, a block's) are compiled three times, for AVX-512, for AVX2 and for
// any x86-64, and the best the processor runs is chosen when the module loads (GCC's function
// multiversioning, with every call inlined into each version): a block's loops over its times then
// work on 8 or 4 doubles at once instead of 2, and a lookup's conversions and branches take fewer
// instructions. The operations are the same IEEE ones in the same order (no contraction into fused
// multiply-adds: -ffp-contract=off), so every version answers the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define TFCORE_VECTOR_VERSIONS __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#else
#define TFCORE_VECTOR_VERSIONS
#endif

// One frame's history as the walk reads it (core.hpp's Store, kept up to date by its Core): rows
// start..end of the columns; `has` is false for a root or a frame not yet seen.
struct History {
    bool has = false;
    bool is_static = false;
    int64_t start = 0;
    int64_t end = 0;
    const int64_t* stamps = nullptr;
    const double* values = nullptr;  // 7 per row: tx ty tz qx qy qz qw, as they were sent
    const int32_t* parents = nullptr;
    bool turned = false;  // ROS 2: each rotation is read through tf2::Transform's matrix (through_matrix)
    int32_t sole_parent = -1;  // every row's parent where they all have one (Store::sole_parent), else -1

    // The parent of row `row`.
    int64_t parent(int64_t row) const { return sole_parent >= 0 ? sole_parent : parents[row]; }
    // Whether rows `row` and `row + 1` have one parent.
    bool same_parent(int64_t row) const { return sole_parent >= 0 || parents[row + 1] == parents[row]; }
};

using Histories = std::vector<History>;

constexpr int64_t MAX_GRAPH_DEPTH = 1000;  // tf2's: a walk longer than this is taken for a loop

struct Vec { double x = 0.0, y = 0.0, z = 0.0; };
struct Quat { double x = 0.0, y = 0.0, z = 0.0, w = 1.0; };
struct Pose { Vec v; Quat q; };

// --- rotation.py ------------------------------------------------------------------------------

inline Quat multiply(const Quat& a, const Quat& b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y + a.y * b.w + a.z * b.x - a.x * b.z,
            a.w * b.z + a.z * b.w + a.x * b.y - a.y * b.x, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

inline Vec rotate(const Quat& q, const Vec& v) {
    const double px = q.w * v.x + q.y * v.z - q.z * v.y;
    const double py = q.w * v.y + q.z * v.x - q.x * v.z;
    const double pz = q.w * v.z + q.x * v.y - q.y * v.x;
    const double pw = -q.x * v.x - q.y * v.y - q.z * v.z;
    return {pw * -q.x + px * q.w + py * -q.z - pz * -q.y, pw * -q.y + py * q.w + pz * -q.x - px * -q.z,
            pw * -q.z + pz * q.w + px * -q.y - py * -q.x};
}

inline Quat conjugate(const Quat& q) { return {-q.x, -q.y, -q.z, q.w}; }

// ROS 2's tf2 holds a rotation as a tf2::Transform's basis: a quaternion goes in through
// Matrix3x3::setRotation and comes back out through Matrix3x3::getRotation (Shepperd's method,
// which branches on the matrix's trace), on setTransform (what is checked, compared and held: the
// history keeps the sample as sent, pose_at reads it so) and on lookupTransform (what is returned).
// The trip normalizes, gives Shepperd's sign (w > 0 where the trace is positive, else the largest of
// x, y, z > 0), and turns a zero or non-finite quaternion into NaNs. rotation.py's matrix_from_quat
// and quat_from_matrix, compiled: tf2's operations in tf2's order, without contraction (its bits on x86-64).
struct Basis { double m[3][3]; };

inline Basis basis_of(const Quat& q) {  // Matrix3x3::setRotation
    const double s = 2.0 / (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    const double xs = q.x * s, ys = q.y * s, zs = q.z * s;
    const double wx = q.w * xs, wy = q.w * ys, wz = q.w * zs;
    const double xx = q.x * xs, xy = q.x * ys, xz = q.x * zs;
    const double yy = q.y * ys, yz = q.y * zs, zz = q.z * zs;
    return {{{1.0 - (yy + zz), xy - wz, xz + wy},  //
             {xy + wz, 1.0 - (xx + zz), yz - wx},
             {xz - wy, yz + wx, 1.0 - (xx + yy)}}};
}

inline Quat rotation_of(const Basis& b) {  // Matrix3x3::getRotation
    const auto& m = b.m;
    double t[4];
    const double trace = m[0][0] + m[1][1] + m[2][2];
    if (trace > 0.0) {
        double r = std::sqrt(trace + 1.0);
        t[3] = r * 0.5;
        r = 0.5 / r;
        t[0] = (m[2][1] - m[1][2]) * r;
        t[1] = (m[0][2] - m[2][0]) * r;
        t[2] = (m[1][0] - m[0][1]) * r;
    } else {
        const int i = m[0][0] < m[1][1] ? (m[1][1] < m[2][2] ? 2 : 1) : (m[0][0] < m[2][2] ? 2 : 0);
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        double r = std::sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0);
        t[i] = r * 0.5;
        r = 0.5 / r;
        t[3] = (m[k][j] - m[j][k]) * r;
        t[j] = (m[j][i] + m[i][j]) * r;
        t[k] = (m[k][i] + m[i][k]) * r;
    }
    return {t[0], t[1], t[2], t[3]};
}

inline Quat through_matrix(const Quat& q) { return rotation_of(basis_of(q)); }

// `count` rotations (x y z w, `stride` doubles apart from one to the next) through the matrix, in place.
inline void through_matrix_all(double* q, int64_t count, int64_t stride) {
    for (int64_t i = 0; i < count; ++i, q += stride) {
        const Quat r = through_matrix({q[0], q[1], q[2], q[3]});
        q[0] = r.x, q[1] = r.y, q[2] = r.z, q[3] = r.w;
    }
}

// Rotations at once: through_matrix_rows' block.
constexpr int64_t TURN_BLOCK = 64;

// through_matrix's first case (a positive trace: every rotation of less than 120 degrees) for rows
// 0..n of the columns x, y, z, w, in place, in vector lanes (turn.cpp); `fast[i]` is 0 where the
// trace is not positive (or is NaN), whose lanes hold nothing.
void turn_positive_traces(double* x, double* y, double* z, double* w, uint8_t* fast, int64_t n);

// through_matrix_all of `count` rows of `q` (4 doubles a row) into `out` (4 a row, or `q` itself):
// the same bits, a block of rows at a time in vector lanes, those with no positive trace one by one.
inline void through_matrix_rows(const double* q, double* out, int64_t count) {
    double x[TURN_BLOCK], y[TURN_BLOCK], z[TURN_BLOCK], w[TURN_BLOCK];
    uint8_t fast[TURN_BLOCK];
    for (int64_t first = 0; first < count; first += TURN_BLOCK) {
        const int64_t n = std::min(TURN_BLOCK, count - first);
        const double* in = q + 4 * first;
        for (int64_t i = 0; i < n; ++i) x[i] = in[4 * i], y[i] = in[4 * i + 1], z[i] = in[4 * i + 2], w[i] = in[4 * i + 3];
        turn_positive_traces(x, y, z, w, fast, n);
        double* to = out + 4 * first;
        for (int64_t i = 0; i < n; ++i) {
            if (fast[i]) {
                to[4 * i] = x[i], to[4 * i + 1] = y[i], to[4 * i + 2] = z[i], to[4 * i + 3] = w[i];
            } else {
                const Quat r = through_matrix({in[4 * i], in[4 * i + 1], in[4 * i + 2], in[4 * i + 3]});
                to[4 * i] = r.x, to[4 * i + 1] = r.y, to[4 * i + 2] = r.z, to[4 * i + 3] = r.w;
            }
        }
    }
}

// `edge` applied after `acc`, as TransformAccum.accum composes.
inline Pose compose(const Pose& edge, const Pose& acc) {
    const Vec r = rotate(edge.q, acc.v);
    return {{r.x + edge.v.x, r.y + edge.v.y, r.z + edge.v.z}, multiply(edge.q, acc.q)};
}

// What slerp needs of two samples: the angle, 1 / sin(angle), the sign of the dot product.
struct Arc { double theta = 0.0, d = 0.0, sign = 1.0; };

// An arc before its acos: the cosine of its angle (clamped to 1) and the sign of the dot product.
struct Cosine { double value = 1.0, sign = 1.0; };

inline Cosine cosine(const Quat& a, const Quat& b) {
    const double dot = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
    const double norms = std::sqrt((a.x * a.x + a.y * a.y + a.z * a.z + a.w * a.w) *
                                   (b.x * b.x + b.y * b.y + b.z * b.z + b.w * b.w));
    const double value = std::fabs(dot) / norms;
    return {value > 1.0 ? 1.0 : value, dot >= 0 ? 1.0 : -1.0};
}

// The angle of `c`: its acos, which is 0 exactly for a cosine of 1 (two samples of one rotation),
// where the call is left out.
inline double angle(const Cosine& c) { return c.value == 1.0 ? 0.0 : std::acos(c.value); }

// The arc of `c`, whose angle is `theta` (its acos).
inline Arc arc_of(const Cosine& c, double theta) {
    if (theta == 0.0) return {0.0, 0.0, 1.0};
    return {theta, 1.0 / std::sin(theta), c.sign};
}

inline Arc arc(const Quat& a, const Quat& b) {
    const Cosine c = cosine(a, b);
    return arc_of(c, angle(c));
}

// Up to this angle, batches take `small_sin` for std::sin.
constexpr double SMALL_ANGLE = 0.0625;

// sin(x) for |x| <= SMALL_ANGLE by its Taylor series: within an ulp of it and several times
// faster (the terms past x**9 are below 1e-20 x).
inline double small_sin(double x) {
    const double x2 = x * x;
    return x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880))));
}

inline double sine(double x, bool batch) { return (!batch || std::fabs(x) > SMALL_ANGLE) ? std::sin(x) : small_sin(x); }

// Slerp's last step: (a s0 + b s1) d.
inline Quat weigh(const Quat& a, const Quat& b, double s0, double s1, double d) {
    return {(a.x * s0 + b.x * s1) * d, (a.y * s0 + b.y * s1) * d, (a.z * s0 + b.z * s1) * d,
            (a.w * s0 + b.w * s1) * d};
}

// tf2's slerp given `arc`'s constants; `batch` takes small_sin for small angles.
inline Quat slerp(const Quat& a, const Quat& b, double t, const Arc& c, bool batch) {
    if (c.theta == 0.0) return a;
    return weigh(a, b, sine((1.0 - t) * c.theta, batch), sine(t * c.theta, batch) * c.sign, c.d);
}

// Row `row` of `h` as tf2 holds the sample (ROS 2's rotation through its matrix).
inline Pose pose_at(const History& h, int64_t row) {
    const double* v = h.values + 7 * row;
    const Quat q{v[3], v[4], v[5], v[6]};
    return {{v[0], v[1], v[2]}, h.turned ? through_matrix(q) : q};
}

// --- one edge: its sample at a time, as tf2's TimeCache interpolates -----------------------------

// Per frame, the last row a walk used (a cursor: a walk over ascending times moves it instead of
// bisecting) and the row whose arc to the next `arcs` holds. Off for single lookups.
struct Memo {
    bool on = false;
    std::vector<int64_t> cursor, arc_row;
    std::vector<Arc> arcs;

    Memo() = default;
    explicit Memo(size_t frames) : on(true), cursor(frames, -1), arc_row(frames, -1), arcs(frames) {}
};

// bisect_right(stamps, time, lo, hi) knowing that it is at least `lo` and at most `hi`.
inline int64_t bisect(const int64_t* stamps, int64_t lo, int64_t hi, int64_t time) {
    while (lo < hi) {
        const int64_t mid = (lo + hi) >> 1;
        if (time < stamps[mid]) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

// bisect_right(stamps, time, start, end), galloping from row `guess` (up or down, doubling each
// step) to the interval that holds the answer, then bisecting it: few loads where the guess is near.
inline int64_t gallop(const int64_t* stamps, int64_t start, int64_t end, int64_t time, int64_t guess) {
    int64_t step = 1;
    if (stamps[guess] <= time) {
        int64_t lo = guess + 1;
        while (lo + step - 1 < end && stamps[lo + step - 1] <= time) {
            lo += step;
            step *= 2;
        }
        return bisect(stamps, lo, std::min(lo + step - 1, end), time);
    }
    int64_t hi = guess;
    while (hi - step >= start && stamps[hi - step] > time) {
        hi -= step;
        step *= 2;
    }
    return bisect(stamps, std::max(hi - step + 1, start), hi, time);
}

// Where `time` would lie were the stamps evenly spaced (a broadcaster's period): a row of
// [start, end), for stamps[start] < time < stamps[end - 1].
inline int64_t interpolated(const int64_t* stamps, int64_t start, int64_t end, int64_t time) {
    // Unsigned differences: any two int64 stamps are at most 2**64 - 1 apart.
    const auto after_first = [&](int64_t t) {
        return static_cast<double>(static_cast<uint64_t>(t) - static_cast<uint64_t>(stamps[start]));
    };
    const double span = after_first(stamps[end - 1]), offset = after_first(time);
    const auto row = start + static_cast<int64_t>(offset / span * static_cast<double>(end - 1 - start));
    return std::clamp(row, start, end - 1);
}

// bisect_right(stamps, time, start, end) for stamps[start] < time < stamps[end - 1], galloping
// from the memo's cursor when it has one (times ascending), else from where the stamps'
// spacing puts `time`: a single lookup's searches then miss the cache once or twice, not ~log n times.
inline int64_t find(const int64_t* stamps, int64_t start, int64_t end, int64_t time, Memo& memo, int64_t frame) {
    int64_t guess = -1;
    if (memo.on) {
        const int64_t cursor = memo.cursor[frame];
        if (start <= cursor && cursor < end && stamps[cursor] <= time) guess = cursor;
    }
    const int64_t lo = gallop(stamps, start, end, time, guess >= 0 ? guess : interpolated(stamps, start, end, time));
    if (memo.on) memo.cursor[frame] = lo - 1;
    return lo;
}

enum class Kind { FOUND, GAP, ROOT };

// The row to use at a time, or the older of two to interpolate between (tf2's findClosest).
struct RowAt {
    Kind kind;
    int64_t row = 0;
    bool interpolate = false;
};

inline RowAt row_at(const Histories& histories, int64_t frame, int64_t time, Memo& memo) {
    if (frame >= static_cast<int64_t>(histories.size()) || !histories[frame].has) return {Kind::ROOT};
    const History& h = histories[frame];
    if (h.end == h.start) return {Kind::GAP};
    if (h.is_static || time == 0) return {Kind::FOUND, h.end - 1};
    if (h.end - h.start == 1) return h.stamps[h.start] == time ? RowAt{Kind::FOUND, h.start} : RowAt{Kind::GAP};
    const int64_t latest = h.stamps[h.end - 1], earliest = h.stamps[h.start];
    if (time == latest) return {Kind::FOUND, h.end - 1};
    if (time == earliest) return {Kind::FOUND, h.start};
    if (time > latest || time < earliest) return {Kind::GAP};
    return {Kind::FOUND, find(h.stamps, h.start, h.end, time, memo, frame) - 1, true};
}

// The arc between `row` and the next, memoized per frame.
inline Arc arc_at(const History& h, int64_t frame, int64_t row, Memo& memo) {
    if (!memo.on) return arc(pose_at(h, row).q, pose_at(h, row + 1).q);
    if (memo.arc_row[frame] != row) {
        memo.arc_row[frame] = row;
        memo.arcs[frame] = arc(pose_at(h, row).q, pose_at(h, row + 1).q);
    }
    return memo.arcs[frame];
}

// --- the walk ----------------------------------------------------------------------------------

// How a walk ends (tf2's WalkEnding): the target is an ancestor of the source, the source an
// ancestor of the target, both meet at one top frame; or no path.
enum class Ending { AT_TARGET, AT_SOURCE, AT_TOP, NO_PATH };

// Why tf2 fails, of the errors a walk raises (the binding exports them as NO_FAILURE, LOOP, UNCONNECTED,
// EXTRAPOLATION): more than MAX_GRAPH_DEPTH edges, two trees, or a time outside an edge's history.
enum class Failure { NONE, LOOP, UNCONNECTED, EXTRAPOLATION };

// Why a history cannot answer at `time` (history.Extrapolation; its kinds, NO_DATA, ONLY_ONE, FUTURE,
// PAST, exported by the binding): empty, one sample at another `stamp`, after the newest or before the oldest.
struct Extrapolation {
    int64_t kind = 0, time = 0, stamp = 0;
};
enum ExtrapolationKind : int64_t { NO_DATA, ONLY_ONE, FUTURE, PAST };

// The gap of `h` at `time`, where row_at found one (tftools.core.history.Extrapolation's fields).
inline Extrapolation extrapolation_at(const History& h, int64_t time) {
    if (h.end == h.start) return {NO_DATA, time, 0};
    if (h.end - h.start == 1) return {ONLY_ONE, time, h.stamps[h.start]};
    if (time > h.stamps[h.end - 1]) return {FUTURE, time, h.stamps[h.end - 1]};
    return {PAST, time, h.stamps[h.start]};
}

// One edge a walk took: its frame and parent, whether the answer composes it (an edge sampled
// only for its verdict is not), and where `row_at` found it.
struct Step {
    int64_t frame, parent;
    bool composed;
    RowAt at;
};

// One composed edge of a walked chain at its time, as `edges_at` samples it.
struct Edge {
    Pose pose;   // the sample; while interpolating, the lerped translation and the older rotation
    Quat next;   // while interpolating, the newer sample's rotation
    double r = 0.0;  // ... its weight
    Cosine cosine;
    Arc arc;
    int64_t frame = 0, row = 0;
    bool interpolate = false, known = false;  // known: the arc came from the memo
};

// The edges of a walk, up from the source (sides[0]) and up from the target (sides[1]).
struct Chain {
    Ending ending = Ending::NO_PATH;
    bool rooted = false;  // the source side stopped at a frame without history, not at a gap
    int64_t top = 0;      // where the source side stopped (AT_TOP: where the target side met it)
    // Where there is no path, why (tf2's order: a gap on the target side, then one on the source
    // side, then no connection), and the frame whose history has the gap.
    Failure failure = Failure::NONE;
    int64_t extrapolating_frame = 0;
    std::vector<Step> sides[2];
    // The composed ones at the walk's time, as `edges_at` samples them: the first `composed` (the rest are
    // a longer walk's, kept so that a walk writes over edges already built: building one sets every field).
    std::vector<Edge> edges;
    size_t composed = 0;
};

// Start loading the samples `at` points to: a lookup at a time not looked at lately misses the
// cache on them, and the rest of the walk (more misses, on the other histories) then waits for
// them at the same time instead of one after the other.
inline void prefetch(const History& h, const RowAt& at) {
    const double* v = h.values + 7 * at.row;
    __builtin_prefetch(v);
    if (at.interpolate) {  // two rows: 14 doubles over up to three cache lines
        __builtin_prefetch(v + 7);
        __builtin_prefetch(v + 13);
    }
}

// Edges ahead of a single lookup whose samples near its time `ahead` starts loading.
constexpr int64_t AHEAD_DEPTH = 32;

// Start loading, on each edge up from `frame` whose parent is its history's sole parent, the stamps
// and the samples where the stamps' spacing puts `time` (where `find` will look first): the walk's
// misses on them then overlap, where each edge's search otherwise waited for the one before it.
inline void ahead(const Histories& histories, int64_t frame, int64_t time) {
    for (int64_t depth = 0; depth < AHEAD_DEPTH && frame < static_cast<int64_t>(histories.size()); ++depth) {
        const History& h = histories[frame];
        if (!h.has) return;
        if (!h.is_static && h.end - h.start > 2 && h.stamps[h.start] < time && time < h.stamps[h.end - 1]) {
            const int64_t row = interpolated(h.stamps, h.start, h.end, time);
            __builtin_prefetch(h.stamps + row);
            __builtin_prefetch(h.values + 7 * row);
            __builtin_prefetch(h.values + 7 * row + 13);
        }
        if (h.sole_parent < 0) return;
        frame = h.sole_parent;
    }
}

// Chain's `failure`, and its ending: no path.
inline void fail(Chain& chain, Failure failure, int64_t extrapolating_frame = 0) {
    chain.ending = Ending::NO_PATH;
    chain.failure = failure;
    chain.extrapolating_frame = extrapolating_frame;
}

// tf2's walkToTopParent at a resolved `time`, into `chain`: up from the source towards the root,
// then up from the target until the frame where the first walk stopped.
TFCORE_VECTOR_VERSIONS inline void walk(const Histories& histories, int64_t target, int64_t source, int64_t time,
                                        Chain& chain, Memo& memo) {
    auto& up = chain.sides[0];
    auto& down = chain.sides[1];
    up.clear();
    down.clear();
    chain.rooted = true;
    chain.failure = Failure::NONE;
    if (!memo.on) {  // a single lookup, at a time the last may be far from
        ahead(histories, source, time);
        ahead(histories, target, time);
    }
    int64_t frame = source, top = source;
    while (true) {
        const RowAt at = row_at(histories, frame, time, memo);
        if (at.kind != Kind::FOUND) {
            top = frame;
            chain.rooted = at.kind == Kind::ROOT;
            break;
        }
        prefetch(histories[frame], at);
        const int64_t parent = histories[frame].parent(at.row);
        up.push_back({frame, parent, frame != target, at});
        if (frame == target) {
            chain.ending = Ending::AT_TARGET;
            return;
        }
        frame = parent;
        if (static_cast<int64_t>(up.size()) > MAX_GRAPH_DEPTH) return fail(chain, Failure::LOOP);
    }
    chain.top = top;
    frame = target;
    while (frame != top) {
        const RowAt at = row_at(histories, frame, time, memo);
        if (at.kind == Kind::GAP) return fail(chain, Failure::EXTRAPOLATION, frame);
        if (at.kind == Kind::ROOT) {  // not where the source side stopped
            if (!chain.rooted) return fail(chain, Failure::EXTRAPOLATION, top);
            return fail(chain, Failure::UNCONNECTED);
        }
        prefetch(histories[frame], at);
        const int64_t parent = histories[frame].parent(at.row);
        down.push_back({frame, parent, frame != source, at});
        if (frame == source) {  // the inverse of T_source^target: the source side is not used
            for (Step& step : up) step.composed = false;
            chain.ending = Ending::AT_SOURCE;
            return;
        }
        frame = parent;
        if (static_cast<int64_t>(down.size()) > MAX_GRAPH_DEPTH) return fail(chain, Failure::LOOP);
    }
    chain.ending = Ending::AT_TOP;
}

// The frames from source to target that a walk's answer composes (tf2's _chainAsVector order).
inline std::vector<int64_t> frames_of(const Chain& chain) {
    std::vector<int64_t> frames, down;
    for (const Step& step : chain.sides[0]) frames.push_back(step.frame);
    for (const Step& step : chain.sides[1]) down.push_back(step.frame);
    if (chain.ending == Ending::AT_TARGET) return frames;
    if (chain.ending == Ending::AT_SOURCE) return {down.rbegin(), down.rend()};
    // Both sides reached `top`: keep the source side up to the first frame they share.
    frames.push_back(chain.top);
    size_t meet = 0;
    auto shared = down.end();
    for (; meet < frames.size(); ++meet) {
        shared = std::find(down.begin(), down.end(), frames[meet]);
        if (shared != down.end() || frames[meet] == chain.top) break;
    }
    frames.resize(meet + 1);
    frames.insert(frames.end(), std::make_reverse_iterator(shared), down.rend());
    return frames;
}

// `step`'s edge at `time` into `e` (a new Edge), up to its slerp's libm calls (`edges_at` makes those).
inline void sample_before_slerp(const Histories& histories, const Step& step, int64_t time, const Memo& memo,
                                Edge& e) {
    const History& h = histories[step.frame];
    const int64_t row = step.at.row;
    e.pose = pose_at(h, row);
    e.interpolate = e.known = false;
    if (!step.at.interpolate || !h.same_parent(row)) return;
    const int64_t t0 = h.stamps[row];
    const double r = static_cast<double>(time - t0) / static_cast<double>(h.stamps[row + 1] - t0);
    const double s = 1.0 - r;
    const Pose a = e.pose, b = pose_at(h, row + 1);
    e.pose.v = {s * a.v.x + r * b.v.x, s * a.v.y + r * b.v.y, s * a.v.z + r * b.v.z};
    e.next = b.q, e.r = r, e.frame = step.frame, e.row = row, e.interpolate = true;
    if (memo.on && memo.arc_row[step.frame] == row) {
        e.arc = memo.arcs[step.frame], e.known = true;
    } else {
        e.cosine = cosine(a.q, b.q);
    }
}

// The composed edges of both sides of `chain` at `time`, in order, into chain.edges (returning
// where the target side's edges begin): EdgeHistory.sample's operations on each, in stages across the edges
// (the samples, then every acos, then every sine), so that the processor overlaps the edges' libm
// calls instead of waiting for each edge's in turn.
inline size_t edges_at(const Histories& histories, Chain& chain, int64_t time, Memo& memo) {
    std::vector<Edge>& built = chain.edges;
    size_t n = 0;
    const auto sample = [&](const std::vector<Step>& side) {
        for (const Step& step : side) {
            if (!step.composed) continue;
            if (n == built.size()) built.emplace_back();
            sample_before_slerp(histories, step, time, memo, built[n++]);
        }
    };
    sample(chain.sides[0]);
    const size_t split = n;
    sample(chain.sides[1]);
    chain.composed = n;
    Edge* const edges = built.data();
    for (Edge* e = edges; e != edges + n; ++e) {
        if (e->interpolate && !e->known) e->arc.theta = angle(e->cosine);
    }
    for (Edge* e = edges; e != edges + n; ++e) {
        if (!e->interpolate) continue;
        if (!e->known) {
            e->arc = arc_of(e->cosine, e->arc.theta);
            if (memo.on) memo.arc_row[e->frame] = e->row, memo.arcs[e->frame] = e->arc;
        }
        e->pose.q = slerp(e->pose.q, e->next, e->r, e->arc, memo.on);
    }
    return split;
}

// Edges composed in order (TransformAccum.accum).
//
// Where the compiler has vector extensions (GCC 12 and later, Clang), on the four lanes of a vector:
// one lookup's edges wait each for the last, and each edge's rotation and product are then 3 and 4
// products of 4 lanes and their sums, where compose() makes 28 and 16 products and their sums one by
// one, with the accumulator kept in lanes from edge to edge. Each lane makes one of compose()'s
// components with compose()'s own operations in its order, negations and subtractions included (a
// lane that subtracts where the others add takes the difference's lane: x + -y and x - y differ in a
// NaN's sign), so the bits are the same. (A block composes many times at once with compose() itself,
// which the compiler vectorizes across its times.)
#if defined(__clang__) || (defined(__GNUC__) && __GNUC__ >= 12)
using Lanes = double __attribute__((vector_size(32)));
#define TFCORE_PICK(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)

inline Pose compose_all(const Edge* first, const Edge* last) {
    Lanes v = {0.0, 0.0, 0.0, 0.0}, b = {0.0, 0.0, 0.0, 1.0};  // the accumulator (v's lane 3 unused)
    for (const Edge* e = first; e != last; ++e) {
        Lanes t, q;  // the edge's translation (lane 3: its rotation's x, unused) and rotation
        static_assert(sizeof(Pose) == 7 * sizeof(double), "a pose's 7 doubles in a row");
        std::memcpy(&t, &e->pose.v.x, sizeof t);
        std::memcpy(&q, &e->pose.q.x, sizeof q);
        const Lanes n = -q;
        // rotate(q, v): p (px py pz pw) = (qw vx + qy vz - qz vy, ..., -qx vx - qy vy - qz vz)
        const Lanes p1 = TFCORE_PICK(q, n, 3, 3, 3, 4) * TFCORE_PICK(v, v, 0, 1, 2, 0);
        const Lanes p2 = TFCORE_PICK(q, q, 1, 2, 0, 1) * TFCORE_PICK(v, v, 2, 0, 1, 1);
        const Lanes p3 = TFCORE_PICK(q, q, 2, 0, 1, 2) * TFCORE_PICK(v, v, 1, 2, 0, 2);
        const Lanes p = TFCORE_PICK(p1 + p2, p1 - p2, 0, 1, 2, 7) - p3;
        // ... then r = pw (-q) + p qw + p.yzx (-q).zxy - p.zxy (-q).yzx, plus the translation
        const Lanes pw = TFCORE_PICK(p, p, 3, 3, 3, 3), qw = TFCORE_PICK(q, q, 3, 3, 3, 3);
        const Lanes r = ((pw * n + p * qw) + TFCORE_PICK(p, p, 1, 2, 0, 3) * TFCORE_PICK(n, n, 2, 0, 1, 3)) -
                        TFCORE_PICK(p, p, 2, 0, 1, 3) * TFCORE_PICK(n, n, 1, 2, 0, 3);
        // multiply(q, b): (qw bx + qx bw + qy bz - qz by, ..., qw bw - qx bx - qy by - qz bz)
        const Lanes m1 = qw * b;
        const Lanes m2 = TFCORE_PICK(q, q, 0, 1, 2, 0) * TFCORE_PICK(b, b, 3, 3, 3, 0);
        const Lanes m3 = TFCORE_PICK(q, q, 1, 2, 0, 1) * TFCORE_PICK(b, b, 2, 0, 1, 1);
        const Lanes m4 = TFCORE_PICK(q, q, 2, 0, 1, 2) * TFCORE_PICK(b, b, 1, 2, 0, 2);
        const Lanes m12 = TFCORE_PICK(m1 + m2, m1 - m2, 0, 1, 2, 7);
        v = r + t;
        b = TFCORE_PICK(m12 + m3, m12 - m3, 0, 1, 2, 7) - m4;
    }
    return {{v[0], v[1], v[2]}, {b[0], b[1], b[2], b[3]}};
}
#undef TFCORE_PICK
#else
inline Pose compose_all(const Edge* first, const Edge* last) {
    Pose acc;
    for (const Edge* e = first; e != last; ++e) acc = compose(e->pose, acc);
    return acc;
}
#endif

// T_target^source from the source and target sides (TransformAccum.finalize).
inline Pose finish(Ending ending, const Pose& source, const Pose& target) {
    if (ending == Ending::AT_TARGET) return source;
    const Quat iq = conjugate(target.q);
    const Vec iv = rotate(iq, {-target.v.x, -target.v.y, -target.v.z});
    if (ending == Ending::AT_SOURCE) return {iv, iq};
    const Vec r = rotate(iq, source.v);
    return {{r.x + iv.x, r.y + iv.y, r.z + iv.z}, multiply(iq, source.q)};
}

// The top bit set where `x` is not a finite normal number (0, subnormal, infinite, NaN): on the bits
// without the sign, u, u - 2**52 wraps where u is below the least normal's, u + 2**52 reaches the top
// bit from infinity's up. Integer operations, which the compiler vectorizes over a block's times.
inline uint64_t abnormal(double x) {
    constexpr uint64_t SIGN = uint64_t{1} << 63, LEAST = uint64_t{1} << 52;
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    u &= ~SIGN;
    return (u - LEAST) | (u + LEAST);
}

// Whether finish(AT_TOP, source, target) is `source` itself, bit for bit, where the target side has
// no edges (the target is the top: a lookup into a tree's root) and `bad` is abnormal's bits of
// source's components, or-ed: then the target is the identity, its conjugate (-0, -0, -0, 1), and
// each of finish's sums is a component times 1 plus products of a zero, which are zeros (x + 0 and
// x - 0 are x for x not 0). Its two rotations and product (~90 operations) are then left out.
inline bool finish_keeps(Ending ending, bool target_side_empty, uint64_t bad) {
    return ending == Ending::AT_TOP && target_side_empty && (bad >> 63) == 0;
}

// A lookup at a resolved `time`; false where tf2 fails (chain.failure says why).
TFCORE_VECTOR_VERSIONS inline bool lookup_at(const Histories& histories, int64_t target, int64_t source,
                                             int64_t time, Chain& chain, Memo& memo, Pose& out) {
    walk(histories, target, source, time, chain, memo);
    if (chain.ending == Ending::NO_PATH) return false;
    const size_t split = edges_at(histories, chain, time, memo);
    const Edge* begin = chain.edges.data();
    const Pose up = compose_all(begin, begin + split);
    const uint64_t bad = abnormal(up.v.x) | abnormal(up.v.y) | abnormal(up.v.z) | abnormal(up.q.x) |
                         abnormal(up.q.y) | abnormal(up.q.z) | abnormal(up.q.w);
    out = finish_keeps(chain.ending, split == chain.composed, bad)
              ? up
              : finish(chain.ending, up, compose_all(begin + split, begin + chain.composed));
    return true;
}

// --- tf2's getLatestCommonTime -------------------------------------------------------------------

struct Latest {
    bool has;
    int64_t stamp, parent;
};

// EdgeHistory.latest_stamp and latest_parent, where the history has data.
inline Latest latest(const Histories& histories, int64_t frame) {
    if (frame >= static_cast<int64_t>(histories.size())) return {false, 0, 0};
    const History& h = histories[frame];
    if (!h.has || h.end == h.start) return {false, 0, 0};
    return {true, h.is_static ? 0 : h.stamps[h.end - 1], h.parents[h.end - 1]};
}

constexpr int64_t TIME_MAX = INT64_MAX;

// tf2's getLatestCommonTime: the newest stamp every dynamic edge of the chain has (0: all static),
// into `out`; or why it fails.
inline Failure latest_common_time(const Histories& histories, int64_t target, int64_t source, int64_t& out) {
    if (source == target) {
        const Latest l = latest(histories, source);
        out = l.has ? l.stamp : 0;
        return Failure::NONE;
    }
    std::vector<Latest> side;  // (stamp, parent) of each edge up from the source
    int64_t common = TIME_MAX;
    int64_t frame = source;
    while (true) {
        const Latest l = latest(histories, frame);
        if (!l.has) break;
        if (l.stamp) common = std::min(common, l.stamp);
        side.push_back(l);
        frame = l.parent;
        if (frame == target) {
            out = common == TIME_MAX ? 0 : common;
            return Failure::NONE;
        }
        if (static_cast<int64_t>(side.size()) > MAX_GRAPH_DEPTH) return Failure::LOOP;
    }
    common = TIME_MAX;
    int64_t common_parent = 0;
    frame = target;
    int64_t depth = 0;
    while (true) {
        const Latest l = latest(histories, frame);
        if (!l.has) break;
        if (l.stamp) common = std::min(common, l.stamp);
        bool shared = false;
        for (const Latest& s : side) shared = shared || s.parent == l.parent;
        if (shared) {
            common_parent = l.parent;
            break;
        }
        frame = l.parent;
        if (frame == source) {
            out = common == TIME_MAX ? 0 : common;
            return Failure::NONE;
        }
        if (++depth > MAX_GRAPH_DEPTH) return Failure::LOOP;
    }
    if (common_parent == 0) return Failure::UNCONNECTED;
    for (const Latest& s : side) {
        if (s.stamp) common = std::min(common, s.stamp);
        if (s.parent == common_parent) break;
    }
    out = common == TIME_MAX ? 0 : common;
    return Failure::NONE;
}

}  // namespace tfcore
