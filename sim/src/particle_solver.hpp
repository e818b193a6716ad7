// State and steps shared by the solvers: particle arrays in cell order, the grid, neighbor
// lists, collisions, the finite-value check and checkpoint I/O.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <limits>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/grid.hpp"
#include "frnn/parallel.hpp"
#include "frnn/sim/parameters.hpp"
#include "frnn/sim/solver.hpp"
#include "distribution.hpp"
#include "neighbors.hpp"
#include "parallel.hpp"

namespace frnn::sim::detail {

template <class U>
void write_vec(std::ostream& o, const std::vector<U>& v) {
    const std::uint64_t n = v.size();
    o.write(reinterpret_cast<const char*>(&n), sizeof n);
    o.write(reinterpret_cast<const char*>(v.data()), std::streamsize(n * sizeof(U)));
}
/// Bytes from the read position of `in` to its end: a length read from a corrupt file is
/// checked against it before anything is allocated.
inline std::uint64_t bytes_left(std::istream& in) {
    const auto here = in.tellg();
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    in.seekg(here);
    return here < 0 || end < here ? 0 : std::uint64_t(end - here);
}
template <class U>
void read_vec(std::istream& in, std::vector<U>& v, std::size_t expected) {
    std::uint64_t n = 0;
    in.read(reinterpret_cast<char*>(&n), sizeof n);
    if (!in || n != expected) throw error("checkpoint: array of " + std::to_string(n) + " values, expected " + std::to_string(expected));
    if (n > bytes_left(in) / sizeof(U)) throw error("checkpoint: truncated array");
    v.resize(n);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(U)));
    if (!in) throw error("checkpoint: truncated array");
}
template <class U>
void write_pod(std::ostream& o, const U& v) { o.write(reinterpret_cast<const char*>(&v), sizeof v); }
template <class U>
void read_pod(std::istream& in, U& v) {
    in.read(reinterpret_cast<char*>(&v), sizeof v);
    if (!in) throw error("checkpoint: truncated");
}

template <int D>
class particle_solver : public solver {
public:
    particle_solver(const scene& s, int threads)
        : scene_(s), threads_(resolve_thread_count(threads)), colliders_(s.colliders) {
        auto seeded = seed(s);
        spacing_ = seeded.spacing;
        n_ = seeded.count;
        x_ = std::move(seeded.x);
        v_ = std::move(seeded.v);
        rho_.assign(n_, 0);
        p_.assign(n_, 0);
        id_.resize(n_);
        for (std::size_t i = 0; i < n_; ++i) id_[i] = std::uint32_t(i);
        total_ = n_;
        periodic_ = s.is_periodic();
        if (periodic_) {
            for (int a = 0; a < D; ++a) box_[a] = float(s.periodic[a]);  // 0: an open axis
            wrap_into_box();
        }
    }

    particle_view view() const override {
        if (gathered()) {
            const auto& f = gathered_;
            return {D, gathered_id_.size(), f[0].data(), f[1].data(), f[2].data(), f[3].data(), gathered_id_.data()};
        }
        return {D, n_, x_.data(), v_.data(), rho_.data(), p_.data(), id_.data()};
    }

    void set_ranks(std::shared_ptr<rank_comm> ranks, const balance_options& balance) override {
        if (built_) throw error("set_ranks: call it before the first step");
        build_or_rebuild(radius());  // the one-process grid's cells, which the ranks share out
        if (grid_.kind() != grid_kind::uniform)
            throw ranks_agree_error("a simulation across ranks needs the scene's uniform grid (this domain needs the "
                                    "hashed grid: shrink it to a few times the fluid's extent)");
        cells_ = grid_.geometry();
        dist_ = std::make_unique<distribution<D>>(std::move(ranks), balance);
    }

