// Walls as particles (Adami, Hu and Adams, "A generalized wall boundary condition for smoothed
// particle hydrodynamics", J. Comput. Phys. 231, 2012): the static colliders are filled with
// particles, on the fluid's lattice continued, as deep as the kernel's support behind their
// surface. Each step a wall particle takes the pressure its fluid neighbors extrapolate to it,
// with the hydrostatic rise towards it (their eq. 27, a wall at rest), and the density the
// equation of state gives for that pressure; the fluid counts them in its density sum and
// momentum equation as particles at rest. A kernel integral over a wall (sph.cpp) gives a
// particle beside a side wall its own pressure behind the wall, holding up none of the weight
// above it; extrapolated pressure does (validation: the hydrostatic tank).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/error.hpp"
#include "frnn/grid.hpp"
#include "frnn/sim/colliders.hpp"
#include "frnn/sim/scene.hpp"
#include "parallel.hpp"

namespace frnn::sim::detail {

template <int D>
class wall_particles {
public:
    /// Fills the colliders that do not move with particles about `spacing` apart down to
    /// `support` behind their surfaces, for a fluid of `fluid` particles (which bounds the
    /// lattices searched, see below). An axis-aligned box gets a lattice of its own whose
    /// spacing divides its sides, so that each face lies half a spacing in front of its first
    /// layer (Adami et al.'s wall surface) at any resolution; another collider continues the
    /// first fluid box's lattice. A point in the solid of two colliders belongs to the first.
    void seed(const scene& s, const std::vector<collider>& colliders, double spacing, double support, int threads,
              std::size_t fluid) {
        x_.clear();
        holds_.assign(colliders.size(), 0);
        if (s.is_periodic()) throw error("sph.wall_particles: not in a periodic domain");
        if (s.fluid.empty() || s.fluid[0].kind != fluid_block::kind_t::box)
            throw error("sph.wall_particles: the first fluid block must be a box (its lattice continues into the walls)");
        std::vector<posed_collider> still;
        for (std::size_t k = 0; k < colliders.size(); ++k)
            if (at_rest(colliders[k])) holds_[k] = 1, still.emplace_back(colliders[k], 0.0);
        // The lattices over the domain are searched for points in the walls: bounded, so that a
        // domain far larger than its fluid is an error, not an hour of seeding.
        const double most = 64.0 * double(fluid) + double(1 << 20);
        double searched = 0;
        for (std::size_t c = 0; c < still.size(); ++c) {
            const lattice l = lattice_of(s, still[c].desc(), spacing, support);
            // Counted in double: a vast domain's indices need not fit an integer.
            double points = 1;
            for (int a = 0; a < D; ++a) points *= l.hi_index[a] - l.lo_index[a] + 1;
            searched += points;
            if (searched > most)
                throw error("sph.wall_particles: the domain and the kernel's support around it hold " +
                            std::to_string(searched) + " lattice points at spacing " + std::to_string(spacing) +
                            ", more than " + std::to_string(std::llround(most)) +
                            " (64 per fluid particle, plus 2^20): shrink the domain or turn wall_particles off");
            std::int64_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
            for (int a = 0; a < D; ++a) lo[a] = std::int64_t(l.lo_index[a]), hi[a] = std::int64_t(l.hi_index[a]);
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
                for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
                        const std::int64_t idx[3] = {i, j, k};
                        vec3 x{0, 0, 0}, normal;
                        for (int a = 0; a < D; ++a) x[a] = l.first[a] + double(idx[a]) * l.step[a];
                        const double own = still[c].phi(x, normal);  // distance into the fluid's space
                        if (own > 0 || own <= -support) continue;
                        bool keep = true;
                        for (std::size_t o = 0; o < still.size() && keep; ++o) {
                            if (o == c) continue;
                            const double other = still[o].phi(x, normal);
                            keep = other > -support && (o > c || other > 0);
                        }
                        if (keep)
                            for (int a = 0; a < D; ++a) x_.push_back(float(x[a]));
                    }
        }
        p_over_rho2_.assign(size(), 0);
        records_.assign(4 * size(), 0);
        for (std::size_t k = 0; k < size(); ++k) {
            for (int a = 0; a < D; ++a) records_[4 * k + std::size_t(a)] = x_[k * D + std::size_t(a)];
            records_[4 * k + 3] = float(s.sph.rest_density);
        }
        if (empty()) return;
        grid_options o;
        o.threads = threads;
        grid_.build(std::span<const float>(x_), float(support), o);
    }

    bool empty() const { return x_.empty(); }
    std::size_t size() const { return x_.size() / D; }
    /// Whether collider k is made of wall particles (it does not move).
    bool holds(std::size_t k) const { return k < holds_.size() && holds_[k]; }

    /// This step's neighbors: of each fluid particle (the positions x, in the solver's order)
    /// among the walls, by one query of the wall grid; and of each wall particle that has any,
    /// the same pairs transposed. (A query of the fluid grid by those wall particles found the
    /// same rows, as both grids square the same float radius, at twice the cost.)
    void find(std::span<const float> x, profiler& prof) {
        serial(prof, stage::neighbors, [&] {
            fluid_walls_ = grid_.query(x);
            transpose();
        });
    }

    /// Wall neighbors of fluid particle i: [begin, end).
    const std::uint32_t* begin(std::size_t i) const { return fluid_walls_.indices.data() + fluid_walls_.offsets[i]; }
    const std::uint32_t* end(std::size_t i) const { return fluid_walls_.indices.data() + fluid_walls_.offsets[i + 1]; }

