// Weakly compressible SPH (Monaghan, "Simulating free surface flows with SPH", J. Comput.
// Phys. 110, 1994; and "Smoothed particle hydrodynamics", Rep. Prog. Phys. 68, 2005):
// - density by summation, rho_i = sum_j m W(r_ij) (plus the walls' share: from the kernel's
//   half-space integral, or from wall particles with extrapolated pressure, Adami, Hu and
//   Adams 2012, wall_particles.hpp), with the cubic spline kernel of Monaghan and Lattanzio (1985);
// - Tait's equation of state P = rho0 c0^2 / gamma ((rho / rho0)^gamma - 1) (Monaghan 1994,
//   with c0 ten times the largest free-fall speed, so density varies about 1%), or the linear
//   P = c0^2 (rho - rho0);
// - the symmetric momentum equation a_i = -sum_j m (P_i / rho_i^2 + P_j / rho_j^2 + Pi_ij)
//   grad_i W, with Monaghan's artificial viscosity Pi_ij = -alpha c0 mu_ij / rho_bar_ij for
//   approaching pairs, mu_ij = h v_ij . x_ij / (r_ij^2 + 0.01 h^2); or, with the laminar
//   viscosity, Morris, Fox and Zhu ("Modeling low Reynolds number incompressible flows using
//   SPH", J. Comput. Phys. 136, 1997, eq. 8) with mu = rho nu:
//   a_i += sum_j m (mu_i + mu_j) x_ij . grad_i W / (rho_i rho_j (r_ij^2 + 0.01 h^2)) v_ij;
// - symplectic Euler or leapfrog (kick-drift-kick), with a time step from the CFL condition
//   on c0 plus the flow speed, from the force condition 0.25 sqrt(h / |a|) and, with the
//   laminar viscosity, from the viscous condition 0.125 h^2 / nu (Morris et al. 1997);
// - optionally the transport velocity of Adami, Hu and Adams ("A transport-velocity
//   formulation for smoothed particle hydrodynamics", J. Comput. Phys. 241, 2013, eq. 13):
//   particles drift with v~ = v + dt a_b, a_b_i = -p_b sum_j m (1/rho_i^2 + 1/rho_j^2) grad_i W,
//   the force a uniform background pressure p_b would exert. It vanishes on a uniform
//   arrangement and pushes disordered particles back towards one, which keeps the tensile
//   instability from clumping them where the pressure is negative;
// - optionally ("density": "continuity") the density integrated by the continuity equation
//   d rho_i / dt = rho_i sum_j V_j v_ij . grad_i W (Antuono, Colagrossi, Marrone and Molteni,
//   "Free-surface flows solved by means of SPH schemes with numerical diffusive terms",
//   Comput. Phys. Commun. 181, 2010), V_j = m / rho_j, plus the density diffusion of Molteni
//   and Colagrossi ("A simple procedure to improve the pressure evaluation in hydrodynamic
//   context using the SPH", Comput. Phys. Commun. 180, 2009): 2 delta h c0 sum_j V_j
//   (rho_j - rho_i) x_ji . grad_i W / (r_ij^2 + 0.01 h^2), which damps the acoustic noise that
//   the summation's kernel sum filters and the continuity equation keeps. Wall particles
//   enter both sums as particles at rest with their extrapolated density and volume m / rho0
//   (their mass in the summation); the kernel integrals over colliders enter the force only.
//   The density is integrated after the velocity kick, from the kicked velocities, and with
//   symplectic Euler only (leapfrog's kicks would integrate rho and v both from old values).
// - optionally ("bulk_viscosity": alpha_b) a bulk viscosity zeta = alpha_b h c0: each particle's
//   pressure gains q_i = zeta d rho_i / dt = -zeta rho_i div v_i, with the continuity
//   equation's rate rho_i sum_j V_j v_ij . grad_i W (without diffusion). It resists
//   compression and expansion in proportion to their rate, so it damps sound, and it is 0 in a
//   uniform or divergence-free flow, so it leaves a thin fast jet its momentum (the artificial
//   viscosity, acting on every approaching pair, takes it);
// - optionally ("wall_friction") the friction of smooth walls: a particle within the kernel's
//   reach R of a collider's wall, at distance d, sliding along it at u, is slowed by
//   u_tau^2 (-2 dpsi/dd) along -u, with u_tau from the law of the wall at y = max(d, spacing / 2)
//   and nu (wall_friction.hpp), psi the kernel's integral beyond a wall at distance d: the
//   weight integrates to 1 over the depth, so a column of fluid feels the wall's shear stress
//   rho u_tau^2. It is meant for free-slip walls whose boundary layer is thinner than the
//   spacing can resolve: the law stands in for the layer.
// The pair sums (density, momentum equation, the wall particles' extrapolation) run in float,
// 8 neighbors at a time without a branch per pair (sph_pairs_impl.hpp), the same bits on every
// instruction-set level and thread count; the per-particle arithmetic (equation of state, the
// constant factors, the kernel integral over walls) is double.
#include <cmath>
#include <array>
#include <cstring>
#include <memory>
#include <type_traits>

