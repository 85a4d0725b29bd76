// Many lookups along one chain of edges, walked once, then composed edge by edge.
//
// Over a span of time where no frame of the chain changes parent and every time falls strictly
// inside every dynamic edge's history, `walk` takes the same steps at each time: the same frames,
// each sampled by interpolation, composed in the same order. Such a span is composed here
// edge-major: the chain is walked once, at the block's first time, then for a block of times each
// edge in turn is sampled at every time of the block and composed into per-time accumulators
// (`edge_block`), with exactly the operations of `edges_at` and `compose_all` in their order, so
// the answers are bit-identical. Per time, a one-time walk is a long chain of dependent multiplications (each edge
// waits for the previous one); across the times of a block they are independent, which lets the
// processor overlap them (and the compiler vectorize them), and the per-time frame lookups,
// parent checks and branches go away.
//
// Whatever does not fit (a time of 0, a time on or outside a history's first or last stamp, a
// parent that changes, an unconnected chain, a gap) makes its whole block fall back to
// `lookup_at` at each time, which answers everything.
#pragma once

#include <algorithm>
#include <cstring>
#include <memory>

#include "walk.hpp"

namespace tfcore {

// Times per block: a side's two accumulators (below) stay in the L1 cache.
constexpr int64_t BLOCK = 256;

// Lanes the chosen version's vector loops take at once (walk.hpp's versions): 8 doubles with AVX-512,
// else 4 (AVX2's; SSE2's 2 divide it). A run of times is composed in whole groups of them (`interval`),
// its last group running past the run into lanes the next run writes again.
constexpr int64_t LANES = 8;  // the most
inline int64_t vector_lanes() {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
    static const int64_t lanes = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("x86-64-v4") ? LANES : 4;
    }();
    return lanes;
#else
    return 4;
#endif
}

// An accumulator: component c (tx ty tz qx qy qz qw) of the k-th time at c[c][k]. Fixed strides, so
// that the loops over k have no dependence the compiler cannot see; LANES more than a block, for a
// last group past it.
constexpr int64_t LANED = BLOCK + LANES;
struct Accumulator {
    alignas(64) double c[7][LANED];

    void reset(int64_t n) {
        for (int i = 0; i < 7; ++i) std::fill(c[i], c[i] + n, i == 6 ? 1.0 : 0.0);
    }
    Pose get(int64_t k) const { return {{c[0][k], c[1][k], c[2][k]}, {c[3][k], c[4][k], c[5][k], c[6][k]}}; }
    void set(int64_t k, const Pose& p) {
        c[0][k] = p.v.x, c[1][k] = p.v.y, c[2][k] = p.v.z;
        c[3][k] = p.q.x, c[4][k] = p.q.y, c[5][k] = p.q.z, c[6][k] = p.q.w;
    }
};

// A side's two accumulators: each edge composes the times' poses so far (`in`) into the other (`out`),
// as `walk` accumulates (out = edge * in); then the two swap. Composed out of place, a group of lanes
// past a run's end reads what the next run reads and writes what it overwrites, so that every
// run is composed in whole vectors (in place, those lanes would be composed twice).
struct Side {
    Accumulator* in;
    Accumulator* out;
    int64_t lanes;  // vector_lanes()
    void swap() { std::swap(in, out); }
};

// What a block is composed in: both sides' accumulators (the source side's answer in one of the first
// two, the target side's in one of the other two).
struct Blocks {
    Accumulator acc[3];
};

// Where a lookup answers: row `rows[k]` of the outputs for the k-th time.
struct Outputs {
    const int64_t* rows;
    int64_t* stamps;  // the time used (0 resolved to the latest common time)
    double* values;   // 7 per row; identity where it failed
    bool* valid;      // whether tf2 would have succeeded
    // Whether stamps and valid already hold each row's resolved time and true (`fill`): then only
    // the values, and a failure's valid, are written to the row (fewer scattered writes).
    bool filled = false;
};

// Each row's resolved time (0: `common`) and true into out's stamps and valid, rows lo..hi of times.
inline void fill(const Outputs& out, const int64_t* times, int64_t lo, int64_t hi, int64_t common) {
    for (int64_t k = lo; k < hi; ++k) out.stamps[k] = times[k] == 0 ? common : times[k];
    std::fill(out.valid + lo, out.valid + hi, true);
}

// A static edge: its last sample at every time (`row_at`). False if it has none (or another parent).
inline bool static_block(const History& h, int64_t parent, int64_t n, Side& side, bool composed) {
    if (h.end == h.start || h.parents[h.end - 1] != parent) return false;
    if (composed) {
        const Pose edge = pose_at(h, h.end - 1);
        for (int64_t k = 0; k < n; ++k) side.out->set(k, compose(edge, side.in->get(k)));
        side.swap();
    }
    return true;
}

// times[k] less `t0` as a double, for differences in [0, 2**52) ns (52 days): made from its bits
// (2**52 + d, less 2**52: exact, as the conversion is), which the compiler vectorizes where AVX2 has no
// conversion of 64-bit integers.
inline double lag_of(int64_t time, int64_t t0) {
    constexpr uint64_t TWO_52_BITS = 0x4330000000000000;  // 2**52 as a double
    const uint64_t bits = static_cast<uint64_t>(time - t0) | TWO_52_BITS;
    double shifted;
    std::memcpy(&shifted, &bits, sizeof shifted);
    return shifted - 4503599627370496.0;
}

