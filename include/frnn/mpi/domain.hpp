// frnn::mpi::domain: the fixed-radius neighbor search across MPI ranks.
//
// Every particle carries a global id (uint64). A time step:
//   balance(coords, ids)  wraps particles outside the periodic box into it (as frnn::grid
//                         does, frnn/periodic_wrap.hpp), moves every particle to the rank that
//                         owns its place (recursive coordinate bisection, recomputed when asked,
//                         on the first call, or when the load imbalance exceeds
//                         options.imbalance) and returns the distributor that moved them:
//                         migrate the caller's other fields with it;
//   build(coords, ids)    receives the ghosts (particles within r + skin of this rank's
//                         sub-domain, periodic images shifted) and builds frnn's CPU grid over
//                         local + ghost particles;
//   update(coords)        later steps: refreshes ghost positions through the same plan and
//                         rebuilds the grid, as long as no particle moved more than skin / 2;
//   neighbor_lists()      rows for the local particles, indices into local + ghost arrays;
//                         halo() gathers and scatter_adds any other field in that layout.
// The pairs found are exactly those of a single-process frnn::grid over all particles (same
// distance formula, minimum image when periodic), whatever the number of ranks or threads.
//
// Bad input on any rank (ranks disagreeing on the radius, the box or the skin, non-finite
// coordinates, points outside the periodic box given to build, fewer particles than ranks,
// arrays of the wrong size) makes every rank throw the same frnn::error.
// Complexity: balance O(n log ranks) plus the decomposition when recomputed, build and update
// O(n + ghosts) plus one message per neighboring rank, lists as frnn::grid's.
// Rank safety: every member but the accessors is collective over the communicator given at
// construction (duplicated: frnn's messages never meet the caller's). Thread safety: const
// members may be called concurrently.
#pragma once
#include <mpi.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/grid.hpp"
#include "frnn/mpi/decomposition.hpp"
#include "frnn/mpi/distributor.hpp"
#include "frnn/mpi/halo.hpp"

namespace frnn::mpi {

struct domain_options {
    std::vector<double> periodic;  ///< box lengths, each > 2 (r + skin); empty: open
    double skin = 0;               ///< ghosts reach r + skin: particles may move skin / 2
    double imbalance = 0.1;        ///< balance() re-cuts past this imbalance (max / mean - 1)
    int threads = 0;               ///< the local grid's threads (0: frnn::default_thread_count())
};

/// What the last balance() and build() (or update()) cost on this rank, for reports and
/// benchmarks: wall times and the bytes sent to other ranks (the payload of the messages; the
/// counts of each plan's MPI_Alltoall and the reductions of the cut are not included).
struct domain_stats {
    double decompose_ms = 0;  ///< cutting space (reductions on every level); 0 when the cuts were kept
    double migrate_ms = 0;    ///< moving particles and ids to their owners
    double halo_ms = 0;       ///< the ghost plan and the ghosts' coordinates and ids
    double grid_ms = 0;       ///< the local grid over local + ghost particles (no messages)
    std::uint64_t migrate_bytes = 0, halo_bytes = 0;
};

template <class T, int D>
class domain {
public:
    /// Collective over `comm` (which is duplicated): checks that every rank passed the same
    /// radius and options.
    domain(MPI_Comm comm, T radius, domain_options options = {});
    domain(const domain&) = delete;
    domain& operator=(const domain&) = delete;
    ~domain();

    /// Moves this rank's particles (coords n*D values, ids, optional weights: a cost per
    /// particle for the cut) to their owners; on return they hold this rank's particles,
    /// wrapped into the periodic box.
    /// `rebalance` re-cuts space whatever the imbalance.
    const distributor& balance(std::vector<T>& coords, std::vector<std::uint64_t>& ids,
                               std::vector<double>* weights = nullptr, bool rebalance = false);
    /// Ghosts and the local grid for this rank's particles (as balance() left them).
    void build(std::span<const T> coords, std::span<const std::uint64_t> ids);
    /// New coordinates of the same local particles: refreshes the ghosts through the plan of
    /// the last build and rebuilds the grid. Returns false (on every rank, changing nothing)
    /// when some particle moved more than skin / 2 since that build: balance and build again.
    bool update(std::span<const T> coords);

    MPI_Comm comm() const { return comm_; }
    T radius() const { return radius_; }
    const decomposition<T, D>& cuts() const { return cuts_; }
    const frnn::mpi::halo<T, D>& halo() const { return halo_; }
    const domain_stats& stats() const { return stats_; }
    std::size_t local_size() const { return halo_.local_size(); }
    std::size_t ghost_size() const { return halo_.ghost_size(); }
    /// Local then ghost particles: coordinates (ghosts shifted by their images) and ids.
    std::span<const T> positions() const { return positions_; }
    std::span<const std::uint64_t> ids() const { return ids_; }

    /// Neighbors of each local particle (rows local_size()), indices into positions(), by
    /// increasing index, with distances when asked.
    csr<T> neighbor_lists(bool distances = false) const;
    /// Every pair (id of a local particle, id of its neighbor), sorted.
    std::vector<std::array<std::uint64_t, 2>> global_pairs() const;

private:
    void build_grid();
    bool has_periodic_axis() const;
    /// Whether the local grid's own distance test gives exactly the single-process pairs of
    /// every particle but the shifted ghosts: the same search scale, coordinates in the box.
    bool grid_decides() const;
    /// The lists with candidates decided again by the single-process test on the owners'
    /// coordinates, through the minimum image only: the shifted ghosts if only_shifted, else
    /// every one.
    csr<T> decided_by_owners(csr<T> lists, bool distances, bool only_shifted) const;

    MPI_Comm comm_ = MPI_COMM_NULL;
    T radius_;
    domain_options options_;
    T candidate_radius_;  // the grid's radius: r, plus rounding slack for shifted images
    T scale_ = 1;         // the single-process search scale (frnn/search_scale.hpp)
    decomposition<T, D> cuts_;
    bool have_cuts_ = false;
    distributor moved_;
    frnn::mpi::halo<T, D> halo_;
    std::vector<T> raw_;        // local + ghost coordinates as their owners hold them
    std::vector<T> positions_;  // the same, ghosts shifted by their images
    std::vector<T> built_;      // local coordinates at the last build
    std::vector<std::uint64_t> ids_;
    std::vector<char> shifted_;  // per ghost: at another periodic image than its owner's
    std::vector<T> radii_;       // periodic box: the grid's radius per point (r; shifted ghosts wider)
    bool in_box_ = true;         // every coordinate below its periodic box length (as T)
    grid<T, D> grid_;
    domain_stats stats_;
};

extern template class domain<float, 2>;
extern template class domain<float, 3>;
extern template class domain<double, 2>;
extern template class domain<double, 3>;

}  // namespace frnn::mpi