#include "frnn/sim/kernels.hpp"
#include "particle_solver.hpp"
#include "solvers.hpp"
#include "sph_pairs.hpp"
#include "wall_friction.hpp"
#include "wall_particles.hpp"

namespace frnn::sim {
namespace detail {
namespace {

template <int D>
class sph final : public particle_solver<D> {
    using base = particle_solver<D>;
    using base::n_, base::x_, base::v_, base::rho_, base::p_, base::id_, base::threads_, base::neighbors_;

public:
    sph(const scene& s, int threads, std::string_view level)
        : base(s, threads), prm_(s.sph), h_(prm_.h_ratio * this->spacing_), w_(2 * h_), psi_(w_),
          pairs_(sph_pairs_for<D>(level)) {
        acc_.assign(n_ * D, 0);
        background_acc_.assign(n_ * D, 0);
        // The continuity equation starts from the rest density (the lattice's kernel sum).
        if (continuity()) {
            if (prm_.integrator != sph_params::integrator_t::symplectic_euler)
                throw error("sph.density: \"continuity\" needs the \"symplectic-euler\" integrator");
            rho_.assign(n_, float(prm_.rest_density));
        }
        position_.assign(4 * n_, 0);
        velocity_.assign(4 * n_, 0);
        // Mass: an interior particle of the initial lattice has exactly the rest density.
        const double sp = this->spacing_;
        const int k = int(std::ceil(2 * h_ / sp));
        double sum = 0;
        for (int i = -k; i <= k; ++i)
            for (int j = -k; j <= k; ++j)
                for (int l = (D == 3 ? -k : 0); l <= (D == 3 ? k : 0); ++l) sum += w_(sp * std::sqrt(double(i * i + j * j + l * l)));
        mass_ = prm_.rest_density / sum;
        wall_density_ = mass_ / std::pow(sp, D);
        double lo = 1e300, hi = -1e300;
        for (std::size_t i = 0; i < n_; ++i) lo = std::min(lo, double(x_[i * D + 1])), hi = std::max(hi, double(x_[i * D + 1]));
        const double fluid_height = hi - lo + sp;
        if (prm_.sound_speed > 0) {
            c0_ = prm_.sound_speed;
        } else {
            const double g = std::sqrt(s.gravity[0] * s.gravity[0] + s.gravity[1] * s.gravity[1] + s.gravity[2] * s.gravity[2]);
            c0_ = 10 * std::sqrt(2 * std::max(g, 1e-3) * fluid_height);
        }
        settle_rate_ = 3.14159265358979323846 * c0_ / fluid_height;
        seed_walls();
    }
    double radius() const override { return 2 * h_; }
    double rest_density() const override { return prm_.rest_density; }
    double sound_speed() const { return c0_; }

