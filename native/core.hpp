// The buffer's state, one owner, as tf2's BufferCore owns its caches: the frames' and publishers'
// names and ids, each child frame's history (contiguous columns, the history it replaced under ROS 2),
// each frame's last publisher, the rows reserved for a bulk load and the block they go in, and the
// arrivals counted. Pure C++: module.cpp binds it, Python reads the histories through numpy views of
// the columns (each view keeps its block alive), and every sample comes in through `insert`
// (insert.hpp's rules) or its one-row case `insert_common`.
#pragma once

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <new>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "insert.hpp"

namespace tfbuffer {

// A row's flags (EdgeHistory.flags; the binding exports them to Python).
constexpr uint8_t FROM_STATIC_TOPIC = 1, PARENT_HAD_SLASH = 2, CHILD_HAD_SLASH = 4;

// Names to ids and back: ids in order of first interning, after the `reserved` names (never interned).
class Names {
   public:
    explicit Names(std::vector<std::string> reserved = {}) : names_(reserved.begin(), reserved.end()) {}
    Names(const Names&) = delete;
    Names& operator=(const Names&) = delete;

    // The id of `name`; -1 if it has none.
    int32_t find(std::string_view name) const {
        const auto it = ids_.find(name);
        return it == ids_.end() ? -1 : it->second;
    }
    int32_t intern(std::string_view name) {
        const auto it = ids_.find(name);
        if (it != ids_.end()) return it->second;
        const auto id = static_cast<int32_t>(names_.size());
        names_.emplace_back(name);
        ids_.emplace(names_.back(), id);
        return id;
    }
    const std::string& name(int64_t id) const { return names_.at(id); }
    size_t size() const { return names_.size(); }

   private:
    std::deque<std::string> names_;  // a deque: its strings never move, ids_'s keys view them
    std::unordered_map<std::string_view, int32_t> ids_;
};

// The bytes of one row in each column of a history's block: stamp, values (7), parent, authority,
// record time, sequence, flags, laid one column after another (each aligned to its items).
constexpr int64_t COLUMN_BYTES[7] = {8, 7 * 8, 4, 4, 8, 8, 1};
constexpr int64_t ROW_BYTES = 89;

// A history's block for `capacity` rows, rounded up to a cache line (blocks laid one after another
// stay aligned).
inline int64_t block_bytes(int64_t capacity) { return (capacity * ROW_BYTES + 63) / 64 * 64; }

// A history's columns, in memory that `memory` owns (a view of them holds it too).
struct Block {
    std::shared_ptr<void> memory;
    int64_t capacity = 0;
    int64_t* stamps = nullptr;
    double* values = nullptr;  // 7 per row: tx ty tz qx qy qz qw, as sent
    int32_t* parents = nullptr;
    int32_t* authorities = nullptr;
    int64_t* record_times = nullptr;
    int64_t* sequence = nullptr;
    uint8_t* flags = nullptr;

    Block() = default;
    Block(std::shared_ptr<void> owner, uint8_t* base, int64_t rows) : memory(std::move(owner)), capacity(rows) {
        uint8_t* at = base;
        const auto next = [&](int column) {
            uint8_t* here = at;
            at += COLUMN_BYTES[column] * rows;
            return here;
        };
        stamps = reinterpret_cast<int64_t*>(next(0));
        values = reinterpret_cast<double*>(next(1));
        parents = reinterpret_cast<int32_t*>(next(2));
        authorities = reinterpret_cast<int32_t*>(next(3));
        record_times = reinterpret_cast<int64_t*>(next(4));
        sequence = reinterpret_cast<int64_t*>(next(5));
        flags = next(6);
    }

