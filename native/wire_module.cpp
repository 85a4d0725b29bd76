// tftools.sources.codecs._wire: TFMessages of ROS1 and CDR decoded in bulk (tf_wire.hpp), and why each
// message that is not well-formed is not.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cstdint>
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

using Decoded = std::tuple<Output<int64_t>, Output<int64_t>, Output<double>, Output<int32_t>, Output<int32_t>,
                           Output<int64_t>, Output<int64_t>, Output<int64_t>>;

// A wire as Python gives it: (encapsulation or -1, big_endian, origin, align, seq, signed_sec, nul, exact).
using WireFields = std::tuple<int, bool, int64_t, int64_t, bool, bool, bool, bool>;

Decoded decode_transforms(Input<uint8_t, nb::ndim<1>> raw, Input<int64_t, nb::ndim<1>> starts,
                          Input<int64_t, nb::ndim<1>> lengths, const std::vector<WireFields>& wire_fields,
                          bool counted) {
    const auto n = static_cast<int64_t>(starts.shape(0));
    const auto size = static_cast<int64_t>(raw.shape(0));
    if (static_cast<int64_t>(lengths.shape(0)) != n) throw nb::value_error("decode_transforms: starts and lengths differ");
    if (wire_fields.empty()) throw nb::value_error("decode_transforms: no wire");
    std::vector<tfwire::Wire> wires;
    int64_t smallest = INT64_MAX;
    for (const auto& [encapsulation, big_endian, origin, align, seq, signed_sec, nul, exact] : wire_fields) {
        if (origin < 0 || align < 1 || (align & (align - 1)) != 0) {
            throw nb::value_error("decode_transforms: a wire without an origin, or an alignment not a power of 2");
        }
        wires.push_back({encapsulation, big_endian, origin, align, seq, signed_sec, nul, exact});
        smallest = std::min(smallest, wires.back().smallest());
    }
    int64_t total = 0;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t start = starts.data()[i], length = lengths.data()[i];
        if (start < 0 || length < 0 || length > size - start) {
            throw nb::value_error("decode_transforms: a payload outside the bytes given");
        }
        total += length;
    }
    tfwire::Rows rows;
    {
        nb::gil_scoped_release unlocked;
        // As many rows as the bytes can hold (payloads may overlap: no more than all the bytes).
        rows.reserve(static_cast<size_t>(counted ? std::min(total, size) / smallest : n));
        tfwire::Reader reader(raw.data(), std::move(wires), counted);
        for (int64_t i = 0; i < n; ++i) reader.read(i, starts.data()[i], lengths.data()[i], rows);
    }
    return {owned(std::move(rows.message)),     owned(std::move(rows.stamp)),       owned(std::move(rows.values), 7),
            owned(std::move(rows.parent)),      owned(std::move(rows.child)),       owned(std::move(rows.name_start)),
            owned(std::move(rows.name_length)), owned(std::move(rows.failed), 4)};
}

}  // namespace

NB_MODULE(_wire, m) {
    m.doc() = "TFMessages of ROS1 and CDR decoded in bulk, each failure told (tftools.sources.codecs.wire.Reason).";
    m.def("decode_transforms", &decode_transforms, "raw"_a, "starts"_a, "lengths"_a, "wires"_a, "counted"_a);
}
