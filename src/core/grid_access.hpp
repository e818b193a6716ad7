// The one door into frnn::grid's traversal internals: the candidate runs of a cell's stencil,
// the cell starts and the sorted coordinates in search space. frnn's sweeps, queries and tests
// go through it, so the public class keeps to what a user calls (the pattern of ArborX's
// HappyTreeFriends). Nothing here checks its arguments: callers pass cells and indices of the
// grid they hold.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "frnn/grid.hpp"

namespace frnn::detail {

struct grid_access {
    template <class T, int D>
    using point = typename grid<T, D>::point;
    using cell = std::array<std::int64_t, 3>;

    /// All coordinates on `axis` in cell order, in search space, then coordinate_padding zeros.
    template <class T, int D>
    static const T* search_coords(const grid<T, D>& g, int axis) { return g.search_coords(axis); }
    template <class T, int D>
    static T search_coord(const grid<T, D>& g, std::size_t s, int axis) { return g.search_coord(s, axis); }
    /// Sorted points [s, end) lie in one cell and share their candidate runs.
    template <class T, int D>
    static std::uint32_t cell_group_end(const grid<T, D>& g, std::uint32_t s) { return g.cell_group_end(s); }

    /// The runs of sorted points whose cells lie within reach of x (search space).
    template <class T, int D>
    static std::size_t candidate_runs(const grid<T, D>& g, const point<T, D>& x, candidate_run* out) {
        return g.candidate_runs(x, out);
    }
    /// The runs of the stencil of `c`, and its forward half: see grid::stencil_runs and
    /// grid::forward_runs for `width` and `images`.
    template <class T, int D>
    static std::size_t stencil_runs(const grid<T, D>& g, const cell& c, candidate_run* out, std::int64_t width = 1,
                                    run_image* images = nullptr) {
        return g.stencil_runs(c, out, width, images);
    }
    /// A radius per point: their squares in search space, cell order, then coordinate_padding
    /// zeros; null for a grid of one radius.
    template <class T, int D>
    static const T* point_r2(const grid<T, D>& g) { return g.point_radii_ ? g.point_r2_.data() : nullptr; }
    template <class T, int D>
    static std::size_t forward_runs(const grid<T, D>& g, const cell& c, candidate_run* out, std::int64_t width = 1,
                                    run_image* images = nullptr) {
        return g.forward_runs(c, out, width, images);
    }
    /// Periodic box: the run images are the minimum images.
    template <class T, int D>
    static bool images_exact(const grid<T, D>& g) { return g.images_exact(); }

    /// Uniform grid: the sorted points of cell c are [starts[c], starts[c + 1]). Hashed grid:
    /// the starts of the occupied table slots, in slot order, then size().
    template <class T, int D>
    static std::span<const std::uint32_t> cell_starts(const grid<T, D>& g) { return g.cell_starts(); }
    /// Hashed grid: whether sorted point j lies in cell c.
    template <class T, int D>
    static bool hashed_point_in_cell(const grid<T, D>& g, std::uint32_t j, const cell& c) {
        return g.hashed_point_in_cell(j, c);
    }
    /// Distance squared between x and sorted point j in search space (minimum image if periodic).
    template <class T, int D>
    static T distance_squared_sorted(const grid<T, D>& g, const point<T, D>& x, std::uint32_t j) {
        return g.distance_squared_sorted(x, j);
    }
    /// The caller's query point x in search space, checked (index: for the message).
    template <class T, int D>
    static point<T, D> search_point(const grid<T, D>& g, const point<T, D>& x, std::size_t index) {
        return g.search_point(x, index);
    }
};

}  // namespace frnn::detail