    void step(profiler& prof) override {
        prof.set_step(this->steps_);
        if (prm_.integrator == sph_params::integrator_t::leapfrog) {
            if (!have_acc_) evaluate(prof, this->time_), have_acc_ = true;
            const double dt = time_step();
            kick(prof, dt / 2);
            drift(prof, dt, dt / 2);
            this->collide(prof, this->time_ + dt);
            evaluate(prof, this->time_ + dt);
            kick(prof, dt / 2);
            settle(prof, dt);
            finish(prof, dt);
        } else {
            evaluate(prof, this->time_);
            const double dt = time_step();
            if (continuity()) {
                // The density from the kicked velocities: symplectic in (rho, v), whose sound
                // waves forward Euler (both from the old state) would amplify every step.
                kick(prof, dt);
                integrate_density(prof, dt);
                drift(prof, dt, dt);
            } else {
                kick_and_drift(prof, dt);
            }
            this->collide(prof, this->time_ + dt);
            settle(prof, dt);
            finish(prof, dt);
        }
    }

    void save(std::ostream& o) const override {
        this->save_common(o);
        write_vec(o, this->gathered() ? this->gathered_[4] : acc_);
        write_vec(o, this->gathered() ? this->gathered_[5] : background_acc_);
        write_pod(o, std::uint8_t(have_acc_));
        if (this->gathered()) return write_vec(o, gathered_walls_);
        std::vector<float> walls(2 * walls_.size());
        for (std::size_t k = 0; k < walls_.size(); ++k) {
            const std::array<float, 2> state = walls_.state(k);
            walls[2 * k] = state[0], walls[2 * k + 1] = state[1];
        }
        write_vec(o, walls);
    }
    void load(std::istream& in) override {
        this->load_common(in);
        read_vec(in, acc_, n_ * D);
        read_vec(in, background_acc_, n_ * D);
        std::uint8_t h = 0;
        read_pod(in, h);
        have_acc_ = h != 0;
        std::vector<float> walls;
        read_vec(in, walls, 2 * walls_.size());
        for (std::size_t k = 0; k < walls_.size(); ++k) walls_.set_state(k, {walls[2 * k], walls[2 * k + 1]});
    }

    /// Across ranks, also each wall particle's state, from the rank whose slab holds it: all
    /// the fluid within reach of it is there (the ghosts reach two radii).
    void gather() override {
        base::gather();
        if (!this->gathered() || walls_.empty()) return;
        gathered_walls_.assign(2 * walls_.size(), 0);
        for_each_wall_state(this->dist_->comm().gather(owned_wall_states()), [&](std::size_t k, const float* s) {
            gathered_walls_[2 * k] = s[0], gathered_walls_[2 * k + 1] = s[1];
        });
    }

    std::size_t wall_particle_count() const override { return walls_.size(); }

    void set_ranks(std::shared_ptr<rank_comm> ranks, const balance_options& balance) override {
        base::set_ranks(std::move(ranks), balance);
        if (walls_.empty()) return;
        // A wall particle within one radius of a particle takes its pressure from the fluid
        // within one radius of it (wall_particles.hpp): ghosts up to two radii away. Its state
        // is right on the rank whose slab holds it; a new cut takes it from there.
        this->dist_->set_halo_depth(2);
        this->dist_->before_rebalance([this] { share_wall_states(this->dist_->comm().all_gather(owned_wall_states())); });
    }

    void set_colliders(const std::vector<collider>& colliders) override {
        base::set_colliders(colliders);
        seed_walls();
    }

private:
    void parameters_changed() override { prm_ = this->scene_.sph; }
    std::vector<carried_field> extra_fields() override { return {{&acc_, D}, {&background_acc_, D}}; }
    bool laminar() const { return prm_.viscosity == sph_params::viscosity_t::laminar; }
    bool continuity() const { return prm_.density == sph_params::density_t::continuity; }

    void finish(profiler& prof, double dt) {
        this->time_ += dt;
        this->last_dt_ = dt;
        ++this->steps_;
        prof.end_step();
        this->check_finite(this->steps_);
    }