    tfinsert::Columns columns() const {
        return {stamps, values, parents, authorities, record_times, sequence, flags};
    }
};

// Allocations of this size and up are given large pages where the kernel has them, as numpy asks for its
// arrays' (with THP in "madvise" mode, nothing else does).
constexpr int64_t LARGE_PAGES_FROM = 4 << 20;

// Ask for large pages for the pages wholly within `bytes` at `memory`.
inline void large_pages(void* memory, int64_t bytes) {
    constexpr uintptr_t PAGE = 4096;
    const auto start = reinterpret_cast<uintptr_t>(memory);
    const uintptr_t first = (start + PAGE - 1) & ~(PAGE - 1);
    if (bytes < LARGE_PAGES_FROM || static_cast<int64_t>(first - start) >= bytes) return;
    madvise(reinterpret_cast<void*>(first), bytes - (first - start), MADV_HUGEPAGE);
}

// A block of its own for `capacity` rows.
inline Block new_block(int64_t capacity) {
    const int64_t bytes = block_bytes(std::max<int64_t>(capacity, 1));
    void* memory = std::aligned_alloc(64, bytes);
    if (memory == nullptr) throw std::bad_alloc();
    large_pages(memory, bytes);
    return {std::shared_ptr<void>(memory, std::free), static_cast<uint8_t*>(memory), capacity};
}

// A large page: what one fault brings in for memory the kernel gives large pages (4 MiB and up).
constexpr int64_t LARGE_PAGE = 2 << 20;

// The largest room for a bulk load's histories that comes in large pages.
constexpr int64_t LARGE_PAGES_UP_TO = 64 << 20;

// The memory of a bulk load's room, brought in on another thread while the rows are still read.
//
// A fresh large page's first write costs ~0.3 ms, or ~3.5 ms where the host of a virtual machine took
// the block back (virtio-balloon's free page reporting): a 22 MiB room now and then 40 ms. Brought in
// here, ahead of the rows read so far, that cost is paid on the other core while the read goes on,
// not in the insert (docs/performance.md, "One slow run in five"). Up to `LARGE_PAGES_UP_TO`, the
// largest room in large pages; what the room does not use is given back when it is taken.
class Spare {
   public:
    // Without the address space or a thread, a spare that brings nothing in: the room is made as before.
    Spare() {
        // the room's largest size, and a large page's slack to start it on one: address space, not memory
        void* mapped = mmap(nullptr, LARGE_PAGES_UP_TO + LARGE_PAGE, PROT_READ | PROT_WRITE,
                            MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
        if (mapped == MAP_FAILED) return;
        const auto start = reinterpret_cast<uintptr_t>(mapped);
        const uintptr_t aligned = (start + LARGE_PAGE - 1) / LARGE_PAGE * LARGE_PAGE;
        if (aligned > start) munmap(mapped, aligned - start);
        if (start + LARGE_PAGE > aligned) {
            munmap(reinterpret_cast<void*>(aligned + LARGE_PAGES_UP_TO), start + LARGE_PAGE - aligned);
        }
        memory_ = reinterpret_cast<uint8_t*>(aligned);
        madvise(memory_, LARGE_PAGES_UP_TO, MADV_HUGEPAGE);
        try {
            worker_ = std::thread([this] { work(); });
        } catch (const std::system_error&) {
            take(0);
        }
    }
    Spare(const Spare&) = delete;
    Spare& operator=(const Spare&) = delete;
    ~Spare() {
        stop();
        if (memory_ != nullptr) munmap(memory_, LARGE_PAGES_UP_TO);
    }

    // A room of `rows` rows or more to come: its memory brought in, and as much again as one read's
    // part adds before the next call (at most the room's largest size). Past that size the room is not
    // laid on large pages: all of it given back at once.
    void ahead(int64_t rows) {
        if (memory_ == nullptr) return;
        if (rows * ROW_BYTES > LARGE_PAGES_UP_TO) {
            take(0);
            return;
        }
        const int64_t bytes = std::min(rows * ROW_BYTES + AHEAD, LARGE_PAGES_UP_TO);
        {
            const std::lock_guard<std::mutex> held(mutex_);
            if (bytes <= wanted_ || stopping_) return;
            wanted_ = bytes;
        }
        changed_.notify_one();
    }

    // The memory for a room of `size` bytes (at most `LARGE_PAGES_UP_TO`), what was brought in of it
    // ready, the rest given back; none once taken.
    std::shared_ptr<void> take(int64_t size) {
        stop();
        if (memory_ == nullptr) return nullptr;
        const int64_t kept = size > LARGE_PAGES_UP_TO ? 0 : (size + LARGE_PAGE - 1) / LARGE_PAGE * LARGE_PAGE;
        if (kept < LARGE_PAGES_UP_TO) munmap(memory_ + kept, LARGE_PAGES_UP_TO - kept);
        uint8_t* memory = std::exchange(memory_, nullptr);
        if (kept == 0) return nullptr;
        return std::shared_ptr<void>(memory, [kept](void* p) { munmap(p, kept); });
    }

    // Bytes brought in and still held here, not yet taken or given back.
    int64_t brought() {
        const std::lock_guard<std::mutex> held(mutex_);
        return memory_ == nullptr ? 0 : brought_;
    }

   private:
    // Bytes brought in beyond the rows read so far: a part's rows (a read decodes 4 MiB of messages at once).
    static constexpr int64_t AHEAD = 2 * LARGE_PAGE;

    void work() {
        // Never put ahead of the read on waking (SCHED_BATCH: no wakeup preemption), its share of the CPU
        // the same: on a busy machine it would otherwise take the read's core, a page at a time.
        const sched_param none{};
        pthread_setschedparam(pthread_self(), SCHED_BATCH, &none);
        std::unique_lock<std::mutex> held(mutex_);
        while (true) {
            changed_.wait(held, [this] { return stopping_ || brought_ < wanted_; });
            if (stopping_) return;
            uint8_t* page = memory_ + brought_;
            held.unlock();
            // Written, not MADV_POPULATE_WRITE, which holds the process's mmap lock while it zeroes: the
            // read's own mmap and brk calls would wait for it. Nothing else touches the memory until taken.
            for (int64_t at = 0; at < LARGE_PAGE; at += 4096) static_cast<volatile uint8_t*>(page)[at] = 0;
            held.lock();
            brought_ += LARGE_PAGE;
        }
    }

    // The worker stopped between two large pages, and joined: nothing writes the memory after.
    void stop() {
        {
            const std::lock_guard<std::mutex> held(mutex_);
            stopping_ = true;
        }
        changed_.notify_one();
        if (worker_.joinable()) worker_.join();
    }

    uint8_t* memory_ = nullptr;
    std::mutex mutex_;
    std::condition_variable changed_;
    int64_t wanted_ = 0, brought_ = 0;
    bool stopping_ = false;
    std::thread worker_;
};

// One block for the histories of a bulk load, each taking its part as it is made.
//
// Up to `large_pages_up_to` it starts on a large page, so the kernel brings it in a fault a large
// page, not page by page (faults are most of a bulk load's cost otherwise). The price is that each
// column's large page is resident from its first row on, while the rows not yet inserted are still
// held: a 258k-transform load peaks 13 MiB higher. A larger room stays in small pages, or that price
// would grow with the histories (2 MiB a column: a 4.1M-transform load would hold 136 B a transform,
// not 112). On a virtual machine whose host takes back the free blocks it is told of (virtio-balloon's
// free page reporting), a fresh large page's first write now and then costs ~3.5 ms, not ~0.3: one
// ingest in five was 40 ms slower. Small pages never are, and cost ~5 ms more in every ingest: kept
// large, and brought in ahead on another thread where a read gives a `Spare` (docs/performance.md, "One
// slow run in five").
class Room {
   public:
    // `spare`: memory brought in ahead for it (taken where the room is in large pages).
    Room(int64_t size, int64_t large_pages_up_to, Spare* spare = nullptr) : size_(size) {
        const bool large = size <= large_pages_up_to && size + LARGE_PAGE >= LARGE_PAGES_FROM;
        if (large && spare != nullptr) memory_ = spare->take(size);
        if (memory_) return;
        if (size > large_pages_up_to) {
            void* memory = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (memory == MAP_FAILED) throw std::bad_alloc();
            madvise(memory, size, MADV_NOHUGEPAGE);
            memory_ = std::shared_ptr<void>(memory, [size](void* p) { munmap(p, size); });
            small_pages_ = true;
        } else {
            const int64_t rounded = (size + LARGE_PAGE - 1) / LARGE_PAGE * LARGE_PAGE;
            void* memory = std::aligned_alloc(LARGE_PAGE, rounded);
            if (memory == nullptr) throw std::bad_alloc();
            // numpy's rule, as for the block with its alignment's slack that it used to be
            if (large) madvise(memory, rounded, MADV_HUGEPAGE);
            memory_ = std::shared_ptr<void>(memory, std::free);
        }
    }

