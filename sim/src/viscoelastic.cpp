// The viscoelastic fluid of Clavet, Beaudoin and Poulin, "Particle-based Viscoelastic Fluid
// Simulation" (SCA 2005), made deterministic and lock-free: every pairwise update of the paper
// (applied to i and j in turn) is gathered by each particle from its own neighbor list into a
// separate buffer (Jacobi style), so each pair gives each side half of the paper's update.
// The paper's algorithms, where they are here: 1 the step (step), 2 double density relaxation
// (relax), 3 and 4 spring adjustment and displacements (springs), 5 viscosity impulses
// (viscosity). q = r_ij / h throughout.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "particle_solver.hpp"
#include "solvers.hpp"
#include "viscoelastic_pairs.hpp"

namespace frnn::sim {
namespace detail {
namespace {

struct spring {
    std::uint32_t partner;  // particle id
    float rest;             // rest length L
};

template <int D>
class viscoelastic final : public particle_solver<D> {
    using base = particle_solver<D>;
    using base::n_, base::x_, base::v_, base::rho_, base::p_, base::id_, base::threads_, base::neighbors_;

public:
    viscoelastic(const scene& s, int threads) : base(s, threads), prm_(s.viscoelastic) {
        h_ = prm_.h_ratio * this->spacing_;
        rho0_ = prm_.rest_density > 0 ? prm_.rest_density : lattice_density();
        prev_.resize(n_ * D);
        buf_.resize(n_ * D);
        v_buf_.resize(n_ * D);
        near_.resize(n_);
        pairs_ = viscoelastic_pairs_for<D>();
        if (prm_.springs) springs_.resize(n_), slot_of_id_.resize(n_);
    }
    double radius() const override { return h_; }
    double rest_density() const override { return rho0_; }
    /// Across ranks: ghosts two radii deep hold most spring partners (a spring lives while its
    /// rest length is at most h, and stretches beyond); the others are fetched by id.
    void set_ranks(std::shared_ptr<rank_comm> ranks, const balance_options& balance) override {
        base::set_ranks(std::move(ranks), balance);
        this->dist_->set_halo_depth(2);
    }

    /// Across ranks, also each particle's springs, to rank 0 by id.
    void gather() override {
        base::gather();
        if (!this->gathered() || !prm_.springs) return;
        rank_bytes mine;
        for (std::size_t i = 0; i < n_; ++i)
            if (this->owned(i)) append_springs(mine, id_[i]);
        gathered_springs_.assign(this->total_, {});
        for (const rank_bytes& b : this->dist_->comm().gather(mine)) read_spring_lists(b, gathered_springs_);
    }

    void step(profiler& prof) override {
        prof.set_step(this->steps_);
        const double step_dt = time_step();
        const bool ranks = this->dist_ != nullptr;
        const float dt = float(step_dt);
        const float g[3] = {float(this->scene_.gravity[0]), float(this->scene_.gravity[1]), float(this->scene_.gravity[2])};
        // Algorithm 1, with the viscosity after the prediction (it corrects the predicted
        // positions from its new velocities). Gravity, then predicted positions; the grid is
        // built on the prediction, so the relaxation sees the neighbors of the positions it
        // corrects. Velocities from the displacement, (x - x_prev) / dt, then collisions.
        parallel_for(n_, threads_, prof, stage::integration, [&](std::size_t i) {
            for (int a = 0; a < D; ++a) {
                const std::size_t k = i * D + a;
                v_[k] += dt * g[a];
                prev_[k] = x_[k];
                x_[k] += dt * v_[k];
            }
        }, min_parallel_light);
        this->rebuild_grid(prof, h_, prev_);
        if (ranks) {  // n_ changed: this rank's particles and ghosts
            buf_.resize(n_ * D), v_buf_.resize(n_ * D), near_.resize(n_);
            if (prm_.springs) serial(prof, stage::exchange, [&] { move_springs(); });
        }
        // Across ranks a ghost's own row lacks the neighbors beyond the halo: after each pass
        // that moves particles or sets what the next pass reads, the ghosts take their owners'.
        if (prm_.sigma > 0 || prm_.beta > 0) {
            viscosity(prof, dt);
            if (ranks) serial(prof, stage::exchange, [&] { this->dist_->refresh({{&x_, D}, {&v_, D}}); });
        }
        if (prm_.springs) {
            springs(prof, dt);
            if (ranks) serial(prof, stage::exchange, [&] { this->dist_->refresh({{&x_, D}}); });
        }
        relax(prof, dt);
        this->collide(prof, this->time_ + step_dt);
        this->time_ += step_dt;
        this->last_dt_ = step_dt;
        ++this->steps_;
        prof.end_step();
        this->check_finite(this->steps_);
    }