    void gather() override {
        if (!dist_ || !dist_->started()) return;  // before the first step every rank holds every particle
        std::vector<carried_field> fields = {{&x_, D}, {&v_, D}, {&rho_, 1}, {&p_, 1}};
        for (const carried_field& f : extra_fields()) fields.push_back(f);
        dist_->gather(fields, id_, gathered_, gathered_id_);
        report_ = dist_->report();
    }
    particle_view id_share() override {
        if (!dist_) return view();
        const std::size_t rank = std::size_t(dist_->comm().rank()), ranks = std::size_t(dist_->comm().size());
        const std::size_t first = total_ * rank / ranks, end = total_ * (rank + 1) / ranks;
        std::vector<carried_field> fields = {{&x_, D}, {&v_, D}, {&rho_, 1}, {&p_, 1}};
        if (dist_->started()) {
            dist_->share_by_id(fields, id_, total_, share_, share_id_);
        } else {  // every rank holds every particle
            share_.assign(fields.size(), {});
            share_id_.clear();
            for (std::size_t i = 0; i < n_; ++i) {
                if (id_[i] < first || id_[i] >= end) continue;
                share_id_.push_back(id_[i]);
                for (std::size_t f = 0; f < fields.size(); ++f)
                    for (std::size_t c = 0; c < fields[f].components; ++c)
                        share_[f].push_back((*fields[f].data)[i * fields[f].components + c]);
            }
        }
        return {D, share_id_.size(), share_[0].data(), share_[1].data(), share_[2].data(), share_[3].data(), share_id_.data()};
    }
    ranks_report report_ranks() const override { return report_; }
    double largest_coordinate(int axis) override {
        if (!dist_ || !dist_->started()) return solver::largest_coordinate(axis);
        const double mine = reduce(
            n_, threads_, -std::numeric_limits<double>::infinity(),
            [&](std::size_t i) { return owned(i) ? double(x_[i * D + std::size_t(axis)]) : -std::numeric_limits<double>::infinity(); },
            [](double a, double b) { return std::max(a, b); });
        return dist_->max(mine);  // a max is exact in any order
    }
    double time() const override { return time_; }
    std::uint64_t steps() const override { return steps_; }
    double last_dt() const override { return last_dt_; }
    double spacing() const override { return spacing_; }
    const scene& get_scene() const override { return scene_; }
    std::uint32_t neighbor_count(std::size_t i) const override { return neighbors_.count(i); }
    const grid_geometry<float>& geometry() const override { return grid_.geometry(); }

    void set_parameters(const scene& s) override {
        const std::string section = parameter_section(scene_.solver);
        for (const auto& p : parameters())
            if (p.section == section && !p.live && p.get(s) != p.get(scene_))
                throw error("parameter " + p.name() + " cannot change while the scene runs; restart the scene");
        scene_.viscoelastic = s.viscoelastic;
        scene_.sph = s.sph;
        scene_.gravity = s.gravity;
        parameters_changed();
    }

    void set_velocities(std::span<const float> by_id) override {
        if (by_id.size() != n_ * D)
            throw error("set_velocities: " + std::to_string(by_id.size()) + " values for " + std::to_string(n_) +
                        " particles in " + std::to_string(D) + "D");
        for (std::size_t i = 0; i < n_; ++i)
            for (int a = 0; a < D; ++a) v_[i * D + a] = by_id[std::size_t(id_[i]) * D + a];
    }

    void set_colliders(const std::vector<collider>& colliders) override {
        scene_.colliders = colliders;  // a checkpoint saves them
        colliders_ = collider_set(colliders);
    }

protected:
    /// Called after set_parameters() changed scene_: the solver copies what it reads per step.
    virtual void parameters_changed() = 0;
    /// The solver's own per-particle state that a checkpoint holds (across ranks, gather()
    /// brings it to rank 0 after x, v, rho and p: gathered_[4], ...).
    virtual std::vector<carried_field> extra_fields() { return {}; }

    /// Across ranks after the first step: view() and save() show gather()'s particles.
    bool gathered() const { return dist_ && !gathered_.empty(); }

    /// Whether particle i is this rank's (always in one process; not a ghost across ranks).
    bool owned(std::size_t i) const { return !dist_ || !dist_->started() || !dist_->ghost(i); }