    // A block for a history of `capacity` rows; none where there is no room left.
    std::optional<Block> take(int64_t capacity) {
        const int64_t size = block_bytes(capacity);
        if (used_ + size > size_) return std::nullopt;
        used_ += size;
        return Block(memory_, static_cast<uint8_t*>(memory_.get()) + used_ - size, capacity);
    }

    bool small_pages() const { return small_pages_; }

   private:
    std::shared_ptr<void> memory_;
    int64_t size_, used_ = 0;
    bool small_pages_ = false;
};

// A column that grows at its end and is cut at its front (a log that keeps its latest rows): the rows a
// numpy view shows never change (a cut or a growth moves the rows on to new memory; an append writes past
// every view's end), and each view holds the memory it shows.
template <typename T, int64_t WIDTH = 1>
class Tail {
   public:
    int64_t size() const { return end_ - start_; }
    const T* data() const { return static_cast<const T*>(memory_.get()) + WIDTH * start_; }
    const std::shared_ptr<void>& memory() const { return memory_; }

    void push(const T* row) {
        if (end_ == capacity_) move_to(2 * size() + 64);
        std::copy(row, row + WIDTH, static_cast<T*>(memory_.get()) + WIDTH * end_++);
    }
    void push(T value) { push(&value); }

    // Only the latest `rows` kept.
    void keep_last(int64_t rows) {
        if (size() > rows) start_ = end_ - rows;
    }

   private:
    void move_to(int64_t capacity) {
        auto* moved = new T[WIDTH * capacity];
        std::copy(data(), data() + WIDTH * size(), moved);
        memory_ = std::shared_ptr<void>(moved, [](void* p) { delete[] static_cast<T*>(p); });
        end_ = size(), start_ = 0, capacity_ = capacity;
    }

    std::shared_ptr<void> memory_;
    int64_t start_ = 0, end_ = 0, capacity_ = 0;
};

// A live buffer (a finite cache time) keeps its latest this many refusals and duplicates (about: up to
// twice as many); a whole recording's keeps every one. Every refusal is counted.
constexpr int64_t LIVE_REJECTIONS_KEPT = 10000;

// What tf2 refused (rejection.RejectionLog reads it), a row per refusal, in the order refused: the
// code (tfinsert::Refusal), the frames as tf2 names them (ids into `frames`: a refused sample's frames
// are not interned in the buffer's, as tf2 interns none), stamp, publisher (the buffer's id), record
// time, arrival number, the 7 values as sent and the flags a history would have given the row.
struct Refusals {
    Tail<uint8_t> code, flags;
    Tail<int32_t> parent, child, authority;
    Tail<int64_t> stamp, record_time, sequence;
    Tail<double, 7> values;
    Names frames;
    int64_t total = 0;  // every refusal, kept or not