// Compose, at times[k0..k1), the edge interpolated between the samples at `row` and `row + 1`:
// `edges_at`'s lerp and slerp, from side.in into side.out. Where every angle is small enough for
// small_sin (the arc is) and the samples less than 2**52 ns apart (`lag_of`), the loop has no branch
// and compiles to vector instructions, in whole groups of side.lanes but at the block's end `n` (the
// last group past k1: the next run writes those lanes again).
inline void interval(const Side& side, const int64_t* times, int64_t k0, int64_t k1, int64_t n, const History& h,
                     int64_t row, const Arc& c) {
    const Pose a = pose_at(h, row), b = pose_at(h, row + 1);
    const Accumulator& in = *side.in;
    Accumulator& out = *side.out;
    const int64_t t0 = h.stamps[row], apart = h.stamps[row + 1] - t0;
    const double span = static_cast<double>(apart);
    const auto edge = [&](int64_t k, double lag) {
        const double r = lag / span, s = 1.0 - r;
        const Quat q = c.theta == 0.0 || c.theta > SMALL_ANGLE
                           ? slerp(a.q, b.q, r, c, true)
                           : weigh(a.q, b.q, small_sin((1.0 - r) * c.theta), small_sin(r * c.theta) * c.sign, c.d);
        out.set(k, compose({{s * a.v.x + r * b.v.x, s * a.v.y + r * b.v.y, s * a.v.z + r * b.v.z}, q}, in.get(k)));
    };
    // (Negative: stamps too far apart for int64.)
    if (c.theta == 0.0 || c.theta > SMALL_ANGLE || apart < 0 || apart > (int64_t{1} << 52)) {
        for (int64_t k = k0; k < k1; ++k) edge(k, static_cast<double>(times[k] - t0));
        return;
    }
    const int64_t end = std::min(n, k0 + (k1 - k0 + side.lanes - 1) / side.lanes * side.lanes);
#pragma GCC ivdep
    for (int64_t k = k0; k < end; ++k) {  // slerp where both sines are small_sin: (1 - r) * theta <= theta
        const double r = lag_of(times[k], t0) / span, s = 1.0 - r;
        const double s0 = small_sin((1.0 - r) * c.theta), s1 = small_sin(r * c.theta) * c.sign;
        const Quat q = weigh(a.q, b.q, s0, s1, c.d);
        out.set(k, compose({{s * a.v.x + r * b.v.x, s * a.v.y + r * b.v.y, s * a.v.z + r * b.v.z}, q}, in.get(k)));
    }
}

// Compose `step`'s edge at times[0..n) into `side` as row_at, edges_at and compose_all do. False
// (`side` then half done) unless each time lies strictly between the history's first and last stamps and
// both rows it interpolates between have the step's parent: then edges_at interpolates at every
// time, which is all this does. For each run of times within one interval of the history, the
// row is found (galloping from the cursor), its parents checked and its arc taken once.
inline bool edge_block(const Histories& histories, const Step& step, const int64_t* times, int64_t n, bool sorted,
                       Side& side, Memo& memo) {
    const History& h = histories[step.frame];
    if (h.is_static) return static_block(h, step.parent, n, side, step.composed);
    if (h.end - h.start < 2) return false;
    const int64_t earliest = h.stamps[h.start], latest = h.stamps[h.end - 1];
    int64_t k = 0;
    while (k < n) {
        const int64_t time = times[k];
        if (time <= earliest || time >= latest) return false;
        const int64_t row = find(h.stamps, h.start, h.end, time, memo, step.frame) - 1;
        if (h.sole_parent != step.parent && (h.parents[row] != step.parent || h.parents[row + 1] != step.parent)) {
            return false;
        }
        const int64_t t0 = h.stamps[row], t1 = h.stamps[row + 1];
        const int64_t low = row > h.start ? t0 : t0 + 1;  // at the first stamp itself, row_at does not interpolate
        int64_t last = k + 1;  // the run: times[k..last), all within [low, t1)
        if (sorted) {  // each at least times[k], which is at least `low`
            last = std::lower_bound(times + last, times + n, t1) - times;
        } else {
            while (last < n && low <= times[last] && times[last] < t1) ++last;
        }
        if (step.composed) interval(side, times, k, last, n, h, row, arc_at(h, step.frame, row, memo));
        k = last;
    }
    if (step.composed) side.swap();
    return true;
}

// Identity into side.in, then each edge of one side of the chain, in walk order (`sorted`: the times
// ascend); the answers in side.in.
inline bool side_block(const Histories& histories, const std::vector<Step>& steps, const int64_t* times, int64_t n,
                       bool sorted, Side& side, Memo& memo) {
    side.in->reset(n);
    for (const Step& step : steps) {
        if (!edge_block(histories, step, times, n, sorted, side, memo)) return false;
    }
    return true;
}

