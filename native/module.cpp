// tftools.core._kernels: the compiled lookups over the buffer's edge histories (walk.hpp, blocks.hpp).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <structmember.h>

#include <cstdlib>
#include <initializer_list>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "insert.hpp"
#include "many.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T, typename... Shape>
using Array = nb::ndarray<T, nb::c_contig, nb::device::cpu, Shape...>;
using Int64s = Array<const int64_t, nb::ndim<1>>;

// A lookup's answer as Transform takes it: (tx, ty, tz), (qx, qy, qz, qw) and the time it was made at.
using Found = std::tuple<std::tuple<double, double, double>, std::tuple<double, double, double, double>, int64_t>;

// Why a walk failed, as tftools.core.walk reads it: what failed (tfcore::Failure), and for an
// extrapolation the gap's kind, time and stamp (history.Gap).
using Failed = std::tuple<int, int64_t, int64_t, int64_t>;

Failed failed(tfcore::Failure failure, const tfcore::Gap& gap = {}) {
    return {static_cast<int>(failure), gap.kind, gap.time, gap.stamp};
}

// history.FROM_STATIC_TOPIC: the flag of a sample from /tf_static.
constexpr uint8_t FROM_STATIC_TOPIC = 1;

// `object.name`, or an invalid object with the error set.
nb::object attribute(nb::handle object, const nb::str& name) {
    return nb::steal(PyObject_GetAttr(object.ptr(), name.ptr()));
}

// The answer's (Transform's) fields, in its order.
enum Field { TRANSLATION, ROTATION, STAMP, FRAME_ID, CHILD_FRAME_ID };

// The attributes the table reads and sets, their names made once.
struct Names {
    nb::str translation{"translation"}, rotation{"rotation"}, stamp{"stamp"}, frame_id{"frame_id"},
        child_frame_id{"child_frame_id"}, storage{"storage"}, is_static{"static"}, start{"_start"}, end{"_end"},
        prune{"prune"}, grow{"grow"};
};

// A lock's acquire and release, found once on its type: a call then skips looking them up by name.
struct LockMethods {
    nb::object acquire, release;

    explicit LockMethods(nb::handle lock)
        : acquire(nb::getattr(lock.type(), "acquire")), release(nb::getattr(lock.type(), "release")) {}
};

// `method(lock)`, or nullptr with the error set.
PyObject* call(const nb::object& method, nb::handle lock) {
    PyObject* self = lock.ptr();
    return PyObject_Vectorcall(method.ptr(), &self, 1, nullptr);
}

// `lock` (the buffer's threading.RLock) held for a scope: acquired as Python's `with` acquires it
// (letting go of the GIL while it waits).
class Locked {
   public:
    Locked(nb::handle lock, const LockMethods& methods) : lock_(lock), methods_(methods) {
        PyObject* taken = call(methods_.acquire, lock_);
        if (taken == nullptr) throw nb::python_error();
        Py_DECREF(taken);
    }
    Locked(const Locked&) = delete;
    Locked& operator=(const Locked&) = delete;
    ~Locked() {
        PyObject* released = call(methods_.release, lock_);
        if (released == nullptr) PyErr_WriteUnraisable(lock_.ptr());  // cannot happen: this thread holds it
        Py_XDECREF(released);
    }

   private:
    nb::handle lock_;
    const LockMethods& methods_;
};

// An int in `dict` under `key` (a frame's or a publisher's id); 0 where it has none.
int64_t id_in(nb::handle dict, nb::handle key) {
    PyObject* value = PyDict_GetItemWithError(dict.ptr(), key.ptr());
    if (value == nullptr) {
        PyErr_Clear();  // an unhashable key: the caller's Python path says what is wrong
        return 0;
    }
    return PyLong_AsLongLong(value);
}

// A frame name as tf2's validateFrameId takes it as is: a str, not empty, without a leading slash.
bool plain_name(nb::handle name) {
    return PyUnicode_Check(name.ptr()) && PyUnicode_GET_LENGTH(name.ptr()) > 0 &&
           PyUnicode_READ_CHAR(name.ptr(), 0) != '/';
}

// `count` numbers of a tuple or list of floats or ints into `out`; false for anything else.
bool read_numbers(nb::handle sequence, Py_ssize_t count, double* out) {
    PyObject* s = sequence.ptr();
    const bool tuple = PyTuple_Check(s);
    if (!(tuple || PyList_Check(s)) || Py_SIZE(s) != count) return false;
    for (Py_ssize_t i = 0; i < count; ++i) {
        PyObject* item = tuple ? PyTuple_GET_ITEM(s, i) : PyList_GET_ITEM(s, i);
        if (PyFloat_Check(item)) {
            out[i] = PyFloat_AS_DOUBLE(item);
        } else if (PyLong_Check(item)) {
            out[i] = PyLong_AsDouble(item);
            if (out[i] == -1.0 && PyErr_Occurred()) {
                PyErr_Clear();
                return false;
            }
        } else {
            return false;
        }
    }
    return true;
}

