// A scene run one step at a time, for interactive use (the viewer) where run() would run it to
// its end: step, reset, change a parameter (live when the solver allows it, else by restarting
// the scene), and copy the particles into a snapshot for drawing.
//
// Steps are those of run(): the same scene gives the same particles, bit for bit, after the
// same number of steps. Complexity: a step is the solver's; a snapshot is O(N).
// Thread safety: none inside; one thread steps it, and a snapshot is a plain value that
// another thread may read once handed over.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "frnn/sim/parameters.hpp"
#include "frnn/sim/profiler.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

namespace frnn::sim {

/// The particles at one step, in particle-id order (entry k is the particle created k-th), so
/// every field of every entry comes from the same step.
struct particle_snapshot {
    int dim = 3;
    std::uint64_t step = 0;
    double time = 0;
    double spacing = 0;  ///< the lattice spacing the scene was seeded with
    std::size_t n = 0;
    std::vector<float> x;  ///< n * 3; z = 0 in 2D
    std::vector<float> speed, density, pressure;
    std::vector<std::uint32_t> neighbors;  ///< in the last step's lists
    double radius = 0;                     ///< the solver's neighbor (kernel support) radius
    grid_geometry<float> geometry;         ///< the last step's grid (solver::geometry())
};

class simulation {
public:
    /// Seeds the scene (throws frnn::error as make_solver does). threads 0: all.
    explicit simulation(scene s, int threads = 0);

    /// Advances one time step.
    void step();
    /// Back to step 0 of the current scene, with its current parameters.
    void reset();
    /// Replaces the scene and starts it at step 0.
    void set_scene(scene s);
    /// Sets one parameter of the table. Returns true when the scene restarted (the parameter is
    /// not live, see parameter::live); a parameter of the other solver only changes the scene.
    /// A value outside the parameter's range throws frnn::error and changes nothing.
    bool set_parameter(const parameter& p, double value);
    /// Sets the gravity from the next step on.
    void set_gravity(const vec3& g);
    /// Replaces the colliders from the next step on, keeping the particles: colliders moved,
    /// added or deleted by hand. Flattened to the xy plane in a 2D scene.
    void set_colliders(std::vector<collider> colliders);

    const scene& current_scene() const { return scene_; }
    const solver& state() const { return *solver_; }
    std::uint64_t steps() const { return solver_->steps(); }
    double time() const { return solver_->time(); }
    const profiler& timings() const { return prof_; }
    /// Times the steps from now on with `p` (a tracing one captures a Chrome trace of the next
    /// steps); reset(), a new scene and a loaded checkpoint start a fresh, non-tracing one.
    void set_profiler(profiler p) { prof_ = std::move(p); }

    /// Writes the scene (with its current parameters) and the full state to `path` in the
    /// format of `frnn sim`'s checkpoint.bin: `frnn sim --resume DIR` continues a folder holding
    /// it as checkpoint.bin, and load_checkpoint() restores it bit for bit.
    void save_checkpoint(const std::string& path) const;
    /// Replaces the scene and the state by those of a checkpoint (this one's or a run's). A file
    /// that is not a checkpoint throws frnn::error naming it and leaves the simulation as it was.
    void load_checkpoint(const std::string& path);

    /// Copies the particles into `out`, reusing its memory.
    void snapshot(particle_snapshot& out) const;

private:
    scene scene_;
    int threads_;
    std::unique_ptr<solver> solver_;
    profiler prof_;
};

}  // namespace frnn::sim
