// frnn.Grid's view of its cells (frnn/grid_geometry.hpp): the cell of a point, the cells a
// query at a point visits and a cell's corners, in the caller's units, so that Python users
// can draw or check what the search does.
#include <cmath>
#include <string>

#include "grid_object.hpp"

namespace frnn::python {

namespace {

// The point x (a sequence of dim numbers) in search space, checked: finite, and near enough
// that its cell coordinates fit (2^62 cells out).
template <class T, int D>
std::array<T, D> search_point(const grid<T, D>& g, const py::object& x, const char* what) {
    const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(x);
    if (!values || values.ndim() != 1 || values.shape(0) != D)
        throw py::value_error(std::string(what) + ": x needs " + std::to_string(D) + " coordinates");
    const auto& geo = g.geometry();
    std::array<T, D> p;
    for (int a = 0; a < D; ++a) {
        const double v = values.at(a);
        p[a] = T(v) * geo.scale;
        const double cells = (double(p[a]) - geo.origin[a]) * geo.inv_cell[a];
        if (!std::isfinite(v) || !std::isfinite(double(p[a])) || std::abs(cells) >= 0x1p62)
            throw py::value_error(std::string(what) + ": coordinate " + std::to_string(a) + " of x is " +
                                  std::to_string(v) + ", not finite or too far out for cell coordinates");
    }
    return p;
}

template <int D>
py::tuple to_tuple(const cell_index& c) {
    py::tuple out(D);
    for (int a = 0; a < D; ++a) out[a] = c[std::size_t(a)];
    return out;
}

}  // namespace

py::tuple grid_object::cell_of(const py::object& x) const {
    std::shared_lock lock(mutex_);
    return std::visit(
        [&](auto& g) {
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            return to_tuple<D>(g.geometry().cell_of(search_point(g, x, "cell_of")));
        },
        g_);
}

py::tuple grid_object::cells_within(const py::object& x) const {
    std::shared_lock lock(mutex_);
    return std::visit(
        [&](auto& g) {
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            const cell_range r = g.geometry().cells_within(search_point(g, x, "cells_within"));
            return py::make_tuple(to_tuple<D>(r.first), to_tuple<D>(r.last));
        },
        g_);
}

py::tuple grid_object::cell_bounds(const py::object& cell) const {
    std::shared_lock lock(mutex_);
    return std::visit(
        [&](auto& g) {
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            const auto values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(cell);
            if (!values || values.ndim() != 1 || values.shape(0) != D)
                throw py::value_error("cell_bounds: cell needs " + std::to_string(D) + " integers");
            cell_index c{0, 0, 0};
            for (int a = 0; a < D; ++a) c[std::size_t(a)] = values.at(a);
            const auto b = g.geometry().cell_bounds(c);
            py::tuple lower(D), upper(D);
            for (int a = 0; a < D; ++a) lower[a] = b[0][std::size_t(a)], upper[a] = b[1][std::size_t(a)];
            return py::make_tuple(lower, upper);
        },
        g_);
}

}  // namespace frnn::python