    void save(std::ostream& o) const override {
        this->save_common(o);
        write_vec(o, this->gathered() ? this->gathered_[4] : near_);
        const auto& springs = this->gathered() && prm_.springs ? gathered_springs_ : springs_;
        write_pod(o, std::uint64_t(springs.size()));
        for (const auto& list : springs) write_vec(o, list);
    }
    void load(std::istream& in) override {
        this->load_common(in);
        read_vec(in, near_, n_);
        std::uint64_t lists = 0;
        read_pod(in, lists);
        if (lists != springs_.size()) throw error("checkpoint: spring lists do not match the scene");
        for (std::size_t k = 0; k < springs_.size(); ++k) {
            auto& list = springs_[k];
            std::uint64_t count = 0;
            auto pos = in.tellg();
            read_pod(in, count);
            in.seekg(pos);
            read_vec(in, list, count);
            // Partners index the particles; a rest length is a distance.
            for (const auto& s : list)
                if (s.partner >= n_ || !std::isfinite(s.rest) || s.rest < 0)
                    throw error("checkpoint: particle " + std::to_string(k) + " has a spring to particle " +
                                std::to_string(s.partner) + " of rest length " + std::to_string(s.rest) + " (" +
                                std::to_string(n_) + " particles)");
        }
    }

private:
    void parameters_changed() override { prm_ = this->scene_.viscoelastic; }
    std::vector<carried_field> extra_fields() override { return {{&near_, 1}}; }

    template <class U>
    static void append_pod(rank_bytes& b, const U& v) {
        const char* at = reinterpret_cast<const char*>(&v);
        b.insert(b.end(), at, at + sizeof v);
    }
    /// Particle id's springs as {id, count, springs}.
    void append_springs(rank_bytes& b, std::uint32_t id) const {
        const auto& list = springs_[id];
        append_pod(b, id);
        append_pod(b, std::uint32_t(list.size()));
        const char* at = reinterpret_cast<const char*>(list.data());
        b.insert(b.end(), at, at + list.size() * sizeof(spring));
    }
    /// Lists written as {id, count, springs} into lists[id].
    void read_spring_lists(const rank_bytes& b, std::vector<std::vector<spring>>& lists) const {
        for (std::size_t at = 0; at < b.size();) {
            std::uint32_t id = 0, count = 0;
            if (at + 2 * sizeof(std::uint32_t) > b.size()) throw error("ranks: a truncated spring message");
            std::memcpy(&id, b.data() + at, sizeof id), at += sizeof id;
            std::memcpy(&count, b.data() + at, sizeof count), at += sizeof count;
            if (id >= lists.size() || at + std::size_t(count) * sizeof(spring) > b.size())
                throw error("ranks: a spring message for particle " + std::to_string(id) + " out of range");
            lists[id].resize(count);
            std::memcpy(lists[id].data(), b.data() + at, std::size_t(count) * sizeof(spring)), at += std::size_t(count) * sizeof(spring);
        }
    }
    /// Across ranks: the springs of the particles that went to other ranks go with them.
    void move_springs() {
        std::vector<rank_bytes> out(std::size_t(this->dist_->comm().size()));
        for (const auto& [id, q] : this->dist_->departures()) {
            append_springs(out[std::size_t(q)], id);
            std::vector<spring>().swap(springs_[id]);
        }
        for (const rank_bytes& b : this->dist_->comm().exchange(out)) read_spring_lists(b, springs_);
    }