    void keep_last(int64_t rows) {
        code.keep_last(rows), flags.keep_last(rows), parent.keep_last(rows), child.keep_last(rows);
        authority.keep_last(rows), stamp.keep_last(rows), record_time.keep_last(rows), sequence.keep_last(rows);
        values.keep_last(rows);
    }
};

// A frame name as tf2 keys it as given: not empty, without a leading slash.
inline bool plain(std::string_view name) { return !name.empty() && name[0] != '/'; }

// x - y - 1 within int64 (what a prune keeps stamps above, where Python's ints would go past it).
inline int64_t below(int64_t x, int64_t y) {
    int64_t difference = 0;
    if (__builtin_sub_overflow(x, y, &difference)) return y > 0 ? INT64_MIN : INT64_MAX;
    return difference == INT64_MIN ? difference : difference - 1;
}

// One child frame's samples (tf2's TimeCache or StaticCache): rows start..end of its block.
//
// A dynamic history is sorted by stamp: with no stamp twice under ROS 1's tf2, several samples of one
// stamp in arrival order under ROS 2's. A static one keeps every sample in arrival order and answers
// with the last at every time (tf2's StaticCache keeps only that one). Each row holds its parent, so a
// frame can change parent over time. The block grows in amortized steps; pruning (a finite cache time)
// drops a prefix by moving `start`. `replaced`: the history this one replaced when ROS 2's tf2 turned
// the frame static or dynamic (kept only where every sample is kept).
struct Store {
    bool is_static = false;
    int64_t start = 0, end = 0;
    Block block;
    std::shared_ptr<Store> replaced;
    // The parent of every row of start..end where they all have one (-1: rows of several parents, or none
    // yet): the walk then knows an edge's parent without reading its row, and does not wait for that load
    // before it goes on to the next edge. Pruning that leaves one parent keeps -1 (only slower).
    int32_t sole_parent = -1;

    int64_t size() const { return end - start; }

    // Rows from..end written (appended, or the whole history restored): sole_parent brought up to date.
    void added_rows(int64_t from) {
        if (from == start && from < end) sole_parent = block.parents[from];
        for (int64_t row = from; row < end && sole_parent >= 0; ++row) {
            if (block.parents[row] != sole_parent) sole_parent = -1;
        }
    }

    // tf2's getLatestTimestamp: 0 for a static history or an empty one.
    int64_t latest_stamp() const { return is_static || end == start ? 0 : block.stamps[end - 1]; }
    int64_t oldest_stamp() const { return is_static || end == start ? 0 : block.stamps[start]; }
    // The newest sample's parent (a static history's current one); 0 if empty.
    int32_t latest_parent() const { return end > start ? block.parents[end - 1] : 0; }

    // tf2's TimeCache::getParent: the parent at `time` (of the older of the two samples around it); -1
    // where the history has no sample then. Where samples share a stamp (ROS 2), tf2's newest-first
    // list makes the last to arrive count, except at the oldest stamp, its list's back: the first one.
    int64_t parent_at(int64_t time) const {
        if (end == start) return -1;
        const int64_t* stamps = block.stamps;
        int64_t row;
        if (is_static || time == 0 || time == stamps[end - 1]) {
            row = end - 1;
        } else if (time == stamps[start]) {
            row = start;
        } else if (stamps[start] < time && time < stamps[end - 1]) {
            row = std::upper_bound(stamps + start, stamps + end, time) - stamps - 1;
        } else {
            return -1;
        }
        return block.parents[row];
    }

    // The rows in use moved to the front of `to` (a new block), which the history then uses.
    void move_to(Block to) {
        const int64_t n = size();
        const Block& from = block;
        std::memcpy(to.stamps, from.stamps + start, n * 8);
        std::memcpy(to.values, from.values + 7 * start, n * 56);
        std::memcpy(to.parents, from.parents + start, n * 4);
        std::memcpy(to.authorities, from.authorities + start, n * 4);
        std::memcpy(to.record_times, from.record_times + start, n * 8);
        std::memcpy(to.sequence, from.sequence + start, n * 8);
        std::memcpy(to.flags, from.flags + start, n);
        block = std::move(to);
        start = 0, end = n;
    }

    // Room for `rows` more samples and as many again (the columns move): amortized growth.
    void grow(int64_t rows) { move_to(new_block(std::max<int64_t>(2 * (size() + rows), 8))); }

    // Room for `rows` more samples, exactly (a bulk load's reserved rows for a history it already has).
    void reserve(int64_t rows) {
        if (end + rows > block.capacity) move_to(new_block(size() + rows));
    }

    // tf2's pruneList: samples older than `cache_time` before `latest` dropped; the rows moved to a
    // block's front once more than half of it lies before them.
    void prune(int64_t cache_time, int64_t latest) {
        if (is_static || end == start) return;
        start = std::upper_bound(block.stamps + start, block.stamps + end, below(latest, cache_time)) - block.stamps;
        if (start > block.capacity / 2) move_to(new_block(block.capacity));
    }
};

// What a buffer answers as: its cache's length (none: every sample kept), ROS 2's tf2 or ROS 1's, the
// squared quaternion norm's tolerance, and the largest bulk load's room in large pages.
struct Settings {
    std::optional<int64_t> cache_time;
    bool ros2 = false;
    double tolerance = 10e-3;
    int64_t large_pages_up_to = LARGE_PAGES_UP_TO;
};

// A batch of samples as Buffer.insert takes it (TransformBatch's columns): each row's frames and
// publisher are indices into its names.
struct Batch {
    std::vector<std::string_view> names, authorities;
    int64_t n = 0;
    const int32_t *parent = nullptr, *child = nullptr, *authority = nullptr;
    const int64_t *stamp = nullptr, *record_time = nullptr;
    const double *translation = nullptr, *rotation = nullptr;  // (n, 3), (n, 4)
    const bool* is_static = nullptr;
};

// What an insertion did: how many rows tf2 accepted; the refused rows in the order tf2 refused them,
// in groups of one code (`codes`, `bounds` into `refused`); the rows ROS 2's tf2 accepted without
// storing them (identical to one held); each publisher of the batch's id in the buffer.
struct Inserted {
    int64_t accepted = 0;
    std::vector<int64_t> refused, bounds, duplicates;
    std::vector<uint8_t> codes;
    std::vector<int32_t> authority_ids;
};

// Rows passed the checks, as the histories store them.
struct Rows {
    int64_t first = 0;  // row 0's arrival number
    const int32_t *parent, *child, *authority;
    const int64_t *stamp, *record_time;
    const double *translation, *rotation;  // as sent
    bool turned;                           // ROS 2: rotations checked and compared through the matrix
    const bool* is_static;
    const int32_t* frame_of;       // a name's frame id
    const uint8_t* slash;          // whether a name had a leading slash
    const int32_t* authority_ids;  // a publisher's id in the buffer

