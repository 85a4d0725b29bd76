// tftools.core._kernels: the compiled lookups over the buffer's edge histories (walk.hpp, blocks.hpp).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>

#include <optional>
#include <string>
#include <tuple>

#include "many.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T, typename... Shape>
using Array = nb::ndarray<T, nb::c_contig, nb::device::cpu, Shape...>;
using Int64s = Array<const int64_t, nb::ndim<1>>;
using Rows = Array<const double, nb::shape<-1, 7>>;
using Int32s = Array<const int32_t, nb::ndim<1>>;

// A lookup's answer as Transform takes it: (tx, ty, tz), (qx, qy, qz, qw) and the time it was made at.
using Found = std::tuple<std::tuple<double, double, double>, std::tuple<double, double, double, double>, int64_t>;

// The arrays a history's row points into, held so that they outlive it.
struct Pinned {
    Int64s stamps;
    Rows values;
    Int32s parents;
};

class EdgeTable {
   public:
    void update(int64_t frame, bool is_static, Int64s stamps, Rows values, Int32s parents, int64_t start,
                int64_t end) {
        const auto capacity = static_cast<int64_t>(std::min({stamps.shape(0), values.shape(0), parents.shape(0)}));
        if (frame < 0 || start < 0 || start > end || end > capacity) {
            throw nb::value_error("EdgeTable.update: rows outside the history's arrays");
        }
        if (frame >= static_cast<int64_t>(histories_.size())) {
            histories_.resize(frame + 1);
            pinned_.resize(frame + 1);
        }
        histories_[frame] = {true, is_static, start, end, stamps.data(), values.data(), parents.data()};
        pinned_[frame] = {std::move(stamps), std::move(values), std::move(parents)};
    }

    std::optional<Found> lookup(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        if (time == 0 && !tfcore::latest_common_time(histories_, target, source, time)) return std::nullopt;
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        tfcore::Pose p;
        if (!tfcore::lookup_at(histories_, target, source, time, chain, memo, p)) return std::nullopt;
        return Found{{p.v.x, p.v.y, p.v.z}, {p.q.x, p.q.y, p.q.z, p.q.w}, time};
    }

    bool can_transform(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        if (time == 0 && !tfcore::latest_common_time(histories_, target, source, time)) return false;
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        tfcore::walk(histories_, target, source, time, chain, memo);
        return chain.ending != tfcore::Ending::NO_PATH;
    }

    std::optional<int64_t> latest_common_time(int64_t target, int64_t source) const {
        check_frames(target, source);
        int64_t time = 0;
        if (!tfcore::latest_common_time(histories_, target, source, time)) return std::nullopt;
        return time;
    }

    void lookup_many(int64_t target, int64_t source, Int64s times, Int64s rows, Array<int64_t, nb::ndim<1>> stamps,
                     Array<double, nb::shape<-1, 7>> values, Array<bool, nb::ndim<1>> valid, bool chained) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        const auto outputs = static_cast<int64_t>(stamps.shape(0));
        if (static_cast<int64_t>(rows.shape(0)) != n || static_cast<int64_t>(values.shape(0)) != outputs ||
            static_cast<int64_t>(valid.shape(0)) != outputs) {
            throw nb::value_error("EdgeTable.lookup_many: times and rows, or the outputs, differ in length");
        }
        for (int64_t k = 0; k < n; ++k) {
            if (rows.data()[k] < 0 || rows.data()[k] >= outputs) {
                throw nb::value_error("EdgeTable.lookup_many: a row outside the outputs");
            }
        }
        nb::gil_scoped_release unlocked;
        tfcore::lookup_many(histories_, target, source, times.data(), n,
                            {rows.data(), stamps.data(), values.data(), valid.data()}, chained);
    }

    void lookup_in_parallel(int64_t target, int64_t source, Int64s times, Array<int64_t, nb::ndim<1>> stamps,
                            Array<double, nb::shape<-1, 7>> values, Array<bool, nb::ndim<1>> valid, int threads) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        if (static_cast<int64_t>(stamps.shape(0)) != n || static_cast<int64_t>(values.shape(0)) != n ||
            static_cast<int64_t>(valid.shape(0)) != n) {
            throw nb::value_error("EdgeTable.lookup_in_parallel: the times and the outputs differ in length");
        }
        if (threads < 1) throw nb::value_error("EdgeTable.lookup_in_parallel: at least one thread");
        nb::gil_scoped_release unlocked;
        tfcore::lookup_any_order(histories_, target, source, times.data(), n,
                                 {nullptr, stamps.data(), values.data(), valid.data()}, threads);
    }

    int chain_takes(int64_t target, int64_t source, Int64s times) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        if (n < 1 || n > tfcore::BLOCK) throw nb::value_error("EdgeTable.chain_takes: 1 to BLOCK times");
        return tfcore::chain_takes(histories_, target, source, times.data(), n);
    }

   private:
    static void check_frames(int64_t target, int64_t source) {
        if (target < 0 || source < 0) throw nb::value_error("EdgeTable: a negative frame id");
    }

    tfcore::Histories histories_;
    std::vector<Pinned> pinned_;
};

}  // namespace

NB_MODULE(_kernels, m) {
    m.doc() = "The compiled lookups: tftools.core.walk's tf2 walk over the buffer's edge histories.";
    m.attr("BLOCK") = tfcore::BLOCK;
    nb::class_<EdgeTable>(m, "EdgeTable")
        .def(nb::init<>())
        .def("update", &EdgeTable::update, "frame"_a, "static"_a, "stamps"_a, "values"_a, "parents"_a, "start"_a,
             "end"_a)
        .def("lookup", &EdgeTable::lookup, "target"_a, "source"_a, "time"_a)
        .def("can_transform", &EdgeTable::can_transform, "target"_a, "source"_a, "time"_a)
        .def("latest_common_time", &EdgeTable::latest_common_time, "target"_a, "source"_a)
        .def("lookup_many", &EdgeTable::lookup_many, "target"_a, "source"_a, "times"_a, "rows"_a, "stamps"_a,
             "values"_a, "valid"_a, "chained"_a = true)
        .def("lookup_in_parallel", &EdgeTable::lookup_in_parallel, "target"_a, "source"_a, "times"_a, "stamps"_a,
             "values"_a, "valid"_a, "threads"_a)
        .def("chain_takes", &EdgeTable::chain_takes, "target"_a, "source"_a, "times"_a);
}