    /// CFL condition on sound speed plus flow speed, and the force condition.
    double time_step() const {
        // Both largest squared lengths in one parallel loop (a max is exact in any order).
        auto [vmax2, amax2] = reduce(
            n_, threads_, std::pair<double, double>(0, 0),
            [&](std::size_t i) {
                double v2 = 0, a2 = 0;
                if (!this->owned(i)) return std::pair<double, double>(0, 0);  // a ghost's forces are not computed
                for (int a = 0; a < D; ++a) v2 += double(v_[i * D + a]) * v_[i * D + a], a2 += double(acc_[i * D + a]) * acc_[i * D + a];
                return std::pair<double, double>(v2, a2);
            },
            [](const std::pair<double, double>& l, const std::pair<double, double>& r) {
                return std::pair<double, double>(std::max(l.first, r.first), std::max(l.second, r.second));
            });
        if (this->dist_) vmax2 = this->dist_->max(vmax2), amax2 = this->dist_->max(amax2);
        double dt = std::min(prm_.max_dt, prm_.cfl * h_ / (c0_ + std::sqrt(vmax2)));
        if (amax2 > 0) dt = std::min(dt, 0.25 * std::sqrt(h_ / std::sqrt(amax2)));
        if (laminar() && prm_.nu > 0) dt = std::min(dt, 0.125 * h_ * h_ / prm_.nu);
        if (prm_.bulk_viscosity > 0) dt = std::min(dt, 0.125 * h_ / (prm_.bulk_viscosity * c0_));  // 0.125 h^2 / zeta
        if (dt < 1e-3 * std::min(prm_.max_dt, prm_.cfl * h_ / c0_))
            throw ranks_agree_error("simulation unstable at step " + std::to_string(this->steps_ + 1) + ": a particle moves at " +
                        std::to_string(std::sqrt(vmax2)) + " m/s, the time step collapsed to " + std::to_string(dt) + " s");
        return dt;
    }

    void kick(profiler& prof, double dt) {
        const float d = float(dt);
        parallel_for(
            n_, threads_, prof, stage::integration,
            [&](std::size_t i) {
                for (std::size_t k = i * D; k < i * D + D; ++k) v_[k] += d * acc_[k];
            },
            min_parallel_light);
    }
    /// kick(dt) then drift(dt, dt) in one loop: each particle's own arithmetic, as the two do.
    void kick_and_drift(profiler& prof, double dt) {
        const float d = float(dt), kd = transport_velocity() ? d : 0.0f;
        parallel_for(
            n_, threads_, prof, stage::integration,
            [&](std::size_t i) {
                for (std::size_t k = i * D; k < i * D + D; ++k) {
                    v_[k] += d * acc_[k];
                    x_[k] += d * (v_[k] + kd * background_acc_[k]);
                }
            },
            min_parallel_light);
    }
    /// x += dt v, or with the transport velocity x += dt (v + kick_dt a_b) (Adami et al.
    /// 2013: the background pressure's kick, of the same length as the last velocity kick).
    void drift(profiler& prof, double dt, double kick_dt) {
        const float d = float(dt), kd = transport_velocity() ? float(kick_dt) : 0.0f;  // a_b is 0 when off
        parallel_for(
            n_, threads_, prof, stage::integration,
            [&](std::size_t i) {
                for (std::size_t k = i * D; k < i * D + D; ++k) x_[k] += d * (v_[k] + kd * background_acc_[k]);
            },
            min_parallel_light);
    }
    /// During the settling time, v /= 1 + rate dt (implicit friction, stable at any rate).
    void settle(profiler& prof, double dt) {
        if (this->time_ >= prm_.settle_time) return;
        const float keep = float(1 / (1 + settle_rate_ * dt));
        parallel_for(
            n_, threads_, prof, stage::integration,
            [&](std::size_t i) {
                for (std::size_t k = i * D; k < i * D + D; ++k) v_[k] *= keep;
            },
            min_parallel_light);
    }
    bool transport_velocity() const { return prm_.background_pressure > 0; }

    /// x^gamma; by squaring for a whole gamma up to 16 (Tait's 7: 4 products, a sixth of the
    /// time of std::pow).
    double power_gamma(double x) const {
        const double g = prm_.gamma;
        if (g < 1 || g > 16 || g != std::floor(g)) return std::pow(x, g);
        double result = 1, square = x;
        for (unsigned e = unsigned(g);; square *= square) {
            if (e & 1) result *= square;
            if ((e >>= 1) == 0) return result;
        }
    }