    /// Builds (first call) or rebuilds the grid over x and permutes x and every extra array
    /// (D values per particle, as x) into cell order. Across ranks a rank may hold no particle.
    template <class... Arrays>
    void rebuild_grid(profiler& prof, double radius, Arrays&... arrays) {
        if (dist_) return rebuild_distributed(prof, radius, arrays...);
        serial(prof, stage::grid, [&] {
            try {
                build_or_rebuild(radius);
            } catch (const error&) {
                check_finite(steps_ + 1);  // a non-finite position: say which particle
                throw;
            }
            grid_.reorder(std::span<float>(x_), D);
            grid_.reorder(std::span<float>(v_), D);
            grid_.reorder(std::span<std::uint32_t>(id_), 1);
            (grid_.reorder(std::span<typename Arrays::value_type>(arrays), D), ...);
        });
        neighbors_.build(grid_, prof);
    }

    /// rebuild_grid across ranks: the particles move to their ranks and the ghosts come in
    /// (distribution.hpp) before the grid sorts them.
    template <class... Arrays>
    void rebuild_distributed(profiler& prof, double, Arrays&... arrays) {
        serial(prof, stage::exchange, [&] {
            std::vector<carried_field> fields = {{&x_, D}, {&v_, D}, {&arrays, D}...};
            dist_->redistribute(grid_.geometry(), fields, id_);
            n_ = id_.size();
        });
        serial(prof, stage::grid, [&] {
            // A failure here is this rank's alone (the positions were checked at the end of the
            // last step): no collective call, the tool ends the job with its message.
            grid_.rebuild(std::span<const float>(x_));
            check_cells();
            grid_.reorder(std::span<float>(x_), D);
            grid_.reorder(std::span<float>(v_), D);
            grid_.reorder(std::span<std::uint32_t>(id_), 1);
            (grid_.reorder(std::span<typename Arrays::value_type>(arrays), D), ...);
            dist_->reorder(grid_);
            dist_->sorted(grid_, x_);
            rho_.resize(n_);
            p_.resize(n_);
        });
        neighbors_.build(grid_, prof);
    }

    /// A rank's grid must have the one-process grid's cells (their order is the row order).
    /// They are laid out for all the particles over the scene's domain (build_or_rebuild), so
    /// any part of the particles gets them; checked, as a wrong order would go unnoticed.
    void check_cells() const {
        const grid_geometry<float>& g = grid_.geometry();
        for (int a = 0; a < D; ++a)
            if (g.dims[a] != cells_.dims[a] || g.origin[a] != cells_.origin[a] || g.cell[a] != cells_.cell[a] ||
                g.kind != cells_.kind || g.reach != cells_.reach)
                throw error("this rank's " + std::to_string(n_) + " particles and ghosts do not give the one-process grid's "
                            "cells (" + std::to_string(g.dims[a]) + " instead of " + std::to_string(cells_.dims[a]) +
                            " along axis " + std::to_string(a) + ")");
    }

    void build_or_rebuild(double radius) {
        if (!built_) {
            grid_options o;
            o.kind = grid_kind::uniform;
            o.threads = threads_;
            // A fixed domain (the scene's, padded; a periodic axis spans its box) laid out for
            // all the particles keeps the cells, and so the neighbor order, a function of the
            // positions alone: the same on every rank, whatever part of them it holds.
            if (periodic_)
                for (int a = 0; a < D; ++a) o.periodic.push_back(box_[a]);
            o.domain_min.resize(D);
            o.domain_max.resize(D);
            for (int a = 0; a < D; ++a) {
                o.domain_min[std::size_t(a)] = scene_.domain_min[a] - radius;
                o.domain_max[std::size_t(a)] = scene_.domain_max[a] + radius;
            }
            o.layout_points = total_;
            try {
                grid_.build(std::span<const float>(x_), float(radius), o);
            } catch (const error&) {
                if (periodic_) throw;
                // A domain that needs more cells than a uniform grid may have (many times the
                // fluid's extent): the hashed grid, whose cells too are a function of the
                // positions alone. Any other bad input fails it the same way.
                o.kind = grid_kind::hashed;
                o.domain_min.clear();
                o.domain_max.clear();
                grid_.build(std::span<const float>(x_), float(radius), o);
            }
            built_ = true;
        } else {
            grid_.rebuild(std::span<const float>(x_));
        }
    }

