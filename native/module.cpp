// tftools.core._kernels: the buffer's state (core.hpp) and tf2's lookups over it (walk.hpp,
// blocks.hpp, many.hpp), bound: Python's values in and out, the buffer's lock held around a call.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>
#include <structmember.h>

#include <algorithm>
#include <cstdlib>
#include <initializer_list>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "core.hpp"
#include "lock.hpp"
#include "many.hpp"
#include "python.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using namespace tfpython;

// A lookup's answer as Transform takes it: (tx, ty, tz), (qx, qy, qz, qw) and the time it was made at.
using Found = std::tuple<std::tuple<double, double, double>, std::tuple<double, double, double, double>, int64_t>;

// Why a walk failed, as tftools.core.walk reads it: what failed (tfcore::Failure), and for an
// extrapolation its kind, time and stamp (history.Extrapolation).
using Failed = std::tuple<int, int64_t, int64_t, int64_t>;

Failed failed(tfcore::Failure failure, const tfcore::Extrapolation& missing = {}) {
    return {static_cast<int>(failure), missing.kind, missing.time, missing.stamp};
}

// A column of a history, rows start..end.
template <typename T>
nb::object rows_of(const tfbuffer::Store& s, const T* column) {
    return view(s.block.memory, column + s.start, s.size());
}

// The history of `columns` (a copy's: static, stamps, values, parents, authorities, record times,
// sequence, flags), which replaced `replaced`.
std::shared_ptr<tfbuffer::Store> store_of(const nb::tuple& columns, std::shared_ptr<tfbuffer::Store> replaced) {
    auto s = std::make_shared<tfbuffer::Store>();
    s->is_static = nb::cast<bool>(columns[0]);
    s->replaced = std::move(replaced);
    const auto stamps = nb::cast<Column<const int64_t>>(columns[1]);
    const auto values = nb::cast<Array<const double, nb::shape<-1, 7>>>(columns[2]);
    const auto parents = nb::cast<Column<const int32_t>>(columns[3]);
    const auto authorities = nb::cast<Column<const int32_t>>(columns[4]);
    const auto record_times = nb::cast<Column<const int64_t>>(columns[5]);
    const auto sequence = nb::cast<Column<const int64_t>>(columns[6]);
    const auto flags = nb::cast<Column<const uint8_t>>(columns[7]);
    const auto n = static_cast<int64_t>(stamps.shape(0));
    for (const size_t rows : {values.shape(0), parents.shape(0), authorities.shape(0), record_times.shape(0),
                              sequence.shape(0), flags.shape(0)}) {
        if (static_cast<int64_t>(rows) != n) throw nb::value_error("a history's columns of other lengths");
    }
    s->block = tfbuffer::new_block(std::max<int64_t>(n, 8));
    const tfbuffer::Block& b = s->block;
    std::copy(stamps.data(), stamps.data() + n, b.stamps);
    std::copy(values.data(), values.data() + 7 * n, b.values);
    std::copy(parents.data(), parents.data() + n, b.parents);
    std::copy(authorities.data(), authorities.data() + n, b.authorities);
    std::copy(record_times.data(), record_times.data() + n, b.record_times);
    std::copy(sequence.data(), sequence.data() + n, b.sequence);
    std::copy(flags.data(), flags.data() + n, b.flags);
    s->end = n;
    s->added_rows(0);
    return s;
}

// Rows start..end of a history's values, from column `first`, `width` of them.
nb::object values_of(const tfbuffer::Store& s, int64_t first = 0, int64_t width = 7) {
    return view(s.block.memory, s.block.values + 7 * s.start + first, s.size(), width, 7);
}

// `s` and the histories it replaced, newest first, as plain values (a copy's, pickle's): each one's
// static, stamps, values, parents, authorities, record times, sequence, flags.
nb::list chain_of(const tfbuffer::Store* s) {
    nb::list chain;
    for (; s != nullptr; s = s->replaced.get()) {
        const tfbuffer::Block& b = s->block;
        chain.append(nb::make_tuple(s->is_static, rows_of(*s, b.stamps), values_of(*s), rows_of(*s, b.parents),
                                    rows_of(*s, b.authorities), rows_of(*s, b.record_times), rows_of(*s, b.sequence),
                                    rows_of(*s, b.flags)));
    }
    return chain;
}

// The history chain_of() gave (null for none).
std::shared_ptr<tfbuffer::Store> from_chain(const nb::list& chain) {
    std::shared_ptr<tfbuffer::Store> s;
    for (size_t i = chain.size(); i-- > 0;) s = store_of(nb::cast<nb::tuple>(chain[i]), std::move(s));
    return s;
}

// The answer's (Transform's) fields, in its order.
enum Field { TRANSLATION, ROTATION, STAMP, FRAME_ID, CHILD_FRAME_ID };

// The attributes read of a transform, their names made once.
struct Names {
    nb::str translation{"translation"}, rotation{"rotation"}, stamp{"stamp"}, frame_id{"frame_id"},
        child_frame_id{"child_frame_id"}, frame_names{"frame_names"}, authorities{"authorities"};
};

// Where a slot (a __slots__ member's descriptor) keeps its value in an instance: its offset, or -1 for
// another kind of descriptor.
Py_ssize_t slot_offset(PyObject* descriptor) {
    if (!Py_IS_TYPE(descriptor, &PyMemberDescr_Type)) return -1;
    const PyMemberDef* member = reinterpret_cast<PyMemberDescrObject*>(descriptor)->d_member;
    return member->type == T_OBJECT_EX && !(member->flags & READONLY) ? member->offset : -1;
}

// The buffer's state (tfbuffer::Core) as Buffer calls it: see _kernels.pyi.
class BufferCore {
   public:
    BufferCore(nb::handle answer, std::optional<int64_t> cache_time, bool ros2, double tolerance,
               int64_t large_pages_up_to)
        : core(tfbuffer::Settings{cache_time, ros2, tolerance, large_pages_up_to}), lock(std::make_shared<Lock>()) {
        if (!PyType_Check(answer.ptr())) throw nb::type_error("BufferCore: answer must be a type");
        answer_ = nb::borrow(answer);
        const nb::object slots = nb::getattr(answer, "__dict__");
        const nb::str* fields[] = {&names_.translation, &names_.rotation, &names_.stamp, &names_.frame_id,
                                   &names_.child_frame_id};
        for (int i = 0; i < 5; ++i) {
            fields_[i] = slots[*fields[i]];
            const PyTypeObject* kind = Py_TYPE(fields_[i].ptr());
            if (kind->tp_descr_get == nullptr || kind->tp_descr_set == nullptr) {
                throw nb::type_error("BufferCore: answer's fields must be data descriptors (slots)");
            }
            offsets_[i] = slot_offset(fields_[i].ptr());
        }
#ifndef Py_GIL_DISABLED
        in_slots_ = std::all_of(std::begin(offsets_), std::end(offsets_), [](Py_ssize_t at) { return at >= 0; });
#endif
    }