    tfinsert::Offered offered(const int64_t* rows, int64_t k) const {
        return {rows, k, stamp, translation, rotation, parent, frame_of, turned};
    }
};

class Core {
   public:
    explicit Core(Settings settings) : settings_(settings) { grow_frames(); }

    const Settings& settings() const { return settings_; }
    const tfcore::Histories& view() const { return view_; }

    Names frames{{"NO_PARENT"}};  // tf2's ids, from 1: 0 is no parent
    Names publishers;
    int64_t arrivals = 0;  // samples offered so far, stored or refused: the next one's sequence number
    Refusals refusals;      // what tf2 refused
    Tail<int64_t> duplicates;  // arrival numbers of samples ROS 2's tf2 took without storing (identical to one held)

    // Frame `frame`'s history (null: a root, or a frame not known).
    const std::shared_ptr<Store>& store(int64_t frame) const {
        static const std::shared_ptr<Store> none;
        return frame > 0 && frame < static_cast<int64_t>(stores_.size()) ? stores_[frame] : none;
    }
    // Each frame's publisher of its last accepted sample; -1 where none.
    const std::vector<int32_t>& broadcasters() const { return broadcasters_; }

    // Restoring a copy: `frame`'s history, and its last publisher.
    void restore(int32_t frame, std::shared_ptr<Store> store, int32_t broadcaster) {
        grow_frames();
        stores_.at(frame) = std::move(store);
        broadcasters_.at(frame) = broadcaster;
        refresh(frame);
    }

    // `rows` more rows of the frame `name` (without its leading slash) about to come: its history is
    // made or sized for them once, in one room with the other reserved ones.
    // `spare`: memory brought in for the room while the rows were read (taken if the room fits it).
    void reserve(const std::vector<std::pair<std::string, int64_t>>& expected, Spare* spare = nullptr) {
        for (const auto& [name, rows] : expected) expected_[name] += rows;
        int64_t size = 0;
        for (const auto& [name, rows] : expected_) size += block_bytes(std::max<int64_t>(rows, 1));
        room_ = size ? std::make_shared<Room>(size, settings_.large_pages_up_to, spare) : nullptr;
    }
    const std::unordered_map<std::string, int64_t>& expected() const { return expected_; }
    void expect(std::string name, int64_t rows) { expected_[std::move(name)] = rows; }

    // tf2's BufferCore::clear: each dynamic history emptied, static ones kept, every name and id kept.
    void clear() {
        for (size_t frame = 1; frame < stores_.size(); ++frame) {
            if (!stores_[frame] || stores_[frame]->is_static) continue;
            auto emptied = std::make_shared<Store>();
            emptied->block = new_block(8);
            stores_[frame] = std::move(emptied);
            refresh(frame);
        }
    }

    // Buffer.insert: the batch's rows as that many tf2 setTransform calls (see _kernels.pyi).
    Inserted insert(const Batch& b);

    // Buffer.set_transform's common case, through the same rules: both frames known (`parent`, `child`:
    // their ids, or -1; named without a leading slash), different, a valid sample of the child's kind,
    // newer than its newest (unless static), a known publisher (its id, or -1), no rows reserved. False,
    // having changed nothing, otherwise.
    bool insert_common(int32_t parent, int32_t child, int64_t stamp, const double (&values)[7], bool is_static,
                       int64_t record_time, int32_t publisher);
    static void put(const tfinsert::Columns& c, int64_t at, const Rows& r, int64_t row);

   private:
    static constexpr int64_t NEVER = INT64_MAX;

    void grow_frames() {
        const size_t n = frames.size();
        if (stores_.size() >= n) return;
        stores_.resize(n);
        view_.resize(n);
        broadcasters_.resize(n, -1);
    }

    // The walk's view of `frame`'s history, as the history is now.
    void refresh(size_t frame) {
        const Store* s = stores_[frame].get();
        view_[frame] = s == nullptr ? tfcore::History{}
                                    : tfcore::History{true,          s->is_static,     s->start,
                                                      s->end,        s->block.stamps, s->block.values,
                                                      s->block.parents, settings_.ros2,  s->sole_parent};
    }

    // The rows reserved for the frame `name`, no longer reserved.
    int64_t take_reserved(std::string_view name) {
        if (expected_.empty()) return 0;
        const auto it = expected_.find(std::string(name));
        if (it == expected_.end()) return 0;
        const int64_t rows = it->second;
        expected_.erase(it);
        return rows;
    }

    int64_t store(int32_t frame, std::string_view name, const Rows& r, const int64_t* rows, int64_t k, Inserted& out);
    void log(const Batch& b, const Inserted& out, const std::vector<uint8_t>& slash, int64_t first);
    void append(int32_t frame, const Rows& r, const int64_t* rows, const std::vector<uint8_t>& verdicts);