// An int as int64; false for anything else or out of range.
bool read_int(nb::handle number, int64_t& out) {
    if (!PyLong_Check(number.ptr())) return false;
    int overflow = 0;
    out = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
    if (overflow || (out == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        return false;
    }
    return true;
}

template <typename T>
using Column = Array<T, nb::ndim<1>>;

// One EdgeHistory as the table holds it: the object (whose bounds an append in place moves)
// and its columns (EdgeHistory.storage()), held so that they outlive its row.
struct Held {
    nb::object history;
    Column<int64_t> stamps;
    Array<double, nb::shape<-1, 7>> values;
    Column<int32_t> parents, authorities;
    Column<int64_t> record_times, sequence;
    Column<uint8_t> flags;
};

// x - y - 1 within int64 (EdgeHistory.prune's bound, past which Python's ints would go).
int64_t below(int64_t x, int64_t y) {
    int64_t difference = 0;
    if (__builtin_sub_overflow(x, y, &difference)) return y > 0 ? INT64_MIN : INT64_MAX;
    return difference == INT64_MIN ? difference : difference - 1;
}

class EdgeTable {
   public:
    EdgeTable(nb::object lock, nb::dict frames, nb::handle answer, nb::dict authorities, nb::dict broadcasters,
              nb::dict reserved, std::optional<int64_t> cache_time, bool ros2, double tolerance)
        : lock_(std::move(lock)),
          lock_methods_(lock_),
          frames_(std::move(frames)),
          authorities_(std::move(authorities)),
          broadcasters_(std::move(broadcasters)),
          reserved_(std::move(reserved)),
          cache_time_(cache_time),
          ros2_(ros2),
          tolerance_(tolerance) {
        if (!PyType_Check(answer.ptr())) throw nb::type_error("EdgeTable: answer must be a type");
        answer_ = nb::borrow(answer);
        const nb::object slots = nb::getattr(answer, "__dict__");
        const nb::str* fields[] = {&names_.translation, &names_.rotation, &names_.stamp, &names_.frame_id,
                                   &names_.child_frame_id};
        for (int i = 0; i < 5; ++i) {
            fields_[i] = slots[*fields[i]];
            if (Py_TYPE(fields_[i].ptr()) != &PyMemberDescr_Type ||
                reinterpret_cast<PyMemberDescrObject*>(fields_[i].ptr())->d_member->type != T_OBJECT_EX) {
                throw nb::type_error("EdgeTable: answer's fields must be slots");
            }
            offsets_[i] = reinterpret_cast<PyMemberDescrObject*>(fields_[i].ptr())->d_member->offset;
        }
    }

    // Describe `history` (an EdgeHistory, or None), the history of `frame`, as it is now.
    void update(int64_t frame, nb::handle history) {
        if (frame < 0) throw nb::value_error("EdgeTable.update: a negative frame id");
        if (frame >= static_cast<int64_t>(histories_.size())) {
            histories_.resize(frame + 1);
            held_.resize(frame + 1);
        }
        if (history.is_none()) {
            histories_[frame] = {};
            held_[frame] = {};
            return;
        }
        const nb::tuple storage = nb::cast<nb::tuple>(attribute(history, names_.storage)());
        Held held{nb::borrow(history),
                  nb::cast<Column<int64_t>>(storage[0]),
                  nb::cast<Array<double, nb::shape<-1, 7>>>(storage[1]),
                  nb::cast<Column<int32_t>>(storage[2]),
                  nb::cast<Column<int32_t>>(storage[3]),
                  nb::cast<Column<int64_t>>(storage[4]),
                  nb::cast<Column<int64_t>>(storage[5]),
                  nb::cast<Column<uint8_t>>(storage[6])};
        const int64_t start = nb::cast<int64_t>(storage[7]), end = nb::cast<int64_t>(storage[8]);
        const int64_t capacity = capacity_of(held);
        if (start < 0 || start > end || end > capacity) {
            throw nb::value_error("EdgeTable.update: rows outside the history's arrays");
        }
        const bool is_static = nb::cast<bool>(attribute(history, names_.is_static));
        histories_[frame] = {true, is_static, start, end, held.stamps.data(), held.values.data(), held.parents.data(),
                             ros2_};
        held_[frame] = std::move(held);
    }

    // Buffer.set_transform's common case, stored in place under the buffer's lock: see _kernels.pyi.
    bool set_transform(nb::handle transform, nb::handle authority, nb::handle is_static, nb::handle record_time) {
        const Locked locked(lock_, lock_methods_);
        if (!append(transform, authority, is_static, record_time)) return false;
        ++arrivals;
        return true;
    }

    // Buffer.lookup where the walk answers, under the buffer's lock: a `answer` (Transform); None
    // for the Python path (a frame to itself, an unknown or invalid name, a failure to word).
    nb::object lookup_frames(nb::handle target_frame, nb::handle source_frame, int64_t time) const {
        if (!plain_name(target_frame) || !plain_name(source_frame)) return nb::none();
        const Locked locked(lock_, lock_methods_);
        const int64_t target = frame_id(target_frame, 0), source = frame_id(source_frame, 1);
        if (target <= 0 || source <= 0 || target == source) return nb::none();
        tfcore::Pose p;
        if (!lookup_pose(target, source, time, p)) return nb::none();
        return make_answer(p, time, target_frame, source_frame);
    }

    // Buffer.can_transform, under the buffer's lock.
    bool can_transform_frames(nb::handle target_frame, nb::handle source_frame, int64_t time) const {
        const int same = PyObject_RichCompareBool(target_frame.ptr(), source_frame.ptr(), Py_EQ);
        if (same < 0) throw nb::python_error();
        if (same) return true;
        // tf2's validateFrameId: a name with a leading slash (a frame published as "//b" is
        // stored as "/b") is refused, as lookup refuses it.
        if (!plain_name(target_frame) || !plain_name(source_frame)) return false;
        const Locked locked(lock_, lock_methods_);
        const int64_t target = frame_id(target_frame, 0), source = frame_id(source_frame, 1);
        return target > 0 && source > 0 && can_transform(target, source, time);
    }

    // Samples offered to the buffer so far, stored or refused: the next one's sequence number.
    int64_t arrivals = 0;

    // `raw`: under ROS 2, the rotation as composed, before tf2::Transform's round trip (lookup_full's).
    std::optional<Found> lookup(int64_t target, int64_t source, int64_t time, bool raw) const {
        tfcore::Pose p;
        if (!lookup_pose(target, source, time, p, raw)) return std::nullopt;
        return Found{{p.v.x, p.v.y, p.v.z}, {p.q.x, p.q.y, p.q.z, p.q.w}, time};
    }

    bool can_transform(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        if (time == 0 && tfcore::latest_common_time(histories_, target, source, time) != tfcore::Failure::NONE) {
            return false;
        }
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        tfcore::walk(histories_, target, source, time, chain, memo);
        return chain.ending != tfcore::Ending::NO_PATH;
    }

    std::tuple<int64_t, Failed> latest_common_time(int64_t target, int64_t source) const {
        check_frames(target, source);
        int64_t time = 0;
        return {time, failed(tfcore::latest_common_time(histories_, target, source, time))};
    }

    // The walk at `time` (0: the latest common time): the frames it passes through, from source
    // to target, or why it fails.
    std::tuple<std::vector<int64_t>, Failed> chain(int64_t target, int64_t source, int64_t time) const {
        check_frames(target, source);
        const std::vector<int64_t> none;
        if (time == 0) {
            const tfcore::Failure failure = tfcore::latest_common_time(histories_, target, source, time);
            if (failure != tfcore::Failure::NONE) return {none, failed(failure)};
        }
        tfcore::Memo memo;
        tfcore::Chain chain;
        tfcore::walk(histories_, target, source, time, chain, memo);
        if (chain.ending != tfcore::Ending::NO_PATH) return {tfcore::frames_of(chain), failed(tfcore::Failure::NONE)};
        if (chain.failure != tfcore::Failure::EXTRAPOLATION) return {none, failed(chain.failure)};
        return {none, failed(chain.failure, tfcore::gap_at(histories_[chain.gap_frame], time))};
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
        returned(values, valid, rows.data(), n);
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
        returned(values, valid, nullptr, n);
    }

    int chain_takes(int64_t target, int64_t source, Int64s times) const {
        check_frames(target, source);
        const auto n = static_cast<int64_t>(times.shape(0));
        if (n < 1 || n > tfcore::BLOCK) throw nb::value_error("EdgeTable.chain_takes: 1 to BLOCK times");
        return tfcore::chain_takes(histories_, target, source, times.data(), n);
    }

   private:
    friend class BulkInsert;

    // The id of the frame named `name` (0: none), remembered per argument (`which`, 0 or 1) by the
    // name's object: a loop looks the same two frames up again and again. Frames are only ever
    // added to the table, so a name's id never changes; held, its object cannot be another's.
    int64_t frame_id(nb::handle name, int which) const {
        Remembered& last = remembered_[which];
        if (name.ptr() == last.name.ptr()) return last.id;
        const int64_t id = id_in(frames_, name);
        if (id > 0) last = {nb::borrow(name), id};
        return id;
    }

    // set_transform's sample stored, if it is the common case: see _kernels.pyi's EdgeTable.set_transform.
    bool append(nb::handle transform, nb::handle authority, nb::handle is_static, nb::handle record_time) {
        if (PyDict_GET_SIZE(reserved_.ptr()) != 0) return false;
        const nb::object child_name = field(transform, CHILD_FRAME_ID, names_.child_frame_id);
        const nb::object parent_name = field(transform, FRAME_ID, names_.frame_id);
        if (!child_name.is_valid() || !parent_name.is_valid()) return clear_error();
        const int64_t child = id_in(frames_, child_name), parent = id_in(frames_, parent_name);
        if (child <= 0 || parent <= 0 || parent == child || child >= static_cast<int64_t>(histories_.size())) {
            return false;
        }
        tfcore::History& h = histories_[child];
        const int wanted_static = PyObject_IsTrue(is_static.ptr());
        if (wanted_static < 0) return clear_error();
        if (!h.has || h.is_static != static_cast<bool>(wanted_static)) return false;
        if (!plain_name(child_name) || !plain_name(parent_name)) return false;
        double v[7];
        int64_t stamp = 0, recorded = 0;
        const nb::object translation = field(transform, TRANSLATION, names_.translation);
        const nb::object rotation = field(transform, ROTATION, names_.rotation);
        const nb::object stamp_object = field(transform, STAMP, names_.stamp);
        if (!translation.is_valid() || !rotation.is_valid() || !stamp_object.is_valid()) return clear_error();
        if (!read_numbers(translation, 3, v) || !read_numbers(rotation, 4, v + 3) || !read_int(stamp_object, stamp) ||
            !read_int(record_time, recorded)) {
            return false;
        }
        double q[4] = {v[3], v[4], v[5], v[6]};
        if (ros2_) tfcore::through_matrix_all(q, 1, 4);  // what ROS 2's tf2 checks (and holds: pose_at)
        const double x = q[0], y = q[1], z = q[2], w = q[3];
        // The sum of infinities and NaNs is not finite (of large values neither: the batch path decides those).
        if (!std::isfinite(v[0] + v[1] + v[2] + x + y + z + w) ||
            !(std::fabs((w * w + x * x + y * y + z * z) - 1.0) < tolerance_)) {
            return false;
        }
        const nb::object authority_id = nb::borrow(PyDict_GetItemWithError(authorities_.ptr(), authority.ptr()));
        if (!authority_id.is_valid()) return clear_error();
        Held& held = held_[child];
        int64_t end = h.end;
        const bool empty = end == h.start;
        if (!(h.is_static || empty || stamp > h.stamps[end - 1])) return false;
        if (end == capacity_of(held)) {  // the arrays move: `h` and `held` describe the new ones
            attribute(held.history, names_.grow)(1);
            update(child, nb::object(held.history));
            end = h.end;
        }
        const int64_t newest = ros2_ && !empty ? h.stamps[end - 1] : stamp;  // what ROS 2's tf2 prunes by

        held.stamps.data()[end] = stamp;
        std::copy(v, v + 7, held.values.data() + 7 * end);
        held.parents.data()[end] = static_cast<int32_t>(parent);
        held.authorities.data()[end] = static_cast<int32_t>(PyLong_AsLong(authority_id.ptr()));
        held.record_times.data()[end] = recorded;
        held.sequence.data()[end] = arrivals;
        held.flags.data()[end] = h.is_static ? FROM_STATIC_TOPIC : 0;
        h.end = end + 1;
        set_bound(held.history, Bound::END, h.end);
        if (cache_time_ && !h.is_static) prune(child, newest);
        const nb::object key = nb::int_(child);
        if (PyDict_SetItem(broadcasters_.ptr(), key.ptr(), authority_id.ptr()) < 0) throw nb::python_error();
        return true;
    }

    // A lookup; false where tf2 fails. `time` 0 becomes the latest common time. ROS 2's tf2 returns
    // the rotation through a matrix (unless `raw`).
    bool lookup_pose(int64_t target, int64_t source, int64_t& time, tfcore::Pose& p, bool raw = false) const {
        check_frames(target, source);
        if (time == 0 && tfcore::latest_common_time(histories_, target, source, time) != tfcore::Failure::NONE) {
            return false;
        }
        tfcore::Memo memo;
        thread_local tfcore::Chain chain;
        if (!tfcore::lookup_at(histories_, target, source, time, chain, memo, p)) return false;
        if (ros2_ && !raw) p.q = tfcore::through_matrix(p.q);
        return true;
    }

    // ROS 2's tf2 returns each answer's rotation through a matrix: the valid `rows` of `values` so.
    void returned(Array<double, nb::shape<-1, 7>>& values, const Array<bool, nb::ndim<1>>& valid,
                  const int64_t* rows, int64_t n) const {
        if (!ros2_) return;
        std::vector<uint8_t> done(rows != nullptr ? values.shape(0) : 0);  // rows given more than once: once
        for (int64_t k = 0; k < n; ++k) {
            const int64_t row = rows != nullptr ? rows[k] : k;
            if (!valid.data()[row] || (rows != nullptr && std::exchange(done[row], 1))) continue;
            tfcore::through_matrix_all(values.data() + 7 * row + 3, 1, 7);
        }
    }

    // A new `answer` (Transform), its slots filled in place (its frozen __setattr__ refuses).
    nb::object make_answer(const tfcore::Pose& p, int64_t stamp, nb::handle target_frame,
                           nb::handle source_frame) const {
        auto* type = reinterpret_cast<PyTypeObject*>(answer_.ptr());
        const nb::object answer = nb::steal(type->tp_alloc(type, 0));
        if (!answer.is_valid()) throw nb::python_error();
        const auto put = [&](Field field, PyObject* value) {  // into a slot of a new object: empty
            if (value == nullptr) throw nb::python_error();
            *reinterpret_cast<PyObject**>(reinterpret_cast<char*>(answer.ptr()) + offsets_[field]) = value;
        };
        put(TRANSLATION, floats({p.v.x, p.v.y, p.v.z}));
        put(ROTATION, floats({p.q.x, p.q.y, p.q.z, p.q.w}));
        put(STAMP, PyLong_FromLongLong(stamp));
        put(FRAME_ID, Py_NewRef(target_frame.ptr()));
        put(CHILD_FRAME_ID, Py_NewRef(source_frame.ptr()));
        return answer;
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

    // EdgeHistory.prune after an append to `frame`, against `latest`: the history's start moved
    // here, or by EdgeHistory.prune itself where it also moves the samples to the arrays' front.
    void prune(int64_t frame, int64_t latest) {
        tfcore::History& h = histories_[frame];
        Held& held = held_[frame];
        const int64_t cache_time = *cache_time_;
        const int64_t first = std::upper_bound(h.stamps + h.start, h.stamps + h.end, below(latest, cache_time)) -
                              h.stamps;
        if (first > capacity_of(held) / 2) {
            attribute(held.history, names_.prune)(cache_time, latest);
            update(frame, nb::object(held.history));
        } else if (first != h.start) {
            h.start = first;
            set_bound(held.history, Bound::START, first);
        }
    }

    // `transform`'s field (the answer's `index`-th) read through its slot where it is an answer
    // (what Python's attribute lookup would find, minus the search), else as an attribute.
    nb::object field(nb::handle transform, int index, const nb::str& name) const {
        if (Py_TYPE(transform.ptr()) != reinterpret_cast<PyTypeObject*>(answer_.ptr())) {
            return attribute(transform, name);
        }
        PyObject* slot = fields_[index].ptr();
        return nb::steal(Py_TYPE(slot)->tp_descr_get(slot, transform.ptr(), answer_.ptr()));
    }

    enum class Bound { START, END };

    // history._start or _end = `value`, through the slot of the histories' type (looked up once; its
    // descriptors keep the type alive).
    void set_bound(nb::handle history, Bound bound, int64_t value) {
        const nb::object number = nb::int_(value);
        PyTypeObject* type = Py_TYPE(history.ptr());
        if (type != bounds_type_) {
            const nb::object slots = nb::getattr(nb::handle(reinterpret_cast<PyObject*>(type)), "__dict__");
            start_slot_ = slots[names_.start];
            end_slot_ = slots[names_.end];
            bounds_type_ = type;
        }
        PyObject* slot = (bound == Bound::START ? start_slot_ : end_slot_).ptr();
        if (Py_TYPE(slot)->tp_descr_set(slot, history.ptr(), number.ptr()) < 0) throw nb::python_error();
    }

    static int64_t capacity_of(const Held& held) {
        return static_cast<int64_t>(std::min({held.stamps.shape(0), held.values.shape(0), held.parents.shape(0),
                                              held.authorities.shape(0), held.record_times.shape(0),
                                              held.sequence.shape(0), held.flags.shape(0)}));
    }

    // An attribute missing or a value refusing conversion: the Python path will meet it again.
    static bool clear_error() {
        PyErr_Clear();
        return false;
    }

    static void check_frames(int64_t target, int64_t source) {
        if (target < 0 || source < 0) throw nb::value_error("EdgeTable: a negative frame id");
    }

    Names names_;
    nb::object lock_;  // the buffer's
    LockMethods lock_methods_;
    nb::dict frames_;  // frame name -> id (FrameTable.ids)
    // What a sample stored in place needs of its buffer: publishers' ids, each child frame's last
    // publisher, the rows reserved, the cache's length, the tf2 answered as, the norm's tolerance.
    nb::dict authorities_, broadcasters_, reserved_;
    std::optional<int64_t> cache_time_;
    bool ros2_;
    double tolerance_;
    nb::object answer_;
    PyTypeObject* bounds_type_ = nullptr;  // the type of the history whose _start and _end slots are these
    nb::object start_slot_, end_slot_;
    struct Remembered {
        nb::object name;
        int64_t id = 0;
    };
    mutable Remembered remembered_[2];  // frame_id's last name and id per argument (under the lock)
    nb::object fields_[5];  // the answer's fields' slot descriptors, in FIELD order
    Py_ssize_t offsets_[5];  // ... and where each slot lies in an answer
    tfcore::Histories histories_;
    std::vector<Held> held_;
};

// --- Buffer.insert: a batch in one call (insert.hpp) ---------------------------------------------

// history.PARENT_HAD_SLASH and CHILD_HAD_SLASH: a sample's frame names had a leading slash.
constexpr uint8_t PARENT_HAD_SLASH = 2, CHILD_HAD_SLASH = 4;

// A new numpy array holding `values`.
template <typename T>
nb::ndarray<nb::numpy, T, nb::ndim<1>> to_numpy(std::vector<T> values) {
    auto* owned = new std::vector<T>(std::move(values));
    const nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T, nb::ndim<1>>(owned->data(), {owned->size()}, owner);
}

// EdgeTable.insert of one batch (see _kernels.pyi): its rows checked, grouped by child frame, and
// each frame's rows offered to its history as tf2's setTransform offers them one by one.
class BulkInsert {
   public:
    BulkInsert(EdgeTable& table, nb::handle batch, Column<const int32_t> authority_ids, nb::list histories,
               nb::handle intern, nb::handle new_history)
        : t_(table),
          names_(nb::getattr(batch, "frame_names")),
          parent_(nb::cast<Column<const int32_t>>(nb::getattr(batch, "parent"))),
          child_(nb::cast<Column<const int32_t>>(nb::getattr(batch, "child"))),
          authority_(nb::cast<Column<const int32_t>>(nb::getattr(batch, "authority"))),
          stamp_(nb::cast<Column<const int64_t>>(nb::getattr(batch, "stamp"))),
          record_time_(nb::cast<Column<const int64_t>>(nb::getattr(batch, "record_time"))),
          translation_(nb::cast<Array<const double, nb::shape<-1, 3>>>(nb::getattr(batch, "translation"))),
          rotation_(nb::cast<Array<const double, nb::shape<-1, 4>>>(nb::getattr(batch, "rotation"))),
          static_(nb::cast<Column<const bool>>(nb::getattr(batch, "static"))),
          authority_ids_(std::move(authority_ids)),
          histories_(std::move(histories)),
          intern_(intern),
          new_history_(new_history),
          n_(static_cast<int64_t>(stamp_.shape(0))) {
        for (const size_t rows : {parent_.shape(0), child_.shape(0), authority_.shape(0), record_time_.shape(0),
                                  translation_.shape(0), rotation_.shape(0), static_.shape(0)}) {
            if (static_cast<int64_t>(rows) != n_) throw nb::value_error("EdgeTable.insert: columns of other lengths");
        }
        const Py_ssize_t names = PySequence_Size(names_.ptr());
        if (names < 0) throw nb::python_error();
        const auto authorities = static_cast<int32_t>(authority_ids_.shape(0));
        for (int64_t i = 0; i < n_; ++i) {
            if (parent_.data()[i] < 0 || parent_.data()[i] >= names || child_.data()[i] < 0 ||
                child_.data()[i] >= names || authority_.data()[i] < 0 || authority_.data()[i] >= authorities) {
                throw nb::index_error("EdgeTable.insert: a frame or publisher index outside the batch's names");
            }
        }
        name_count_ = names;
    }

    // (accepted, refused rows, their codes, their groups' bounds, rows ROS 2's tf2 ignored as identical).
    nb::tuple run() {
        key_names();
        rotations_ = rotation_.data();
        if (t_.ros2_) {  // ROS 2's tf2 checks and compares each rotation as it comes back from its matrix
            turned_.assign(rotations_, rotations_ + 4 * n_);
            tfcore::through_matrix_all(turned_.data(), n_, 4);
            rotations_ = turned_.data();
        }
        first_ = t_.arrivals;
        t_.arrivals += n_;
        std::vector<uint8_t> refusals(n_);
        const int32_t* parent = parent_.data();
        const int32_t* child = child_.data();
        bool refused = false;
        for (int64_t i = 0; i < n_; ++i) {
            refusals[i] = tfinsert::checks(keys_[parent[i]], keys_[child[i]], empty_key_, checked(i), t_.tolerance_);
            refused = refused || refusals[i];
        }
        for (int check = 0; check < tfinsert::CHECKS && refused; ++check) {
            for (int64_t i = 0; i < n_; ++i) {
                if (refusals[i] & (1 << check)) refused_.push_back(i);
            }
            close_group(static_cast<tfinsert::Refusal>(check));
        }
        // Of the rows that passed, in one pass: where each name first appears (as a child before
        // as a parent, as tf2 interns them) and how many rows each child has.
        std::vector<int64_t> appearance(stripped_.size(), NEVER), bounds(stripped_.size() + 1, 0);
        for (int64_t i = 0; i < n_; ++i) {
            if (refusals[i]) continue;
            const int32_t as_child = keys_[child[i]], as_parent = keys_[parent[i]];
            if (appearance[as_child] == NEVER) appearance[as_child] = 2 * i;
            if (appearance[as_parent] == NEVER) appearance[as_parent] = 2 * i + 1;
            ++bounds[as_child + 1];
        }
        intern_frames(appearance);
        int64_t accepted = 0;
        const std::vector<int64_t> rows = rows_per_child(refusals, bounds);
        for (size_t key = 0; key + 1 < bounds.size(); ++key) {
            const int64_t* group = rows.data() + bounds[key];
            for (const auto& [begin, end] : cache_runs(group, bounds[key + 1] - bounds[key])) {
                accepted += store(key_to_id_[key], stripped_[key], group + begin, end - begin);
            }
        }
        return nb::make_tuple(accepted, to_numpy(std::move(refused_)), to_numpy(std::move(codes_)),
                              to_numpy(std::move(bounds_)), to_numpy(std::move(duplicates_)));
    }

   private:
    static constexpr int64_t NEVER = INT64_MAX;

    // Row `row` as it was sent (as it is stored), and as tf2 checks and compares it (ROS 2's rotation
    // through its matrix).
    tfinsert::Values values(int64_t row) const {
        return tfinsert::values_of(translation_.data(), rotation_.data(), row);
    }
    tfinsert::Values checked(int64_t row) const {
        return tfinsert::values_of(translation_.data(), rotations_, row);
    }

    // Each name a row uses, without its leading slash, as a key: keys_, slash_, stripped_, empty_key_.
    void key_names() {
        std::vector<uint8_t> used(name_count_);
        for (int64_t i = 0; i < n_; ++i) used[parent_.data()[i]] = used[child_.data()[i]] = 1;
        keys_.assign(name_count_, -1);
        slash_.assign(name_count_, 0);
        const nb::dict index;
        for (int64_t j = 0; j < name_count_; ++j) {
            if (!used[j]) continue;
            nb::object name = nb::steal(PySequence_GetItem(names_.ptr(), j));
            if (!name.is_valid()) throw nb::python_error();
            if (!PyUnicode_Check(name.ptr())) throw nb::type_error("EdgeTable.insert: a frame name that is not a str");
            const Py_ssize_t length = PyUnicode_GET_LENGTH(name.ptr());
            if (length > 0 && PyUnicode_READ_CHAR(name.ptr(), 0) == '/') {
                name = nb::steal(PyUnicode_Substring(name.ptr(), 1, length));
                slash_[j] = 1;
            }
            if (index.contains(name)) {
                keys_[j] = nb::cast<int32_t>(index[name]);
            } else {
                keys_[j] = static_cast<int32_t>(stripped_.size());
                index[name] = keys_[j];
                stripped_.push_back(name);
            }
        }
        const nb::str empty("");
        empty_key_ = index.contains(empty) ? nb::cast<int32_t>(index[empty]) : -1;
    }

    // The rows refused since the last group, as one group of `code`.
    void close_group(tfinsert::Refusal code) {
        if (static_cast<int64_t>(refused_.size()) == bounds_.back()) return;
        codes_.push_back(code);
        bounds_.push_back(static_cast<int64_t>(refused_.size()));
    }

    // Frame ids for the names of rows that passed the checks, new ones interned in order of
    // `appearance` (NEVER: not used); the buffer's histories made as many.
    void intern_frames(const std::vector<int64_t>& appearance) {
        std::vector<size_t> order;
        for (size_t key = 0; key < appearance.size(); ++key) {
            if (appearance[key] != NEVER) order.push_back(key);
        }
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return appearance[a] < appearance[b]; });
        key_to_id_.assign(stripped_.size(), 0);
        for (const size_t key : order) key_to_id_[key] = nb::cast<int32_t>(intern_(stripped_[key]));
        frame_of_.resize(name_count_);
        for (int64_t j = 0; j < name_count_; ++j) frame_of_[j] = keys_[j] < 0 ? 0 : key_to_id_[keys_[j]];
        const Py_ssize_t frames = PyDict_Size(t_.frames_.ptr()) + 1;  // and NO_PARENT
        while (static_cast<Py_ssize_t>(histories_.size()) < frames) histories_.append(nb::none());
    }

    // The rows that passed the checks by child key, each key's in arrival order, from `bounds[key]`
    // to `bounds[key + 1]` (given each key's count at `bounds[key + 1]`).
    std::vector<int64_t> rows_per_child(const std::vector<uint8_t>& refusals, std::vector<int64_t>& bounds) const {
        std::partial_sum(bounds.begin(), bounds.end(), bounds.begin());
        std::vector<int64_t> rows(bounds.back()), next(bounds.begin(), bounds.end() - 1);
        for (int64_t i = 0; i < n_; ++i) {
            if (!refusals[i]) rows[next[keys_[child_.data()[i]]]++] = i;
        }
        return rows;
    }

    // A frame's `count` rows in parts that go to one cache: all of them, except under ROS 2, where
    // each change between static and dynamic replaces the frame's cache.
    std::vector<std::pair<int64_t, int64_t>> cache_runs(const int64_t* rows, int64_t count) const {
        std::vector<std::pair<int64_t, int64_t>> runs;
        int64_t begin = 0;
        for (int64_t j = 1; j <= count; ++j) {
            if (j == count || (t_.ros2_ && static_.data()[rows[j]] != static_.data()[rows[begin]])) {
                runs.emplace_back(begin, j);
                begin = j;
            }
        }
        return runs;
    }

    // The rows reserved for the frame `name`, no longer reserved.
    int64_t take_reserved(nb::handle name) {
        PyObject* reserved = t_.reserved_.ptr();
        if (PyDict_GET_SIZE(reserved) == 0) return 0;
        PyObject* rows = PyDict_GetItemWithError(reserved, name.ptr());
        if (rows == nullptr) {
            if (PyErr_Occurred()) throw nb::python_error();
            return 0;
        }
        const int64_t count = nb::cast<int64_t>(nb::handle(rows));
        if (PyDict_DelItem(reserved, name.ptr()) < 0) throw nb::python_error();
        return count;
    }

    // Offer one frame's `k` rows (passed the checks, in arrival order, all static or all dynamic under
    // ROS 2) to its cache, as tf2's setTransform does; returns how many tf2 accepted.
    int64_t store(int32_t frame, nb::handle name, const int64_t* rows, int64_t k) {
        nb::object hist = nb::borrow(PyList_GET_ITEM(histories_.ptr(), frame));
        const int64_t expected = take_reserved(name);
        const bool run_static = static_.data()[rows[0]];
        // ROS 1's tf2 makes a frame static or dynamic once, by its first accepted sample; ROS 2's
        // replaces the frame's cache whenever a sample of the other kind comes.
        if (hist.is_none() || (t_.ros2_ && t_.histories_[frame].is_static != run_static)) {
            const nb::object replaced = t_.cache_time_ ? nb::none() : hist;
            hist = new_history_(run_static, std::max(k, expected), replaced);
            PyList_SetItem(histories_.ptr(), frame, nb::object(hist).release().ptr());
            t_.update(frame, hist);
        } else if (expected) {
            attribute(hist, reserve_)(expected);
            t_.update(frame, hist);
        }
        const tfcore::History& h = t_.histories_[frame];
        const bool is_static = h.is_static;
        const tfinsert::Offered offered{rows,           k, stamp_.data(), translation_.data(), rotations_,
                                        parent_.data(), frame_of_.data()};
        std::vector<uint8_t> verdicts(k, tfinsert::KEEP);
        int64_t prune_from = 0;  // ROS 2's
        if (!is_static) {
            verdicts = tfinsert::stamp_verdicts({h.stamps, h.values, h.parents, h.start, h.end, h.turned}, offered,
                                                t_.cache_time_, t_.ros2_);
            refuse(rows, verdicts, tfinsert::OLD, tfinsert::OLD_DATA);
            if (t_.ros2_) {
                for (int64_t i = 0; i < k; ++i) {
                    if (verdicts[i] == tfinsert::IGNORED) duplicates_.push_back(rows[i]);
                }
                prune_from = tfinsert::newest_before_last(h.end > h.start ? h.stamps + h.end - 1 : nullptr, offered);
            } else {
                refuse(rows, verdicts, tfinsert::IGNORED, tfinsert::REPEATED_DATA);
            }
        }
        append(frame, hist, rows, verdicts);
        const tfcore::History& after = t_.histories_[frame];
        if (t_.cache_time_ && !is_static && after.end > after.start) {
            t_.prune(frame, t_.ros2_ ? prune_from : after.stamps[after.end - 1]);
        }
        int64_t accepted = 0, last = -1;
        for (int64_t i = 0; i < k; ++i) {
            if (verdicts[i] == tfinsert::KEEP || (t_.ros2_ && verdicts[i] == tfinsert::IGNORED)) {
                ++accepted;
                last = rows[i];
            }
        }
        if (last >= 0) {
            const nb::object key = nb::int_(frame), publisher = nb::int_(authority_ids_.data()[authority_.data()[last]]);
            if (PyDict_SetItem(t_.broadcasters_.ptr(), key.ptr(), publisher.ptr()) < 0) throw nb::python_error();
        }
        return accepted;
    }

    // The rows of `verdict`, refused as `code` (one group).
    void refuse(const int64_t* rows, const std::vector<uint8_t>& verdicts, tfinsert::Verdict verdict,
                tfinsert::Refusal code) {
        for (size_t i = 0; i < verdicts.size(); ++i) {
            if (verdicts[i] == verdict) refused_.push_back(rows[i]);
        }
        close_group(code);
    }

    // The kept rows appended to `frame`'s history (grown if full), merged in by stamp where a dynamic
    // history's order needs it.
    void append(int32_t frame, nb::handle hist, const int64_t* rows, const std::vector<uint8_t>& verdicts) {
        const auto kept = static_cast<int64_t>(std::count(verdicts.begin(), verdicts.end(), tfinsert::KEEP));
        if (kept == 0) return;
        if (t_.histories_[frame].end + kept > EdgeTable::capacity_of(t_.held_[frame])) {
            attribute(hist, t_.names_.grow)(kept);
            t_.update(frame, hist);
        }
        tfcore::History& h = t_.histories_[frame];
        Held& held = t_.held_[frame];
        const tfinsert::Columns c{held.stamps.data(),       held.values.data(),   held.parents.data(),
                                  held.authorities.data(),  held.record_times.data(), held.sequence.data(),
                                  held.flags.data()};
        const int64_t end_old = h.end;
        int64_t end = end_old;
        for (size_t i = 0; i < verdicts.size(); ++i) {
            if (verdicts[i] != tfinsert::KEEP) continue;
            const int64_t row = rows[i];
            const int32_t parent = parent_.data()[row], child = child_.data()[row];
            c.stamps[end] = stamp_.data()[row];
            const tfinsert::Values v = values(row);
            for (int j = 0; j < 7; ++j) c.values[7 * end + j] = v.v[j];  // not std::copy: a call to memmove
            c.parents[end] = frame_of_[parent];
            c.authorities[end] = authority_ids_.data()[authority_.data()[row]];
            c.record_times[end] = record_time_.data()[row];
            c.sequence[end] = first_ + row;
            c.flags[end] = (static_.data()[row] ? FROM_STATIC_TOPIC : 0) | (slash_[parent] ? PARENT_HAD_SLASH : 0) |
                           (slash_[child] ? CHILD_HAD_SLASH : 0);
            ++end;
        }
        bool in_order = end_old == h.start || c.stamps[end_old] > c.stamps[end_old - 1];
        for (int64_t r = end_old + 1; r < end && in_order; ++r) in_order = c.stamps[r] > c.stamps[r - 1];
        if (!h.is_static && !in_order) tfinsert::merge_by_stamp(c, h.start, end_old, end);
        h.end = end;
        t_.set_bound(hist, EdgeTable::Bound::END, end);
    }

    EdgeTable& t_;
    nb::object names_;  // the batch's frame names
    Column<const int32_t> parent_, child_, authority_;
    Column<const int64_t> stamp_, record_time_;
    Array<const double, nb::shape<-1, 3>> translation_;
    Array<const double, nb::shape<-1, 4>> rotation_;
    const double* rotations_ = nullptr;  // the rotations tf2 checks and compares: rotation_'s, or (ROS 2) turned_
    std::vector<double> turned_;
    Column<const bool> static_;
    Column<const int32_t> authority_ids_;  // a batch publisher's id in the buffer
    nb::list histories_;                   // the buffer's, by frame id
    nb::handle intern_, new_history_;      // FrameTable.intern, EdgeHistory
    const nb::str reserve_{"reserve"};
    int64_t n_, name_count_ = 0, first_ = 0;
    std::vector<int32_t> keys_, key_to_id_, frame_of_;
    std::vector<uint8_t> slash_;
    std::vector<nb::object> stripped_;  // per key, the name
    int32_t empty_key_ = -1;
    std::vector<int64_t> refused_, bounds_{0}, duplicates_;
    std::vector<uint8_t> codes_;
};

}  // namespace

