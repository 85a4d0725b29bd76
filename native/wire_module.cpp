// tftools.sources.codecs._wire: TFMessages of ROS1 and CDR decoded in bulk (tf_wire.hpp), and why each
// message that is not well-formed is not.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "tf_wire.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T, typename... Shape>
using Input = nb::ndarray<const T, nb::c_contig, nb::device::cpu, Shape...>;
template <typename T>
using Output = nb::ndarray<nb::numpy, T>;

// ``values`` as a numpy array that owns them, of ``rows`` rows of ``width`` (1: a vector).
template <typename T>
Output<T> owned(std::vector<T>&& values, size_t width = 1) {
    auto* held = new std::vector<T>(std::move(values));
    nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    const size_t rows = held->size() / width;
    if (width == 1) return Output<T>(held->data(), {rows}, owner);
    return Output<T>(held->data(), {rows, width}, owner);
}

// ``column``'s values as a numpy array that owns them, of rows of ``width`` (1: a vector).
template <typename T>
Output<T> owned(tfwire::Column<T>&& column, size_t width = 1) {
    const size_t rows = column.size() / width;
    T* held = column.release();
    nb::capsule owner(held, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    if (width == 1) return Output<T>(held, {rows}, owner);
    return Output<T>(held, {rows, width}, owner);
}

using Decoded = std::tuple<Output<int64_t>, Output<int64_t>, Output<double>, Output<double>, Output<int32_t>,
                           Output<int32_t>, Output<int64_t>, Output<int64_t>, Output<int64_t>>;

// A wire as Python gives it: (encapsulation or -1, big_endian, origin, align, seq, signed_sec, nul, exact).
using WireFields = std::tuple<int, bool, int64_t, int64_t, bool, bool, bool, bool>;

// A decode's inputs checked: its wires, and the rows it makes room for at first.
struct Job {
    std::vector<tfwire::Wire> wires;
    size_t rows = 0;
};

Job checked(const Input<uint8_t, nb::ndim<1>>& raw, const Input<int64_t, nb::ndim<1>>& starts,
            const Input<int64_t, nb::ndim<1>>& lengths, const std::vector<WireFields>& wire_fields, bool counted) {
    const auto n = static_cast<int64_t>(starts.shape(0));
    const auto size = static_cast<int64_t>(raw.shape(0));
    if (static_cast<int64_t>(lengths.shape(0)) != n) throw nb::value_error("decode_transforms: starts and lengths differ");
    if (wire_fields.empty()) throw nb::value_error("decode_transforms: no wire");
    Job job;
    int64_t smallest = INT64_MAX;
    for (const auto& [encapsulation, big_endian, origin, align, seq, signed_sec, nul, exact] : wire_fields) {
        if (origin < 0 || align < 1 || (align & (align - 1)) != 0) {
            throw nb::value_error("decode_transforms: a wire without an origin, or an alignment not a power of 2");
        }
        job.wires.push_back({encapsulation, big_endian, origin, align, seq, signed_sec, nul, exact});
        smallest = std::min(smallest, job.wires.back().smallest());
    }
    int64_t total = 0;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t start = starts.data()[i], length = lengths.data()[i];
        if (start < 0 || length < 0 || length > size - start) {
            throw nb::value_error("decode_transforms: a payload outside the bytes given");
        }
        total += length;
    }
    // As many rows as the bytes can hold (payloads may overlap: no more than all the bytes).
    job.rows = static_cast<size_t>(counted ? std::min(total, size) / smallest : n);
    return job;
}

// The job's payloads read into ``rows``; touches no Python object (run without the GIL).
void read_all(const uint8_t* raw, const int64_t* starts, const int64_t* lengths, int64_t n, Job&& job, bool counted,
              tfwire::Rows& rows) {
    rows.reserve(job.rows);
    tfwire::Reader reader(raw, std::move(job.wires), counted);
    for (int64_t i = 0; i < n; ++i) reader.read(i, starts[i], lengths[i], rows);
}

