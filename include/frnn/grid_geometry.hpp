// frnn::grid_geometry: where a grid's cells are and how they are numbered.
//
// A grid chooses its geometry in full before it changes anything (grid::build) and keeps it as
// this one value: the kind, the cell edges, the cells per axis or table slots, the periodic
// box and the search scale. It locates points (cell_of), numbers cells (slot_of_cell) and says
// which cells a query visits (cells_within), so that everything that walks the cells, and a
// viewer that draws them, agrees with the search.
//
// Coordinates here are in search space: the caller's times search_scale() (1 except for
// extreme radii, see frnn/search_scale.hpp); cell_bounds converts back. Plain value; safe to
// copy and share between threads.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "frnn/options.hpp"
#include "frnn/periodic_wrap.hpp"

namespace frnn {

namespace detail {
/// Hash of a row of cells (y, z) for the hashed grid. Cell (x, y, z) lives in table slot
/// (row_hash(y, z) + x) mod slots, so the cells of one stencil row sit in consecutive slots
/// and their points form contiguous runs, as in the uniform grid.
inline std::uint64_t row_hash(std::int64_t y, std::int64_t z) {
    std::uint64_t h = std::uint64_t(y) * 0x9E3779B97F4A7C15ull + std::uint64_t(z) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return h;
}

/// The table slot of cell (x, y, z) of a hashed grid whose slot count is mask + 1.
inline std::uint64_t hashed_slot(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t mask) {
    return (row_hash(y, z) + std::uint64_t(x)) & mask;
}

/// floor(v) as an integer for |v| < 2^63, without a library call on CPUs lacking SSE4.1
/// rounding.
inline std::int64_t floor_to_int(double v) {
    const auto i = std::int64_t(v);
    return i - std::int64_t(double(i) > v);
}
}  // namespace detail

/// Integer coordinates of a cell (unused axes 0).
using cell_index = std::array<std::int64_t, 3>;

/// The cells a query visits: every cell whose coordinates lie in [first, last] on each axis.
/// On a periodic axis the coordinates may leave [0, cells per axis): such a cell is the one at
/// the coordinate modulo the cells per axis, in the neighboring image of the box.
struct cell_range {
    cell_index first{}, last{};
};

/// The geometry of a grid over coordinates of type T (see above); grid::geometry() gives it.
template <class T>
struct grid_geometry {
    grid_kind kind = grid_kind::uniform;  ///< never automatic
    bool periodic = false;             ///< some axis is periodic
    std::array<bool, 3> wraps{};       ///< which axes are periodic
    int reach = 1;                     ///< cells visited on each side
    std::array<double, 3> origin{};    ///< lower corner of cell (0,0,0)
    std::array<double, 3> cell{};      ///< effective cell edge per axis
    std::array<double, 3> inv_cell{};
    std::array<std::int64_t, 3> dims{1, 1, 1};  ///< cells per axis (uniform grid)
    std::array<T, 3> box{};            ///< periodic box lengths (0 on open axes)
    std::size_t slots = 0;             ///< cells (uniform) or table slots (hashed, a power of 2)
    T scale = 1;                       ///< search scale (frnn/search_scale.hpp)
    T search_radius = 0;               ///< radius * scale
    double far_bound = INFINITY;       ///< hashed: query coordinates beyond +-this have no neighbors

    /// The cell of point x (search space): clamped to the uniform grid (points outside it share
    /// its border cells), wrapped into a periodic box on its periodic axes (as the search
    /// wraps it, frnn/periodic_wrap.hpp).
    template <std::size_t D>
    cell_index cell_of(const std::array<T, D>& x) const {
        cell_index c{0, 0, 0};
        for (std::size_t a = 0; a < D; ++a) {
            const double v = double(x[a]);
            if (wraps[a]) {
                const double w = double(wrap_into_box(x[a], box[a])) * inv_cell[a];
                c[a] = std::int64_t(std::clamp(w, 0.0, double(dims[a] - 1)));
            } else if (kind == grid_kind::uniform) {
                c[a] = std::int64_t(std::clamp((v - origin[a]) * inv_cell[a], 0.0, double(dims[a] - 1)));
            } else {
                c[a] = detail::floor_to_int((v - origin[a]) * inv_cell[a]);
            }
        }
        return c;
    }

    /// The number of a cell: x + nx * (y + ny * z) on the uniform grid (a cell of it), its table
    /// slot on the hashed grid (shared by the cells that hash alike).
    std::size_t slot_of_cell(const cell_index& c) const {
        if (kind == grid_kind::uniform) return std::size_t(c[0] + dims[0] * (c[1] + dims[1] * c[2]));
        return std::size_t(detail::hashed_slot(c[0], c[1], c[2], slots - 1));
    }

    /// The cells a query at x (search space) visits: reach cells on each side of its cell,
    /// within the uniform grid, or around the box on a periodic axis.
    template <std::size_t D>
    cell_range cells_within(const std::array<T, D>& x) const {
        cell_range r;
        const cell_index c = cell_of(x);
        for (std::size_t a = 0; a < D; ++a) {
            r.first[a] = c[a] - reach;
            r.last[a] = c[a] + reach;
            if (kind == grid_kind::uniform && !wraps[a]) {
                r.first[a] = std::max<std::int64_t>(r.first[a], 0);
                r.last[a] = std::min(r.last[a], dims[a] - 1);
            }
        }
        return r;
    }

    /// Lower and upper corner of a cell in the caller's coordinates (search space divided by
    /// the scale). The border cells of a uniform grid also hold the points beyond it.
    std::array<std::array<double, 3>, 2> cell_bounds(const cell_index& c) const {
        std::array<std::array<double, 3>, 2> b{};
        for (std::size_t a = 0; a < 3; ++a) {
            b[0][a] = (origin[a] + double(c[a]) * cell[a]) / double(scale);
            b[1][a] = (origin[a] + double(c[a] + 1) * cell[a]) / double(scale);
        }
        return b;
    }
};

}  // namespace frnn
