// Transform sequences of ROS1 and CDR read message by message: every field checked against its
// message's end before it is read, and a message that is not well-formed told why (a Reason, where
// and a figure), which tftools.sources.codecs.wire.REASONS words. Frame names are told apart here
// (the first time each is seen), their bytes decoded in Python.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

namespace tfwire {

// How an encoding lays out its fields (tftools.sources.codecs.wire.Wire).
struct Wire {
    int encapsulation;  // CDR: the payloads in this wire, by their second byte (the first is 0); -1: any
    bool big_endian;
    int64_t origin;  // bytes before the fields, from which alignment counts
    int64_t align;   // the largest alignment: 1 packed (ROS1), 8 (CDR), 4 (XCDR2)
    bool seq;        // a header has a uint32 seq before its stamp (ROS1)
    bool signed_sec;
    bool nul;    // a string's length counts its terminating NUL (CDR)
    bool exact;  // nothing may follow the last field (ROS1)

    int64_t smallest() const { return 4 * seq + 8 + 4 + 4 + 56; }

    // The same layout (the encapsulation aside, which is checked before a message is read).
    bool same_layout(const Wire& w) const {
        return big_endian == w.big_endian && origin == w.origin && align == w.align && seq == w.seq &&
               signed_sec == w.signed_sec && nul == w.nul && exact == w.exact;
    }
};

// The layouts of nearly every recording, whose messages are read with the wire's fields known at compile
// time (ROS 2's little-endian CDR, ROS1): each field's alignment, byte order and header a constant, not
// read and tested at every field. The 300 s robot's 258,007 transforms: 91.4M instructions to 75.3M
// (ROS1), 94.4M to 86.6M (CDR). Any other wire is read as given.
struct AnyLayout {
    static Wire fixed(const Wire& given) { return given; }
};
struct CdrLittleLayout {
    static constexpr Wire kWire{-1, false, 4, 8, false, true, true, false};
    static Wire fixed(const Wire&) { return kWire; }
};
struct Ros1Layout {
    static constexpr Wire kWire{-1, false, 0, 1, true, false, false, true};
    static Wire fixed(const Wire&) { return kWire; }
};

// Why a message is not well-formed (tftools.sources.codecs.wire.Reason), with an offset in the
// message and a figure.
enum Reason : int64_t {
    ENCAPSULATION,  // in none of the wires: figure, its first (at most 2) bytes, big endian
    TRUNCATED,      // a field runs past the end: offset, where the field starts; figure, its size
    COUNT,          // more transforms than the bytes can hold: offset, after the count; figure, the count
    TRAILING,       // bytes after the last transform (ROS1): offset, where they start; figure, how many
};

struct Failure {
    Reason reason;
    int64_t offset, figure;
};

// A column of rows grown message by message: room for a message's rows is made once, then each row is
// written without a check of its own (a vector's push_back checks its capacity at every value).
template <typename T>
class Column {
   public:
    Column() = default;
    Column(const Column&) = delete;
    Column& operator=(const Column&) = delete;
    ~Column() { delete[] data_; }

    // Room for ``count`` more values (at least twice the room when it grows, so values are copied once
    // or twice in all).
    void room(size_t count) {
        if (size_ + count > capacity_) grow(std::max(size_ + count, 2 * capacity_));
    }
    void reserve(size_t count) {
        if (count > capacity_) grow(count);
    }
    T* tail() { return data_ + size_; }  // where the next value goes, within the room made
    void extend(size_t count) { size_ += count; }  // ``count`` values written at ``tail``, within the room
    void shrink(size_t size) { size_ = std::min(size, size_); }
    size_t size() const { return size_; }

    // The values, handed to their new owner (who frees them with delete[]); the column is left empty.
    T* release() {
        T* data = data_ != nullptr ? data_ : new T[1];
        data_ = nullptr;
        size_ = capacity_ = 0;
        return data;
    }

   private:
    void grow(size_t capacity) {
        T* fresh = new T[capacity];
        std::copy(data_, data_ + size_, fresh);
        delete[] data_;
        data_ = fresh;
        capacity_ = capacity;
    }