    /// The boundaries at time t: wraps positions into the periodic box, then projects
    /// particles out of the colliders and reflects their velocities.
    void collide(profiler& prof, double t) {
        if (periodic_) parallel_for(n_, threads_, prof, stage::collisions, [&](std::size_t i) { wrap_point(i); });
        if (colliders_.empty()) return;
        const auto posed = colliders_.at(t);
        const double margin = 0.5 * spacing_;
        parallel_for(n_, threads_, prof, stage::collisions, [&](std::size_t i) {
            vec3 x{0, 0, 0}, v{0, 0, 0};
            for (int a = 0; a < D; ++a) x[a] = x_[i * D + a], v[a] = v_[i * D + a];
            bool moved = false;
            // Twice, so a particle pushed by one collider into another is resolved too.
            for (int pass = 0; pass < 2; ++pass)
                for (const auto& c : posed) moved |= c.resolve(x, v, margin);
            if (moved)
                for (int a = 0; a < D; ++a) x_[i * D + a] = float(x[a]), v_[i * D + a] = float(v[a]);
        });
    }

    /// The largest squared length of the per-particle vectors in `field` (D floats each), over
    /// this rank's particles (not its ghosts).
    double largest_norm_squared(const std::vector<float>& field) const {
        return reduce(
            n_, threads_, 0.0,
            [&](std::size_t i) {
                if (!owned(i)) return 0.0;
                double sum = 0;
                for (int a = 0; a < D; ++a) sum += double(field[i * D + a]) * field[i * D + a];
                return sum;
            },
            [](double a, double b) { return std::max(a, b); });
    }

    /// Throws if any position or velocity is not finite, naming the step and particle.
    void check_finite(std::uint64_t step) const {
        const auto finite = [&](std::size_t i) {
            for (int a = 0; a < D; ++a)
                if (!std::isfinite(x_[i * D + a]) || !std::isfinite(v_[i * D + a])) return false;
            return true;
        };
        const std::size_t bad = reduce(
            n_, threads_, n_, [&](std::size_t i) { return finite(i) || !owned(i) ? n_ : i; },
            [](std::size_t a, std::size_t b) { return std::min(a, b); });
        std::string what = diverged_message(step, bad);
        // Across ranks, the particle first in the one-process order, on every rank.
        if (dist_) what = dist_->first_found(bad < n_ ? &dist_->key(bad) : nullptr, what);
        if (what.empty()) return;
        if (dist_) throw ranks_agree_error(what);
        throw error(what);
    }
    std::string diverged_message(std::uint64_t step, std::size_t bad) const {
        if (bad < n_) {
            std::string what = "simulation diverged at step " + std::to_string(step) + " (t = " + std::to_string(time_) +
                               " s): particle " + std::to_string(id_[bad]) + " has position (";
            for (int a = 0; a < D; ++a) what += (a ? ", " : "") + std::to_string(x_[bad * D + a]);
            what += ") and velocity (";
            for (int a = 0; a < D; ++a) what += (a ? ", " : "") + std::to_string(v_[bad * D + a]);
            return what + "); try a smaller time step";
        }
        return {};
    }

