// The Python side of the compiled core's binding (module.cpp): arrays, names and numbers as Python hands
// them over, and numpy arrays handed back.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

namespace tfpython {

namespace nb = nanobind;

template <typename T, typename... Shape>
using Array = nb::ndarray<T, nb::c_contig, nb::device::cpu, Shape...>;
template <typename T>
using Column = Array<T, nb::ndim<1>>;
using Int64s = Column<const int64_t>;
using Values = Array<double, nb::shape<-1, 7>>;

// `object.name`, or an invalid object with the error set.
inline nb::object attribute(nb::handle object, const nb::str& name) {
    return nb::steal(PyObject_GetAttr(object.ptr(), name.ptr()));
}

// A str's UTF-8 (which the str keeps); false for anything else.
inline bool text(nb::handle s, std::string_view& out) {
    if (!PyUnicode_Check(s.ptr())) return false;
    Py_ssize_t size = 0;
    const char* data = PyUnicode_AsUTF8AndSize(s.ptr(), &size);
    if (data == nullptr) {
        PyErr_Clear();
        return false;
    }
    out = {data, static_cast<size_t>(size)};
    return true;
}

// A frame name as tf2's validateFrameId takes it as is: a str, not empty, without a leading slash.
inline bool plain_name(nb::handle name) {
    return PyUnicode_Check(name.ptr()) && PyUnicode_GET_LENGTH(name.ptr()) > 0 &&
           PyUnicode_READ_CHAR(name.ptr(), 0) != '/';
}

// `count` numbers of a tuple or list of floats or ints into `out`; false for anything else.
inline bool read_numbers(nb::handle sequence, Py_ssize_t count, double* out) {
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
inline bool read_int(nb::handle number, int64_t& out) {
    if (!PyLong_Check(number.ptr())) return false;
    int overflow = 0;
    out = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
    if (overflow || (out == -1 && PyErr_Occurred())) {
        PyErr_Clear();
        return false;
    }
    return true;
}

// A new numpy array holding `values`.
template <typename T>
nb::ndarray<nb::numpy, T, nb::ndim<1>> to_numpy(std::vector<T> values) {
    auto* owned = new std::vector<T>(std::move(values));
    const nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return nb::ndarray<nb::numpy, T, nb::ndim<1>>(owned->data(), {owned->size()}, owner);
}

// A read-only numpy view of `rows` rows of `width` items (`stride` apart) at `data`, which keeps
// `memory` (the history's block) alive.
template <typename T>
nb::object view(const std::shared_ptr<void>& memory, const T* data, int64_t rows, int64_t width = 0,
                int64_t stride = 0) {
    auto* held = new std::shared_ptr<void>(memory);
    const nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::shared_ptr<void>*>(p); });
    const size_t shape[2] = {static_cast<size_t>(rows), static_cast<size_t>(width)};
    const int64_t strides[2] = {stride, 1};
    return nb::cast(nb::ndarray<nb::numpy, const T>(data, width ? 2 : 1, shape, owner, width ? strides : nullptr),
                    nb::rv_policy::reference);
}

}  // namespace tfpython