    float pressure(float rho) const {
        const double r = rho, r0 = prm_.rest_density;
        double p = prm_.eos == sph_params::eos_t::tait ? r0 * c0_ * c0_ / prm_.gamma * (power_gamma(r / r0) - 1)
                                                       : c0_ * c0_ * (r - r0);
        if (prm_.clamp_negative_pressure && p < 0) p = 0;
        return float(p);
    }

    /// Density at which the equation of state gives pressure p >= 0.
    double density_of(double p) const {
        const double r0 = prm_.rest_density;
        if (prm_.eos == sph_params::eos_t::tait) return r0 * std::pow(prm_.gamma * p / (r0 * c0_ * c0_) + 1, 1 / prm_.gamma);
        return r0 + p / (c0_ * c0_);
    }

    /// Wall particles for the static colliders (sph.wall_particles), or none.
    void seed_walls() {
        if (prm_.wall_particles)
            walls_.seed(this->scene_, this->colliders_.list(), this->spacing_, 2 * h_, threads_, n_);
    }

    /// Grid, density and pressure, then accelerations, at the current positions.
    void evaluate(profiler& prof, double t) {
        // Leapfrog's next drift reads the background accelerations of this evaluation; the
        // continuity equation's density is state that moves with its particle (carried in the
        // first of D floats per particle, as the grid moves D per particle).
        if (continuity()) {
            carried_rho_.assign(n_ * D, 0);
            for (std::size_t i = 0; i < n_; ++i) carried_rho_[i * D] = rho_[i];
            if (transport_velocity()) this->rebuild_grid(prof, 2 * h_, acc_, background_acc_, carried_rho_);
            else this->rebuild_grid(prof, 2 * h_, acc_, carried_rho_);
            rho_.resize(n_);
            for (std::size_t i = 0; i < n_; ++i) rho_[i] = carried_rho_[i * D];
        } else if (transport_velocity()) {
            this->rebuild_grid(prof, 2 * h_, acc_, background_acc_);
        } else {
            this->rebuild_grid(prof, 2 * h_, acc_);
        }
        position_.resize(4 * n_);  // across ranks, n_ changes every step
        velocity_.resize(4 * n_);
        const bool wall_particles = !walls_.empty();
        if (wall_particles) walls_.find(std::span<const float>(x_), prof);
        // Colliders that are not wall particles count by the kernel's integral over them.
        std::vector<posed_collider> walls;
        if (prm_.wall_density) {
            const auto posed = this->colliders_.at(t);
            for (std::size_t k = 0; k < posed.size(); ++k)
                if (!walls_.holds(k)) walls.push_back(posed[k]);
        }
        const bool use_walls = !walls.empty();
        const double R = 2 * h_, inv_rho0 = 1 / prm_.rest_density, norm = w_(0);  // W = norm w(r / R)
        // The pair passes' records: {x, rho} and {v, p / rho^2} (rho and p once known).
        parallel_for(
            n_, threads_, prof, stage::density,
            [&](std::size_t i) {
                for (int a = 0; a < D; ++a) position_[4 * i + a] = x_[i * D + a];
            },
            min_parallel_light);
        const sph_view view = pair_view(wall_particles);
        const auto row = [&](std::size_t i) { return row_of(i, wall_particles); };
        const bool summation = !continuity();
        parallel_for(n_, threads_, prof, stage::density, [&](std::size_t i) {
            if (!summation) return state_records(i);
            for (int a = 0; a < D; ++a) velocity_[4 * i + a] = v_[i * D + a];
            if (!this->owned(i)) return;  // a ghost takes its owner's density (refresh_ghosts)
            float fluid = 0, wall = 0;  // sum_j w_ij, sum_w w_iw rho_w
            pairs_.density(view, row(i), &fluid, &wall);
            double rho = mass_ * norm * (1 + double(fluid) + double(wall) * inv_rho0);
            if (use_walls) {
                vec3 x{0, 0, 0};
                for (int a = 0; a < D; ++a) x[a] = x_[i * D + a];
                for (const auto& c : walls) c.for_each_wall(x, R, [&](double d, const vec3&) { rho += wall_density_ * psi_(d); });
            }
            rho_[i] = float(rho);
            state_records(i);
        });
        if (this->dist_) serial(prof, stage::exchange, [&] { refresh_ghosts(); });
        if (prm_.bulk_viscosity > 0) add_bulk_viscosity(prof, view);
        const float g[3] = {float(this->scene_.gravity[0]), float(this->scene_.gravity[1]), float(this->scene_.gravity[2])};
        if (wall_particles) {
            walls_.extrapolate(
                threads_, prof,
                [&](std::size_t w, const std::uint32_t* begin, const std::uint32_t* end) {
                    return pairs_.extrapolation(view, w, begin, end, g);
                },
                [&](double p) { return density_of(p); });
        }
        // m dW/dr = m 6 norm / R g(q) (sph_pairs_impl.hpp).
        const double slope = mass_ * 6 * norm / R, nu = laminar() ? prm_.nu : 0, pb = prm_.background_pressure;
        const std::vector<posed_collider> friction_walls = prm_.wall_friction && prm_.nu > 0 ? this->colliders_.at(t) : std::vector<posed_collider>{};
        // The loop without friction is compiled apart: with the friction's call in it, the
        // forces took 13% longer (2D dam break, 20,000 particles).
        const auto forces = [&](auto with_friction) {
            parallel_for(n_, threads_, prof, stage::forces, [&](std::size_t i) {
                if (!this->owned(i)) return;  // a ghost's own row lacks the neighbors beyond the halo
                float pressure_sum[D], laminar_sum[D], background_sum[D];
                pairs_.forces(view, row(i), pressure_sum, laminar_sum, background_sum);
                double acc[D];
                for (int a = 0; a < D; ++a) acc[a] = slope * double(pressure_sum[a]) + slope * nu * double(laminar_sum[a]);
                if (use_walls && p_[i] > 0) {
                    vec3 x{0, 0, 0};
                    for (int a = 0; a < D; ++a) x[a] = x_[i * D + a];
                    // Mirror particles behind the wall with the particle's own pressure.
                    const double pi_term = velocity_[4 * i + 3];
                    for (const auto& c : walls)
                        c.for_each_wall(x, R, [&](double d, const vec3& nrm) {
                            const double s = -2 * pi_term * wall_density_ * psi_.derivative(d);
                            for (int a = 0; a < D; ++a) acc[a] += s * nrm[a];
                        });
                }
                if constexpr (decltype(with_friction)::value) add_wall_friction(i, friction_walls, acc);
                for (int a = 0; a < D; ++a) acc_[i * D + a] = float(acc[a] + g[a]);
                if (pb > 0)
                    for (int a = 0; a < D; ++a) background_acc_[i * D + a] = float(slope * pb * double(background_sum[a]));
            });
        };
        if (friction_walls.empty()) forces(std::false_type{});
        else forces(std::true_type{});
    }