NB_MODULE(_kernels, m) {
    m.doc() = "The compiled lookups: tf2's walk over the buffer's edge histories.";
    // A live command ends with its receiving threads still holding buffers: nanobind would list them
    // as leaks on the user's terminal at exit. TFX_DEBUG=1 keeps the report, for developers.
    if (std::getenv("TFX_DEBUG") == nullptr) nb::set_leak_warnings(false);
    m.attr("BLOCK") = tfcore::BLOCK;
    nb::class_<EdgeTable>(m, "EdgeTable")
        .def(nb::init<nb::object, nb::dict, nb::handle, nb::dict, nb::dict, nb::dict, std::optional<int64_t>, bool,
                      double>(),
             "lock"_a, "frames"_a, "answer"_a, "authorities"_a, "broadcasters"_a, "reserved"_a,
             "cache_time"_a.none(), "ros2"_a, "tolerance"_a)
        .def("update", &EdgeTable::update, "frame"_a, "history"_a.none())
        .def_rw("arrivals", &EdgeTable::arrivals)
        .def("set_transform", &EdgeTable::set_transform, "transform"_a, "authority"_a, "static"_a, "record_time"_a)
        .def("lookup_frames", &EdgeTable::lookup_frames, "target_frame"_a, "source_frame"_a, "time"_a)
        .def("can_transform_frames", &EdgeTable::can_transform_frames, "target_frame"_a, "source_frame"_a, "time"_a)
        .def("lookup", &EdgeTable::lookup, "target"_a, "source"_a, "time"_a, "raw"_a = false)
        .def("can_transform", &EdgeTable::can_transform, "target"_a, "source"_a, "time"_a)
        .def("latest_common_time", &EdgeTable::latest_common_time, "target"_a, "source"_a)
        .def("chain", &EdgeTable::chain, "target"_a, "source"_a, "time"_a)
        .def("lookup_many", &EdgeTable::lookup_many, "target"_a, "source"_a, "times"_a, "rows"_a, "stamps"_a,
             "values"_a, "valid"_a, "chained"_a = true)
        .def("lookup_in_parallel", &EdgeTable::lookup_in_parallel, "target"_a, "source"_a, "times"_a, "stamps"_a,
             "values"_a, "valid"_a, "threads"_a)
        .def("chain_takes", &EdgeTable::chain_takes, "target"_a, "source"_a, "times"_a);

    m.def(
        "through_matrix",
        [](Array<double, nb::shape<-1, 4>> rotations) {
            tfcore::through_matrix_all(rotations.data(), static_cast<int64_t>(rotations.shape(0)), 4);
        },
        "rotations"_a, "Rotations (N, 4), in place, as they come back from ROS 2's tf2::Transform.");
    // Buffer.insert's bulk path, bound apart from the class's other methods.
    nb::cpp_function_def(
        [](EdgeTable& table, nb::handle batch, Column<const int32_t> authority_ids, nb::list histories,
           nb::handle intern, nb::handle new_history) {
            return BulkInsert(table, batch, std::move(authority_ids), std::move(histories), intern, new_history).run();
        },
        nb::scope(nb::type<EdgeTable>()), nb::name("insert"), nb::is_method(), "batch"_a, "authority_ids"_a,
        "histories"_a, "intern"_a, "new_history"_a);
}
