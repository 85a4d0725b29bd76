// tf2's rules for each sample, as its setTransform and caches apply them: the checks of each sample,
// the samples a dynamic cache refuses or (ROS 2) ignores for their stamp, and new rows merged into a
// history by stamp. core.hpp's Core::insert (a batch) and Core::insert_common (set_transform's one
// sample) both apply them, through the same Core::store.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include "walk.hpp"

namespace tfinsert {

// Why a row is refused, in the order the buffer records the checks; named for Python (the binding's
// REFUSALS: rejection.RejectionCode's names) by REFUSAL_NAMES.
enum Refusal : uint8_t {
    SELF_TRANSFORM,
    NO_CHILD_FRAME_ID,
    NO_FRAME_ID,
    NAN_INPUT,
    DENORMALIZED_QUATERNION,
    OLD_DATA,
    REPEATED_DATA,
};
constexpr const char* REFUSAL_NAMES[] = {"SELF_TRANSFORM", "NO_CHILD_FRAME_ID", "NO_FRAME_ID", "NAN_INPUT",
                                         "DENORMALIZED_QUATERNION", "OLD_DATA", "REPEATED_DATA"};
static_assert(sizeof(REFUSAL_NAMES) / sizeof(REFUSAL_NAMES[0]) == REPEATED_DATA + 1, "a name per refusal");

// The checks of setTransform, each refusal a bit (1 << Refusal) of the answer.
constexpr int CHECKS = 5;

// One row's values: tx ty tz qx qy qz qw.
struct Values {
    double v[7];
};

// Row `row` of a batch's translations (N, 3) and rotations (N, 4).
inline Values values_of(const double* translation, const double* rotation, int64_t row) {
    const double* t = translation + 3 * row;
    const double* r = rotation + 4 * row;
    return {{t[0], t[1], t[2], r[0], r[1], r[2], r[3]}};
}

// setTransform's checks of one sample (`values` as tf2 checks them: ROS 2's rotation through its
// matrix), whose frames have the keys `parent` and `child` (names without their leading slash;
// `empty` is the empty name's).
inline uint8_t checks(int32_t parent, int32_t child, int32_t empty, const Values& values, double tolerance) {
    const double* v = values.v;
    uint8_t bits = 0;
    if (parent == child) bits |= 1 << SELF_TRANSFORM;
    if (child == empty) bits |= 1 << NO_CHILD_FRAME_ID;
    if (parent == empty) bits |= 1 << NO_FRAME_ID;
    // tf2 checks isnan only: an infinite rotation is refused by the norm check alone (ROS 2's, through
    // its matrix, turned to NaNs, by both). It would store an infinite translation; we refuse it.
    // Every value tested, without a branch a value (most rows have none of these: ~27 instructions less a row).
    bool refused = false;
    for (int j = 0; j < 7; ++j) refused |= std::isnan(v[j]);
    for (int j = 0; j < 3; ++j) refused |= std::isinf(v[j]);
    if (refused) bits |= 1 << NAN_INPUT;
    const double x = v[3], y = v[4], z = v[5], w = v[6];
    if (!(std::fabs((w * w + x * x + y * y + z * z) - 1.0) < tolerance)) bits |= 1 << DENORMALIZED_QUATERNION;
    return bits;
}

// A history's rows start..end as the stamp checks read them.
struct Held {
    const int64_t* stamps;
    const double* values;  // as sent
    const int32_t* parents;
    int64_t start, end;
    bool turned;  // ROS 2: compared with each rotation through tf2::Transform's matrix

    Values compared(int64_t row) const {
        const double* v = values + 7 * row;
        Values out{{v[0], v[1], v[2], v[3], v[4], v[5], v[6]}};
        if (turned) tfcore::through_matrix_all(out.v + 3, 1, 4);
        return out;
    }
};

// The rows of a batch offered to one history, in arrival order (`rows` into the batch's columns).
struct Offered {
    const int64_t* rows;
    int64_t count;
    const int64_t* stamp;
    const double *translation, *rotation;  // as sent
    const int32_t* parent;    // the batch's parent names
    const int32_t* frame_of;  // a name's frame id
    bool turned;              // ROS 2: compared with each rotation through tf2::Transform's matrix