    T* data_ = nullptr;
    size_t size_ = 0, capacity_ = 0;
};

// Rows of the well-formed messages, in message order; names as ids into (name_start, name_length).
struct Rows {
    Column<int64_t> message, stamp;
    // The 7 values of a row written where the core takes them: its translation (3 a row) and rotation (4 a
    // row) apart, each contiguous (the values as (N, 7) were copied into the two again: ~2 ms and 14 MB of
    // fresh pages for 258k transforms).
    Column<double> translation, rotation;
    Column<int32_t> parent, child;
    std::vector<int64_t> name_start, name_length;  // each distinct name's first bytes in raw
    std::vector<int64_t> failed;  // 4 per message not read to a well-formed end: it, reason, offset, figure

    // Room for ``count`` rows at first: grown as they come, the rows would be copied again and again.
    void reserve(size_t count) {
        message.reserve(count);
        stamp.reserve(count);
        translation.reserve(3 * count);
        rotation.reserve(4 * count);
        parent.reserve(count);
        child.reserve(count);
    }

    // Room for ``count`` more rows.
    void room(size_t count) {
        message.room(count);
        stamp.room(count);
        translation.room(3 * count);
        rotation.room(4 * count);
        parent.room(count);
        child.room(count);
    }
};

// Names told apart: each distinct name's id, by its bytes (in ``raw``, where ``Rows`` keeps each
// name's first). A publisher names the same frames in the same places of its messages, mostly: the id
// last seen in the same place (a message of the same count, the same first name, the same position in
// it) is tried first, a comparison of a few words with that name's latest sighting (in the cache,
// where the first may be megabytes back); else open addressing with a mask, each slot's hash kept.
class NameIds {
   public:
    explicit NameIds(const uint8_t* raw) : raw_(raw), slots_(64), guesses_(kGuesses, kEmpty) {}

    // The id of ``bytes`` among the names of ``rows``, where it is added when it is new; ``place``
    // says where it is (``Reader::place``): names of one place are tried first as the last one there.
    // Inlined: called from each layout's reader, the compiler would otherwise call it (+8M instructions).
    __attribute__((always_inline)) int32_t find_or_add(std::string_view bytes, Rows& rows, uint64_t place) {
        int32_t& guess = guesses_[(place * 0x9E3779B97F4A7C15ull) >> (64 - kGuessBits)];
        // An id forgotten since may name another name now: its bytes are compared all the same.
        if (guess >= 0 && static_cast<size_t>(guess) < known_.size() &&
            same(known_[static_cast<size_t>(guess)], bytes)) {
            known_[static_cast<size_t>(guess)].latest = bytes.data();
            return guess;
        }
        guess = looked_up(bytes, rows);
        return guess;
    }

    // The names from ``first`` on let go (those of a message that is not well-formed).
    void forget(Rows& rows, size_t first) {
        for (size_t k = first; k < rows.name_start.size(); ++k) {
            const uint64_t hash = hash_of(name(rows, static_cast<int32_t>(k)));
            size_t at = hash & (slots_.size() - 1);
            while (slots_[at].id != static_cast<int32_t>(k)) at = (at + 1) & (slots_.size() - 1);
            slots_[at].id = kForgotten;  // still taken: the names placed past it stay found
        }
        rows.name_start.resize(first);
        rows.name_length.resize(first);
        known_.resize(first);
    }

   private:
    struct Slot {
        uint64_t hash = 0;
        int32_t id = kEmpty;
    };
    struct Known {
        const char* latest;  // the name's latest sighting
        size_t length;
    };
    static constexpr int32_t kEmpty = -1, kForgotten = -2;
    static constexpr int kGuessBits = 12;  // places remembered (a table of fixed size: a collision, a miss)
    static constexpr size_t kGuesses = size_t{1} << kGuessBits;