Decoded outputs(tfwire::Rows&& rows) {
    return {owned(std::move(rows.message)),         owned(std::move(rows.stamp)),
            owned(std::move(rows.translation), 3),  owned(std::move(rows.rotation), 4),
            owned(std::move(rows.parent)),          owned(std::move(rows.child)),
            owned(std::move(rows.name_start)),      owned(std::move(rows.name_length)),
            owned(std::move(rows.failed), 4)};
}

Decoded decode_transforms(Input<uint8_t, nb::ndim<1>> raw, Input<int64_t, nb::ndim<1>> starts,
                          Input<int64_t, nb::ndim<1>> lengths, const std::vector<WireFields>& wire_fields,
                          bool counted) {
    Job job = checked(raw, starts, lengths, wire_fields, counted);
    tfwire::Rows rows;
    {
        nb::gil_scoped_release unlocked;
        read_all(raw.data(), starts.data(), lengths.data(), static_cast<int64_t>(starts.shape(0)), std::move(job),
                 counted, rows);
    }
    return outputs(std::move(rows));
}

// ``decode_transforms`` on a thread of its own, started at once; ``result`` waits for it. The inputs are
// held (and so their bytes alive) until it is done; a reader goes on reading meanwhile (docs/performance.md,
// "decoded on the other core").
class Decoding {
   public:
    Decoding(Input<uint8_t, nb::ndim<1>> raw, Input<int64_t, nb::ndim<1>> starts, Input<int64_t, nb::ndim<1>> lengths,
             const std::vector<WireFields>& wire_fields, bool counted)
        : raw_(std::move(raw)), starts_(std::move(starts)), lengths_(std::move(lengths)) {
        Job job = checked(raw_, starts_, lengths_, wire_fields, counted);
        const uint8_t* bytes = raw_.data();
        const int64_t* at = starts_.data();
        const int64_t* length = lengths_.data();
        const auto n = static_cast<int64_t>(starts_.shape(0));
        worker_ = std::thread([this, bytes, at, length, n, counted, job = std::move(job)]() mutable {
            try {
                read_all(bytes, at, length, n, std::move(job), counted, rows_);
            } catch (...) {
                failure_ = std::current_exception();
            }
        });
    }
    Decoding(const Decoding&) = delete;
    Decoding& operator=(const Decoding&) = delete;
    ~Decoding() {
        if (worker_.joinable()) worker_.join();  // it holds no GIL: never waits for this one
    }

    Decoded result() {
        if (!worker_.joinable()) throw nb::value_error("Decoding.result: taken already");
        {
            nb::gil_scoped_release unlocked;
            worker_.join();
        }
        if (failure_) std::rethrow_exception(failure_);
        return outputs(std::move(rows_));
    }

   private:
    Input<uint8_t, nb::ndim<1>> raw_;
    Input<int64_t, nb::ndim<1>> starts_, lengths_;
    tfwire::Rows rows_;
    std::exception_ptr failure_;
    std::thread worker_;
};

// Records ahead whose header ``match_records`` asks for while it reads one.
constexpr int64_t kAhead = 16;

using Matched = std::tuple<Output<bool>, Output<int64_t>, Output<int64_t>, Output<int64_t>, Output<int64_t>>;

