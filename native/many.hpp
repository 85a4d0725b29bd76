// lookup_many over times in any order, across threads.
//
// lookup_many is fastest over ascending times (one walk per block, runs of times per interval),
// so times in another order are put in order first: a counting sort of each time into one of
// about n / TIMES_PER_BUCKET buckets of equal span, then a sort of each bucket (a few times each, in the cache).
// That is linear where an argsort is not, and leaves each row's place with its time. The buckets
// are then cut into pieces, several per thread, each thread taking the next piece left, sorting its
// buckets and walking their times a cache-sized chunk at a time. The answers do not depend on the order (the same operations at each time).
#pragma once

#include <algorithm>
#include <atomic>
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

// Times a bucket holds at least on average (buckets span a power of two: up to twice as many): few
// enough that a bucket sorts by rank in a few comparisons a time, many enough that each thread's
// bucket counters (8 bytes a bucket) stay near its L2 cache as it counts and places the times. 1M
// random times, one thread's CPU time: 8 (14 a bucket) bucketed 7.5 ms and sorted 12 ms, 4 (7 a
// bucket) 8.3 ms and 7.5 ms; 2 sorted no faster.
constexpr int64_t TIMES_PER_BUCKET = 4;

// How a time sorts within its bucket: one 64-bit key, its offset in the bucket (less the `drop`
// lowest bits) above its row, so that placing a time writes one value and a bucket sorts plain
// integers. Where the offset and the row do not fit 64 bits together (spans of centuries), the
// offset's lowest bits go: a bucket is then only nearly sorted, which lookup_many answers all the
// same (it takes any order), and a time is read back from its row.
struct Packing {
    uint64_t low = 0;  // the earliest time
    int shift = 0;     // a bucket spans 2**shift ns
    int row_bits = 0;
    int drop = 0;

    uint64_t key(int64_t time, int64_t row) const {
        const uint64_t offset = (static_cast<uint64_t>(time) - low) & ((uint64_t{1} << shift) - 1);
        return (offset >> drop) << row_bits | static_cast<uint64_t>(row);
    }
    int64_t row(uint64_t key) const { return static_cast<int64_t>(key & ((uint64_t{1} << row_bits) - 1)); }
    int64_t time(uint64_t key, int64_t bucket, const int64_t* times) const {
        if (drop != 0) return times[row(key)];
        return static_cast<int64_t>(low + (static_cast<uint64_t>(bucket) << shift) + (key >> row_bits));
    }
};

// Where each bucket of sorted times begins (bucket b: [starts[b], starts[b + 1])), and its keys' packing.
struct Buckets {
    std::vector<int64_t> starts;
    Packing packing;
};

// How many times ahead `bucket` asks for the line a time's key will go to (1M random times, one thread:
// placing them 9.5 ms without, 6.2 ms at 16; 8 and 32 alike).
constexpr int64_t PLACE_AHEAD = 16;

// times[0..n), each as its key, into keys[0..n) by bucket of equal span, each bucket still
// unordered. A counting sort on `threads` threads (n >= threads), each counting, then placing, its
// share of the times (within a bucket, the first thread's times come first); counting, each also
// fills its share of the stamps and valid outputs (`fill`).
inline Buckets bucket(const int64_t* times, int64_t n, uint64_t* keys, int threads, const Outputs& out,
                      int64_t common) {
    const auto share = [&](int t) { return std::pair{n * t / threads, n * (t + 1) / threads}; };
    std::vector<std::pair<int64_t, int64_t>> ranges(threads);
    on_threads(threads, [&](int t) {
        const auto [lo, hi] = share(t);
        int64_t low = times[lo], high = times[lo];  // (branch-free: std::minmax_element branches on every time)
        for (int64_t k = lo; k < hi; ++k) low = std::min(low, times[k]), high = std::max(high, times[k]);
        ranges[t] = {low, high};
    });
    int64_t low = ranges[0].first, high = ranges[0].second;
    for (const auto& [l, h] : ranges) low = std::min(low, l), high = std::max(high, h);
    Packing packing;
    packing.low = static_cast<uint64_t>(low);
    // Unsigned: any span of int64 times fits, negative ones included.
    const uint64_t span = static_cast<uint64_t>(high) - packing.low;
    const uint64_t wanted = std::max<uint64_t>(1, static_cast<uint64_t>(n / TIMES_PER_BUCKET));
    while (packing.shift < 63 && (span >> packing.shift) >= wanted) ++packing.shift;
    while ((static_cast<uint64_t>(n - 1) >> packing.row_bits) != 0) ++packing.row_bits;
    packing.drop = std::max(0, packing.shift + packing.row_bits - 64);
    const auto bucket_of = [&](int64_t time) {
        return static_cast<int64_t>((static_cast<uint64_t>(time) - packing.low) >> packing.shift);
    };
    const int64_t buckets = bucket_of(high) + 1;
    // Per thread, the count of its times in each bucket, then where the next of them goes.
    std::vector<std::vector<int64_t>> next(threads);
    on_threads(threads, [&](int t) {
        next[t].assign(buckets, 0);
        const auto [lo, hi] = share(t);
        for (int64_t k = lo; k < hi; ++k) ++next[t][bucket_of(times[k])];
        fill(out, times, lo, hi, common);
    });
    std::vector<int64_t> starts(buckets + 1, n);
    int64_t placed = 0;
    for (int64_t b = 0; b < buckets; ++b) {
        starts[b] = placed;
        for (std::vector<int64_t>& counts : next) placed += std::exchange(counts[b], placed);
    }
    on_threads(threads, [&](int t) {
        const auto [lo, hi] = share(t);
        int64_t* const places = next[t].data();
        // Each key goes to a line of `keys` that the cache does not hold: the lines of the times PLACE_AHEAD
        // on (and those times' counters, twice as far) are asked for first, so that the misses overlap.
        for (int64_t k = lo; k < hi; ++k) {
            if (k + 2 * PLACE_AHEAD < hi) __builtin_prefetch(places + bucket_of(times[k + 2 * PLACE_AHEAD]));
            if (k + PLACE_AHEAD < hi) __builtin_prefetch(keys + places[bucket_of(times[k + PLACE_AHEAD])]);
            keys[places[bucket_of(times[k])]++] = packing.key(times[k], k);
        }
    });
    return {std::move(starts), packing};
}