    tfbuffer::Core core;
    std::shared_ptr<Lock> lock;  // the buffer's (Buffer.lock), held by every change of `core`

    // --- insertion ---------------------------------------------------------------------------

    // Buffer.set_transform's common case (Core::insert_common), under the buffer's lock.
    bool set_transform(nb::handle transform, nb::handle authority, nb::handle is_static, nb::handle record_time) {
        const Locked locked(*lock);
        const nb::object child = field(transform, CHILD_FRAME_ID, names_.child_frame_id);
        const nb::object parent = field(transform, FRAME_ID, names_.frame_id);
        const nb::object translation = field(transform, TRANSLATION, names_.translation);
        const nb::object rotation = field(transform, ROTATION, names_.rotation);
        const nb::object stamp_object = field(transform, STAMP, names_.stamp);
        if (!child.is_valid() || !parent.is_valid() || !translation.is_valid() || !rotation.is_valid() ||
            !stamp_object.is_valid()) {
            PyErr_Clear();  // the batch path meets it again, and says what is wrong
            return false;
        }
        const int wanted_static = PyObject_IsTrue(is_static.ptr());
        if (wanted_static < 0) {
            PyErr_Clear();
            return false;
        }
        double v[7];
        int64_t stamp = 0, recorded = 0;
        if (!read_numbers(translation, 3, v) || !read_numbers(rotation, 4, v + 3) || !read_int(stamp_object, stamp) ||
            !read_int(record_time, recorded)) {
            return false;
        }
        const int32_t parent_id = id_of(parent, false), child_id = id_of(child, false);
        const int32_t publisher = id_of(authority, true);
        if (!core.insert_common(parent_id, child_id, stamp, v, wanted_static, recorded, publisher)) return false;
        lock->notify_all();
        return true;
    }

    // Buffer.insert's work in one call, under the lock, its waiters woken: see _kernels.pyi.
    int64_t insert(nb::handle batch) {
        const nb::object names = nb::getattr(batch, names_.frame_names), authorities = nb::getattr(batch, names_.authorities);
        tfbuffer::Batch b;
        b.names = texts(names);
        b.authorities = texts(authorities);
        const auto parent = nb::cast<Column<const int32_t>>(nb::getattr(batch, "parent"));
        const auto child = nb::cast<Column<const int32_t>>(nb::getattr(batch, "child"));
        const auto authority = nb::cast<Column<const int32_t>>(nb::getattr(batch, "authority"));
        const auto stamp = nb::cast<Column<const int64_t>>(nb::getattr(batch, "stamp"));
        const auto record_time = nb::cast<Column<const int64_t>>(nb::getattr(batch, "record_time"));
        const auto translation = nb::cast<Array<const double, nb::shape<-1, 3>>>(nb::getattr(batch, "translation"));
        const auto rotation = nb::cast<Array<const double, nb::shape<-1, 4>>>(nb::getattr(batch, "rotation"));
        const auto is_static = nb::cast<Column<const bool>>(nb::getattr(batch, "static"));
        b.n = static_cast<int64_t>(stamp.shape(0));
        for (const size_t rows : {parent.shape(0), child.shape(0), authority.shape(0), record_time.shape(0),
                                  translation.shape(0), rotation.shape(0), is_static.shape(0)}) {
            if (static_cast<int64_t>(rows) != b.n) throw nb::value_error("BufferCore.insert: columns of other lengths");
        }
        b.parent = parent.data(), b.child = child.data(), b.authority = authority.data();
        b.stamp = stamp.data(), b.record_time = record_time.data();
        b.translation = translation.data(), b.rotation = rotation.data(), b.is_static = is_static.data();
        const Locked locked(*lock);
        const int64_t accepted = core.insert(b).accepted;
        lock->notify_all();
        return accepted;
    }

    void reserve(const std::vector<std::pair<std::string, int64_t>>& rows, tfbuffer::Spare* spare) {
        const Locked locked(*lock);
        core.reserve(rows, spare);
    }

    void clear() {
        const Locked locked(*lock);
        core.clear();
        lock->notify_all();
    }

    // The refusal log's columns (rejection.RejectionLog's), viewed: code, parent, child, stamp,
    // authority, record time, sequence, values (N, 7), flags.
    nb::tuple refusals() const {
        const tfbuffer::Refusals& r = core.refusals;
        return nb::make_tuple(tail(r.code), tail(r.parent), tail(r.child), tail(r.stamp), tail(r.authority),
                              tail(r.record_time), tail(r.sequence), tail(r.values), tail(r.flags));
    }

    // --- the frames, the publishers, the histories -------------------------------------------

    // The id of the frame `name` (0: none).
    int64_t frame_id(nb::handle name) const {
        std::string_view s;
        return text(name, s) ? std::max(core.frames.find(s), 0) : 0;
    }

    std::vector<std::string> frame_names() const { return all(core.frames); }
    std::vector<std::string> publisher_names() const { return all(core.publishers); }

    // (frame names from id 1, publishers, arrivals, each frame's last publisher, the rows reserved,
    // each frame's histories newest first: its own, then those it replaced) as a copy needs them.
    nb::tuple state() const {
        nb::list histories;
        for (size_t frame = 0; frame < core.frames.size(); ++frame) histories.append(chain_of(core.store(frame).get()));
        std::vector<std::pair<std::string, int64_t>> expected(core.expected().begin(), core.expected().end());
        std::vector<std::string> frames = frame_names();
        frames.erase(frames.begin());
        const tfbuffer::Refusals& r = core.refusals;
        const nb::tuple log = nb::make_tuple(all(r.frames), r.total, refusals(), tail(core.duplicates));
        return nb::make_tuple(frames, publisher_names(), core.arrivals, core.broadcasters(), expected, histories, log);
    }

    // A new buffer's state made `state()`'s.
    void restore(const nb::tuple& state) {
        if (core.frames.size() != 1 || core.publishers.size() != 0) throw nb::value_error("BufferCore.restore: not new");
        for (const nb::handle name : nb::cast<nb::list>(state[0])) core.frames.intern(nb::cast<std::string>(name));
        for (const nb::handle name : nb::cast<nb::list>(state[1])) core.publishers.intern(nb::cast<std::string>(name));
        core.arrivals = nb::cast<int64_t>(state[2]);
        const auto broadcasters = nb::cast<std::vector<int32_t>>(state[3]);
        for (const auto& [name, rows] : nb::cast<std::vector<std::pair<std::string, int64_t>>>(state[4])) {
            core.expect(name, rows);
        }
        const nb::list histories = nb::cast<nb::list>(state[5]);
        for (size_t frame = 1; frame < histories.size(); ++frame) {
            core.restore(static_cast<int32_t>(frame), from_chain(nb::cast<nb::list>(histories[frame])),
                         broadcasters.at(frame));
        }
        restore_log(nb::cast<nb::tuple>(state[6]));
    }