    /// p_i += zeta d rho_i / dt (the bulk viscosity), and the records the forces read. Across
    /// ranks the ghosts take their owners' sums (a ghost's row lacks the neighbors beyond the
    /// halo).
    void add_bulk_viscosity(profiler& prof, sph_view view) {
        view.diffusion = 0;  // the rate of compression alone
        const double zeta = prm_.bulk_viscosity * h_ * c0_, factor = mass_ * 6 * w_(0) / (2 * h_);
        const bool wall_particles = !walls_.empty();
        bulk_.assign(n_, 0.0f);
        parallel_for(n_, threads_, prof, stage::density, [&](std::size_t i) {
            if (!this->owned(i)) return;
            bulk_[i] = float(zeta * factor * double(pairs_.density_rate(view, row_of(i, wall_particles))));
        });
        parallel_for(
            n_, threads_, prof, stage::density,
            [&](std::size_t i) {
                if (!this->owned(i)) return;
                p_[i] += bulk_[i];
                velocity_[4 * i + 3] = float(p_[i] / (double(rho_[i]) * rho_[i]));
            },
            min_parallel_light);
        if (this->dist_) serial(prof, stage::exchange, [&] { refresh_ghosts(); });
    }

    /// The walls' friction on particle i (wall_friction.hpp), added to acc.
    void add_wall_friction(std::size_t i, const std::vector<posed_collider>& walls, double* acc) const {
        vec3 x{0, 0, 0};
        for (int a = 0; a < D; ++a) x[a] = x_[i * D + a];
        const double y_min = 0.5 * this->spacing_;
        for (const auto& c : walls) {
            const vec3 wall_v = c.velocity_at(x);
            c.for_each_wall(x, 2 * h_, [&](double d, const vec3& normal) {
                double rel[D], normal_part = 0, u2 = 0;
                for (int a = 0; a < D; ++a) rel[a] = double(v_[i * D + a]) - wall_v[a], normal_part += rel[a] * normal[a];
                for (int a = 0; a < D; ++a) rel[a] -= normal_part * normal[a], u2 += rel[a] * rel[a];
                if (!(u2 > 0)) return;
                const double u = std::sqrt(u2), u_tau = friction_velocity(u, std::max(d, y_min), prm_.nu);
                const double slow = u_tau * u_tau * -2 * psi_.derivative(d) / u;
                for (int a = 0; a < D; ++a) acc[a] -= slow * rel[a];
            });
        }
    }