    void save_common(std::ostream& o) const {
        write_pod(o, std::uint32_t(D));
        write_pod(o, time_);
        write_pod(o, steps_);
        write_pod(o, last_dt_);
        if (gathered()) {  // rank 0's gathered particles, as one process holds them
            write_pod(o, std::uint64_t(gathered_id_.size()));
            for (std::size_t f = 0; f < 4; ++f) write_vec(o, gathered_[f]);
            write_vec(o, gathered_id_);
            return;
        }
        write_pod(o, std::uint64_t(n_));
        write_vec(o, x_);
        write_vec(o, v_);
        write_vec(o, rho_);
        write_vec(o, p_);
        write_vec(o, id_);
    }
    void load_common(std::istream& in) {
        if (dist_) throw error("load: call it before set_ranks");
        std::uint32_t d = 0;
        std::uint64_t n = 0;
        read_pod(in, d);
        if (d != D) throw error("checkpoint: dimension " + std::to_string(d) + ", scene has " + std::to_string(D));
        read_pod(in, time_);
        read_pod(in, steps_);
        read_pod(in, last_dt_);
        read_pod(in, n);
        if (n != n_) throw error("checkpoint: " + std::to_string(n) + " particles, scene seeds " + std::to_string(n_));
        read_vec(in, x_, n_ * D);
        read_vec(in, v_, n_ * D);
        read_vec(in, rho_, n_);
        read_vec(in, p_, n_);
        read_vec(in, id_, n_);
        // Ids index arrays (output order, springs): they must be 0 .. n-1, each once.
        std::vector<bool> seen(n_, false);
        for (std::size_t i = 0; i < n_; ++i) {
            if (id_[i] >= n_ || seen[id_[i]])
                throw error("checkpoint: particle slot " + std::to_string(i) + " holds id " + std::to_string(id_[i]) +
                            ", not one of 0.." + std::to_string(n_ - 1) + " unused so far");
            seen[id_[i]] = true;
        }
    }

    /// r = x_j - x_i (the minimum image in a periodic box, the grid's formula); returns |r|.
    float dist(std::size_t i, std::size_t j, float* r) const {
        if (periodic_) [[unlikely]]
            return periodic_dist(i, j, r);
        float d2 = 0;
        for (int a = 0; a < D; ++a) {
            r[a] = x_[j * D + a] - x_[i * D + a];
            d2 += r[a] * r[a];
        }
        return std::sqrt(d2);
    }
    // Apart from dist(), so that the open boxes' loop stays as short as it was (a test per
    // axis inside it cost the default scene about 1% of its step).
    float periodic_dist(std::size_t i, std::size_t j, float* r) const {
        float d2 = 0;
        for (int a = 0; a < D; ++a) {
            r[a] = x_[j * D + a] - x_[i * D + a];
            if (box_[a] > 0) r[a] -= box_[a] * std::nearbyint(r[a] / box_[a]);
            d2 += r[a] * r[a];
        }
        return std::sqrt(d2);
    }

    /// Particle i's position moved into [0, L) on every periodic axis of the box.
    void wrap_point(std::size_t i) {
        for (int a = 0; a < D; ++a) {
            if (!(box_[a] > 0)) continue;  // an open axis
            float& x = x_[i * D + a];
            x -= box_[a] * std::floor(x / box_[a]);
            if (x >= box_[a]) x = 0;  // -tiny wraps to L after rounding
        }
    }
    void wrap_into_box() {
        for (std::size_t i = 0; i < n_; ++i) wrap_point(i);
    }

    scene scene_;
    int threads_;
    collider_set colliders_;
    double spacing_ = 0, time_ = 0, last_dt_ = 0;
    std::uint64_t steps_ = 0;
    std::size_t n_ = 0;
    std::vector<float> x_, v_, rho_, p_;
    std::vector<std::uint32_t> id_;
    grid<float, D> grid_;
    bool built_ = false;
    bool periodic_ = false;
    float box_[D] = {};  // periodic box lengths (0 on open axes)
    neighbor_table neighbors_;
    std::unique_ptr<distribution<D>> dist_;  // across ranks (set_ranks); null in one process
    grid_geometry<float> cells_;             // across ranks: the one-process grid's cells
    std::vector<std::vector<float>> gathered_;  // gather(): x, v, rho, p, then extra_fields()
    std::vector<std::uint32_t> gathered_id_;
    std::size_t total_ = 0;                   // the particles of all ranks
    std::vector<std::vector<float>> share_;  // id_share(): x, v, rho, p
    std::vector<std::uint32_t> share_id_;
    ranks_report report_;
};

}  // namespace frnn::sim::detail
