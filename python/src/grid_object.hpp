// frnn::python::grid_object: the C++ side of frnn.Grid. It owns one frnn::grid of the input's
// precision (float32 or float64) and dimension (2 or 3), chosen at run time, and turns numpy
// inputs into spans and results into numpy arrays.
//
// Build and queries run with the GIL released. A shared mutex lets several Python threads query
// one Grid at once while update() waits for them and runs alone, so no thread interleaving can
// make a query read a half-rebuilt grid. The mutex is never held while taking the GIL (results
// are computed under the lock, then converted), which rules out lock-order deadlocks.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <shared_mutex>
#include <string>
#include <variant>

#include "frnn/grid.hpp"

namespace frnn::python {

namespace py = pybind11;

/// The coordinate type and dimension of a grid type.
template <class G>
struct grid_traits;
template <class T, int D>
struct grid_traits<grid<T, D>> {
    using type = T;
    static constexpr int dim = D;
};

/// Keyword options of frnn.Grid, as Python gave them.
struct grid_args {
    std::string grid = "auto";
    std::optional<double> cell_size;
    py::object periodic = py::none();
    std::optional<int> threads;
    std::string rule = "gather";  ///< with a radius per point
};

class grid_object {
public:
    /// `radius`: one value, or an array of one per point (a radius per point).
    grid_object(const py::object& points, const py::object& radius, const grid_args& args);

    py::array query_pairs() const;
    py::tuple neighbors(bool return_distances, const py::object& sort, bool half, const py::object& rows) const;
    py::array count_neighbors() const;
    py::object query_ball_point(const py::object& x, const py::object& r, bool return_distances,
                                const py::object& sort, bool return_length) const;
    py::tuple query_knn(std::int64_t k, const py::object& x) const;
    void update(const py::object& points);
    py::array reorder(const py::object& array) const;
    py::array restore_order(const py::object& array) const;
    py::array permutation() const;
    // The cells (grid_cells.cpp), in the caller's units.
    py::tuple cell_of(const py::object& x) const;
    py::tuple cells_within(const py::object& x) const;
    py::tuple cell_bounds(const py::object& cell) const;

    std::size_t size() const;
    double radius() const;
    py::object radii() const;
    py::object rule() const;
    int dim() const;
    py::dtype dtype() const;
    std::string kind() const;
    std::size_t slots() const;
    std::size_t occupied_slots() const;
    double cell_size() const;
    py::object periodic() const;
    int threads() const;
    std::size_t memory_bytes() const;
    std::string repr() const;

private:
    using any_grid = std::variant<grid<float, 2>, grid<float, 3>, grid<double, 2>, grid<double, 3>>;

    grid_object() = default;
    bool is_float32() const { return g_.index() < 2; }
    /// Builds `target` over `points` (any accepted array) with these radius (one value or one
    /// per point) and options.
    static void build_into(any_grid& target, py::handle points, const py::object& radius,
                           const grid_options& options);
    /// The grid's points in the caller's order (exact copies of the stored coordinates).
    py::array original_points() const;
    /// Runs f(grid) with the GIL released under the shared (reading) lock.
    template <class F>
    auto under_read_lock(F&& f) const;

    any_grid g_;
    grid_options options_;
    mutable std::shared_mutex mutex_;
    bool valid_ = true;  // false after a failed update(), until one succeeds
};

}  // namespace frnn::python