    /// The scene's dt, shortened so no particle moves more than cfl * h in one step (the
    /// relaxation only corrects displacements that are small against h).
    double time_step() const {
        if (prm_.cfl <= 0) return prm_.dt;
        const double g2 = this->scene_.gravity[0] * this->scene_.gravity[0] + this->scene_.gravity[1] * this->scene_.gravity[1] +
                          this->scene_.gravity[2] * this->scene_.gravity[2];
        double vmax2 = this->largest_norm_squared(v_);
        if (this->dist_) vmax2 = this->dist_->max(vmax2);
        const double v = std::sqrt(vmax2) + std::sqrt(g2) * prm_.dt;
        // With half the neighbors, the 2D relaxation tolerates less motion per step (measured:
        // the 2D dam break needs cfl 0.15 where 3D runs at 0.25).
        const double cfl = D == 2 ? 0.6 * prm_.cfl : prm_.cfl;
        const double dt = v > 0 ? std::min(prm_.dt, cfl * h_ / v) : prm_.dt;
        if (dt < 1e-3 * prm_.dt)
            throw ranks_agree_error("simulation unstable at step " + std::to_string(this->steps_ + 1) + ": a particle moves at " +
                        std::to_string(std::sqrt(vmax2)) + " m/s, the time step collapsed to " + std::to_string(dt) +
                        " s; lower viscoelastic.stiffness or dt");
        return dt;
    }

    /// Kernel sum (1 - q)^2 of an interior particle of the initial lattice.
    double lattice_density() const {
        const double s = this->spacing_;
        const int k = int(std::ceil(h_ / s));
        double sum = 0;
        for (int i = -k; i <= k; ++i)
            for (int j = -k; j <= k; ++j)
                for (int l = (D == 3 ? -k : 0); l <= (D == 3 ? k : 0); ++l) {
                    if (i == 0 && j == 0 && l == 0) continue;
                    const double q = s * std::sqrt(double(i * i + j * j + l * l)) / h_;
                    if (q < 1) sum += (1 - q) * (1 - q);
                }
        return sum;
    }

    /// Algorithm 5: for each approaching pair (u = (v_i - v_j) . r_hat > 0) the impulse
    /// I = dt (1 - q) (sigma u + beta u^2) r_hat, half to each side: linear (sigma) and
    /// quadratic (beta) viscosity.
    void viscosity(profiler& prof, float dt) {
        const viscosity_coefficients c{dt, float(prm_.sigma), float(prm_.beta)};
        const pair_view view = pair_arrays();
        // Each particle writes only its own new velocity and re-predicted position, so the
        // re-prediction x = x_prev + dt v shares the loop.
        parallel_for(n_, threads_, prof, stage::viscosity, [&](std::size_t i) {
            float dv[D];
            pairs_.viscosity(view, row(i), c, dv);
            for (int a = 0; a < D; ++a) {
                const std::size_t k = i * D + a;
                v_buf_[k] = v_[k] + dv[a];
                buf_[k] = prev_[k] + dt * v_buf_[k];
            }
        });
        v_.swap(v_buf_);
        x_.swap(buf_);
    }

    /// Algorithms 3 and 4: springs between neighbors closer than h, rest length L; beyond the
    /// tolerable deformation d = gamma L, L moves toward r_ij at rate alpha (plasticity), and
    /// springs longer than h break. Displacement dt^2 k (1 - L/h) (L - r_ij) r_hat, half to
    /// each side (the scene's spring_stiffness holds dt^2 k). Each particle keeps its own copy
    /// of each spring and updates it from the same symmetric distance as its partner does.
    void springs(profiler& prof, float dt) {
        const float h = float(h_), gamma = float(prm_.yield_ratio), alpha = float(prm_.plasticity);
        const float ks = float(prm_.spring_stiffness * dt2_scale(dt));
        if (this->dist_) std::fill(slot_of_id_.begin(), slot_of_id_.end(), far_partner);
        for (std::size_t i = 0; i < n_; ++i) slot_of_id_[id_[i]] = std::uint32_t(i);
        if (this->dist_) serial(prof, stage::exchange, [&] { fetch_far_partners(); });
        parallel_for(n_, threads_, prof, stage::springs, [&](std::size_t i) {
            if (!this->owned(i)) return;  // a ghost's springs are its owner's
            auto& list = springs_[id_[i]];
            for (auto* it = neighbors_.begin(i); it != neighbors_.end(i); ++it) {
                float r[D];
                const float len = this->dist(i, *it, r);
                if (len >= h) continue;
                const std::uint32_t pid = id_[*it];
                bool found = false;
                for (const auto& s : list) found |= s.partner == pid;
                if (!found) list.push_back({pid, len});
            }
            std::size_t kept = 0;
            for (auto s : list) {
                float r[D];
                const float len = partner_dist(i, s.partner, r);
                const float d = gamma * s.rest;
                if (len > s.rest + d) s.rest += dt * alpha * (len - s.rest - d);
                else if (len < s.rest - d) s.rest -= dt * alpha * (s.rest - d - len);
                if (s.rest <= h) list[kept++] = s;
            }
            list.resize(kept);
        });
        parallel_for(n_, threads_, prof, stage::springs, [&](std::size_t i) {
            float dx[D] = {};
            for (const auto& s : springs_[id_[i]]) {
                if (!this->owned(i)) break;  // a ghost takes its owner's position after the pass
                float r[D];
                const float len = partner_dist(i, s.partner, r);
                if (len <= 0) continue;
                const float mag = 0.5f * ks * (1 - s.rest / h) * (s.rest - len) / len;
                for (int a = 0; a < D; ++a) dx[a] -= mag * r[a];
            }
            for (int a = 0; a < D; ++a) buf_[i * D + a] = x_[i * D + a] + dx[a];
        });
        x_.swap(buf_);
    }

