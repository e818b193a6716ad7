// frnn._frnn._lattice_pairs: frnn::lattice_grid for Python, the engine of frnn.neighbor_list
// (python/frnn/_neighbor_list.py, which gives it ASE's signature).
#include "lattice_list.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "frnn/buffer.hpp"
#include "frnn/lattice.hpp"
#include "frnn/parallel.hpp"
#include "numpy_io.hpp"

namespace frnn::python {

namespace {

template <int D>
lattice<D> read_cell(const py::object& cell_obj, const py::object& pbc_obj) {
    auto cell = as_contiguous<double>(as_array(cell_obj));
    if (cell.ndim() != 2 || cell.shape(0) != D || cell.shape(1) != D)
        throw py::value_error("cell must have shape (" + std::to_string(D) + ", " + std::to_string(D) +
                              ") for points of dimension " + std::to_string(D) + "; got shape " + shape_text(cell));
    auto pbc = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(as_array(pbc_obj));
    if (!pbc || pbc.ndim() != 1 || pbc.shape(0) != D)
        throw py::value_error("pbc must hold " + std::to_string(D) + " booleans");
    lattice<D> l;
    for (int k = 0; k < D; ++k) {
        l.pbc[k] = pbc.at(k);
        for (int c = 0; c < D; ++c) l.vectors[k][c] = cell.at(k, c);
    }
    return l;
}

template <class T, int D>
py::tuple pairs(const py::array& points, const py::object& cell_obj, const py::object& pbc_obj,
                const py::object& cutoff, bool self_interaction, bool strict, std::optional<int> threads) {
    const auto coords = as_contiguous<T>(points);
    const lattice<D> cell = read_cell<D>(cell_obj, pbc_obj);
    const std::size_t n = std::size_t(coords.shape(0));
    lattice_options options;
    options.strict = strict;
    options.threads = threads.value_or(0);
    std::vector<T> radii;
    T one = 0;
    if (py::isinstance<py::float_>(cutoff) || py::isinstance<py::int_>(cutoff) ||
        (py::isinstance<py::array>(cutoff) && py::reinterpret_borrow<py::array>(cutoff).ndim() == 0)) {
        one = cutoff.cast<T>();
    } else {
        const auto r = as_contiguous<T>(as_array(cutoff));
        if (r.ndim() != 1 || std::size_t(r.shape(0)) != n)
            throw py::value_error("cutoff: one radius per atom needs shape (" + std::to_string(n) + ",); got shape " +
                                  shape_text(r));
        radii.assign(r.data(), r.data() + n);
    }
    lattice_list_options lo;
    lo.self = self_interaction;
    lo.distances = lo.vectors = true;
    lattice_csr<T, D> lists;
    {
        py::gil_scoped_release nogil;
        lattice_grid<T, D> g;
        const std::span<const T> span(coords.data(), n * D);
        if (radii.empty())
            g.build(span, cell, one, options);
        else
            g.build(span, cell, std::span<const T>(radii), options);
        lists = g.neighbor_lists(lo);
    }
    const std::size_t m = lists.size();
    std::vector<std::int64_t, buffer_allocator<std::int64_t>> i(m), j(m), s(m * D);
    {
        // ASE's int64 arrays, converted in parallel by rows (the copies of a large list take as
        // long as a part of the search).
        py::gil_scoped_release nogil;
        // Small lists in one chunk on this thread: waking the pool costs more than they do.
        const std::size_t parts = m < (std::size_t(1) << 16) ? std::min<std::size_t>(n, 1) : std::min<std::size_t>(n, 64);
        parallel_chunks(parts, options.threads, [&](std::size_t part, int) {
            for (std::size_t row = n * part / parts; row < n * (part + 1) / parts; ++row)
                for (std::uint64_t e = lists.offsets[row]; e < lists.offsets[row + 1]; ++e) {
                    i[e] = std::int64_t(row);
                    j[e] = lists.indices[e];
                    for (int k = 0; k < D; ++k) s[e * D + k] = lists.shifts[e * D + k];
                }
        });
    }
    const auto rows = py::ssize_t(m);
    return py::make_tuple(to_numpy(std::move(i)), to_numpy(std::move(j)), to_numpy(std::move(s), {rows, D}),
                          to_numpy(std::move(lists.distances)), to_numpy(std::move(lists.vectors), {rows, D}));
}

constexpr const char* doc = R"(Neighbor pairs of atoms in a periodic cell (the engine of frnn.neighbor_list).

_lattice_pairs(positions, cell, pbc, cutoff, self_interaction, strict, threads)
-> (i, j, S, d, D): rows sorted by i; d <= cutoff (d < cutoff when strict), or within
cutoff[i] + cutoff[j] when cutoff is one radius per atom.
)";

}  // namespace

void add_lattice_pairs(py::module_& m) {
    m.def(
        "_lattice_pairs",
        [](const py::object& positions, const py::object& cell, const py::object& pbc, const py::object& cutoff,
           bool self_interaction, bool strict, std::optional<int> threads) {
            py::array points = check_points_shape(as_array(positions), "positions", 0, false);
            const bool f32 = is_float32_input(points, "positions");
            const bool three = points.shape(1) == 3;
            if (f32) return three ? pairs<float, 3>(points, cell, pbc, cutoff, self_interaction, strict, threads)
                                  : pairs<float, 2>(points, cell, pbc, cutoff, self_interaction, strict, threads);
            return three ? pairs<double, 3>(points, cell, pbc, cutoff, self_interaction, strict, threads)
                         : pairs<double, 2>(points, cell, pbc, cutoff, self_interaction, strict, threads);
        },
        doc, py::arg("positions"), py::arg("cell"), py::arg("pbc"), py::arg("cutoff"),
        py::arg("self_interaction") = false, py::arg("strict") = true, py::arg("threads") = py::none());
}

}  // namespace frnn::python