    // --- lookups -----------------------------------------------------------------------------

    // Buffer.lookup where the walk answers (ReadLocked): a `answer` (Transform); None
    // for the Python path (a frame to itself, an unknown or invalid name, a failure to word: which
    // `last_failure` then gives, from this one walk). `given_time`: the int `time` was read from, if
    // any, which the answer takes as its stamp where that is `time` (no int made, none freed).
    nb::object lookup_frames(nb::handle target_frame, nb::handle source_frame, int64_t time,
                             nb::handle given_time = nb::handle()) const {
        last_failure_.walked = false;
        if (!plain_name(target_frame) || !plain_name(source_frame)) return nb::none();
        const ReadLocked locked(*lock);
        const int64_t target = id_of(target_frame, false), source = id_of(source_frame, false);
        if (target <= 0 || source <= 0 || target == source) return nb::none();
        tfcore::Pose p;
        const int64_t asked = time;
        Failed why;
        if (!lookup_pose(target, source, time, p, false, &why)) {
            last_failure_ = {true, target, source, asked, why};
            return nb::none();
        }
        const bool given = given_time.is_valid() && PyLong_CheckExact(given_time.ptr()) && time == asked;
        return make_answer(p, given ? nb::borrow(given_time) : nb::steal(PyLong_FromLongLong(time)), target_frame,
                           source_frame);
    }

    // Why this thread's last lookup_frames failed, if it walked from `source` to `target` at `time`.
    std::optional<Failed> last_failure(int64_t target, int64_t source, int64_t time) const {
        const LastFailure& last = last_failure_;
        if (!last.walked || last.target != target || last.source != source || last.time != time) return std::nullopt;
        return last.failure;
    }

    // Buffer.can_transform (ReadLocked).
    bool can_transform_frames(nb::handle target_frame, nb::handle source_frame, int64_t time) const {
        const int same = PyObject_RichCompareBool(target_frame.ptr(), source_frame.ptr(), Py_EQ);
        if (same < 0) throw nb::python_error();
        if (same) return true;
        // tf2's validateFrameId: a name with a leading slash (a frame published as "//b" is
        // stored as "/b") is refused, as lookup refuses it.
        if (!plain_name(target_frame) || !plain_name(source_frame)) return false;
        const ReadLocked locked(*lock);
        const int64_t target = id_of(target_frame, false), source = id_of(source_frame, false);
        return target > 0 && source > 0 && can_transform(target, source, time);
    }

    // The lookup's answer, or None and why it failed, from one walk. `raw`: under ROS 2, the rotation
    // as composed, before tf2::Transform's round trip (lookup_full's).
    std::tuple<std::optional<Found>, Failed> lookup(int64_t target, int64_t source, int64_t time, bool raw) const {
        tfcore::Pose p;
        Failed why = failed(tfcore::Failure::NONE);
        if (!lookup_pose(target, source, time, p, raw, &why)) return {std::nullopt, why};
        return {Found{{p.v.x, p.v.y, p.v.z}, {p.q.x, p.q.y, p.q.z, p.q.w}, time}, why};
    }

    bool can_transform(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        const tfcore::Histories& histories = core.view();
        if (time == 0 && tfcore::latest_common_time(histories, target, source, time) != tfcore::Failure::NONE) {
            return false;
        }
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        tfcore::walk(histories, target, source, time, chain, memo);
        return chain.ending != tfcore::Ending::NO_PATH;
    }

    std::tuple<int64_t, Failed> latest_common_time(int64_t target, int64_t source) const {
        check_frames(target, source);
        int64_t time = 0;
        return {time, failed(tfcore::latest_common_time(core.view(), target, source, time))};
    }

    // The walk at `time` (0: the latest common time): the frames it passes through, from source
    // to target, or why it fails.
    std::tuple<std::vector<int64_t>, Failed> chain(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        const tfcore::Histories& histories = core.view();
        const std::vector<int64_t> none;
        if (time == 0) {
            const tfcore::Failure failure = tfcore::latest_common_time(histories, target, source, time);
            if (failure != tfcore::Failure::NONE) return {none, failed(failure)};
        }
        tfcore::Memo memo;
        tfcore::Chain chain;
        tfcore::walk(histories, target, source, time, chain, memo);
        if (chain.ending != tfcore::Ending::NO_PATH) return {tfcore::frames_of(chain), failed(tfcore::Failure::NONE)};
        if (chain.failure != tfcore::Failure::EXTRAPOLATION) return {none, failed(chain.failure)};
        return {none, failed(chain.failure, tfcore::extrapolation_at(histories[chain.extrapolating_frame], time))};
    }