    int32_t looked_up(std::string_view bytes, Rows& rows) {
        const uint64_t hash = hash_of(bytes);
        size_t at = hash & (slots_.size() - 1);
        for (;; at = (at + 1) & (slots_.size() - 1)) {
            Slot& slot = slots_[at];
            if (slot.id == kEmpty) break;
            if (slot.hash == hash && slot.id >= 0 && same(known_[static_cast<size_t>(slot.id)], bytes)) {
                known_[static_cast<size_t>(slot.id)].latest = bytes.data();
                return slot.id;
            }
        }
        const auto id = static_cast<int32_t>(rows.name_start.size());
        rows.name_start.push_back(bytes.data() - reinterpret_cast<const char*>(raw_));
        rows.name_length.push_back(static_cast<int64_t>(bytes.size()));
        known_.push_back({bytes.data(), bytes.size()});
        slots_[at] = {hash, id};
        if (2 * ++used_ > slots_.size()) grow();
        return id;
    }

    std::string_view name(const Rows& rows, int32_t id) const {
        return {reinterpret_cast<const char*>(raw_ + rows.name_start[id]), static_cast<size_t>(rows.name_length[id])};
    }

    // Whether ``bytes`` are ``known``'s, compared a word at a time (a name is a few words: a call of
    // memcmp would cost more than the comparison).
    static bool same(const Known& known, std::string_view bytes) {
        const size_t n = bytes.size();
        if (known.length != n) return false;
        const char *a = known.latest, *b = bytes.data();
        if (n < 8) return tail(a, n) == tail(b, n);
        for (size_t at = 0; at + 8 < n; at += 8) {
            if (load<uint64_t>(a + at) != load<uint64_t>(b + at)) return false;
        }
        return load<uint64_t>(a + n - 8) == load<uint64_t>(b + n - 8);
    }

    static uint64_t hash_of(std::string_view bytes) {
        const char* p = bytes.data();
        const size_t n = bytes.size();
        uint64_t hash = 0x9E3779B97F4A7C15ull ^ n;
        for (size_t at = 0; at + 8 < n; at += 8) hash = mix(hash, load<uint64_t>(p + at));
        return mix(hash, tail(p, n));
    }

    // The last (at most) 8 bytes of ``p[0:n]`` as a word, read in at most two loads: a copy of a
    // variable length would be stored byte by byte and read back. Below 8 bytes, every byte is in it.
    static uint64_t tail(const char* p, size_t n) {
        if (n >= 8) return load<uint64_t>(p + n - 8);
        if (n >= 4) return (uint64_t{load<uint32_t>(p)} << 32) | load<uint32_t>(p + n - 4);
        if (n == 0) return 0;
        const auto byte = [p](size_t at) { return uint64_t{static_cast<uint8_t>(p[at])}; };
        return (byte(0) << 16) | (byte(n / 2) << 8) | byte(n - 1);
    }

    template <typename T>
    static T load(const char* p) {
        T w;
        std::memcpy(&w, p, sizeof w);
        return w;
    }

    static uint64_t mix(uint64_t hash, uint64_t w) {
        hash = (hash ^ w) * 0xBF58476D1CE4E5B9ull;
        return hash ^ (hash >> 31);
    }

    // Twice the slots, the forgotten left behind.
    void grow() {
        std::vector<Slot> old(slots_.size() * 2);
        old.swap(slots_);
        used_ = 0;
        for (const Slot& slot : old) {
            if (slot.id < 0) continue;
            size_t at = slot.hash & (slots_.size() - 1);
            while (slots_[at].id != kEmpty) at = (at + 1) & (slots_.size() - 1);
            slots_[at] = slot;
            ++used_;
        }
    }