    static constexpr std::uint32_t far_partner = std::numeric_limits<std::uint32_t>::max();

    /// r = x_partner - x_i and |r|, as dist() gives them: from the partner's slot here, or
    /// across ranks from its position fetched by id (fetch_far_partners).
    float partner_dist(std::size_t i, std::uint32_t partner, float* r) const {
        const std::uint32_t slot = slot_of_id_[partner];
        if (slot != far_partner) return this->dist(i, slot, r);
        const auto it = std::lower_bound(far_ids_.begin(), far_ids_.end(), partner);
        if (it == far_ids_.end() || *it != partner) throw error("ranks: spring partner " + std::to_string(partner) + " not fetched");
        const float* x = far_.data() + std::size_t(it - far_ids_.begin()) * D;
        float d2 = 0;
        for (int a = 0; a < D; ++a) {
            r[a] = x[a] - x_[i * D + a];
            if (this->periodic_ && this->box_[a] > 0) r[a] -= this->box_[a] * std::nearbyint(r[a] / this->box_[a]);
            d2 += r[a] * r[a];
        }
        return std::sqrt(d2);
    }

    /// Across ranks: the positions of the spring partners of this rank's particles that are
    /// neither its particles nor its ghosts, from their owners, by id.
    void fetch_far_partners() {
        far_ids_.clear();
        for (std::size_t i = 0; i < n_; ++i)
            if (this->owned(i))
                for (const auto& s : springs_[id_[i]])
                    if (slot_of_id_[s.partner] == far_partner) far_ids_.push_back(s.partner);
        std::sort(far_ids_.begin(), far_ids_.end());
        far_ids_.erase(std::unique(far_ids_.begin(), far_ids_.end()), far_ids_.end());
        rank_comm& comm = this->dist_->comm();
        rank_bytes wanted(far_ids_.size() * sizeof(std::uint32_t));
        if (!far_ids_.empty()) std::memcpy(wanted.data(), far_ids_.data(), wanted.size());
        const std::vector<rank_bytes> asked = comm.all_gather(wanted);
        std::vector<rank_bytes> answers(asked.size());
        for (std::size_t q = 0; q < asked.size(); ++q)
            for (std::size_t at = 0; at + sizeof(std::uint32_t) <= asked[q].size(); at += sizeof(std::uint32_t)) {
                std::uint32_t id = 0;
                std::memcpy(&id, asked[q].data() + at, sizeof id);
                const std::uint32_t slot = id < slot_of_id_.size() ? slot_of_id_[id] : far_partner;
                if (slot == far_partner || !this->owned(slot)) continue;
                append_pod(answers[q], id);
                for (int a = 0; a < D; ++a) append_pod(answers[q], x_[std::size_t(slot) * D + a]);
            }
        far_.assign(far_ids_.size() * D, 0);
        constexpr std::size_t record = sizeof(std::uint32_t) + D * sizeof(float);
        for (const rank_bytes& b : comm.exchange(answers))
            for (std::size_t at = 0; at + record <= b.size(); at += record) {
                std::uint32_t id = 0;
                std::memcpy(&id, b.data() + at, sizeof id);
                const auto it = std::lower_bound(far_ids_.begin(), far_ids_.end(), id);
                if (it == far_ids_.end() || *it != id) throw error("ranks: an answer for particle " + std::to_string(id) + " not asked for");
                std::memcpy(far_.data() + std::size_t(it - far_ids_.begin()) * D, b.data() + at + sizeof id, D * sizeof(float));
            }
    }