    void lookup_many(int64_t target, int64_t source, Int64s times, Int64s rows, Column<int64_t> stamps, Values values,
                     Column<bool> valid, bool chained) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        const auto outputs = static_cast<int64_t>(stamps.shape(0));
        if (static_cast<int64_t>(rows.shape(0)) != n || static_cast<int64_t>(values.shape(0)) != outputs ||
            static_cast<int64_t>(valid.shape(0)) != outputs) {
            throw nb::value_error("BufferCore.lookup_many: times and rows, or the outputs, differ in length");
        }
        for (int64_t k = 0; k < n; ++k) {
            if (rows.data()[k] < 0 || rows.data()[k] >= outputs) {
                throw nb::value_error("BufferCore.lookup_many: a row outside the outputs");
            }
        }
        nb::gil_scoped_release unlocked;
        tfcore::lookup_many(core.view(), target, source, times.data(), n,
                            {rows.data(), stamps.data(), values.data(), valid.data()}, chained);
        returned(values, valid, rows.data(), n);
    }

    void lookup_in_parallel(int64_t target, int64_t source, Int64s times, Column<int64_t> stamps, Values values,
                            Column<bool> valid, int threads) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        if (static_cast<int64_t>(stamps.shape(0)) != n || static_cast<int64_t>(values.shape(0)) != n ||
            static_cast<int64_t>(valid.shape(0)) != n) {
            throw nb::value_error("BufferCore.lookup_in_parallel: the times and the outputs differ in length");
        }
        if (threads < 1) throw nb::value_error("BufferCore.lookup_in_parallel: at least one thread");
        nb::gil_scoped_release unlocked;
        tfcore::lookup_any_order(core.view(), target, source, times.data(), n,
                                 {nullptr, stamps.data(), values.data(), valid.data()}, threads);
        returned(values, valid, nullptr, n);
    }

    int chain_takes(int64_t target, int64_t source, Int64s times) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        if (n < 1 || n > tfcore::BLOCK) throw nb::value_error("BufferCore.chain_takes: 1 to BLOCK times");
        return tfcore::chain_takes(core.view(), target, source, times.data(), n);
    }

   private:
    // The refusal log and the duplicates of state()'s `log` into this new core's.
    void restore_log(const nb::tuple& log) {
        tfbuffer::Refusals& r = core.refusals;
        for (const nb::handle name : nb::cast<nb::list>(log[0])) r.frames.intern(nb::cast<std::string>(name));
        r.total = nb::cast<int64_t>(log[1]);
        const auto c = nb::cast<nb::tuple>(log[2]);
        const auto code = nb::cast<Column<const uint8_t>>(c[0]), flags = nb::cast<Column<const uint8_t>>(c[8]);
        const auto parent = nb::cast<Column<const int32_t>>(c[1]), child = nb::cast<Column<const int32_t>>(c[2]);
        const auto stamp = nb::cast<Column<const int64_t>>(c[3]), record_time = nb::cast<Column<const int64_t>>(c[5]);
        const auto authority = nb::cast<Column<const int32_t>>(c[4]);
        const auto sequence = nb::cast<Column<const int64_t>>(c[6]);
        const auto values = nb::cast<Array<const double, nb::shape<-1, 7>>>(c[7]);
        const size_t n = code.shape(0);
        for (const size_t rows : {flags.shape(0), parent.shape(0), child.shape(0), stamp.shape(0), record_time.shape(0),
                                  authority.shape(0), sequence.shape(0), values.shape(0)}) {
            if (rows != n) throw nb::value_error("BufferCore.restore: a refusal log's columns of other lengths");
        }
        for (size_t i = 0; i < n; ++i) {
            r.code.push(code.data()[i]), r.flags.push(flags.data()[i]), r.parent.push(parent.data()[i]);
            r.child.push(child.data()[i]), r.stamp.push(stamp.data()[i]), r.record_time.push(record_time.data()[i]);
            r.authority.push(authority.data()[i]), r.sequence.push(sequence.data()[i]);
            r.values.push(values.data() + 7 * i);
        }
        const auto duplicates = nb::cast<Column<const int64_t>>(log[3]);
        for (size_t i = 0; i < duplicates.shape(0); ++i) core.duplicates.push(duplicates.data()[i]);
    }

    // Each name of `names` (a sequence of str), viewed.
    static std::vector<std::string_view> texts(nb::handle names) {
        const nb::object items = nb::steal(PySequence_Fast(names.ptr(), "BufferCore.insert: names must be a sequence"));
        if (!items.is_valid()) throw nb::python_error();
        const Py_ssize_t n = PySequence_Fast_GET_SIZE(items.ptr());
        std::vector<std::string_view> out(n);
        for (Py_ssize_t i = 0; i < n; ++i) {
            if (!text(PySequence_Fast_GET_ITEM(items.ptr(), i), out[i])) {
                throw nb::type_error("BufferCore.insert: a name that is not a str");
            }
        }
        return out;
    }

   public:
    static std::vector<std::string> names_of(const tfbuffer::Names& names) { return all(names); }

    // A log's column, viewed.
    template <typename T, int64_t WIDTH>
    static nb::object tail(const tfbuffer::Tail<T, WIDTH>& column) {
        return view(column.memory(), column.data(), column.size(), WIDTH > 1 ? WIDTH : 0, WIDTH > 1 ? WIDTH : 0);
    }

   private:
    static std::vector<std::string> all(const tfbuffer::Names& names) {
        std::vector<std::string> out;
        out.reserve(names.size());
        for (size_t id = 0; id < names.size(); ++id) out.push_back(names.name(id));
        return out;
    }

    // Names met lately, of frames and of publishers, remembered each in one of this many slots by its address.
    static constexpr size_t SEEN = 64;

    // The id of the frame (`publisher`: the publisher) named `name`, -1 for none (a frame's name must not start
    // with a slash). Remembered by the name's object: a loop names the same few frames again and again, found
    // so without hashing their text. Frames and publishers are only ever added, so a name's id never changes;
    // held, its object cannot be another's. Under the GIL or the buffer's lock.
    int32_t id_of(nb::handle name, bool publisher) const {
        Remembered& seen = (publisher ? seen_publishers_ : seen_frames_)[(reinterpret_cast<uintptr_t>(name.ptr()) >> 4) % SEEN];
        if (name.ptr() == seen.name.ptr()) return seen.id;
        std::string_view s;
        if (!text(name, s) || (!publisher && !tfbuffer::plain(s))) return -1;
        const int32_t id = (publisher ? core.publishers : core.frames).find(s);
        if (id >= 0) seen = {nb::borrow(name), id};
        return id;
    }

    // A lookup; false where tf2 fails, and why into `why`. `time` 0 becomes the latest common time.
    // ROS 2's tf2 returns the rotation through a matrix (unless `raw`).
    bool lookup_pose(int64_t target, int64_t source, int64_t& time, tfcore::Pose& p, bool raw, Failed* why) const {
        check_frames(target, source);
        const tfcore::Histories& histories = core.view();
        if (time == 0) {
            const tfcore::Failure failure = tfcore::latest_common_time(histories, target, source, time);
            if (failure != tfcore::Failure::NONE) {
                *why = failed(failure);
                return false;
            }
        }
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        if (!tfcore::lookup_at(histories, target, source, time, chain, memo, p)) {
            *why = chain.failure != tfcore::Failure::EXTRAPOLATION
                       ? failed(chain.failure)
                       : failed(chain.failure, tfcore::extrapolation_at(histories[chain.extrapolating_frame], time));
            return false;
        }
        if (core.settings().ros2 && !raw) p.q = tfcore::through_matrix(p.q);
        return true;
    }

    // ROS 2's tf2 returns each answer's rotation through a matrix: the valid `rows` of `values` so.
    void returned(Values& values, const Column<bool>& valid, const int64_t* rows, int64_t n) const {
        if (!core.settings().ros2) return;
        std::vector<uint8_t> done(rows != nullptr ? values.shape(0) : 0);  // rows given more than once: once
        for (int64_t k = 0; k < n; ++k) {
            const int64_t row = rows != nullptr ? rows[k] : k;
            if (!valid.data()[row] || (rows != nullptr && std::exchange(done[row], 1))) continue;
            tfcore::through_matrix_all(values.data() + 7 * row + 3, 1, 7);
        }
    }

    // A new `answer` (Transform), its fields set as its __init__ sets them through their slots' setters
    // (its frozen __setattr__ refuses), without the Python frame of that __init__: written in its slots
    // (the object comes zeroed, nothing to let go), else through the setters. Where the last answer is
    // held by nothing but this core (a loop that lets each answer go before the next lookup), that one is
    // written over instead: no one can see it change, and its object, tuples and floats are not freed and
    // made again (~950 of a robot lookup's ~9,700 instructions).
    nb::object make_answer(const tfcore::Pose& p, nb::object stamp, nb::handle target_frame,
                           nb::handle source_frame) const {
        if (in_slots_ && kept_answer_.is_valid() && Py_REFCNT(kept_answer_.ptr()) == 1) {
            write_over(kept_answer_.ptr(), p, std::move(stamp), target_frame, source_frame);
            return kept_answer_;
        }
        auto* type = reinterpret_cast<PyTypeObject*>(answer_.ptr());
        const nb::object answer = nb::steal(type->tp_alloc(type, 0));
        if (!answer.is_valid()) throw nb::python_error();
        const auto put = [&](Field field, nb::object value) {
            if (!value.is_valid()) throw nb::python_error();
            if (offsets_[field] >= 0) {
                *slot(answer.ptr(), field) = value.release().ptr();
                return;
            }
            PyObject* descriptor = fields_[field].ptr();
            if (Py_TYPE(descriptor)->tp_descr_set(descriptor, answer.ptr(), value.ptr()) != 0) throw nb::python_error();
        };
        put(TRANSLATION, nb::steal(floats({p.v.x, p.v.y, p.v.z})));
        put(ROTATION, nb::steal(floats({p.q.x, p.q.y, p.q.z, p.q.w})));
        put(STAMP, std::move(stamp));
        put(FRAME_ID, nb::borrow(target_frame));
        put(CHILD_FRAME_ID, nb::borrow(source_frame));
        if (in_slots_) kept_answer_ = answer;
        return answer;
    }

    // Where `answer`'s `field` lies (its slot).
    PyObject** slot(PyObject* answer, Field field) const {
        return reinterpret_cast<PyObject**>(reinterpret_cast<char*>(answer) + offsets_[field]);
    }

    // `value` into `*at`, letting go of what was there (after: letting go runs no code that could read it).
    static void replace(PyObject** at, PyObject* value) {
        if (value == nullptr) throw nb::python_error();
        PyObject* old = *at;
        *at = value;
        Py_XDECREF(old);
    }

    // The answer `answer`, which only this core holds, made the one make_answer would make. Its tuples and
    // their floats that nothing else holds either are written in place, every other one made anew.
    void write_over(PyObject* answer, const tfcore::Pose& p, nb::object stamp, nb::handle target_frame,
                    nb::handle source_frame) const {
        write_floats(slot(answer, TRANSLATION), {p.v.x, p.v.y, p.v.z});
        write_floats(slot(answer, ROTATION), {p.q.x, p.q.y, p.q.z, p.q.w});
        replace(slot(answer, STAMP), stamp.release().ptr());
        replace(slot(answer, FRAME_ID), nb::borrow(target_frame).release().ptr());
        replace(slot(answer, CHILD_FRAME_ID), nb::borrow(source_frame).release().ptr());
    }

    // The tuple of floats at `at` made to hold `values`.
    static void write_floats(PyObject** at, std::initializer_list<double> values) {
        PyObject* tuple = *at;
        const auto n = static_cast<Py_ssize_t>(values.size());
        if (tuple == nullptr || !PyTuple_CheckExact(tuple) || Py_REFCNT(tuple) != 1 || PyTuple_GET_SIZE(tuple) != n) {
            replace(at, floats(values));
            return;
        }
        Py_ssize_t i = 0;
        for (const double value : values) {
            PyObject* number = PyTuple_GET_ITEM(tuple, i);
            if (PyFloat_CheckExact(number) && Py_REFCNT(number) == 1) {
                reinterpret_cast<PyFloatObject*>(number)->ob_fval = value;
            } else {
                replace(&reinterpret_cast<PyTupleObject*>(tuple)->ob_item[i], PyFloat_FromDouble(value));
            }
            ++i;
        }
    }

    // A new tuple of floats, or nullptr with the error set.
    static PyObject* floats(std::initializer_list<double> values) {
        PyObject* tuple = PyTuple_New(static_cast<Py_ssize_t>(values.size()));
        Py_ssize_t i = 0;
        for (const double value : values) {
            if (tuple == nullptr) return nullptr;
            PyObject* number = PyFloat_FromDouble(value);
            if (number == nullptr) Py_CLEAR(tuple);
            else PyTuple_SET_ITEM(tuple, i++, number);
        }
        return tuple;
    }

    // `transform`'s field (the answer's `index`-th) read from its slot where it is an answer (what
    // Python's attribute lookup would find, minus the search), else as an attribute.
    nb::object field(nb::handle transform, int index, const nb::str& name) const {
        if (Py_TYPE(transform.ptr()) != reinterpret_cast<PyTypeObject*>(answer_.ptr())) {
            return attribute(transform, name);
        }
        if (offsets_[index] >= 0) {  // unset: the batch path reads it again, and says what is wrong
            return nb::borrow(*reinterpret_cast<PyObject**>(reinterpret_cast<char*>(transform.ptr()) + offsets_[index]));
        }
        PyObject* slot = fields_[index].ptr();
        return nb::steal(Py_TYPE(slot)->tp_descr_get(slot, transform.ptr(), answer_.ptr()));
    }

    void check_frames(int64_t target, int64_t source) const {
        const auto frames = static_cast<int64_t>(core.frames.size());
        if (target < 0 || source < 0 || target >= frames || source >= frames) {
            throw nb::value_error("BufferCore: a frame id outside the buffer's frames");
        }
    }

    Names names_;
    nb::object answer_;
    struct Remembered {
        nb::object name;
        int32_t id = -1;
    };
    mutable Remembered seen_frames_[SEEN], seen_publishers_[SEEN];  // id_of's
    // A failed lookup_frames' walk, kept for the Python path that words it (per thread: another
    // thread's lookups come between).
    struct LastFailure {
        bool walked = false;
        int64_t target = 0, source = 0, time = 0;
        Failed failure;
    };
    static thread_local LastFailure last_failure_;
    nb::object fields_[5];  // the answer's fields' slot descriptors, in FIELD order
    Py_ssize_t offsets_[5];  // ... and where their values lie in an answer (slot_offset)
    // Whether every field is a slot, and the last answer kept to be written over (make_answer): not where
    // threads run Python at once (a free-threaded build), where a count of 1 could change under it.
