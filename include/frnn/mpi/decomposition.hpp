// frnn::mpi::decomposition: which rank owns which part of space, by recursive coordinate
// bisection (RCB). The ranks are split in two halves, space is cut across the axis along which
// the particles spread furthest so that each half gets its share of the particles (or of their
// costs), and each half is split again, until every rank has one box.
//
// Cuts lie on the cell lattice: at integer multiples of `cell` (the search radius), so that
// sub-domain faces never split a cell. A point belongs to the side of a cut by its cell index
// floor(x / cell) on that axis; the outer faces of an open domain are infinite (every point has
// an owner, however far), those of a periodic box are 0 and L.
//
// Complexity: building costs O(n log(cells) log(ranks)) per rank with n its particles, and
// about 70 reductions per level of the tree (a bisection search for each cut); owner() walks
// the tree, O(log ranks). Rank safety: construction is collective over `comm`; the result is
// the same on every rank. Thread safety: const members may be called concurrently.
#pragma once
#include <mpi.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace frnn::mpi {

template <class T, int D>
class decomposition {
    static_assert(D == 2 || D == 3, "frnn supports 2D and 3D points");

public:
    decomposition() = default;
    /// Collective over `comm`: cuts space for this rank's particles `coords` (n*D interleaved
    /// values) and the other ranks'. `periodic`: box lengths (empty: open), points must then
    /// lie in [0, L). `weights`: one non-negative cost per particle (empty: 1 each). Throws
    /// frnn::error on every rank for bad input on any rank (non-finite coordinates, points
    /// outside the box, ranks disagreeing on cell or box, fewer particles than ranks).
    decomposition(MPI_Comm comm, std::span<const T> coords, double cell, std::span<const double> periodic = {},
                  std::span<const double> weights = {});

    int ranks() const { return int(lower_.size()); }
    double cell() const { return cell_; }
    std::span<const double> periodic() const { return periodic_; }
    /// The rank whose sub-domain holds point x (D values).
    int owner(const T* x) const;
    std::vector<int> owners(std::span<const T> coords) const;
    /// Faces of a rank's sub-domain: [lower, upper) per axis, +-infinity on open outer faces.
    const std::array<double, D>& lower(int rank) const { return lower_[rank]; }
    const std::array<double, D>& upper(int rank) const { return upper_[rank]; }
    /// Appends to `out` every rank whose sub-domain lies within Euclidean distance `reach` of x
    /// (x as given, not wrapped), in increasing rank order.
    void ranks_near(const double* x, double reach, std::vector<int>& out) const;

private:
    struct node {
        int axis = 0;
        std::int64_t cut = 0;  // cells below `cut` go left
        int left = -1, right = -1, rank = -1;  // children, or the rank of a leaf
    };
    void find_near(int n, const double* x, double reach, std::vector<int>& out) const;
    std::int64_t cell_index(double x) const;

    double cell_ = 0;
    std::vector<double> periodic_;
    std::vector<node> nodes_;  // nodes_[0] is the root
    std::vector<std::array<double, D>> lower_, upper_;
};

/// Load imbalance: the largest rank's weight over the mean, minus 1 (0: perfect balance).
/// Collective over `comm`.
double imbalance(MPI_Comm comm, double local_weight);

extern template class decomposition<float, 2>;
extern template class decomposition<float, 3>;
extern template class decomposition<double, 2>;
extern template class decomposition<double, 3>;

}  // namespace frnn::mpi