    /// Algorithm 2: density rho = sum (1 - q)^2 and near density sum (1 - q)^3, pressure
    /// P = k (rho - rho0) and near pressure k_near rho_near, then the displacement
    /// D = dt^2 (P (1 - q) + P_near (1 - q)^2) r_hat, half to each side. Here the pressures are
    /// dimensionless, divided by rho0, and a displacement is in units of h in place of dt^2
    /// (the scene's stiffnesses absorb the scale): each side moves by
    /// h/2 ((P_i + P_j)(1 - q) + (N_i + N_j)(1 - q)^2) r_hat, N the near pressures.
    /// The second pass also sets the velocities from the displacement, (x - x_prev) / dt.
    void relax(profiler& prof, float dt) {
        const float rho0 = float(rho0_), k = float(prm_.stiffness * dt2_scale(dt)), kn = float(prm_.near_stiffness * dt2_scale(dt));
        const pair_view view = pair_arrays();
        parallel_for(n_, threads_, prof, stage::relaxation, [&](std::size_t i) {
            float rho = 0, rho_near = 0;
            pairs_.density(view, row(i), &rho, &rho_near);
            rho_[i] = rho / rho0;             // relative density: 1 at rest
            p_[i] = k * (rho - rho0) / rho0;  // pressure, in units of h per unit (1 - q)
            near_[i] = kn * rho_near / rho0;
        });
        if (this->dist_) serial(prof, stage::exchange, [&] { this->dist_->refresh({&rho_, &p_, &near_}); });
        parallel_for(n_, threads_, prof, stage::relaxation, [&](std::size_t i) {
            float dx[D];
            pairs_.displacement(view, row(i), dx);
            for (int a = 0; a < D; ++a) {
                const std::size_t c = i * D + a;
                buf_[c] = x_[c] + dx[a];
                v_[c] = (buf_[c] - prev_[c]) / dt;
            }
        });
        x_.swap(buf_);
    }

    /// The stiffnesses hold dt^2 of the scene's dt; a step the CFL shortens scales them by
    /// (dt / scene dt)^2, as the paper's dt^2 does. Unscaled, a shorter step would move
    /// particles as far in less time: faster, so the next step is shorter still (the default
    /// scene at 125,000 particles ran away at step 27).
    double dt2_scale(float dt) const {
        const double ratio = double(dt) / prm_.dt;
        return ratio * ratio;
    }

    pair_view pair_arrays() const {
        return {x_.data(), v_.data(), p_.data(), near_.data(), this->periodic_ ? this->box_ : nullptr, float(h_)};
    }
    pair_row row(std::size_t i) const { return {i, neighbors_.begin(i), neighbors_.end(i)}; }

    viscoelastic_params prm_;
    double h_ = 0, rho0_ = 0;
    std::vector<float> prev_, buf_, v_buf_, near_;
    std::vector<std::vector<spring>> springs_;  // by particle id (across ranks: of this rank's particles)
    std::vector<std::uint32_t> slot_of_id_;
    std::vector<std::vector<spring>> gathered_springs_;  // across ranks: gather()'s, by id
    std::vector<std::uint32_t> far_ids_;  // across ranks: spring partners beyond the ghosts, ascending
    std::vector<float> far_;              // and their positions (fetch_far_partners)
    viscoelastic_pair_kernels<D> pairs_{};
};

}  // namespace

std::unique_ptr<solver> make_viscoelastic(const scene& s, int threads) {
    if (s.dim == 2) return std::make_unique<viscoelastic<2>>(s, threads);
    return std::make_unique<viscoelastic<3>>(s, threads);
}

}  // namespace detail
}  // namespace frnn::sim