#ifdef Py_GIL_DISABLED
    static constexpr bool in_slots_ = false;
#else
    bool in_slots_ = false;
#endif
    mutable nb::object kept_answer_;
};

thread_local BufferCore::LastFailure BufferCore::last_failure_;

// Buffer.lookup, Buffer.can_transform and Buffer.set_transform, methods in C (the module's `buffer_lookup`,
// `buffer_can_transform`, `buffer_set_transform`, which Buffer's class takes): called as any method,
// (target_frame, source_frame, time=0) or (transform, authority="", static=False, record_time=0), keywords
// too, without a Python frame or the binding's dispatch (argument matching, overloads, the instance found by
// type: together a tenth of a lookup, a third of a set_transform). Each finds the buffer's core as its
// `_core`; a lookup the walk does not answer goes to Python, `_lookup_by_ids` (which words tf2's error from
// this walk's failure), and a sample that set_transform's common case does not store goes to the batch
// path, `_set_transform_by_batch`.
struct MethodNames {
    PyObject *core, *by_ids, *by_batch, *empty, *zero;
    PyObject* frames_and_time[3];  // lookup's and can_transform's arguments
    PyObject* transform_and_how[4];  // set_transform's
};
MethodNames method_names;  // made at the module's load
PyTypeObject* core_type = nullptr;