    /// rho += dt d rho / dt by the continuity equation with density diffusion, at this step's
    /// positions and densities (evaluate()'s records and wall states) and the kicked velocities.
    void integrate_density(profiler& prof, double dt) {
        parallel_for(
            n_, threads_, prof, stage::density,
            [&](std::size_t i) {
                for (int a = 0; a < D; ++a) velocity_[4 * i + a] = v_[i * D + a];
            },
            min_parallel_light);
        // Across ranks a ghost's acceleration misses the neighbors beyond the halo: its
        // owner's kicked velocity instead.
        if (this->dist_) serial(prof, stage::exchange, [&] { refresh_ghost_velocities(); });
        const bool wall_particles = !walls_.empty();
        const sph_view view = pair_view(wall_particles);
        const double factor = mass_ * 6 * w_(0) / (2 * h_);  // m dW/dr = m 6 norm / R g(q)
        parallel_for(n_, threads_, prof, stage::density, [&](std::size_t i) {
            if (!this->owned(i)) return;  // a ghost's row lacks the neighbors beyond the halo
            rho_[i] = float(rho_[i] + dt * factor * double(pairs_.density_rate(view, row_of(i, wall_particles))));
        });
    }
    void refresh_ghost_velocities() {
        std::vector<float> v[D];
        for (int a = 0; a < D; ++a) {
            v[a].resize(n_);
            for (std::size_t i = 0; i < n_; ++i) v[a][i] = v_[i * D + a];
        }
        if constexpr (D == 2) this->dist_->refresh({&v[0], &v[1]});
        else this->dist_->refresh({&v[0], &v[1], &v[2]});
        for (std::size_t i = 0; i < n_; ++i)
            if (!this->owned(i))
                for (int a = 0; a < D; ++a) velocity_[4 * i + a] = v[a][i];
    }

    /// Particle i's pressure from its density, and its records for the pair passes.
    void state_records(std::size_t i) {
        p_[i] = pressure(rho_[i]);
        position_[4 * i + 3] = rho_[i];
        for (int a = 0; a < D; ++a) velocity_[4 * i + a] = v_[i * D + a];
        // The pressure term of the momentum equation, once per particle, not per pair.
        velocity_[4 * i + 3] = float(p_[i] / (double(rho_[i]) * rho_[i]));
    }

    /// Across ranks: {index, rho, p / rho^2} of the wall particles in this rank's slab.
    rank_bytes owned_wall_states() const {
        rank_bytes mine;
        const int me = this->dist_->comm().rank();
        for (std::size_t k = 0; k < walls_.size(); ++k) {
            if (this->dist_->owner_of(this->grid_.geometry(), walls_.positions() + k * D) != me) continue;
            const std::uint32_t index = std::uint32_t(k);
            const std::array<float, 2> s = walls_.state(k);
            const char* at = reinterpret_cast<const char*>(&index);
            mine.insert(mine.end(), at, at + sizeof index);
            at = reinterpret_cast<const char*>(s.data());
            mine.insert(mine.end(), at, at + sizeof s);
        }
        return mine;
    }
    template <class F>
    void for_each_wall_state(const std::vector<rank_bytes>& parts, F&& f) const {
        constexpr std::size_t record = sizeof(std::uint32_t) + 2 * sizeof(float);
        for (const rank_bytes& b : parts)
            for (std::size_t at = 0; at + record <= b.size(); at += record) {
                std::uint32_t k = 0;
                float s[2];
                std::memcpy(&k, b.data() + at, sizeof k);
                std::memcpy(s, b.data() + at + sizeof k, sizeof s);
                if (k >= walls_.size()) throw error("ranks: wall particle " + std::to_string(k) + " out of range");
                f(std::size_t(k), s);
            }
    }
    void share_wall_states(const std::vector<rank_bytes>& parts) {
        for_each_wall_state(parts, [&](std::size_t k, const float* s) { walls_.set_state(k, {s[0], s[1]}); });
    }