    const uint8_t* raw_;
    std::vector<Slot> slots_;
    size_t used_ = 0;  // slots taken, forgotten ones included
    std::vector<Known> known_;  // by id
    std::vector<int32_t> guesses_;  // by place's hash: the id last found there
};

// A little-endian wire's 7 doubles copied as they are: the translation's 3 as a 16-byte word and an 8-byte
// one, the rotation's 4 as two 16-byte words. GCC compiled a memcpy of the 56 bytes in ROS1's reader as
// `rep movsl`, a string instruction whose start costs more than the copy: that line was 40% of a .bag's decode.
inline void copy_values(double* translation, double* rotation, const uint8_t* from) {
    using Pair = uint64_t __attribute__((vector_size(16)));
    Pair a, b, c;
    uint64_t z;
    std::memcpy(&a, from, 16);
    std::memcpy(&z, from + 16, 8);
    std::memcpy(&b, from + 24, 16);
    std::memcpy(&c, from + 40, 16);
    std::memcpy(translation, &a, 16);
    std::memcpy(translation + 2, &z, 8);
    std::memcpy(rotation, &b, 16);
    std::memcpy(rotation + 2, &c, 16);
}

class Reader {
   public:
    // ``wires``: one, or CDR's, told apart by the encapsulation each payload starts with.
    // ``counted``: a uint32 count of transforms first, else a single transform.
    Reader(const uint8_t* raw, std::vector<Wire> wires, bool counted)
        : raw_(raw), wires_(std::move(wires)), counted_(counted), names_(raw) {}

    // The message raw[start : start + length] into ``rows``; when it is not well-formed or in none
    // of the wires, nothing of it, and why into ``rows.failed``.
    void read(int64_t id, int64_t start, int64_t length, Rows& rows) {
        if (!well_formed(id, start, length, rows)) {
            rows.failed.insert(rows.failed.end(), {id, failure_.reason, failure_.offset, failure_.figure});
        }
    }

   private:
    // Where the reading of one message is, with its wire: a local that the compiler keeps in registers.
    // (As the reader's members, they were read again from memory after every value of a row written,
    // an int64_t that might have been one of them, and every name looked up: 15% more instructions.)
    struct Cursor {
        const uint8_t* raw;
        Wire wire;
        int64_t start, origin, end, pos;
        Failure& failure;

        // Where the next ``size`` bytes start, aligned to ``align`` (at most the wire's) from the origin.
        template <int64_t align>
        bool take(int64_t size, int64_t& at) {
            at = pos;
            if constexpr (align > 1) at += (origin - at) & ((align < wire.align ? align : wire.align) - 1);
            if (size > end - at) return fail(TRUNCATED, at - start, size);
            pos = at + size;
            return true;
        }

        // False, the message being not well-formed for ``reason``.
        bool fail(Reason reason, int64_t offset, int64_t figure) {
            failure = {reason, offset, figure};
            return false;
        }

        uint64_t u32(int64_t at) const {
            uint32_t v;
            std::memcpy(&v, raw + at, 4);
            return wire.big_endian ? __builtin_bswap32(v) : v;
        }

        double f64(int64_t at) const {
            uint64_t bits;
            std::memcpy(&bits, raw + at, 8);
            if (wire.big_endian) bits = __builtin_bswap64(bits);
            double v;
            std::memcpy(&v, &bits, 8);
            return v;
        }
    };

    bool well_formed(int64_t id, int64_t start, int64_t length, Rows& rows) {
        if (!choose(start, length)) return false;
        Cursor c{raw_, wire_, start, start + wire_.origin, start + length, start + wire_.origin, failure_};
        if (length < c.wire.origin) return c.fail(TRUNCATED, 0, c.wire.origin);
        uint64_t count = 1;
        if (counted_) {
            int64_t at;
            if (!c.take<4>(4, at)) return false;
            count = c.u32(at);
        }
        if (static_cast<int64_t>(count) * c.wire.smallest() > c.end - c.pos) {
            return c.fail(COUNT, c.pos - c.start, static_cast<int64_t>(count));
        }
        rows.room(count);  // as many as its bytes can hold: a count too large for them was refused above
        const size_t first = rows.message.size(), names = rows.name_start.size();
        const bool read = c.wire.same_layout(CdrLittleLayout::kWire) ? transforms<CdrLittleLayout>(id, count, c, rows)
                          : c.wire.same_layout(Ros1Layout::kWire)    ? transforms<Ros1Layout>(id, count, c, rows)
                                                                     : transforms<AnyLayout>(id, count, c, rows);
        if (!read) return forget(rows, first, names);
        if (c.wire.exact && c.pos != c.end) {
            c.fail(TRAILING, c.pos - c.start, c.end - c.pos);
            return forget(rows, first, names);
        }
        return true;
    }