    /// Positions, D floats per wall particle.
    const float* positions() const { return x_.data(); }
    /// Wall particle k's extrapolated state, {rho, p / rho^2}: the density pass reads the
    /// last step's (extrapolate() runs after it), so a checkpoint holds it.
    std::array<float, 2> state(std::size_t k) const { return {records_[4 * k + 3], p_over_rho2_[k]}; }
    void set_state(std::size_t k, const std::array<float, 2>& s) { records_[4 * k + 3] = s[0], p_over_rho2_[k] = s[1]; }
    /// The wall particles' records {x, rho} (4 floats each, see neighbor_lanes.hpp) and p / rho^2.
    const float* records() const { return records_.data(); }
    const float* pressure_terms() const { return p_over_rho2_.data(); }

    /// p_w = max(0, (sum_f p_f W_wf + g . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf) over the
    /// fluid neighbors f, and rho_w = density_of(p_w), for the wall particles near the fluid
    /// (the others keep theirs: no fluid particle sees them). sums(w, begin, end) gives the
    /// three sums (wall_sums: the kernel's constant factor cancels) of wall particle w over its
    /// fluid neighbors [begin, end), in ascending fluid index.
    template <class Sums, class DensityOf>
    void extrapolate(int threads, profiler& prof, Sums sums, DensityOf density_of) {
        parallel_for(active_.size(), threads, prof, stage::density, [&](std::size_t n) {
            const std::size_t k = active_[n];
            const auto s = sums(k, wall_fluid_indices_.data() + wall_fluid_offsets_[n],
                                wall_fluid_indices_.data() + wall_fluid_offsets_[n + 1]);
            // A fluid neighbor exactly at the support weighs 0: pressure 0 when it is the only one.
            const double sum_w = s.weight;
            const double pressure = sum_w > 0 ? std::max(0.0, (double(s.pressure) + double(s.rise)) / sum_w) : 0;
            const float p = float(pressure), rho = float(density_of(pressure));
            records_[4 * k + 3] = rho;
            p_over_rho2_[k] = float(double(p) / (double(rho) * rho));
        });
    }

private:
    /// The wall particles in fluid_walls_ (active_, ascending) and their rows of fluid
    /// neighbors, each in ascending fluid index: a counting sort of the pairs by wall.
    void transpose() {
        const auto& off = fluid_walls_.offsets;
        const auto& walls = fluid_walls_.indices;
        row_of_.assign(size(), 0);
        for (const std::uint32_t w : walls) ++row_of_[w];  // first the count of each wall's row
        active_.clear();
        wall_fluid_offsets_.assign(1, 0);
        for (std::size_t w = 0; w < size(); ++w)
            if (row_of_[w]) {
                wall_fluid_offsets_.push_back(wall_fluid_offsets_.back() + row_of_[w]);
                row_of_[w] = std::uint32_t(active_.size());
                active_.push_back(std::uint32_t(w));
            }
        next_.assign(wall_fluid_offsets_.begin(), wall_fluid_offsets_.end() - 1);
        wall_fluid_indices_.resize(walls.size());
        for (std::size_t f = 0; f + 1 < off.size(); ++f)
            for (std::uint64_t e = off[f]; e < off[f + 1]; ++e) wall_fluid_indices_[next_[row_of_[walls[e]]]++] = std::uint32_t(f);
    }

    struct lattice {
        double step[3] = {1, 1, 1}, first[3] = {0, 0, 0}, lo_index[3] = {0, 0, 0}, hi_index[3] = {0, 0, 0};
    };

    /// Collider c's lattice (see seed) and the index range that covers the domain and the
    /// kernel's support around it.
    static lattice lattice_of(const scene& s, const collider& c, double spacing, double support) {
        lattice l;
        const bool aligned_box = c.kind == shape::box && c.angle == 0;
        const auto& b = s.fluid[0];
        for (int a = 0; a < D; ++a) {
            // A side of length L holds round(L / spacing) steps, as the seeding of a fluid box.
            const double lo = aligned_box ? c.center[a] - c.half[a] : b.min[a];
            const double length = aligned_box ? 2 * c.half[a] : b.max[a] - b.min[a];
            l.step[a] = length / std::max(1.0, std::round(length / spacing));
            l.first[a] = lo + 0.5 * l.step[a];
            // A solid box's particles lie within it: its lattice (as fine as a thin plate is
            // thin) is searched over the box only, not over the whole domain.
            double from = s.domain_min[a] - support, to = s.domain_max[a] + support;
            if (aligned_box && !c.inside) from = std::max(from, lo), to = std::min(to, lo + length);
            l.lo_index[a] = std::floor((from - l.first[a]) / l.step[a]);
            l.hi_index[a] = std::ceil((to - l.first[a]) / l.step[a]);
        }
        return l;
    }

    static bool at_rest(const collider& c) {
        const motion& m = c.path;
        for (int a = 0; a < 3; ++a)
            if (m.velocity[a] != 0 || m.amplitude[a] != 0) return false;
        return m.angular_velocity == 0;
    }

    std::vector<float> x_;
    std::vector<char> holds_;
    grid<float, D> grid_;
    std::vector<float> p_over_rho2_;  ///< p / rho^2 per wall particle
    std::vector<float> records_;      ///< {x, rho} per wall particle
    csr<float> fluid_walls_;
    std::vector<std::uint32_t> row_of_;  ///< per wall particle: its row among active_
    std::vector<std::uint32_t> active_;  ///< this step's wall particles with a fluid neighbor
    std::vector<std::uint64_t> wall_fluid_offsets_, next_;  ///< rows of active_, and a cursor per row
    std::vector<std::uint32_t> wall_fluid_indices_;         ///< their fluid neighbors
};

}  // namespace frnn::sim::detail