// A method's arguments (named `names`, the first `required` of them required) from a vectorcall's, by
// position or keyword, into `out` (null where not given); false with Python's TypeError set where they do
// not match.
template <int N>
bool arguments(const char* method, PyObject* const* args, Py_ssize_t n, PyObject* kwnames, PyObject* const (&names)[N],
               int required, PyObject* (&out)[N]) {
    for (PyObject*& given : out) given = nullptr;
    if (n > N) {
        PyErr_Format(PyExc_TypeError, "%s() takes from %d to %d positional arguments but %zd were given", method,
                     required, N, n);
        return false;
    }
    for (Py_ssize_t i = 0; i < n; ++i) out[i] = args[i];
    const Py_ssize_t keywords = kwnames == nullptr ? 0 : PyTuple_GET_SIZE(kwnames);
    for (Py_ssize_t k = 0; k < keywords; ++k) {
        PyObject* key = PyTuple_GET_ITEM(kwnames, k);
        int which = 0;
        while (which < N && PyUnicode_Compare(key, names[which]) != 0) ++which;
        if (which == N) {
            PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument '%U'", method, key);
            return false;
        }
        if (out[which] != nullptr) {
            PyErr_Format(PyExc_TypeError, "%s() got multiple values for argument '%U'", method, key);
            return false;
        }
        out[which] = args[n + k];
    }
    for (int which = 0; which < required; ++which) {
        if (out[which] == nullptr) {
            PyErr_Format(PyExc_TypeError, "%s() missing required argument '%U'", method, names[which]);
            return false;
        }
    }
    return true;
}

// A method's (target_frame, source_frame, time=0) from a vectorcall's arguments, into `out`; false with
// Python's TypeError set where they do not match.
bool frames_and_time(const char* method, PyObject* const* args, Py_ssize_t n, PyObject* kwnames,
                     PyObject* (&out)[3], int64_t& time) {
    if (!arguments(method, args, n, kwnames, method_names.frames_and_time, 2, out)) return false;
    time = 0;
    if (out[2] != nullptr && !nb::try_cast(nb::handle(out[2]), time)) {
        PyErr_Format(PyExc_TypeError, "%s(): time must be an int (nanoseconds), not %s", method,
                     Py_TYPE(out[2])->tp_name);
        return false;
    }
    return true;
}

// Where instances of the class last seen keep `_core` (-1: not in a slot), while that class is unchanged
// (its version tag, which any change of the class's attributes renews).
// One, read and written under the GIL; per thread where there is none (a free-threaded build runs them at
// once). Not per thread under the GIL: a thread_local of a loaded module is a call (__tls_get_addr) at
// every read, ~50 instructions of a set_transform. The class is held while it is remembered.
struct CoreSlot {
    PyTypeObject* type = nullptr;
    unsigned int version = 0;
    Py_ssize_t offset = -1;
};
#ifdef Py_GIL_DISABLED
thread_local CoreSlot core_slot;
#else
CoreSlot core_slot;
#endif

// Whether `type` is core_slot's, unchanged.
bool known_class(PyTypeObject* type) {
    return type == core_slot.type && PyType_HasFeature(type, Py_TPFLAGS_VALID_VERSION_TAG) &&
           type->tp_version_tag == core_slot.version;
}

// The core of `buffer` (its `_core`: read from its slot where its class keeps it in one, as Buffer does,
// else looked up), or null with the error set.
BufferCore* core_of(PyObject* buffer, nb::object& held) {
    PyTypeObject* type = Py_TYPE(buffer);
    if (!known_class(type)) {
        const nb::object found = nb::steal(PyObject_GetAttr(reinterpret_cast<PyObject*>(type), method_names.core));
        PyErr_Clear();
        PyTypeObject* const forgotten = core_slot.type;
        Py_INCREF(reinterpret_cast<PyObject*>(type));
        core_slot = {type, type->tp_version_tag, found.is_valid() ? slot_offset(found.ptr()) : -1};
        Py_XDECREF(reinterpret_cast<PyObject*>(forgotten));
    }
    PyObject* slot = known_class(type) && core_slot.offset >= 0
                         ? *reinterpret_cast<PyObject**>(reinterpret_cast<char*>(buffer) + core_slot.offset)
                         : nullptr;
    held = slot != nullptr ? nb::borrow(slot) : nb::steal(PyObject_GetAttr(buffer, method_names.core));
    if (!held.is_valid()) return nullptr;
    if (Py_TYPE(held.ptr()) != core_type) {
        PyErr_SetString(PyExc_TypeError, "a Buffer's _core must be a BufferCore");
        return nullptr;
    }
    return nb::inst_ptr<BufferCore>(held);
}

// The C++ exceptions of a call as Python's.
void raised() noexcept {
    try {
        throw;
    } catch (nb::python_error& e) {
        e.restore();
    } catch (const nb::builtin_exception& e) {
        PyObject* kind = e.type() == nb::exception_type::type_error      ? PyExc_TypeError
                         : e.type() == nb::exception_type::runtime_error ? PyExc_RuntimeError
                                                                         : PyExc_ValueError;
        PyErr_SetString(kind, e.what());
    } catch (const std::exception& e) {
        PyErr_SetString(PyExc_RuntimeError, e.what());
    }
}

PyObject* buffer_lookup(PyObject* buffer, PyObject* const* args, Py_ssize_t n, PyObject* kwnames) noexcept {
    try {
        PyObject* given[3];
        int64_t time = 0;
        nb::object held;
        if (!frames_and_time("lookup", args, n, kwnames, given, time)) return nullptr;
        BufferCore* core = core_of(buffer, held);
        if (core == nullptr) return nullptr;
        nb::object found = core->lookup_frames(given[0], given[1], time, given[2]);
        if (!found.is_none()) return found.release().ptr();
        PyObject* call[4] = {buffer, given[0], given[1], nullptr};
        const nb::object at = nb::int_(time);
        call[3] = at.ptr();
        return PyObject_VectorcallMethod(method_names.by_ids, call, 4, nullptr);
    } catch (...) {
        raised();
    }
    return nullptr;
}

PyObject* buffer_can_transform(PyObject* buffer, PyObject* const* args, Py_ssize_t n, PyObject* kwnames) noexcept {
    try {
        PyObject* given[3];
        int64_t time = 0;
        nb::object held;
        if (!frames_and_time("can_transform", args, n, kwnames, given, time)) return nullptr;
        BufferCore* core = core_of(buffer, held);
        if (core == nullptr) return nullptr;
        return Py_NewRef(core->can_transform_frames(given[0], given[1], time) ? Py_True : Py_False);
    } catch (...) {
        raised();
    }
    return nullptr;
}

