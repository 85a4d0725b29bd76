// lookup_many over times in any order, across threads.
//
// lookup_many is fastest over ascending times (one walk per block, runs of times per interval),
// so times in another order are put in order first: a counting sort of each time into one of
// about n / 4 buckets of equal span, then a sort of each bucket (a few times each, in the cache).
// That is linear where an argsort is not, and leaves each row's place with its time. The sorted
// times are then cut into one span per thread, each thread sorting its own buckets and walking
// its span. The answers do not depend on the order (the same operations at each time).
#pragma once

#include <algorithm>
#include <memory>
#include <numeric>
#include <thread>
#include <utility>
#include <vector>

#include "blocks.hpp"

namespace tfcore {

// work(t) for each t in [0, threads), on that many threads (this one among them).
template <typename Work>
inline void on_threads(int threads, const Work& work) {
    std::vector<std::thread> helpers;
    for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
    work(0);
    for (std::thread& helper : helpers) helper.join();
}

// times[0..n) into sorted[0..n) by bucket of equal span, each bucket still unordered, with each
// time's index in rows; returns where each bucket begins (bucket b: [starts[b], starts[b + 1])).
// A counting sort on `threads` threads (n >= threads), each counting, then placing, its share of the
// times; within a bucket, the first thread's times come first.
inline std::vector<int64_t> bucket(const int64_t* times, int64_t n, int64_t* sorted, int64_t* rows, int threads) {
    const auto share = [&](int t) { return std::pair{n * t / threads, n * (t + 1) / threads}; };
    std::vector<std::pair<int64_t, int64_t>> ranges(threads);
    on_threads(threads, [&](int t) {
        const auto [lo, hi] = share(t);
        const auto [low, high] = std::minmax_element(times + lo, times + hi);
        ranges[t] = {*low, *high};
    });
    int64_t low = ranges[0].first, high = ranges[0].second;
    for (const auto& [l, h] : ranges) low = std::min(low, l), high = std::max(high, h);
    // Unsigned: any span of int64 times fits, negative ones included.
    const uint64_t span = static_cast<uint64_t>(high) - static_cast<uint64_t>(low);
    const uint64_t wanted = std::max<uint64_t>(1, static_cast<uint64_t>(n) / 4);
    int shift = 0;
    while ((span >> shift) >= wanted) ++shift;
    const auto key = [&](int64_t time) {
        return static_cast<int64_t>((static_cast<uint64_t>(time) - static_cast<uint64_t>(low)) >> shift);
    };
    const int64_t buckets = key(high) + 1;
    // Per thread, the count of its times in each bucket, then where the next of them goes.
    std::vector<std::vector<int64_t>> next(threads);
    on_threads(threads, [&](int t) {
        next[t].assign(buckets, 0);
        const auto [lo, hi] = share(t);
        for (int64_t k = lo; k < hi; ++k) ++next[t][key(times[k])];
    });
    std::vector<int64_t> starts(buckets + 1, n);
    int64_t placed = 0;
    for (int64_t b = 0; b < buckets; ++b) {
        starts[b] = placed;
        for (std::vector<int64_t>& counts : next) placed += std::exchange(counts[b], placed);
    }
    on_threads(threads, [&](int t) {
        const auto [lo, hi] = share(t);
        for (int64_t k = lo; k < hi; ++k) {
            const int64_t at = next[t][key(times[k])]++;
            sorted[at] = times[k], rows[at] = k;
        }
    });
    return starts;
}

// times[0..n) in order, rows[0..n) alongside: by insertion for the few of a bucket, else by std::sort.
inline void sort_bucket(int64_t* times, int64_t* rows, int64_t n) {
    if (n > 32) {
        std::vector<std::pair<int64_t, int64_t>> pairs(n);
        for (int64_t k = 0; k < n; ++k) pairs[k] = {times[k], rows[k]};
        std::sort(pairs.begin(), pairs.end());
        for (int64_t k = 0; k < n; ++k) times[k] = pairs[k].first, rows[k] = pairs[k].second;
        return;
    }
    for (int64_t k = 1; k < n; ++k) {
        const int64_t time = times[k], row = rows[k];
        int64_t j = k;
        for (; j > 0 && times[j - 1] > time; --j) times[j] = times[j - 1], rows[j] = rows[j - 1];
        times[j] = time, rows[j] = row;
    }
}

// lookup_many at times[0..n), in any order, each answer into its row (k-th time, k-th row), on
// `threads` threads (this one among them).
inline void lookup_any_order(const Histories& histories, int64_t target, int64_t source, const int64_t* times,
                             int64_t n, const Outputs& out, int threads) {
    if (n == 0) return;
    const std::unique_ptr<int64_t[]> sorted(new int64_t[n]), rows(new int64_t[n]);
    std::vector<int64_t> bounds(threads + 1, n);  // thread t walks sorted[bounds[t]:bounds[t + 1]]
    const bool ascending = std::is_sorted(times, times + n);
    std::vector<int64_t> starts;
    if (ascending) {
        std::copy(times, times + n, sorted.get());
        std::iota(rows.get(), rows.get() + n, 0);
        for (int t = 0; t < threads; ++t) bounds[t] = n * t / threads;
    } else {
        starts = bucket(times, n, sorted.get(), rows.get(), static_cast<int>(std::min<int64_t>(threads, n)));
        size_t at = 0;  // each thread's first bucket: where its share of the times begins
        for (int t = 0; t < threads; ++t) {
            while (starts[at] < n * t / threads) ++at;
            bounds[t] = starts[at];
        }
    }
    const auto run = [&](int t) {
        const int64_t lo = bounds[t], hi = bounds[t + 1];
        if (!ascending) {
            for (auto s = std::lower_bound(starts.begin(), starts.end(), lo); s + 1 < starts.end() && *s < hi; ++s) {
                sort_bucket(sorted.get() + s[0], rows.get() + s[0], s[1] - s[0]);
            }
        }
        lookup_many(histories, target, source, sorted.get() + lo, hi - lo,
                    {rows.get() + lo, out.stamps, out.values, out.valid}, true);
    };
    on_threads(threads, run);
}

}  // namespace tfcore
