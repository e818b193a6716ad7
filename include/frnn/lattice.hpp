// frnn::lattice_grid: neighbor lists of atoms in a periodic cell of any shape.
//
// The cell is given by its lattice vectors (rows a, b and, in 3D, c) and is periodic on the
// axes `pbc` marks, as ASE's Atoms.cell and Atoms.pbc. It may be triclinic, left-handed, and
// smaller than the cutoff: a pair of atoms is then listed once for every periodic image within
// the cutoff, each with its integer shift S, and an atom is its own neighbor through every
// non-zero S within reach (never with S = 0). A vector on an open axis may be zero or
// degenerate (it is not used); the vectors of the periodic axes must span their space.
//
// For the entry (i, j, S) the distance vector and the distance are
//     D = (x_j - x_i) + s,   s = S_a a + S_b b + S_c c (in double, then rounded to T),
//     d = sqrt(D_x^2 + D_y^2 + D_z^2)                   (in T, in this order),
// ASE's convention, on the caller's coordinates: atoms may lie anywhere, any number of cells
// out (wrapping into the cell is internal, for binning only), and S refers to the positions as
// given. The entry is listed when d <= the cutoff (d < with lattice_options::strict, as ASE),
// or, with a radius per atom, d <= r_i + r_j (ASE's natural cutoffs).
//
// How: the atoms within the cutoff of the cell's faces are copied once per periodic image the
// cutoff reaches, and the atoms and their copies are searched together by the open-boundary
// grid (frnn::grid, rows for the atoms only). Every candidate is then decided by the formula
// above, so that bounds, ties and rounding are those of the formula, not of the copies.
//
// Results are identical, bit for bit, for any thread count.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "frnn/buffer.hpp"
#include "frnn/csr.hpp"
#include "frnn/grid.hpp"
#include "frnn/options.hpp"

namespace frnn {

/// A periodic cell: lattice vectors as rows, and which axes are periodic.
template <int D>
struct lattice {
    std::array<std::array<double, D>, D> vectors{};  ///< vectors[k] is the k-th lattice vector
    std::array<bool, D> pbc{};                         ///< periodic along vectors[k]
};

struct lattice_options {
    bool strict = false;  ///< list pairs with d < limit (ASE) instead of d <= limit
    /// Threads for build and lists; 0: frnn::default_thread_count(). Searches of fewer than
    /// 4,096 atoms and image copies run on the calling thread (the pool costs more there).
    int threads = 0;
};

struct lattice_list_options {
    /// Each pair of atoms once per image: (i, j, S) with j > i, or j == i and the first
    /// non-zero component of S positive; (j, i, -S) is left out.
    bool half = false;
    bool self = false;       ///< also (i, i, 0) at distance 0, first in its row (when 0 is within i's limit)
    bool distances = false;  ///< fill lattice_csr::distances with d
    bool vectors = false;    ///< fill lattice_csr::vectors with D
    /// Inside each row: none (the search's order: deterministic, cheapest), index (by j,
    /// then S), or distance (by d, then j, then S).
    row_order order = row_order::none;
};

/// Neighbor lists with shifts: row i of the CSR (indices: j) has, per entry, D shift values
/// and, when requested, the distance and D components of the distance vector.
template <class T, int D>
struct lattice_csr : csr<T> {
    buffer<std::int32_t> shifts;  ///< D values per entry: S
    buffer<T> vectors;            ///< D values per entry: the distance vector, or empty
};

template <class T, int D>
class lattice_grid {
    static_assert(D == 2 || D == 3, "frnn supports 2D and 3D points");
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);

public:
    lattice_grid() = default;
    /// Builds over `coords` (N*D interleaved values) in `cell` with one cutoff (finite, > 0).
    lattice_grid(std::span<const T> coords, const lattice<D>& cell, T cutoff, const lattice_options& options = {}) {
        build(coords, cell, cutoff, options);
    }
    void build(std::span<const T> coords, const lattice<D>& cell, T cutoff, const lattice_options& options = {});
    /// The same with a radius per atom (finite, >= 0): i and j are neighbors within r_i + r_j.
    void build(std::span<const T> coords, const lattice<D>& cell, std::span<const T> radii,
               const lattice_options& options = {});

    std::size_t size() const { return coords_.size() / D; }
    /// Copies of atoms the search holds beside the atoms: images within reach of the cell.
    std::size_t image_count() const { return image_atom_.size(); }
    const lattice<D>& cell() const { return cell_; }

    /// Neighbor lists of every atom, rows in the caller's order.
    lattice_csr<T, D> neighbor_lists(const lattice_list_options& options = {}) const;

    /// The number of image copies a build of these atoms would hold, without building
    /// (the same checks as build). Throws as build does.
    static std::size_t count_images(std::span<const T> coords, const lattice<D>& cell, T reach);

private:
    void build_with(std::span<const T> coords, const lattice<D>& cell, T max_limit, std::vector<T> radii,
                    const lattice_options& options);

    lattice<D> cell_;
    lattice_options options_;
    T cutoff_ = 0;                          // one cutoff; unused with radii
    double rounding_ = 0;                   // bound on rounding's change of a distance
    std::vector<T> radii_;                  // radius per atom, or empty
    std::vector<T> coords_;                 // the caller's coordinates
    std::vector<std::int32_t> wrap_;        // D per atom: the cells it lies out (its frac floor)
    std::vector<std::uint32_t> image_atom_; // per image copy: its atom
    std::vector<std::int32_t> image_shift_; // per image copy, D values: its shift from the wrapped atom
    std::vector<T> image_offset_;           // per image copy, D values: its shift times the cell, in T
    std::array<std::array<double, D>, D> shift_rows_{};  // the lattice vectors, 0 on open axes
    grid<double, D> search_;                 // atoms (wrapped) then image copies
};

extern template class lattice_grid<float, 2>;
extern template class lattice_grid<float, 3>;
extern template class lattice_grid<double, 2>;
extern template class lattice_grid<double, 3>;

}  // namespace frnn