// ROS1 message records at ``offsets`` of ``raw`` whose header (``header``: its bytes after its length,
// conn's 4 at ``conn_at`` and time's 8 at ``time_at`` free) is laid out as the template's, its length too, each ending
// within its ``limit`` (or, ``cut``, read only that far: its payload ends there). Which match; of
// those, conn, record time (ns), payload start and end. Python's reading of the same, in one pass.
Matched match_records(Input<uint8_t, nb::ndim<1>> raw, Input<int64_t, nb::ndim<1>> offsets,
                      Input<int64_t, nb::ndim<1>> limits, Input<bool, nb::ndim<1>> cuts, nb::bytes header,
                      int64_t conn_at, int64_t time_at) {
    const auto n = static_cast<int64_t>(offsets.shape(0));
    const auto size = static_cast<int64_t>(raw.shape(0));
    const auto length = static_cast<int64_t>(header.size());
    if (static_cast<int64_t>(limits.shape(0)) != n || static_cast<int64_t>(cuts.shape(0)) != n) {
        throw nb::value_error("match_records: offsets, limits and cuts differ in length");
    }
    if (conn_at < 0 || conn_at + 4 > length || time_at < 0 || time_at + 8 > length) {
        throw nb::value_error("match_records: conn or time outside the header");
    }
    // The header's fixed bytes, as ranges: all but conn's and time's.
    std::vector<std::pair<int64_t, int64_t>> fixed;
    {
        std::vector<bool> free(static_cast<size_t>(length), false);
        for (int64_t k = 0; k < 4; ++k) free[static_cast<size_t>(conn_at + k)] = true;
        for (int64_t k = 0; k < 8; ++k) free[static_cast<size_t>(time_at + k)] = true;
        for (int64_t k = 0; k < length;) {
            if (free[static_cast<size_t>(k)]) {
                ++k;
                continue;
            }
            int64_t end = k;
            while (end < length && !free[static_cast<size_t>(end)]) ++end;
            fixed.emplace_back(k, end);
            k = end;
        }
    }
    const auto* expected = reinterpret_cast<const uint8_t*>(header.c_str());
    std::vector<bool> hit(static_cast<size_t>(n), false);
    std::vector<int64_t> conn, time, data_start, data_end;
    {
        nb::gil_scoped_release unlocked;
        const uint8_t* bytes = raw.data();
        const auto u32 = [bytes](int64_t at) {
            uint32_t v;
            std::memcpy(&v, bytes + at, 4);
            return static_cast<int64_t>(v);
        };
        conn.reserve(static_cast<size_t>(n));
        time.reserve(static_cast<size_t>(n));
        data_start.reserve(static_cast<size_t>(n));
        data_end.reserve(static_cast<size_t>(n));
        for (int64_t i = 0; i < n; ++i) {
            // A record's header is this pass's first touch of its bytes, a miss to memory each: the
            // header kAhead records on is asked for now (a position out of ``raw`` is not).
            if (i + kAhead < n) {
                const int64_t ahead = offsets.data()[i + kAhead];
                if (ahead >= 0 && ahead < size) __builtin_prefetch(bytes + ahead);
            }
            const int64_t offset = offsets.data()[i], limit = std::min(limits.data()[i], size);
            const int64_t length_at = offset + 4 + length;
            if (offset < 0 || length_at + 4 > limit || u32(offset) != length) continue;
            const uint8_t* at = bytes + offset + 4;
            bool same = true;
            for (const auto& [begin, end] : fixed) {
                same = same && std::memcmp(at + begin, expected + begin, static_cast<size_t>(end - begin)) == 0;
            }
            if (!same) continue;
            int64_t ends = length_at + 4 + u32(length_at);
            if (cuts.data()[i] && ends > limit) ends = limit;
            if (ends > limit) continue;
            hit[static_cast<size_t>(i)] = true;
            conn.push_back(u32(offset + 4 + conn_at));
            time.push_back(u32(offset + 4 + time_at) * 1'000'000'000 + u32(offset + 4 + time_at + 4));
            data_start.push_back(length_at + 4);
            data_end.push_back(ends);
        }
    }
    auto* matched = new bool[static_cast<size_t>(n)];
    std::copy(hit.begin(), hit.end(), matched);
    nb::capsule owner(matched, [](void* p) noexcept { delete[] static_cast<bool*>(p); });
    return {Output<bool>(matched, {static_cast<size_t>(n)}, owner), owned(std::move(conn)), owned(std::move(time)),
            owned(std::move(data_start)), owned(std::move(data_end))};
}

// ``rows`` rows of ``width`` (1: a vector) as a numpy array that owns them, not filled: their writer fills
// them (a vector's zeros would be written once more, 27M instructions for the columns of 258k transforms).
template <typename T>
std::pair<Output<T>, T*> unfilled(size_t rows, size_t width = 1) {
    auto* held = new T[std::max<size_t>(rows * width, 1)];
    nb::capsule owner(held, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    if (width == 1) return {Output<T>(held, {rows}, owner), held};
    return {Output<T>(held, {rows, width}, owner), held};
}

using PerRow = std::tuple<Output<int64_t>, Output<bool>, Output<int32_t>>;

// What a batch's rows take from their message, row by row: messages ``messages`` of ``rows`` rows each
// (in that order), message m recorded at ``times[m]`` on channel ``channel_of[m]``, whose ``static_of`` and
// ``authority_of`` are the channel's. numpy would repeat the messages a row each and gather four columns
// through them (~19 instructions a value); here, one pass.
PerRow per_row(Input<int64_t, nb::ndim<1>> messages, Input<int64_t, nb::ndim<1>> rows,
               Input<int64_t, nb::ndim<1>> times, Input<int32_t, nb::ndim<1>> channel_of,
               Input<bool, nb::ndim<1>> static_of, Input<int32_t, nb::ndim<1>> authority_of) {
    const size_t n = messages.shape(0);
    if (rows.shape(0) != n) throw nb::value_error("per_row: messages and rows differ in length");
    if (times.shape(0) != channel_of.shape(0) || static_of.shape(0) != authority_of.shape(0)) {
        throw nb::value_error("per_row: columns of messages, or of channels, differ in length");
    }
    size_t total = 0;
    for (size_t i = 0; i < n; ++i) {
        const int64_t m = messages.data()[i], count = rows.data()[i];
        if (m < 0 || static_cast<size_t>(m) >= times.shape(0) || count < 0) {
            throw nb::value_error("per_row: a message outside the columns, or a negative count");
        }
        const int32_t channel = channel_of.data()[m];
        if (channel < 0 || static_cast<size_t>(channel) >= static_of.shape(0)) {
            throw nb::value_error("per_row: a channel outside the channels' columns");
        }
        total += static_cast<size_t>(count);
    }
    auto [record_time, t] = unfilled<int64_t>(total);
    auto [is_static, s] = unfilled<bool>(total);
    auto [authority, a] = unfilled<int32_t>(total);
    for (size_t i = 0; i < n; ++i) {
        const int64_t m = messages.data()[i];
        const int32_t channel = channel_of.data()[m];
        const int64_t time = times.data()[m];
        const bool still = static_of.data()[channel];
        const int32_t whose = authority_of.data()[channel];
        for (int64_t k = rows.data()[i]; k > 0; --k) {
            *t++ = time;
            *s++ = still;
            *a++ = whose;
        }
    }
    return {record_time, is_static, authority};
}

}  // namespace

NB_MODULE(_wire, m) {
    m.doc() = "TFMessages of ROS1 and CDR decoded in bulk, each failure told (tftools.sources.codecs.wire.Reason).";
    m.def("decode_transforms", &decode_transforms, "raw"_a, "starts"_a, "lengths"_a, "wires"_a, "counted"_a);
    nb::class_<Decoding>(m, "Decoding")
        .def(nb::init<Input<uint8_t, nb::ndim<1>>, Input<int64_t, nb::ndim<1>>, Input<int64_t, nb::ndim<1>>,
                      const std::vector<WireFields>&, bool>(),
             "raw"_a, "starts"_a, "lengths"_a, "wires"_a, "counted"_a)
        .def("result", &Decoding::result);
    m.def("match_records", &match_records, "raw"_a, "offsets"_a, "limits"_a, "cuts"_a, "header"_a, "conn_at"_a,
          "time_at"_a);
    m.def("per_row", &per_row, "messages"_a, "rows"_a, "times"_a, "channel_of"_a, "static_of"_a, "authority_of"_a);
}