    // The wire of the payload at ``start``: the one, or the one its CDR encapsulation names.
    bool choose(int64_t start, int64_t length) {
        for (const Wire& wire : wires_) {
            if (wire.encapsulation < 0 || (length >= wire.origin && length >= 2 && raw_[start] == 0 &&
                                           raw_[start + 1] == wire.encapsulation)) {
                wire_ = wire;
                return true;
            }
        }
        int64_t head = 0;
        for (int64_t k = 0; k < std::min<int64_t>(length, 2); ++k) head = head << 8 | raw_[start + k];
        failure_ = {ENCAPSULATION, 0, head};
        return false;
    }

    // The message's ``count`` transforms into ``rows`` (room made for them), counted there only when
    // every one is well-formed. Where the next name is (``place``): the message's count of transforms
    // and first name's id, and its position there.
    template <typename Layout>
    bool transforms(int64_t id, uint64_t count, Cursor& cursor, Rows& rows) {
        Cursor c = cursor;  // a copy of its own, which neither a name's lookup nor a row written can change
        c.wire = Layout::fixed(c.wire);  // a layout's constants, where it is one of them
        int64_t* const message = rows.message.tail();
        int64_t* const stamps = rows.stamp.tail();
        int32_t* const parents = rows.parent.tail();
        int32_t* const children = rows.child.tail();
        double* translations = rows.translation.tail();
        double* rotations = rows.rotation.tail();
        uint64_t position = 0;
        int32_t first = -1;  // the id of the message's first name (-1 before it)
        for (uint64_t j = 0; j < count; ++j, translations += 3, rotations += 4) {
            int64_t at;
            if (c.wire.seq && !c.take<1>(4, at)) return false;
            if (!c.take<4>(8, at)) return false;
            const int64_t sec = c.wire.signed_sec ? static_cast<int64_t>(static_cast<int32_t>(c.u32(at))) : c.u32(at);
            const int64_t stamp = sec * 1'000'000'000 + static_cast<int64_t>(c.u32(at + 4));
            int32_t frames[2];  // parent, child: a loop, so that the name's reading is written out once
            for (int32_t& found : frames) {
                if (!c.take<4>(4, at)) return false;
                const int64_t size = static_cast<int64_t>(c.u32(at));
                if (!c.take<1>(size, at)) return false;
                const int64_t kept = c.wire.nul ? (size > 0 ? size - 1 : 0) : size;
                const std::string_view bytes(reinterpret_cast<const char*>(c.raw + at), static_cast<size_t>(kept));
                const uint64_t place =
                    (count << 40) ^ (static_cast<uint64_t>(static_cast<uint32_t>(first)) << 8) ^ position;
                found = names_.find_or_add(bytes, rows, place);
                if (position++ == 0) first = found;
            }
            if (!c.take<8>(56, at)) return false;
            message[j] = id;
            stamps[j] = stamp;
            parents[j] = frames[0];
            children[j] = frames[1];
            if (c.wire.big_endian) {  // a little-endian wire's doubles are this machine's, copied as they are
                for (int k = 0; k < 3; ++k) translations[k] = c.f64(at + 8 * k);
                for (int k = 0; k < 4; ++k) rotations[k] = c.f64(at + 24 + 8 * k);
            } else {
                copy_values(translations, rotations, c.raw + at);
            }
        }
        rows.message.extend(count);
        rows.stamp.extend(count);
        rows.parent.extend(count);
        rows.child.extend(count);
        rows.translation.extend(3 * count);
        rows.rotation.extend(4 * count);
        cursor.pos = c.pos;
        return true;
    }

    // The rows from ``first`` on and the names from ``names`` on let go: false.
    bool forget(Rows& rows, size_t first, size_t names) {
        names_.forget(rows, names);
        rows.message.shrink(first);
        rows.stamp.shrink(first);
        rows.parent.shrink(first);
        rows.child.shrink(first);
        rows.translation.shrink(3 * first);
        rows.rotation.shrink(4 * first);
        return false;
    }

    const uint8_t* raw_;
    const std::vector<Wire> wires_;
    const bool counted_;
    Wire wire_{};
    Failure failure_{};
    NameIds names_;
};

}  // namespace tfwire