    int64_t stamp_at(int64_t i) const { return stamp[rows[i]]; }
    int32_t parent_at(int64_t i) const { return frame_of[parent[rows[i]]]; }
    Values values_at(int64_t i) const {
        Values out = values_of(translation, rotation, rows[i]);
        if (turned) tfcore::through_matrix_all(out.v + 3, 1, 4);
        return out;
    }
};

// What becomes of an offered row in a dynamic history.
enum Verdict : uint8_t { KEEP, OLD, IGNORED };

// Whether two samples are tf2's equal TransformStorage (values compared as doubles: 0.0 == -0.0).
inline bool same_sample(const Values& a, int32_t parent_a, const Values& b, int32_t parent_b) {
    if (parent_a != parent_b) return false;
    for (int j = 0; j < 7; ++j) {
        if (!(a.v[j] == b.v[j])) return false;
    }
    return true;
}

// Which `candidates` (fresh rows whose stamp came before) equal an earlier sample of that stamp, held
// or kept from these rows: ROS 2's insertData ignores them (it checks TransformStorage == first).
inline void identical_to_earlier(const Held& held, const Offered& offered, const std::vector<uint8_t>& fresh,
                                 std::vector<uint8_t>& candidates) {
    std::vector<int64_t> asked;
    for (int64_t i = 0; i < offered.count; ++i) {
        if (candidates[i]) asked.push_back(offered.stamp_at(i));
    }
    std::sort(asked.begin(), asked.end());
    std::map<int64_t, std::vector<std::pair<Values, int32_t>>> kept;  // stamp -> samples kept so far
    for (int64_t i = 0; i < offered.count; ++i) {
        const int64_t stamp = offered.stamp_at(i);
        if (!fresh[i] || !std::binary_search(asked.begin(), asked.end(), stamp)) continue;
        const Values values = offered.values_at(i);
        const int32_t parent = offered.parent_at(i);
        bool identical = false;
        if (candidates[i]) {
            const int64_t* end = held.stamps + held.end;
            for (const int64_t* h = std::lower_bound(held.stamps + held.start, end, stamp); h < end && *h == stamp;
                 ++h) {
                const int64_t row = h - held.stamps;
                identical = identical || same_sample(held.compared(row), held.parents[row], values, parent);
            }
            for (const auto& [other, other_parent] : kept[stamp]) {
                identical = identical || same_sample(other, other_parent, values, parent);
            }
        }
        candidates[i] = identical;
        if (!identical) kept[stamp].emplace_back(values, parent);
    }
}

// x + y wrapping as numpy's int64 does.
inline int64_t wrapping_add(int64_t x, int64_t y) {
    return static_cast<int64_t>(static_cast<uint64_t>(x) + static_cast<uint64_t>(y));
}

// The verdict on each offered row of a dynamic history: OLD (TF_OLD_DATA: older by more than the
// cache time than the newest stamp held or offered before it), IGNORED (a stamp held, or offered
// before: ROS 1's TF_REPEATED_DATA; under ROS 2 only a sample identical to one of its stamp), else KEEP.
// Into `verdicts` (reused: the usual case allocates nothing).
inline void stamp_verdicts(const Held& held, const Offered& offered, std::optional<int64_t> cache_time, bool ros2,
                           std::vector<uint8_t>& verdicts) {
    const int64_t k = offered.count;
    verdicts.assign(k, KEEP);
    const bool empty = held.end == held.start;
    bool in_order = empty || offered.stamp_at(0) > held.stamps[held.end - 1];
    for (int64_t i = 1; i < k && in_order; ++i) in_order = offered.stamp_at(i) > offered.stamp_at(i - 1);
    if (in_order) return;  // the usual case: newer than all before, in order
    std::vector<int64_t> s(k);
    for (int64_t i = 0; i < k; ++i) s[i] = offered.stamp_at(i);
    std::vector<uint8_t> fresh(k, 1);
    if (cache_time) {
        int64_t latest_before = empty ? INT64_MIN : held.stamps[held.end - 1];
        for (int64_t i = 0; i < k; ++i) {
            if (wrapping_add(s[i], *cache_time) < latest_before) fresh[i] = 0;
            latest_before = std::max(latest_before, s[i]);
        }
    }
    std::vector<int64_t> order;  // the fresh rows by stamp, then arrival
    for (int64_t i = 0; i < k; ++i) {
        if (fresh[i]) order.push_back(i);
    }
    std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return s[a] < s[b]; });
    std::vector<uint8_t> repeated(k, 0);
    for (size_t j = 0; j < order.size(); ++j) {
        const int64_t i = order[j];
        const bool seen_before = j > 0 && s[order[j - 1]] == s[i];
        repeated[i] = seen_before || std::binary_search(held.stamps + held.start, held.stamps + held.end, s[i]);
    }
    if (ros2) identical_to_earlier(held, offered, fresh, repeated);
    for (int64_t i = 0; i < k; ++i) verdicts[i] = !fresh[i] ? OLD : repeated[i] ? IGNORED : KEEP;
}