PyObject* buffer_set_transform(PyObject* buffer, PyObject* const* args, Py_ssize_t n, PyObject* kwnames) noexcept {
    try {
        PyObject* given[4];
        if (!arguments("set_transform", args, n, kwnames, method_names.transform_and_how, 1, given)) return nullptr;
        PyObject* const defaults[4] = {nullptr, method_names.empty, Py_False, method_names.zero};
        for (int i = 1; i < 4; ++i) given[i] = given[i] != nullptr ? given[i] : defaults[i];
        nb::object held;
        BufferCore* core = core_of(buffer, held);
        if (core == nullptr) return nullptr;
        if (core->set_transform(given[0], given[1], given[2], given[3])) return Py_NewRef(Py_True);
        PyObject* call[5] = {buffer, given[0], given[1], given[2], given[3]};
        return PyObject_VectorcallMethod(method_names.by_batch, call, 5, nullptr);
    } catch (...) {
        raised();
    }
    return nullptr;
}

// The buffer's lock taken and let go in `with` (and acquire, release) as plain C methods: `with` looks
// them up on every entry, and the binding's dispatch cost as much as a failed lookup's walk.
PyObject* lock_acquire(PyObject* lock, PyObject*) noexcept {
    try {
        nb::inst_ptr<Lock>(lock)->acquire();
        return Py_NewRef(Py_True);
    } catch (...) {
        raised();
    }
    return nullptr;
}

PyObject* lock_release(PyObject* lock, PyObject* const*, Py_ssize_t) noexcept {
    try {
        nb::inst_ptr<Lock>(lock)->release();
        return Py_NewRef(Py_None);
    } catch (...) {
        raised();
    }
    return nullptr;
}

PyMethodDef lock_methods[] = {
    {"acquire", lock_acquire, METH_NOARGS, "acquire($self, /)\n--\n\nTaken by this thread (again, if it holds it)."},
    {"__enter__", lock_acquire, METH_NOARGS, "__enter__($self, /)\n--\n\n``acquire``."},
    {"release", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(lock_release)), METH_FASTCALL,
     "release($self, /)\n--\n\nLet go once; RuntimeError where this thread does not hold it."},
    {"__exit__", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(lock_release)), METH_FASTCALL,
     "__exit__($self, kind, error, traceback, /)\n--\n\n``release``."},
};

PyCFunction fastcall(PyObject* (*f)(PyObject*, PyObject* const*, Py_ssize_t, PyObject*)) {
    return reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(f));
}

PyMethodDef buffer_lookup_def = {
    "lookup", fastcall(buffer_lookup), METH_FASTCALL | METH_KEYWORDS,
    "lookup($self, target_frame, source_frame, time=0)\n--\n\n"
    "The transform taking ``source_frame`` data into ``target_frame`` at ``time`` (ns).\n\n"
    "Time 0 means the latest time all edges of the chain share. Raises tf2's errors with tf2's messages:\n"
    "``UnknownFrameError``, ``ConnectivityError``, ``ExtrapolationError``, ``InvalidArgumentError``."};
PyMethodDef buffer_can_transform_def = {
    "can_transform", fastcall(buffer_can_transform), METH_FASTCALL | METH_KEYWORDS,
    "can_transform($self, target_frame, source_frame, time=0)\n--\n\n"
    "Whether ``lookup`` would succeed (tf2's ``canTransform``)."};
PyMethodDef buffer_set_transform_def = {
    "set_transform", fastcall(buffer_set_transform), METH_FASTCALL | METH_KEYWORDS,
    "set_transform($self, transform, authority='', static=False, record_time=0)\n--\n\n"
    "Add one transform as tf2's ``setTransform`` does; False if it was refused (ROS 2's tf2 accepts a\n"
    "sample identical to one it holds, and stores it once)."};

}  // namespace