// abnormal's bits of every component of the first n times of `acc`, or-ed.
inline uint64_t abnormal_all(const Accumulator& acc, int64_t n) {
    uint64_t bad = 0;
    for (int i = 0; i < 7; ++i) {
        for (int64_t k = 0; k < n; ++k) bad |= abnormal(acc.c[i][k]);
    }
    return bad;
}

// lookup_at at times[0..n) along the walked chain: the accumulator of the answers, in `blocks`; null
// where any time does not fit it (the accumulators are then of no use).
TFCORE_VECTOR_VERSIONS inline const Accumulator* chain_block(const Histories& histories, const Chain& chain,
                                                           const int64_t* times, int64_t n, Blocks& blocks,
                                                           Memo& memo) {
    const bool sorted = std::is_sorted(times, times + n);
    Side source{&blocks.acc[0], &blocks.acc[1], vector_lanes()};
    if (!side_block(histories, chain.sides[0], times, n, sorted, source, memo)) return nullptr;
    Accumulator& answer = *source.in;
    // (Checked on the bits: comparisons of doubles into a bool did not vectorize, ~75 instructions a time.)
    if (chain.ending == Ending::AT_TOP && chain.sides[1].empty() &&
        finish_keeps(chain.ending, true, abnormal_all(answer, n))) {
        return &answer;
    }
    Side target{source.out, &blocks.acc[2], source.lanes};
    if (!side_block(histories, chain.sides[1], times, n, sorted, target, memo)) return nullptr;
    if (chain.ending != Ending::AT_TARGET) {
        for (int64_t k = 0; k < n; ++k) answer.set(k, finish(chain.ending, answer.get(k), target.in->get(k)));
    }
    return &answer;
}

inline void put(const Outputs& out, int64_t k, int64_t time, bool ok, const Pose& p) {
    const int64_t row = out.rows[k];
    if (!out.filled) {
        out.stamps[row] = time;
        out.valid[row] = ok;
    } else if (!ok) {
        out.valid[row] = false;
    }
    double* v = out.values + 7 * row;
    v[0] = p.v.x, v[1] = p.v.y, v[2] = p.v.z, v[3] = p.q.x, v[4] = p.q.y, v[5] = p.q.z, v[6] = p.q.w;
}

// lookup_at at each time of a block: what answers any time. `common` is latest_common_time's
// answer (`common_ok` whether it had one), for the times of 0.
inline void each_block(const Histories& histories, int64_t target, int64_t source, const int64_t* times, int64_t n,
                       bool common_ok, int64_t common, const Outputs& out, Chain& chain, Memo& memo) {
    for (int64_t k = 0; k < n; ++k) {
        const int64_t time = times[k] == 0 ? common : times[k];
        Pose p;
        const bool ok = lookup_at(histories, target, source, time, chain, memo, p) && (times[k] != 0 || common_ok);
        put(out, k, time, ok, ok ? p : Pose{});
    }
}

// A lookup at each of times[0..n) (fastest in ascending order), into out's rows: along a walked
// chain where it can, else lookup_at at each time. `chained` false takes the second way always
// (what the tests compare the first with).
inline void lookup_many(const Histories& histories, int64_t target, int64_t source, const int64_t* times, int64_t n,
                        const Outputs& out, bool chained) {
    Memo memo(histories.size());
    int64_t common = 0;
    const bool common_ok = latest_common_time(histories, target, source, common) == Failure::NONE;
    Chain chain, scratch;
    auto blocks = std::make_unique<Blocks>();
    bool resolve = true;  // at the next block's first time: at first, and after a block did not fit
    for (int64_t lo = 0; lo < n; lo += BLOCK) {
        const int64_t m = std::min(BLOCK, n - lo);
        const int64_t* block = times + lo;
        const Outputs part{out.rows + lo, out.stamps, out.values, out.valid, out.filled};
        if (resolve && block[0] != 0) {
            walk(histories, target, source, block[0], chain, memo);
            resolve = false;
        }
        // A walk stopped at a gap may take another way at another time: blocks need a root.
        const bool fits = chained && chain.ending != Ending::NO_PATH && chain.rooted &&
                          std::find(block, block + m, 0) == block + m;
        const Accumulator* answer = fits ? chain_block(histories, chain, block, m, *blocks, memo) : nullptr;
        if (answer != nullptr) {
            for (int64_t k = 0; k < m; ++k) put(part, k, block[k], true, answer->get(k));
            continue;
        }
        resolve = true;
        each_block(histories, target, source, block, m, common_ok, common, part, scratch, memo);
    }
}

// Whether lookup_many takes times[0..n) as one block along its chain (-1: the chain does not
// resolve at the first time), for the tests.
inline int chain_takes(const Histories& histories, int64_t target, int64_t source, const int64_t* times, int64_t n) {
    Memo memo(histories.size());
    Chain chain;
    walk(histories, target, source, times[0], chain, memo);
    if (chain.ending == Ending::NO_PATH || !chain.rooted) return -1;
    auto blocks = std::make_unique<Blocks>();
    return chain_block(histories, chain, times, n, *blocks, memo) != nullptr ? 1 : 0;
}

}  // namespace tfcore