// What ROS 2's tf2 prunes a dynamic history by after these rows: it prunes before each insertion,
// so last against the newest stamp held (`latest`, null if none) or offered before the last row
// (an old row's stamp is never the newest).
inline int64_t newest_before_last(const int64_t* latest, const Offered& offered) {
    int64_t newest = latest != nullptr ? *latest : offered.stamp_at(0);
    for (int64_t i = 0; i + 1 < offered.count; ++i) newest = std::max(newest, offered.stamp_at(i));
    return newest;
}

// A history's writable columns (core.hpp's Block).
struct Columns {
    int64_t* stamps;
    double* values;
    int32_t* parents;
    int32_t* authorities;
    int64_t* record_times;
    int64_t* sequence;
    uint8_t* flags;
};

// The `column` rows [first, first + perm.size()) rewritten as the rows `perm` lists (`width` per row).
template <typename T>
void permute(T* column, int width, int64_t first, const std::vector<int64_t>& perm) {
    std::vector<T> moved(perm.size() * width);
    for (size_t j = 0; j < perm.size(); ++j) {
        std::copy(column + perm[j] * width, column + (perm[j] + 1) * width, moved.begin() + j * width);
    }
    std::copy(moved.begin(), moved.end(), column + first * width);
}

// Rows end_old..end, just appended to the sorted rows start..end_old, merged in by stamp: a stable
// sort of start..end (held rows before new ones of their stamp, new ones in arrival order).
inline void merge_by_stamp(const Columns& c, int64_t start, int64_t end_old, int64_t end) {
    const int64_t* stamps = c.stamps;
    std::vector<int64_t> added(end - end_old);
    std::iota(added.begin(), added.end(), end_old);
    std::stable_sort(added.begin(), added.end(), [&](int64_t a, int64_t b) { return stamps[a] < stamps[b]; });
    const int64_t first = std::upper_bound(stamps + start, stamps + end_old, stamps[added[0]]) - stamps;
    std::vector<int64_t> held(end_old - first);
    std::iota(held.begin(), held.end(), first);
    std::vector<int64_t> perm(end - first);
    std::merge(held.begin(), held.end(), added.begin(), added.end(), perm.begin(),
               [&](int64_t a, int64_t b) { return stamps[a] < stamps[b]; });
    permute(c.stamps, 1, first, perm);
    permute(c.values, 7, first, perm);
    permute(c.parents, 1, first, perm);
    permute(c.authorities, 1, first, perm);
    permute(c.record_times, 1, first, perm);
    permute(c.sequence, 1, first, perm);
    permute(c.flags, 1, first, perm);
}

}  // namespace tfinsert