NB_MODULE(_kernels, m) {
    m.doc() = "The buffer's state and tf2's walk over its edge histories, compiled.";
    // A live command ends with its receiving threads still holding buffers: nanobind would list them
    // as leaks on the user's terminal at exit. TFX_DEBUG=1 keeps the report, for developers.
    if (std::getenv("TFX_DEBUG") == nullptr) nb::set_leak_warnings(false);
    m.attr("BLOCK") = tfcore::BLOCK;
    m.attr("ROW_BYTES") = tfbuffer::ROW_BYTES;
    m.attr("LARGE_PAGES_UP_TO") = tfbuffer::LARGE_PAGES_UP_TO;
    // The codes Python reads, defined once here: why a walk failed (walk.Failure's first item), why a
    // history had no sample (history.Extrapolation.kind), a row's flags, and insert's refusals by number.
    m.attr("NO_FAILURE") = static_cast<int>(tfcore::Failure::NONE);
    m.attr("LOOP") = static_cast<int>(tfcore::Failure::LOOP);
    m.attr("UNCONNECTED") = static_cast<int>(tfcore::Failure::UNCONNECTED);
    m.attr("EXTRAPOLATION") = static_cast<int>(tfcore::Failure::EXTRAPOLATION);
    m.attr("NO_DATA") = static_cast<int>(tfcore::NO_DATA);
    m.attr("ONLY_ONE") = static_cast<int>(tfcore::ONLY_ONE);
    m.attr("FUTURE") = static_cast<int>(tfcore::FUTURE);
    m.attr("PAST") = static_cast<int>(tfcore::PAST);
    m.attr("FROM_STATIC_TOPIC") = tfbuffer::FROM_STATIC_TOPIC;
    m.attr("PARENT_HAD_SLASH") = tfbuffer::PARENT_HAD_SLASH;
    m.attr("CHILD_HAD_SLASH") = tfbuffer::CHILD_HAD_SLASH;
    m.attr("NO_PARENT") = 0;  // tf2's id of no frame: Names' reserved first
    m.attr("LIVE_REJECTIONS_KEPT") = tfbuffer::LIVE_REJECTIONS_KEPT;
    nb::list refusals;
    for (const char* name : tfinsert::REFUSAL_NAMES) refusals.append(name);
    m.attr("REFUSALS") = nb::tuple(refusals);

    using tfbuffer::Store;
    nb::class_<Store>(m, "EdgeHistory")
        .def_ro("static", &Store::is_static)
        .def_ro("replaced", &Store::replaced)
        .def("__len__", &Store::size)
        .def_prop_ro("stamps", [](const Store& s) { return rows_of(s, s.block.stamps); })
        .def_prop_ro("values", [](const Store& s) { return values_of(s); })
        .def_prop_ro("translations", [](const Store& s) { return values_of(s, 0, 3); })
        .def_prop_ro("rotations", [](const Store& s) { return values_of(s, 3, 4); })
        .def_prop_ro("parents", [](const Store& s) { return rows_of(s, s.block.parents); })
        .def_prop_ro("authorities", [](const Store& s) { return rows_of(s, s.block.authorities); })
        .def_prop_ro("record_times", [](const Store& s) { return rows_of(s, s.block.record_times); })
        .def_prop_ro("sequence", [](const Store& s) { return rows_of(s, s.block.sequence); })
        .def_prop_ro("flags", [](const Store& s) { return rows_of(s, s.block.flags); })
        .def_prop_ro("latest_stamp", &Store::latest_stamp)
        .def_prop_ro("oldest_stamp", &Store::oldest_stamp)
        .def_prop_ro("latest_parent", &Store::latest_parent)
        .def("__getstate__", [](const Store& s) { return chain_of(&s); })
        .def("__setstate__", [](Store& s, const nb::list& chain) { new (&s) Store(std::move(*from_chain(chain))); })
        .def("parent_at", [](const Store& s, int64_t time) -> std::optional<int64_t> {
            const int64_t parent = s.parent_at(time);
            return parent < 0 ? std::nullopt : std::optional<int64_t>(parent);
        }, "time"_a);

    auto lock_class = nb::class_<Lock>(m, "BufferLock")
                          .def("wait", &Lock::wait, "timeout"_a)
                          .def("notify_all", &Lock::notify_all)
                          .def("owned", &Lock::owned);
    for (PyMethodDef& method : lock_methods) {
        auto* type = reinterpret_cast<PyTypeObject*>(lock_class.ptr());
        nb::setattr(lock_class, method.ml_name, nb::steal(PyDescr_NewMethod(type, &method)));
    }

    nb::class_<tfbuffer::Spare>(m, "Spare")
        .def(nb::init<>())
        .def("ahead", &tfbuffer::Spare::ahead, "rows"_a)
        .def_prop_ro("brought", &tfbuffer::Spare::brought);

    nb::class_<BufferCore>(m, "BufferCore")
        .def(nb::init<nb::handle, std::optional<int64_t>, bool, double, int64_t>(), "answer"_a, "cache_time"_a.none(),
             "ros2"_a, "tolerance"_a, "large_pages_up_to"_a)
        .def_ro("lock", &BufferCore::lock)
        .def_prop_rw(
            "arrivals", [](const BufferCore& b) { return b.core.arrivals; },
            [](BufferCore& b, int64_t arrivals) { b.core.arrivals = arrivals; })
        .def("set_transform", &BufferCore::set_transform, "transform"_a, "authority"_a, "static"_a, "record_time"_a)
        .def("insert", &BufferCore::insert, "batch"_a)
        .def("reserve", &BufferCore::reserve, "rows"_a, "spare"_a.none() = nb::none())
        .def("clear", &BufferCore::clear)
        .def("refusals", &BufferCore::refusals)
        .def("refused_frame_names", [](const BufferCore& b) { return BufferCore::names_of(b.core.refusals.frames); })
        .def_prop_ro("refusal_total", [](const BufferCore& b) { return b.core.refusals.total; })
        .def_prop_ro("refusals_kept", [](const BufferCore& b) { return b.core.refusals.code.size(); })
        .def("duplicates", [](const BufferCore& b) { return BufferCore::tail(b.core.duplicates); })
        .def("frame_id", &BufferCore::frame_id, "name"_a)
        .def("frame_name", [](const BufferCore& b, int64_t id) { return b.core.frames.name(id); }, "frame_id"_a)
        .def("frame_names", &BufferCore::frame_names)
        .def("publisher_names", &BufferCore::publisher_names)
        .def_prop_ro("publisher_count", [](const BufferCore& b) { return b.core.publishers.size(); })
        .def("history", [](const BufferCore& b, int64_t frame) { return b.core.store(frame); }, "frame_id"_a)
        .def("broadcasters", [](const BufferCore& b) { return b.core.broadcasters(); })
        .def("state", &BufferCore::state)
        .def("restore", &BufferCore::restore, "state"_a)
        .def(
            "lookup_frames",
            [](const BufferCore& core, nb::handle target_frame, nb::handle source_frame, int64_t time) {
                return core.lookup_frames(target_frame, source_frame, time);
            },
            "target_frame"_a, "source_frame"_a, "time"_a)
        .def("can_transform_frames", &BufferCore::can_transform_frames, "target_frame"_a, "source_frame"_a, "time"_a)
        .def("last_failure", &BufferCore::last_failure, "target"_a, "source"_a, "time"_a)
        .def("lookup", &BufferCore::lookup, "target"_a, "source"_a, "time"_a, "raw"_a = false)
        .def("can_transform", &BufferCore::can_transform, "target"_a, "source"_a, "time"_a)
        .def("latest_common_time", &BufferCore::latest_common_time, "target"_a, "source"_a)
        .def("chain", &BufferCore::chain, "target"_a, "source"_a, "time"_a)
        .def("lookup_many", &BufferCore::lookup_many, "target"_a, "source"_a, "times"_a, "rows"_a, "stamps"_a,
             "values"_a, "valid"_a, "chained"_a = true)
        .def("lookup_in_parallel", &BufferCore::lookup_in_parallel, "target"_a, "source"_a, "times"_a, "stamps"_a,
             "values"_a, "valid"_a, "threads"_a)
        .def("chain_takes", &BufferCore::chain_takes, "target"_a, "source"_a, "times"_a);
    core_type = reinterpret_cast<PyTypeObject*>(nb::type<BufferCore>().ptr());
    const auto name = [](const char* text) { return PyUnicode_InternFromString(text); };
    method_names = {name("_core"),
                    name("_lookup_by_ids"),
                    name("_set_transform_by_batch"),
                    name(""),
                    PyLong_FromLong(0),
                    {name("target_frame"), name("source_frame"), name("time")},
                    {name("transform"), name("authority"), name("static"), name("record_time")}};
    // Descriptors of methods of any object (a Buffer's class takes them as its own).
    m.attr("buffer_lookup") = nb::steal(PyDescr_NewMethod(&PyBaseObject_Type, &buffer_lookup_def));
    m.attr("buffer_can_transform") = nb::steal(PyDescr_NewMethod(&PyBaseObject_Type, &buffer_can_transform_def));
    m.attr("buffer_set_transform") = nb::steal(PyDescr_NewMethod(&PyBaseObject_Type, &buffer_set_transform_def));

    m.def(
        "through_matrix",
        [](Array<double, nb::shape<-1, 4>> rotations) {
            tfcore::through_matrix_rows(rotations.data(), rotations.data(), static_cast<int64_t>(rotations.shape(0)));
        },
        "rotations"_a, "Rotations (N, 4), in place, as they come back from ROS 2's tf2::Transform.");
}
