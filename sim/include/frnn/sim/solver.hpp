// The particle-fluid solvers behind one interface: the viscoelastic fluid of Clavet, Beaudoin
// and Poulin (2005) and weakly compressible SPH, in 2D and 3D, both on frnn::grid.
//
// Each step rebuilds the grid (rebuild() reuses its memory), permutes the particle arrays into
// the grid's cell order (grid::reorder) and runs every neighbor loop in parallel over the
// sorted particles. Every loop gathers into the particle it owns (Jacobi style: no scatter, no
// atomics), in the grid's deterministic neighbor order, so results are identical, bit for bit,
// for any thread count. Cost per step: O(N * neighbors).
//
// Thread safety: one solver per thread of the caller; a solver uses `threads` threads of frnn's pool.
#pragma once
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "frnn/grid_geometry.hpp"
#include "frnn/sim/profiler.hpp"
#include "frnn/sim/ranks.hpp"
#include "frnn/sim/scene.hpp"

namespace frnn::sim {

/// Read-only view of the particles, in the solver's current (cell) order. id[i] is the
/// particle's index at creation, so id-order output is stable across frames.
struct particle_view {
    int dim = 3;
    std::size_t n = 0;
    const float* x = nullptr;    ///< n * dim
    const float* v = nullptr;    ///< n * dim
    const float* rho = nullptr;  ///< density (kg/m^3 for SPH; the kernel sum for viscoelastic)
    const float* p = nullptr;    ///< pressure (Pa for SPH; k (rho - rho0) for viscoelastic)
    const std::uint32_t* id = nullptr;
};

class solver {
public:
    virtual ~solver() = default;
    /// Advances one time step. Throws frnn::error naming the step and particle when a position
    /// or velocity becomes non-finite.
    virtual void step(profiler& prof) = 0;
    virtual particle_view view() const = 0;
    virtual double time() const = 0;
    virtual std::uint64_t steps() const = 0;
    virtual double last_dt() const = 0;
    virtual double spacing() const = 0;
    /// Interaction (kernel support) radius.
    virtual double radius() const = 0;
    virtual double rest_density() const = 0;
    /// Checkpoint of the full state; load() restores it bit for bit.
    virtual void save(std::ostream& out) const = 0;
    virtual void load(std::istream& in) = 0;
    virtual const scene& get_scene() const = 0;
    /// Takes the live parameters (frnn/sim/parameters.hpp) of `s` and its gravity from the next
    /// step on. Throws frnn::error naming the parameter when `s` changes one that is not live
    /// for this solver (the scene must restart for it).
    virtual void set_parameters(const scene& s) = 0;
    /// Replaces the colliders from the next step on, keeping the particles (a viewer moving
    /// them by hand); the list must be valid for the scene's dimension (flatten_to_2d).
    virtual void set_colliders(const std::vector<collider>& colliders) = 0;
    /// Replaces every particle's velocity with by_id[id * dim + a] (id: the particle's index
    /// at creation, particle_view::id), e.g. to start from a velocity field. Throws
    /// frnn::error when by_id does not hold n * dim values.
    virtual void set_velocities(std::span<const float> by_id) = 0;
    /// Neighbors of particle i (view() order) in the last step's lists; 0 before the first step.
    virtual std::uint32_t neighbor_count(std::size_t i) const = 0;
    /// The cells of the grid the last step searched (frnn/grid_geometry.hpp), so a viewer can
    /// draw what the search visits; a default value (no slots) before the first step.
    virtual const grid_geometry<float>& geometry() const = 0;
    /// Wall particles standing in for colliders (WCSPH's wall_particles); 0 for none.
    virtual std::size_t wall_particle_count() const { return 0; }
    /// Runs this simulation as one of several ranks (frnn/sim/ranks.hpp), before its first
    /// step: each rank keeps the particles of its part of the domain, and every step gives the
    /// one-process result bit for bit. Throws frnn::ranks_agree_error for what does not run
    /// across ranks (docs/SCALING.md: domains that need the hashed grid).
    virtual void set_ranks(std::shared_ptr<rank_comm> ranks, const balance_options& balance = {});
    /// Across ranks, a collective call that brings every rank's particles to rank 0, in the
    /// one-process order, for view() and save() there (the other ranks' view is then empty);
    /// nothing in one process.
    virtual void gather() {}
    /// Across ranks, a collective call that gives rank r of P the particles whose ids are in
    /// [N r / P, N (r + 1) / P) of all N, in any order, for a frame every rank writes its part
    /// of (write_vtp with ranks, frnn/sim/output.hpp). In one process: view().
    virtual particle_view id_share() { return view(); }
    /// Across ranks, at the last gather(): each rank's particles and ghosts (copies of other
    /// ranks' particles within reach of its part), bytes sent, and the load balance; empty
    /// (no ranks) in one process.
    virtual ranks_report report_ranks() const { return {}; }
    /// The largest coordinate of any particle along `axis` (-infinity for none). Across ranks
    /// a collective call, the same on every rank, without gathering the particles.
    virtual double largest_coordinate(int axis);
};

/// Makes the scene's solver with its particles seeded. threads 0: all hardware threads.
std::unique_ptr<solver> make_solver(const scene& s, int threads = 0);

}  // namespace frnn::sim