// Up to this many keys, a bucket is sorted by rank (into the caller's room), else by std::sort.
constexpr int64_t RANKED = 16;

// keys[0..n) in order, where they are returned: for a few, each key's rank (how many are smaller:
// the keys differ, by their rows) places it in `room`, comparisons without branches that the
// processor cannot predict over random times; for more, std::sort sorts them where they are.
inline const uint64_t* sort_bucket(uint64_t* keys, int64_t n, uint64_t (&room)[RANKED]) {
    if (n > RANKED) {
        std::sort(keys, keys + n);
        return keys;
    }
    for (int64_t i = 0; i < n; ++i) {
        int64_t rank = 0;
        for (int64_t j = 0; j < n; ++j) rank += keys[j] < keys[i];
        room[rank] = keys[i];
    }
    return room;
}

// Times in order with their rows, handed to lookup_many a chunk at a time (and the last, part of
// one, on `flush`): a chunk stays in the cache from being written to being walked, where a sorted
// copy of all the times would be written to memory and read back.
class Chunks {
   public:
    static constexpr int64_t SIZE = 4096;

    Chunks(const Histories& histories, int64_t target, int64_t source, const Outputs& out)
        : histories_(histories), target_(target), source_(source), out_(out) {}

    void add(int64_t time, int64_t row) {
        times_[held_] = time, rows_[held_] = row;
        // The row's answer is written when the chunk is walked: its lines (56 bytes: one or two), at a
        // random place in the outputs, are brought into the L2 cache now, so that those writes do not
        // each wait for memory (1M random times, one thread: the walk 93 -> 71 ms, as over sorted times).
        const double* answer = out_.values + 7 * row;
        __builtin_prefetch(answer, 0, 2);
        __builtin_prefetch(answer + 6, 0, 2);
        if (++held_ == SIZE) flush();
    }

    void flush() {
        if (held_ == 0) return;
        lookup_many(histories_, target_, source_, times_.data(), held_,
                    {rows_.data(), out_.stamps, out_.values, out_.valid, out_.filled}, true);
        held_ = 0;
    }

   private:
    const Histories& histories_;
    int64_t target_, source_;
    Outputs out_;
    std::vector<int64_t> times_ = std::vector<int64_t>(SIZE), rows_ = std::vector<int64_t>(SIZE);
    int64_t held_ = 0;
};

// Pieces of the walk per thread, taken by whichever thread is free: on a busy machine a thread the system
// does not run leaves its share to the others (with one fixed share each, the batch waited for the
// slowest thread).
constexpr int PIECES_PER_THREAD = 16;

// lookup_many at times[0..n), in any order, each answer into its row (k-th time, k-th row), on
// `threads` threads (this one among them).
inline void lookup_any_order(const Histories& histories, int64_t target, int64_t source, const int64_t* times,
                             int64_t n, Outputs out, int threads) {
    if (n == 0) return;
    int64_t common = 0;
    latest_common_time(histories, target, source, common);
    out.filled = true;
    const int pieces = threads > 1 ? threads * PIECES_PER_THREAD : 1;
    std::vector<int64_t> bounds(pieces + 1, n);  // piece p: times[bounds[p]:bounds[p + 1]], walked in order
    const bool ascending = std::is_sorted(times, times + n);
    std::unique_ptr<uint64_t[]> keys;  // each time's key, by bucket
    Buckets buckets;
    if (ascending) {
        for (int p = 0; p < pieces; ++p) bounds[p] = n * p / pieces;
    } else {
        keys.reset(new uint64_t[n]);
        buckets = bucket(times, n, keys.get(), static_cast<int>(std::min<int64_t>(threads, n)), out, common);
        const std::vector<int64_t>& starts = buckets.starts;
        size_t at = 0;  // each piece's first bucket: where its times begin
        for (int p = 0; p < pieces; ++p) {
            while (starts[at] < n * p / pieces) ++at;
            bounds[p] = starts[at];
        }
    }
    std::atomic<int> taken{0};
    const auto run = [&](int) {
        Chunks chunks(histories, target, source, out);
        for (int p = taken.fetch_add(1); p < pieces; p = taken.fetch_add(1)) {
            const int64_t lo = bounds[p], hi = bounds[p + 1];
            if (ascending) {
                fill(out, times, lo, hi, common);
                for (int64_t k = lo; k < hi; ++k) chunks.add(times[k], k);
                continue;
            }
            const std::vector<int64_t>& starts = buckets.starts;
            uint64_t room[RANKED];
            for (auto s = std::lower_bound(starts.begin(), starts.end(), lo); s + 1 < starts.end() && *s < hi; ++s) {
                const uint64_t* in_order = sort_bucket(keys.get() + s[0], s[1] - s[0], room);
                const int64_t b = s - starts.begin();
                for (int64_t k = 0; k < s[1] - s[0]; ++k) {
                    chunks.add(buckets.packing.time(in_order[k], b, times), buckets.packing.row(in_order[k]));
                }
            }
        }
        chunks.flush();
    };
    on_threads(threads, run);
}

}  // namespace tfcore