    Settings settings_;
    std::vector<std::shared_ptr<Store>> stores_;  // by frame id
    tfcore::Histories view_;                      // what the walk reads of them
    std::vector<int32_t> broadcasters_;
    std::unordered_map<std::string, int64_t> expected_;  // rows per child frame reserved and still to come
    std::shared_ptr<Room> room_;                         // where the reserved rows' new histories go
    std::vector<uint8_t> verdicts_;                      // store's, kept: one sample's allocates nothing
};

// The rows refused since the last group, as one group of `code` (`bounds` starts with 0, where an
// insertion can refuse rows).
inline void close_group(Inserted& out, tfinsert::Refusal code) {
    if (out.refused.empty() || static_cast<int64_t>(out.refused.size()) == out.bounds.back()) return;
    out.codes.push_back(code);
    out.bounds.push_back(static_cast<int64_t>(out.refused.size()));
}

// The rows of `verdict`, refused as `code` (one group).
inline void refuse(Inserted& out, const int64_t* rows, const std::vector<uint8_t>& verdicts, tfinsert::Verdict verdict,
                   tfinsert::Refusal code) {
    for (size_t i = 0; i < verdicts.size(); ++i) {
        if (verdicts[i] == verdict) out.refused.push_back(rows[i]);
    }
    close_group(out, code);
}

// Offer one frame's `k` rows (passed the checks, in arrival order, all static or all dynamic under
// ROS 2) to its history, as tf2's setTransform does; returns how many tf2 accepted.
inline int64_t Core::store(int32_t frame, std::string_view name, const Rows& r, const int64_t* rows, int64_t k,
                           Inserted& out) {
    const int64_t expected = take_reserved(name);
    const bool run_static = r.is_static[rows[0]];
    const bool ros2 = settings_.ros2;
    std::shared_ptr<Store>& slot = stores_[frame];
    // ROS 1's tf2 makes a frame static or dynamic once, by its first accepted sample; ROS 2's
    // replaces the frame's cache whenever a sample of the other kind comes.
    if (!slot || (ros2 && slot->is_static != run_static)) {
        auto made = std::make_shared<Store>();
        made->is_static = run_static;
        if (!settings_.cache_time) made->replaced = slot;
        const int64_t capacity = std::max<int64_t>({k, expected, 1});
        std::optional<Block> block = room_ ? room_->take(capacity) : std::nullopt;
        made->block = block ? std::move(*block) : new_block(capacity);
        slot = std::move(made);
        refresh(frame);
    } else if (expected) {
        slot->reserve(expected);
        refresh(frame);
    }
    const tfcore::History& h = view_[frame];
    const bool is_static = h.is_static;
    std::vector<uint8_t>& verdicts = verdicts_;
    verdicts.assign(k, tfinsert::KEEP);
    int64_t prune_from = 0;  // ROS 2's
    if (!is_static) {
        const tfinsert::Offered offered = r.offered(rows, k);
        tfinsert::stamp_verdicts({h.stamps, h.values, h.parents, h.start, h.end, h.turned}, offered,
                                 settings_.cache_time, ros2, verdicts);
        refuse(out, rows, verdicts, tfinsert::OLD, tfinsert::OLD_DATA);
        if (ros2) {
            for (int64_t i = 0; i < k; ++i) {
                if (verdicts[i] == tfinsert::IGNORED) out.duplicates.push_back(rows[i]);
            }
            prune_from = tfinsert::newest_before_last(h.end > h.start ? h.stamps + h.end - 1 : nullptr, offered);
        } else {
            refuse(out, rows, verdicts, tfinsert::IGNORED, tfinsert::REPEATED_DATA);
        }
    }
    append(frame, r, rows, verdicts);
    Store& s = *slot;
    if (settings_.cache_time && !is_static && s.end > s.start) {
        s.prune(*settings_.cache_time, ros2 ? prune_from : s.block.stamps[s.end - 1]);
        refresh(frame);
    }
    int64_t accepted = 0, last = -1;
    for (int64_t i = 0; i < k; ++i) {
        if (verdicts[i] == tfinsert::KEEP || (ros2 && verdicts[i] == tfinsert::IGNORED)) {
            ++accepted;
            last = rows[i];
        }
    }
    if (last >= 0) broadcasters_[frame] = r.authority_ids[r.authority[last]];
    return accepted;
}

// Row `row` of `r` written at `at` of a history's columns.
inline void Core::put(const tfinsert::Columns& c, int64_t at, const Rows& r, int64_t row) {
    const int32_t parent = r.parent[row], child = r.child[row];
    c.stamps[at] = r.stamp[row];
    const tfinsert::Values v = tfinsert::values_of(r.translation, r.rotation, row);
    for (int j = 0; j < 7; ++j) c.values[7 * at + j] = v.v[j];  // not std::copy: a call to memmove
    c.parents[at] = r.frame_of[parent];
    c.authorities[at] = r.authority_ids[r.authority[row]];
    c.record_times[at] = r.record_time[row];
    c.sequence[at] = r.first + row;
    c.flags[at] = (r.is_static[row] ? FROM_STATIC_TOPIC : 0) | (r.slash[parent] ? PARENT_HAD_SLASH : 0) |
                  (r.slash[child] ? CHILD_HAD_SLASH : 0);
}

// The kept rows appended to `frame`'s history (grown if full), merged in by stamp where a dynamic
// history's order needs it.
inline void Core::append(int32_t frame, const Rows& r, const int64_t* rows, const std::vector<uint8_t>& verdicts) {
    const auto kept = static_cast<int64_t>(std::count(verdicts.begin(), verdicts.end(), tfinsert::KEEP));
    if (kept == 0) return;
    Store& s = *stores_[frame];
    if (s.end + kept > s.block.capacity) s.grow(kept);
    const tfinsert::Columns c = s.block.columns();
    const int64_t end_old = s.end;
    int64_t end = end_old;
    for (size_t i = 0; i < verdicts.size(); ++i) {
        if (verdicts[i] == tfinsert::KEEP) put(c, end++, r, rows[i]);
    }
    bool in_order = end_old == s.start || c.stamps[end_old] > c.stamps[end_old - 1];
    for (int64_t row = end_old + 1; row < end && in_order; ++row) in_order = c.stamps[row] > c.stamps[row - 1];
    s.end = end;
    s.added_rows(end_old);  // before the merge moves them
    if (!s.is_static && !in_order) tfinsert::merge_by_stamp(c, s.start, end_old, end);
    refresh(frame);
}

inline bool Core::insert_common(int32_t parent, int32_t child, int64_t stamp, const double (&values)[7],
                                bool is_static, int64_t record_time, int32_t publisher) {
    if (!expected_.empty() || child <= 0 || parent <= 0 || parent == child || publisher < 0) return false;
    const Store* s = stores_.at(child).get();
    if (s == nullptr || s->is_static != is_static) return false;
    if (!(is_static || s->end == s->start || stamp > s->block.stamps[s->end - 1])) return false;
    double checked[4] = {values[3], values[4], values[5], values[6]};
    if (settings_.ros2) tfcore::through_matrix_all(checked, 1, 4);  // what ROS 2's tf2 checks (and holds)
    const tfinsert::Values as_checked{{values[0], values[1], values[2], checked[0], checked[1], checked[2], checked[3]}};
    if (tfinsert::checks(parent, child, -1, as_checked, settings_.tolerance) != 0) return false;
    // The row as a batch of one: names 0 (parent) and 1 (child), publisher 0.
    const int32_t names[2] = {0, 1}, frame_of[2] = {parent, child}, zero = 0;
    const uint8_t slash[2] = {0, 0};
    const Rows r{arrivals,   names,          names + 1,  &zero,    &stamp, &record_time, values,
                 values + 3, settings_.ros2, &is_static, frame_of, slash,  &publisher};
    // What store() does with this one row, which tf2 keeps (checked above): appended, the history
    // pruned (ROS 2's tf2 prunes before the sample goes in: by the newest stamp before it), the
    // walk's view refreshed, the publisher noted.
    Store& held = *stores_[child];
    const int64_t newest_before = held.end > held.start ? held.block.stamps[held.end - 1] : stamp;
    if (held.end + 1 > held.block.capacity) held.grow(1);
    put(held.block.columns(), held.end++, r, 0);
    held.added_rows(held.end - 1);
    ++arrivals;
    if (settings_.cache_time && !is_static) held.prune(*settings_.cache_time, settings_.ros2 ? newest_before : stamp);
    refresh(child);
    broadcasters_[child] = publisher;
    return true;
}

inline Inserted Core::insert(const Batch& b) {
    Inserted out;
    out.bounds.push_back(0);
    for (const std::string_view authority : b.authorities) out.authority_ids.push_back(publishers.intern(authority));
    const int64_t n = b.n;
    const auto name_count = static_cast<int64_t>(b.names.size());
    const auto authorities = static_cast<int32_t>(b.authorities.size());
    for (int64_t i = 0; i < n; ++i) {
        if (b.parent[i] < 0 || b.parent[i] >= name_count || b.child[i] < 0 || b.child[i] >= name_count ||
            b.authority[i] < 0 || b.authority[i] >= authorities) {
            throw std::out_of_range("insert: a frame or publisher index outside the batch's names");
        }
    }
    // Each name a row uses, without its leading slash, as a key.
    std::vector<uint8_t> used(name_count), slash(name_count);
    for (int64_t i = 0; i < n; ++i) used[b.parent[i]] = used[b.child[i]] = 1;
    std::vector<int32_t> keys(name_count, -1);
    std::vector<std::string_view> stripped;  // per key, the name
    std::unordered_map<std::string_view, int32_t> index;
    for (int64_t j = 0; j < name_count; ++j) {
        if (!used[j]) continue;
        std::string_view name = b.names[j];
        if (!name.empty() && name[0] == '/') {
            name.remove_prefix(1);
            slash[j] = 1;
        }
        const auto [it, added] = index.emplace(name, static_cast<int32_t>(stripped.size()));
        if (added) stripped.push_back(name);
        keys[j] = it->second;
    }
    const auto empty = index.find(std::string_view());
    const int32_t empty_key = empty == index.end() ? -1 : empty->second;
    const int64_t first = arrivals;
    arrivals += n;
    std::vector<uint8_t> refusals(n);
    bool refused = false;
    // ROS 2's tf2 checks (and compares: Rows' `turned`) each rotation as it comes back from its
    // matrix: a block's at a time, not a copy of every rotation.
    double turned[4 * tfcore::TURN_BLOCK];
    for (int64_t at = 0; at < n; at += tfcore::TURN_BLOCK) {
        const int64_t m = std::min(tfcore::TURN_BLOCK, n - at);
        const double* checked = b.rotation + 4 * at;
        if (settings_.ros2) {
            tfcore::through_matrix_rows(checked, turned, m);
            checked = turned;
        }
        for (int64_t j = 0; j < m; ++j) {
            const int64_t i = at + j;
            const double *t = b.translation + 3 * i, *q = checked + 4 * j;
            const tfinsert::Values values{{t[0], t[1], t[2], q[0], q[1], q[2], q[3]}};
            refusals[i] = tfinsert::checks(keys[b.parent[i]], keys[b.child[i]], empty_key, values, settings_.tolerance);
            refused = refused || refusals[i];
        }
    }
    for (int check = 0; check < tfinsert::CHECKS && refused; ++check) {
        for (int64_t i = 0; i < n; ++i) {
            if (refusals[i] & (1 << check)) out.refused.push_back(i);
        }
        close_group(out, static_cast<tfinsert::Refusal>(check));
    }
    // Of the rows that passed, in one pass: where each name first appears (as a child before as a
    // parent, as tf2 interns them) and how many rows each child has.
    std::vector<int64_t> appearance(stripped.size(), NEVER), bounds(stripped.size() + 1, 0);
    for (int64_t i = 0; i < n; ++i) {
        if (refusals[i]) continue;
        const int32_t as_child = keys[b.child[i]], as_parent = keys[b.parent[i]];
        if (appearance[as_child] == NEVER) appearance[as_child] = 2 * i;
        if (appearance[as_parent] == NEVER) appearance[as_parent] = 2 * i + 1;
        ++bounds[as_child + 1];
    }
    // Frame ids for the names of rows that passed, new ones interned in order of appearance.
    std::vector<size_t> order;
    for (size_t key = 0; key < appearance.size(); ++key) {
        if (appearance[key] != NEVER) order.push_back(key);
    }
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return appearance[x] < appearance[y]; });
    std::vector<int32_t> key_to_id(stripped.size(), 0), frame_of(name_count, 0);
    for (const size_t key : order) key_to_id[key] = frames.intern(stripped[key]);
    for (int64_t j = 0; j < name_count; ++j) frame_of[j] = keys[j] < 0 ? 0 : key_to_id[keys[j]];
    grow_frames();
    // The rows that passed by child key, each key's in arrival order, from bounds[key] to bounds[key + 1].
    std::partial_sum(bounds.begin(), bounds.end(), bounds.begin());
    std::vector<int64_t> rows(bounds.back()), next(bounds.begin(), bounds.end() - 1);
    for (int64_t i = 0; i < n; ++i) {
        if (!refusals[i]) rows[next[keys[b.child[i]]]++] = i;
    }
    const Rows r{first,         b.parent,  b.child,         b.authority,     b.stamp,
                 b.record_time, b.translation, b.rotation, settings_.ros2,  b.is_static,
                 frame_of.data(), slash.data(), out.authority_ids.data()};
    for (size_t key = 0; key + 1 < bounds.size(); ++key) {
        const int64_t* group = rows.data() + bounds[key];
        const int64_t count = bounds[key + 1] - bounds[key];
        // A frame's rows in parts that go to one cache: all of them, except under ROS 2, where each
        // change between static and dynamic replaces the frame's cache.
        int64_t begin = 0;
        for (int64_t j = 1; j <= count; ++j) {
            if (j == count || (settings_.ros2 && b.is_static[group[j]] != b.is_static[group[begin]])) {
                out.accepted += store(key_to_id[key], stripped[key], r, group + begin, j - begin, out);
                begin = j;
            }
        }
    }
    if (expected_.empty()) room_.reset();
    log(b, out, slash, first);
    return out;
}

