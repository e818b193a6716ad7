// Conversions between numpy arrays and the spans/vectors of the frnn core.
//
// Inputs: coordinates are read in place when they are C-contiguous float32/float64 (N, D)
// arrays; integer and other real arrays are converted (a copy) to float64, non-contiguous ones
// are copied to C order; anything else (bool, complex, object, strings) raises TypeError.
// Outputs: std::vectors are moved into numpy arrays that own them through a capsule, so no
// result is copied on its way to Python.
// All functions need the GIL.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace frnn::python {

namespace py = pybind11;

/// "(5, 3)": a shape as numpy prints it, for error messages.
inline std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) {
        if (k) s += ", ";
        s += std::to_string(a.shape(k));
    }
    return s + (a.ndim() == 1 ? ",)" : ")");
}

/// Any array-like as a numpy array (no copy when it already is one).
inline py::array as_array(py::handle obj) {
    if (py::isinstance<py::array>(obj)) return py::reinterpret_borrow<py::array>(obj);
    return py::module_::import("numpy").attr("asarray")(obj);
}

/// True when coordinates of this dtype go through the float32 path (only float32 itself);
/// every other accepted dtype goes through float64. Raises TypeError for the rest.
inline bool is_float32_input(const py::array& a, const char* what) {
    const py::dtype dt = a.dtype();
    const char kind = dt.kind();
    if (kind == 'f') return dt.itemsize() == 4;
    if (kind == 'i' || kind == 'u') return false;
    throw py::type_error(std::string(what) +
                         " must be a float32 or float64 array (integer arrays are converted to "
                         "float64); got dtype " +
                         std::string(py::str(py::handle(dt))));
}

/// `a` as a C-contiguous array of T: the same object when it already is one, else a copy.
template <class T>
py::array_t<T, py::array::c_style> as_contiguous(const py::array& a) {
    auto out = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!out) throw py::error_already_set();
    return out;
}

/// Checks that `a` is (N, D) with D == dim, or D in {2, 3} when dim == 0. A 1-D array of
/// length D is accepted as one point when `allow_single` (query points).
inline py::array check_points_shape(py::array a, const char* what, int dim, bool allow_single) {
    if (allow_single && a.ndim() == 1 && dim != 0 && a.shape(0) == dim)
        a = a.reshape({py::ssize_t(1), py::ssize_t(dim)});
    const bool ok_cols = a.ndim() == 2 && (dim == 0 ? (a.shape(1) == 2 || a.shape(1) == 3)
                                                    : a.shape(1) == dim);
    if (!ok_cols) {
        const std::string want =
            dim == 0 ? std::string("(N, 2) or (N, 3)")
                     : "(N, " + std::to_string(dim) + ")" +
                           (allow_single ? " or (" + std::to_string(dim) + ",)" : "");
        throw py::value_error(std::string(what) + " must have shape " + want + "; got shape " +
                              shape_text(a));
    }
    if (std::uint64_t(a.shape(0)) > std::uint64_t(UINT32_MAX) - 1)
        throw py::value_error(std::string(what) + ": at most 2^32 - 2 points are supported");
    return a;
}

/// Moves `v` into a 1-D or 2-D numpy array of element type Out (same size and layout as V,
/// e.g. uint64 -> int64) owned by a capsule: no copy of the data.
template <class Out = void, class V, class A>
py::array to_numpy(std::vector<V, A>&& v, std::vector<py::ssize_t> shape = {}) {
    using E = std::conditional_t<std::is_void_v<Out>, V, Out>;
    static_assert(sizeof(E) == sizeof(V));
    if (shape.empty()) shape = {py::ssize_t(v.size())};
    auto owned = std::make_unique<std::vector<V, A>>(std::move(v));
    auto* data = reinterpret_cast<E*>(owned->data());
    py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<V, A>*>(p); });
    owned.release();  // the capsule deletes it from now on
    return py::array_t<E>(shape, data, owner);
}

}  // namespace frnn::python