    /// Across ranks: the ghosts' density and pressure from their owners, where a ghost's own
    /// row lacks the neighbors beyond this rank's halo, and the records the forces read.
    void refresh_ghosts() {
        this->dist_->refresh({&rho_, &p_});
        for (std::size_t i = 0; i < n_; ++i) {
            if (this->owned(i)) continue;
            position_[4 * i + 3] = rho_[i];
            velocity_[4 * i + 3] = float(p_[i] / (double(rho_[i]) * rho_[i]));
        }
    }

    /// Particle i's neighbors among the fluid and (with wall particles) the walls.
    sph_row row_of(std::size_t i, bool wall_particles) const {
        if (!wall_particles) return sph_row{i, neighbors_.begin(i), neighbors_.end(i), nullptr, nullptr};
        return sph_row{i, neighbors_.begin(i), neighbors_.end(i), walls_.begin(i), walls_.end(i)};
    }

    /// The arrays and constants of the pair passes (sph_pairs.hpp), this evaluation's.
    sph_view pair_view(bool with_walls) const {
        sph_view s;
        s.position = position_.data(), s.velocity = velocity_.data(), s.pressure = p_.data();
        s.box = this->periodic_ ? this->box_ : nullptr;
        if (with_walls) s.wall = walls_.records(), s.wall_p_over_rho2 = walls_.pressure_terms();
        s.support = float(2 * h_);
        s.eps2 = float(0.01 * h_ * h_);
        // Monaghan's Pi_ij = -alpha c0 h v_ij . x_ij / ((r^2 + 0.01 h^2) rho_bar_ij), for
        // approaching pairs, is c v_ij . x_ij / ((r^2 + 0.01 h^2)(rho_i + rho_j)).
        s.viscosity = laminar() ? 0.0f : float(-2 * std::max(prm_.alpha, 0.0) * c0_ * h_);
        s.wall_viscosity = prm_.free_slip ? 0.0f : s.viscosity;
        s.laminar = laminar() ? float(prm_.nu) : 0.0f;
        s.background = float(prm_.background_pressure);
        s.diffusion = continuity() ? float(2 * prm_.density_diffusion * h_ * c0_) : 0.0f;
        s.inv_rest_density = float(1 / prm_.rest_density);
        return s;
    }

    sph_params prm_;
    double h_;
    cubic_spline<D> w_;
    half_space_integral<D> psi_;
    double mass_ = 0, wall_density_ = 0, c0_ = 0, settle_rate_ = 0;
    std::vector<float> acc_;
    std::vector<float> background_acc_;  // the transport velocity's a_b
    std::vector<float> carried_rho_;     // continuity: rho moved with the grid, D floats each
    std::vector<float> bulk_;            // the bulk viscosity's pressure q per particle
    std::vector<float> position_, velocity_;  // per particle {x, rho}, {v, p / rho^2} (sph_pairs.hpp)
    bool have_acc_ = false;
    std::vector<float> gathered_walls_;  // across ranks: gather()'s wall states, {rho, p / rho^2} each
    wall_particles<D> walls_;  // sph.wall_particles
    sph_pair_kernels<D> pairs_;
};

}  // namespace

std::unique_ptr<solver> make_sph(const scene& s, int threads, std::string_view level) {
    if (s.dim == 2) return std::make_unique<sph<2>>(s, threads, level);
    return std::make_unique<sph<3>>(s, threads, level);
}

}  // namespace detail
}  // namespace frnn::sim