// The batch's refused rows (`out`'s, in the order refused) into `refusals`, its duplicates into
// `duplicates`; a live buffer keeps the latest of each.
inline void Core::log(const Batch& b, const Inserted& out, const std::vector<uint8_t>& slash, int64_t first) {
    std::vector<int32_t> logged(b.names.size(), -1);  // a batch name's id in the log's frames
    const auto frame = [&](int32_t j) {
        if (logged[j] < 0) logged[j] = refusals.frames.intern(b.names[j].substr(slash[j]));
        return logged[j];
    };
    Refusals& r = refusals;
    for (size_t group = 0; group < out.codes.size(); ++group) {
        for (int64_t k = out.bounds[group]; k < out.bounds[group + 1]; ++k) {
            const int64_t row = out.refused[k];
            const int32_t parent = b.parent[row], child = b.child[row];
            r.code.push(out.codes[group]);
            r.parent.push(frame(parent));
            r.child.push(frame(child));
            r.stamp.push(b.stamp[row]);
            r.authority.push(out.authority_ids[b.authority[row]]);
            r.record_time.push(b.record_time[row]);
            r.sequence.push(first + row);
            r.values.push(tfinsert::values_of(b.translation, b.rotation, row).v);
            r.flags.push(static_cast<uint8_t>((b.is_static[row] ? FROM_STATIC_TOPIC : 0) |
                                              (slash[parent] ? PARENT_HAD_SLASH : 0) |
                                              (slash[child] ? CHILD_HAD_SLASH : 0)));
        }
    }
    r.total += static_cast<int64_t>(out.refused.size());
    for (const int64_t row : out.duplicates) duplicates.push(first + row);
    if (settings_.cache_time) {
        if (r.code.size() > 2 * LIVE_REJECTIONS_KEPT) r.keep_last(LIVE_REJECTIONS_KEPT);
        if (duplicates.size() > 2 * LIVE_REJECTIONS_KEPT) duplicates.keep_last(LIVE_REJECTIONS_KEPT);
    }
}

}  // namespace tfbuffer
