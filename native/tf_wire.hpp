// Transform sequences of ROS1 and CDR read message by message, as tftools.sources.codecs.wire's
// Cursor reads them: every field checked against its message's end before it is read. Frame names
// are told apart here (the first time each is seen), their bytes decoded in Python.
#pragma once

#include <cstdint>
#include <cstring>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace tfwire {

// How an encoding lays out its fields (tftools.sources.codecs.wire.Wire).
struct Wire {
    bool big_endian;
    int64_t origin;  // bytes before the fields, from which alignment counts
    int64_t align;   // the largest alignment: 1 packed (ROS1), 8 (CDR), 4 (XCDR2)
    bool seq;        // a header has a uint32 seq before its stamp (ROS1)
    bool signed_sec;
    bool nul;    // a string's length counts its terminating NUL (CDR)
    bool exact;  // nothing may follow the last field (ROS1)
    bool counted;  // a uint32 count of transforms first, else a single transform

    int64_t smallest() const { return 4 * seq + 8 + 4 + 4 + 56; }
};

// Rows of the well-formed messages, in message order; names as ids into (name_start, name_length).
struct Rows {
    std::vector<int64_t> message, stamp;
    std::vector<double> values;  // 7 a row
    std::vector<int32_t> parent, child;
    std::vector<int64_t> name_start, name_length;  // each distinct name's first bytes in raw
    std::vector<int64_t> bad;                      // the messages that do not read to a well-formed end
};

class Reader {
   public:
    Reader(const uint8_t* raw, const Wire& wire) : raw_(raw), wire_(wire) {}

    // The message raw[start : start + length] into ``rows``, or false (and nothing added) when it
    // is not well-formed.
    bool read(int64_t id, int64_t start, int64_t length, Rows& rows) {
        origin_ = start + wire_.origin;
        end_ = start + length;
        pos_ = origin_;
        if (length < wire_.origin) return false;
        uint64_t count = 1;
        if (wire_.counted) {
            int64_t at;
            if (!take(4, 4, at)) return false;
            count = u32(at);
            if (static_cast<int64_t>(count) * wire_.smallest() > end_ - pos_) return false;
        }
        const size_t first = rows.message.size(), names = rows.name_start.size();
        for (uint64_t j = 0; j < count; ++j) {
            if (!transform(id, j, rows)) return forget(rows, first, names);
        }
        if (wire_.exact && pos_ != end_) return forget(rows, first, names);
        return true;
    }

   private:
    bool transform(int64_t id, uint64_t j, Rows& rows) {
        int64_t at;
        if (wire_.seq && !take(4, 1, at)) return false;
        if (!take(8, 4, at)) return false;
        const int64_t sec = wire_.signed_sec ? static_cast<int64_t>(static_cast<int32_t>(u32(at))) : u32(at);
        const int64_t stamp = sec * 1'000'000'000 + u32(at + 4);
        int32_t parent, child;
        if (!name(rows, 2 * j, parent) || !name(rows, 2 * j + 1, child)) return false;
        if (!take(56, 8, at)) return false;
        rows.message.push_back(id);
        rows.stamp.push_back(stamp);
        rows.parent.push_back(parent);
        rows.child.push_back(child);
        for (int k = 0; k < 7; ++k) rows.values.push_back(f64(at + 8 * k));
        return true;
    }

    // A string's id among the names seen (a NUL left out). ``slot`` is where it stands in its
    // message: the name there in the message before mostly repeats (a publisher's frames, in
    // order), compared before the names are hashed.
    bool name(Rows& rows, uint64_t slot, int32_t& id) {
        int64_t at;
        if (!take(4, 4, at)) return false;
        const int64_t size = u32(at);
        if (!take(size, 1, at)) return false;
        const int64_t kept = wire_.nul ? (size > 0 ? size - 1 : 0) : size;
        const std::string_view bytes(reinterpret_cast<const char*>(raw_ + at), static_cast<size_t>(kept));
        if (slot < recent_.size()) {
            const int32_t last = recent_[slot];
            if (last >= 0 && last < static_cast<int32_t>(rows.name_start.size()) && seen(rows, last) == bytes) {
                id = last;
                return true;
            }
        } else if (slot < kRecentSlots) {
            recent_.resize(slot + 1, -1);
        }
        auto [place, added] = ids_.try_emplace(bytes, static_cast<int32_t>(rows.name_start.size()));
        if (added) {
            rows.name_start.push_back(at);
            rows.name_length.push_back(kept);
        }
        id = place->second;
        if (slot < recent_.size()) recent_[slot] = id;
        return true;
    }

    std::string_view seen(const Rows& rows, int32_t name) const {
        return {reinterpret_cast<const char*>(raw_ + rows.name_start[name]),
                static_cast<size_t>(rows.name_length[name])};
    }

    // Where the next ``size`` bytes start, aligned to ``align`` (at most the wire's) from the origin.
    bool take(int64_t size, int64_t align, int64_t& at) {
        at = pos_;
        const int64_t step = align < wire_.align ? align : wire_.align;
        if (step > 1) at += ((origin_ - at) % step + step) % step;
        if (size > end_ - at) return false;
        pos_ = at + size;
        return true;
    }

    uint64_t u32(int64_t at) const {
        uint32_t v;
        std::memcpy(&v, raw_ + at, 4);
        return wire_.big_endian ? __builtin_bswap32(v) : v;
    }

    double f64(int64_t at) const {
        uint64_t bits;
        std::memcpy(&bits, raw_ + at, 8);
        if (wire_.big_endian) bits = __builtin_bswap64(bits);
        double v;
        std::memcpy(&v, &bits, 8);
        return v;
    }

    // The rows from ``first`` on and the names from ``names`` on let go: false.
    bool forget(Rows& rows, size_t first, size_t names) {
        for (size_t k = names; k < rows.name_start.size(); ++k) ids_.erase(seen(rows, static_cast<int32_t>(k)));
        rows.name_start.resize(names);
        rows.name_length.resize(names);
        rows.message.resize(first);
        rows.stamp.resize(first);
        rows.parent.resize(first);
        rows.child.resize(first);
        rows.values.resize(7 * first);
        return false;
    }

    const uint8_t* raw_;
    Wire wire_;
    int64_t origin_ = 0, end_ = 0, pos_ = 0;
    static constexpr uint64_t kRecentSlots = 256;  // names of a message's first 128 transforms
    std::vector<int32_t> recent_;                  // per slot: the name last there
    std::unordered_map<std::string_view, int32_t> ids_;
};

}  // namespace tfwire
