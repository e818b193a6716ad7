// Physics checks of the SPH solver: a column at rest carries the hydrostatic pressure, and the
// 2D dam break's surge front follows Martin and Moyce's measurements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/sim/martin_moyce.hpp"
#include "frnn/sim/run.hpp"
#include "frnn/sim/solver.hpp"
#include "scratch_dir.hpp"
#include "wall_friction.hpp"

using namespace frnn::sim;

TEST(SimPhysics, HydrostaticColumnPressureMatchesRhoGDepth) {
    // Both integrators with the Tait equation of state, and the linear (ideal-gas) form.
    const std::pair<const char*, const char*> configs[] = {
        {"symplectic-euler", "tait"}, {"leapfrog", "tait"}, {"symplectic-euler", "ideal"}};
    for (const auto& [integrator_name, eos] : configs) {
        const std::string integrator = std::string(integrator_name) + " " + eos;
        const std::string text = std::string(R"({"name": "column", "solver": "sph", "dim": 2, "particles": 400,
          "domain": {"min": [0, 0, 0], "max": [0.1, 0.2, 0.1]},
          "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}],
          "colliders": [{"type": "box", "inside": true, "center": [0.05, 0.1, 0.05], "half": [0.05, 0.1, 0.05]}],
          "sph": {"alpha": 0.2, "integrator": ")") + integrator_name + R"(", "eos": ")" + eos + R"("}})";
        const scene s = parse_scene(text, "column");
        auto sol = make_solver(s, 2);
        profiler p;
        const double rho0 = 1000, g = 9.81;
        // Sloshing modes decay slowly: average the measures over t in [0.2, 0.5].
        double slope_sum = 0, bottom_sum = 0, top_sum = 0;
        int samples = 0;
        while (sol->time() < 0.5) {
            sol->step(p);
            if (sol->time() < 0.2 || sol->steps() % 10) continue;
            const auto v = sol->view();
            double top = 0;
            for (std::size_t i = 0; i < v.n; ++i) top = std::max(top, double(v.x[2 * i + 1]));
            top += sol->spacing() / 2;
            // Least-squares slope of pressure against depth, below the free-surface layers
            // (whose kernel support is cut by the surface).
            double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0, pb = 0, nb = 0;
            for (std::size_t i = 0; i < v.n; ++i) {
                const double depth = top - v.x[2 * i + 1];
                if (v.x[2 * i + 1] < sol->spacing()) pb += v.p[i], nb += 1;
                if (depth < 2 * sol->radius()) continue;
                sx += depth, sy += v.p[i], sxx += depth * depth, sxy += depth * v.p[i], n += 1;
            }
            slope_sum += (n * sxy - sx * sy) / (n * sxx - sx * sx);
            bottom_sum += pb / nb / (rho0 * g * (top - sol->spacing() / 2));
            top_sum += top;
            ++samples;
        }
        ASSERT_GT(samples, 10);
        EXPECT_NEAR(top_sum / samples, 0.1, 0.1 * 0.03) << integrator;  // neither collapsed nor rose
        EXPECT_NEAR(slope_sum / samples / (rho0 * g), 1.0, 0.1) << integrator;
        EXPECT_NEAR(bottom_sum / samples, 1.0, 0.08) << integrator;
        std::printf("[ %s ] dp/d(depth) = %.3f rho0 g, bottom pressure = %.3f rho0 g H\n", integrator.c_str(),
                    slope_sum / samples / (rho0 * g), bottom_sum / samples);
    }
}

TEST(SimPhysics, DamBreakFrontFollowsMartinMoyce) {
    scene_overrides o;
    o.solver = solver_kind::sph;
    o.dim = 2;
    o.particles = 800;  // the scene's default is 3200; coarser here to stay fast
    o.duration = (front_error_t_hi + 0.1) / std::sqrt(2 * 9.81 / 0.25);
    run_options opt;
    const frnn::test::scratch_dir dir("sim_front");
    opt.out_dir = dir.string();
    opt.progress = false;
    opt.print_table = false;
    opt.write_frames = false;
    opt.threads = 1;  // thread counts are covered by SimSolvers; one thread is fastest here
    const auto r = run(builtin_scene_text("dam-break"), "dam-break", o, opt);
    ASSERT_FALSE(r.front.empty());
    EXPECT_NEAR(r.front.front().second, 1.0, 1e-6);  // Z starts at the column's width
    for (std::size_t k = 1; k < r.front.size(); ++k) EXPECT_GT(r.front[k].first, r.front[k - 1].first);
    ASSERT_EQ(r.front_errors.size(), martin_moyce().size());
    for (std::size_t k = 0; k < martin_moyce().size(); ++k) {
        EXPECT_EQ(front_error(r.front, martin_moyce()[k]), r.front_errors[k]);
        EXPECT_LT(r.front_errors[k], 0.10) << "a = " << martin_moyce()[k].a_inches << " in";
    }
}

TEST(SimPhysics, MartinMoyceDataHoldsBothSeries) {
    const auto& series = martin_moyce();
    ASSERT_EQ(series.size(), 2u);
    EXPECT_EQ(series[0].a_inches, 1.125);
    EXPECT_EQ(series[1].a_inches, 2.25);
    for (const auto& s : series) {
        ASSERT_GE(s.points.size(), 10u);
        EXPECT_NEAR(s.points.front().second, 1.2, 0.1);  // the front starts near Z = 1.2
        for (std::size_t k = 1; k < s.points.size(); ++k) {
            EXPECT_GT(s.points[k].first, s.points[k - 1].first);
            EXPECT_GT(s.points[k].second, s.points[k - 1].second);  // the front only advances
        }
    }
}

TEST(SimPhysics, FrontErrorOfTheReferenceItselfIsZero) {
    for (const auto& series : martin_moyce()) {
        EXPECT_NEAR(front_error(series.points, series), 0.0, 1e-12);
        std::vector<std::pair<double, double>> ahead;
        for (const auto& [T, Z] : series.points) ahead.emplace_back(T, 1.1 * Z);
        EXPECT_NEAR(front_error(ahead, series), 0.1, 1e-12);
        // Only the points with T in the range count: a front 10% ahead there and 50% beyond.
        std::vector<std::pair<double, double>> late;
        for (const auto& [T, Z] : series.points) late.emplace_back(T, (T <= front_error_t_hi ? 1.1 : 1.5) * Z);
        EXPECT_NEAR(front_error(late, series), 0.1, 1e-12);
        EXPECT_THROW(front_error({{0, 1}, {2, 2}}, series), frnn::error);   // ends before T = 3
        EXPECT_THROW(front_error(series.points, series, 20, 30), frnn::error);  // no point in range
    }
}

TEST(SimPhysics, FrontDifferenceIsTheMeanRelativeGapOnTheTGrid) {
    // A front straight from (0, 1) to (4, 5), and one a quarter further: D = 0.25 / 1.25.
    const std::vector<std::pair<double, double>> fine{{0, 1.25}, {4, 6.25}}, coarse{{0, 1}, {1, 2}, {4, 5}};
    EXPECT_NEAR(front_difference(coarse, fine), 0.2, 1e-12);
    EXPECT_NEAR(front_difference(fine, fine), 0.0, 1e-15);
    // Only T in [0.5, 3] counts: a gap beyond it changes nothing.
    const std::vector<std::pair<double, double>> late{{0, 1}, {3, 4}, {4, 9}};
    EXPECT_NEAR(front_difference(late, fine), 0.2, 1e-12);
    EXPECT_THROW(front_difference({{0, 1}, {2, 3}}, fine), frnn::error);  // ends before T = 3
    EXPECT_THROW(front_difference(coarse, {{1, 2}, {4, 5}}), frnn::error);  // starts after T = 0.5
}

TEST(SimPhysics, SignedFrontErrorsArePositiveWhereTheFrontLeads) {
    const auto& series = martin_moyce()[1];
    std::vector<std::pair<double, double>> front;  // 10% ahead up to T = 1.5, 5% behind after
    for (const auto& [T, Z] : series.points) front.emplace_back(T, (T <= 1.5 ? 1.1 : 0.95) * Z);
    const auto errors = signed_front_errors(front, series);
    ASSERT_FALSE(errors.empty());
    double mean_abs = 0;
    for (const auto& [T, e] : errors) {
        EXPECT_GE(T, front_error_t_lo);
        EXPECT_LE(T, front_error_t_hi);
        EXPECT_NEAR(e, T <= 1.5 ? 0.1 : -0.05, 1e-12);
        mean_abs += std::abs(e) / double(errors.size());
    }
    EXPECT_NEAR(mean_abs, front_error(front, series), 1e-12);
}

TEST(SimPhysics, RichardsonFrontRemovesAnErrorOfTheObservedOrder) {
    // Fronts Z_h = Z* + C h^p at h = 2 and 1 (p = 1.5): the extrapolation returns Z*, exactly
    // at every T of the grid, and assumes the order it is given.
    const double p = 1.5, C = 0.3;
    std::vector<std::pair<double, double>> coarse, fine, exact;
    for (int k = 0; k <= 40; ++k) {
        const double T = 0.1 * k, Z = 1 + 1.2 * T;
        exact.emplace_back(T, Z);
        coarse.emplace_back(T, Z + C * std::pow(2.0, p));
        fine.emplace_back(T, Z + C);
    }
    const auto front = richardson_front(coarse, fine, p);
    ASSERT_EQ(front.size(), 126u);  // T = 0.5, 0.52, ..., 3
    for (const auto& [T, Z] : front) EXPECT_NEAR(Z, 1 + 1.2 * T, 1e-12);
    EXPECT_NEAR(front_difference(front, exact), 0.0, 1e-12);
    // Another order leaves part of the error: at p = 1 the front is C (2^1.5 - 2) short of Z*.
    for (const auto& [T, Z] : richardson_front(coarse, fine, 1)) EXPECT_NEAR(Z, 1 + 1.2 * T - C * (std::pow(2.0, p) - 2), 1e-12);
    EXPECT_THROW(richardson_front(coarse, fine, 0), frnn::error);
    EXPECT_THROW(richardson_front(coarse, {{1, 2}, {4, 5}}, p), frnn::error);  // starts after T = 0.5
}

// The laminar viscosity (Morris et al. 1997) in a periodic box: a shear wave u_x = U sin(2 pi y)
// keeps its shape (no pressure gradient: u_x depends on y only) and its amplitude decays as
// exp(-nu (2 pi)^2 t), the solution of the diffusion equation it obeys.
TEST(SimPhysics, LaminarViscosityDecaysAShearWaveAtItsRate) {
    const int rows = 32;
    const double U = 0.01, nu = 0.01, pi = 3.14159265358979323846;
    // One fluid block per lattice row, moving at the wave's velocity at that row's height.
    std::string blocks;
    for (int k = 0; k < rows; ++k) {
        const double y0 = double(k) / rows, y1 = double(k + 1) / rows, u = U * std::sin(2 * pi * (k + 0.5) / rows);
        blocks += (k ? ", " : "") + std::string(R"({"type": "box", "min": [0, )") + std::to_string(y0) +
                  R"(, 0], "max": [1, )" + std::to_string(y1) + R"(, 0], "velocity": [)" + std::to_string(u) +
                  ", 0, 0]}";
    }
    const std::string text = R"({"name": "shear", "solver": "sph", "dim": 2, "particles": )" +
                             std::to_string(rows * rows) + R"(, "gravity": [0, 0, 0],
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, 1],
      "fluid": [)" + blocks + R"(],
      "sph": {"viscosity": "laminar", "nu": 0.01, "sound_speed": 0.2, "clamp_negative_pressure": false}})";
    auto sol = make_solver(parse_scene(text, "shear"), 2);
    auto amplitude = [&] {
        const auto v = sol->view();
        double sum = 0;
        for (std::size_t i = 0; i < v.n; ++i) sum += v.v[2 * i] * std::sin(2 * pi * v.x[2 * i + 1]);
        return 2 * sum / double(v.n);
    };
    const double a0 = amplitude();
    EXPECT_NEAR(a0, U, 0.01 * U);
    profiler p;
    while (sol->time() < 1.0) sol->step(p);
    const double expected = std::exp(-nu * 4 * pi * pi * sol->time());
    const double ratio = amplitude() / a0;
    std::printf("[ shear wave ] A(t)/A(0) = %.4f, exp(-nu k^2 t) = %.4f at t = %.3f s (%llu steps)\n", ratio, expected,
                sol->time(), (unsigned long long)sol->steps());
    EXPECT_NEAR(ratio / expected, 1.0, 0.03);
}

// "settle_time": a tank released from the rest-density lattice rings; damped for the first
// 0.2 s, its fastest particle at 0.2 s is several times slower than undamped.
TEST(SimPhysics, SettleTimeDampsATankTowardsRest) {
    double fastest[2] = {};
    for (const int settle : {0, 1}) {
        const std::string text = std::string(R"({"name": "tank", "solver": "sph", "dim": 2, "particles": 400,
          "domain": {"min": [0, 0, 0], "max": [0.1, 0.2, 0.1]},
          "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}],
          "colliders": [{"type": "box", "inside": true, "center": [0.05, 0.1, 0.05], "half": [0.05, 0.1, 0.05]}],
          "sph": {"settle_time": )") + (settle ? "0.2" : "0") + "}}";
        auto sol = make_solver(parse_scene(text, "tank"), 1);
        profiler p;
        while (sol->time() < 0.2) sol->step(p);
        const auto v = sol->view();
        for (std::size_t i = 0; i < v.n; ++i)
            fastest[settle] = std::max(fastest[settle], std::hypot(double(v.v[2 * i]), double(v.v[2 * i + 1])));
    }
    EXPECT_GT(fastest[0], 0.01);  // undamped, the tank does move
    EXPECT_LT(fastest[1], fastest[0] / 3) << fastest[1] << " against " << fastest[0];
}

namespace {

/// The settled 2D tank of SettleTimeDampsATankTowardsRest, its walls as kernel integrals or
/// as wall particles: its fastest particle over t in [0.3, 0.4] and its pressure slope over
/// rho0 g then.
std::pair<double, double> settled_tank(bool wall_particles) {
    const std::string text = std::string(R"({"name": "tank", "solver": "sph", "dim": 2, "particles": 400,
      "domain": {"min": [0, 0, 0], "max": [0.1, 0.2, 0.1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}],
      "colliders": [{"type": "box", "inside": true, "center": [0.05, 0.1, 0.05], "half": [0.05, 0.1, 0.05]}],
      "sph": {"settle_time": 0.2, "wall_particles": )") + (wall_particles ? "true" : "false") + "}}";
    auto sol = make_solver(parse_scene(text, "tank"), 2);
    profiler p;
    double fastest = 0, slope = 0;
    int samples = 0;
    while (sol->time() < 0.4) {
        sol->step(p);
        if (sol->time() < 0.3 || sol->steps() % 10) continue;
        const auto v = sol->view();
        double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
        for (std::size_t i = 0; i < v.n; ++i) {
            fastest = std::max(fastest, std::hypot(double(v.v[2 * i]), double(v.v[2 * i + 1])));
            const double depth = 0.1 - v.x[2 * i + 1];
            if (depth < 2 * sol->radius()) continue;  // below the free surface's layers
            sx += depth, sy += v.p[i], sxx += depth * depth, sxy += depth * v.p[i], n += 1;
        }
        slope += (n * sxy - sx * sy) / (n * sxx - sx * sx) / (1000 * 9.81);
        ++samples;
    }
    return {fastest, slope / samples};
}

}  // namespace

// "wall_particles": walls whose pressure is extrapolated from the fluid hold up the water
// beside them, so the settled tank stays nearer rest than with the kernel integrals' walls
// (whose missing support drives a circulation down the side walls), with the hydrostatic
// pressure slope.
TEST(SimPhysics, WallParticlesKeepASettledTankNearerRest) {
    const auto [integral_speed, integral_slope] = settled_tank(false);
    const auto [particle_speed, particle_slope] = settled_tank(true);
    std::printf("[ tank ] fastest %.4f m/s (wall particles) against %.4f (kernel integrals); slope %.3f against %.3f\n",
                particle_speed, integral_speed, particle_slope, integral_slope);
    EXPECT_LT(particle_speed, integral_speed / 2);
    EXPECT_NEAR(particle_slope, 1.0, 0.05);
}

namespace {

/// A layer of water 0.02 deep sliding at 0.5 m/s along the floor of a long tank of wall
/// particles, alpha 0.3: its mean velocity along the floor after 0.1 s.
double sliding_layer_speed(bool free_slip) {
    const std::string text = std::string(R"({"name": "slide", "solver": "sph", "dim": 2, "particles": 400,
      "domain": {"min": [0, 0, 0], "max": [1, 0.1, 0.1]},
      "fluid": [{"type": "box", "min": [0.1, 0, 0], "max": [0.3, 0.02, 0.1], "velocity": [0.5, 0, 0]}],
      "colliders": [{"type": "box", "inside": true, "center": [0.5, 0.05, 0.05], "half": [0.5, 0.05, 0.05]}],
      "sph": {"alpha": 0.3, "wall_particles": true, "free_slip": )") + (free_slip ? "true" : "false") + "}}";
    auto sol = make_solver(parse_scene(text, "slide"), 1);
    profiler p;
    while (sol->time() < 0.1) sol->step(p);
    const auto v = sol->view();
    double sum = 0;
    for (std::size_t i = 0; i < v.n; ++i) sum += v.v[2 * i];
    return sum / double(v.n);
}

}  // namespace

// "free_slip": without the artificial viscosity against the wall particles, the floor does
// not brake a layer sliding along it; with it (no slip), the floor takes a share of the
// layer's momentum.
TEST(SimPhysics, FreeSlipWallsDoNotBrakeALayerSlidingAlongThem) {
    const double free = sliding_layer_speed(true), no_slip = sliding_layer_speed(false);
    std::printf("[ slide ] mean speed after 0.1 s: %.4f m/s free slip, %.4f no slip (from 0.5)\n", free, no_slip);
    EXPECT_NEAR(free, 0.5, 0.01);
    EXPECT_LT(no_slip, free - 0.02);
}

TEST(SimPhysics, WallParticlesNeedABoxOfFluidNoPeriodicAxisAndABoundedDomain) {
    const auto fails_with = [](const std::string& text, const std::string& what) {
        try {
            make_solver(parse_scene(text, "walls"), 1);
            ADD_FAILURE() << "no error for " << what;
        } catch (const frnn::error& e) {
            EXPECT_NE(std::string(e.what()).find("sph.wall_particles"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    fails_with(R"({"name": "walls", "solver": "sph", "dim": 2, "particles": 300,
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
      "fluid": [{"type": "sphere", "center": [0.5, 0.5, 0], "radius": 0.2}],
      "colliders": [{"type": "box", "inside": true, "center": [0.5, 0.5, 0.5], "half": [0.5, 0.5, 0.5]}],
      "sph": {"wall_particles": true}})",
               "box");
    fails_with(R"({"name": "walls", "solver": "sph", "dim": 2, "particles": 300, "periodic": [1, 0],
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.3, 1]}],
      "sph": {"wall_particles": true}})",
               "periodic");
    // 2,000 particles in a domain of 10^9 lattice points: an error, not minutes of seeding.
    fails_with(R"({"name": "walls", "solver": "sph", "dim": 3, "particles": 2000,
      "domain": {"min": [0, 0, 0], "max": [100, 100, 100]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}],
      "colliders": [{"type": "box", "inside": true, "center": [50, 50, 50], "half": [50, 50, 50]}],
      "sph": {"wall_particles": true}})",
               "lattice points");
    // Lattice indices beyond any integer: still the same error.
    fails_with(R"({"name": "walls", "solver": "sph", "dim": 2, "particles": 300,
      "domain": {"min": [0, 0, 0], "max": [1e30, 1, 1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.3, 1]}],
      "colliders": [{"type": "box", "inside": true, "center": [5e29, 0.5, 0.5], "half": [5e29, 0.5, 0.5]}],
      "sph": {"wall_particles": true}})",
               "lattice points");
}

namespace {

/// A standing sound wave u_x = U sin(2 pi x) (or, with shear, the shear wave u_x = U sin(2 pi y))
/// in the periodic unit box (2D, 32^2 particles, c0 = 1, the ideal equation of state, the
/// sph keys sph_keys): the largest kinetic energy over the last
/// unit of time before t over the initial one, and its time.
std::pair<double, double> wave_energy(const std::string& sph_keys, double t, bool shear = false) {
    const std::string text = R"({"name": "sound", "solver": "sph", "dim": 2, "particles": 1024, "gravity": [0, 0, 0],
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, 1],
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}],
      "sph": {"sound_speed": 1, "eos": "ideal", "clamp_negative_pressure": false, )" + sph_keys + "}}";
    auto sol = make_solver(parse_scene(text, "sound"), 2);
    const double U = 0.01, pi = 3.14159265358979323846;
    auto v = sol->view();
    std::vector<float> by_id(2 * v.n, 0);
    for (std::size_t i = 0; i < v.n; ++i) by_id[2 * v.id[i]] = float(U * std::sin(2 * pi * v.x[2 * i + (shear ? 1 : 0)]));
    sol->set_velocities(by_id);
    auto energy = [&] {
        const auto w = sol->view();
        double e = 0;
        for (std::size_t i = 0; i < w.n; ++i) e += double(w.v[2 * i]) * w.v[2 * i] + double(w.v[2 * i + 1]) * w.v[2 * i + 1];
        return e;
    };
    const double e0 = energy();
    double largest = 0, when = 0;
    profiler p;
    while (sol->time() < t) {
        sol->step(p);
        if (sol->time() > t - 1 && energy() > largest) largest = energy(), when = sol->time();
    }
    return {largest / e0, when};
}

/// The sound wave with the continuity density and density diffusion delta.
std::pair<double, double> sound_wave_energy(double delta, double t) {
    return wave_energy(R"("alpha": 0, "density": "continuity", "density_diffusion": )" + std::to_string(delta), t);
}

}  // namespace

// "density": "continuity": without diffusion a sound wave keeps its energy; Molteni and
// Colagrossi's diffusion approximates delta h c0 times the Laplacian of the density, which
// damps the wave's energy as exp(-delta h c0 k^2 t).
TEST(SimPhysics, DensityDiffusionDampsASoundWaveAtItsRate) {
    const double t = 3, delta = 0.1, h = 1.2 / 32, k = 2 * 3.14159265358979323846;
    const double kept = sound_wave_energy(0, t).first;
    const auto [damped, when] = sound_wave_energy(delta, t);
    const double expected = std::exp(-delta * h * 1.0 * k * k * when);
    std::printf("[ sound wave ] energy kept %.4f without diffusion, %.4f with delta %.1f at t = %.3f: ratio %.4f, "
                "exp(-delta h c0 k^2 t) = %.4f\n", kept, damped, delta, when, damped / kept, expected);
    EXPECT_GT(kept, 0.9);
    EXPECT_NEAR(damped / kept / expected, 1.0, 0.1);
}

// "bulk_viscosity": q = zeta d rho / dt approximates the bulk viscous stress zeta rho div v, which
// damps a sound wave's energy as exp(-zeta k^2 t), zeta = alpha_b h c0; a shear wave, divergence
// free, it leaves alone, where the artificial viscosity damps both.
TEST(SimPhysics, BulkViscosityDampsSoundAtItsRateAndLeavesShearAlone) {
    const double t = 3, alpha_b = 0.2, h = 1.2 / 32, k = 2 * 3.14159265358979323846;
    const double kept = wave_energy(R"("alpha": 0)", t).first;
    const auto [damped, when] = wave_energy(R"("alpha": 0, "bulk_viscosity": 0.2)", t);
    const double rate = -std::log(damped / kept) / (k * k * when);
    std::printf("[ bulk viscosity ] sound wave energy kept %.4f without, %.4f with alpha_b 0.2 at t = %.3f: zeta %.5f, "
                "alpha_b h c0 = %.5f\n", kept, damped, when, rate, alpha_b * h);
    EXPECT_GT(kept, 0.9);
    EXPECT_NEAR(rate / (alpha_b * h), 1.0, 0.15);
    // The shear wave's largest energy from t = 1 to 2 (at t = 1: it decays).
    const double shear = wave_energy(R"("alpha": 0)", 2, true).first;
    const double shear_bulk = wave_energy(R"("alpha": 0, "bulk_viscosity": 0.2)", 2, true).first;
    const double shear_artificial = wave_energy(R"("alpha": 0.2)", 2, true).first;
    std::printf("[ bulk viscosity ] shear wave energy, t = 1 to 2: %.6f without, %.6f with alpha_b 0.2, %.6f with alpha 0.2\n",
                shear, shear_bulk, shear_artificial);
    EXPECT_NEAR(shear_bulk / shear, 1.0, 1e-4);
    EXPECT_LT(shear_artificial / shear, 0.99);
}

namespace {

/// The 2D scene `text` with every particle moving at (u, 0), after one step.
auto one_step_at(const std::string& text, double u) {
    auto sol = make_solver(parse_scene(text, "layer"), 2);
    const auto v = sol->view();
    std::vector<float> by_id(2 * v.n, 0);
    for (std::size_t i = 0; i < v.n; ++i) by_id[2 * v.id[i]] = float(u);
    sol->set_velocities(by_id);
    profiler p;
    sol->step(p);
    return sol;
}

/// A water layer 0.05 m deep on the floor of a 1 m long tank, no gravity, sliding at speed u
/// along x: the mean x and y accelerations over the particles 0.3 to 0.7 m along, after one step.
std::pair<double, double> sliding_layer_acceleration(double u, bool friction, double* spacing) {
    const std::string text = R"({"name": "sliding", "solver": "sph", "dim": 2, "particles": 2000, "gravity": [0, 0, 0],
      "domain": {"min": [0, 0, 0], "max": [1, 0.2, 1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.05, 1]}],
      "colliders": [{"type": "box", "inside": true, "center": [0.5, 0.1, 0.5], "half": [0.5, 0.1, 0.5]}],
      "sph": {"sound_speed": 20, "h_ratio": 1.3, "alpha": 0, "wall_particles": true, "free_slip": true, "nu": 1e-6,
              "wall_friction": )" + std::string(friction ? "true" : "false") + "}}";
    const auto sol = one_step_at(text, u);
    *spacing = sol->spacing();
    const auto v = sol->view();
    double ax = 0, ay = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < v.n; ++i) {
        if (v.x[2 * i] < 0.3 || v.x[2 * i] > 0.7) continue;
        ax += (double(v.v[2 * i]) - u) / sol->last_dt(), ay += double(v.v[2 * i + 1]) / sol->last_dt(), ++count;
    }
    return {ax / double(count), ay / double(count)};
}

}  // namespace

// "wall_friction": the floor takes the layer's momentum at its shear stress rho u_tau^2 per unit
// of floor (the layer's mean deceleration times its depth is u_tau^2), with u_tau from the law of
// the wall at a height between the first layer's, half a spacing, and the kernel's reach, 2h;
// nothing across the floor, nothing at rest, nothing without it.
TEST(SimPhysics, WallFrictionSlowsASlidingLayerAtTheWallsShearStress) {
    const double u = 2, depth = 0.05;
    double spacing = 0;
    const auto [ax, ay] = sliding_layer_acceleration(u, true, &spacing);
    const double lo = detail::friction_velocity(u, 2 * 1.3 * spacing, 1e-6), hi = detail::friction_velocity(u, spacing / 2, 1e-6);
    std::printf("[ wall friction ] layer at %g m/s: -a depth = %.5f m^2/s^2, u_tau^2 from %.5f (2h) to %.5f (spacing / 2)\n", u,
                -ax * depth, lo * lo, hi * hi);
    EXPECT_GT(-ax * depth, lo * lo);
    EXPECT_LT(-ax * depth, hi * hi);
    const auto [ax_off, ay_off] = sliding_layer_acceleration(u, false, &spacing);
    EXPECT_LT(std::abs(ax_off), 1e-2 * std::abs(ax));  // the float noise of the pressure terms
    EXPECT_NEAR(ay, ay_off, 1e-2 * std::abs(ax));
    const auto [ax_rest, ay_rest] = sliding_layer_acceleration(0, true, &spacing);
    EXPECT_LT(std::abs(ax_rest), 1e-2 * std::abs(ax));
}

// The same friction from a moving wall: a layer at rest on a bed sliding at -u (the kernel
// integral's walls, a channel periodic along x) is dragged as a layer sliding at u over a bed
// at rest is slowed: the friction sees the velocity relative to the wall.
TEST(SimPhysics, WallFrictionOfAMovingBedIsThatOfTheRelativeVelocity) {
    const double u = 2, depth = 0.05;
    auto mean_acceleration = [&](double fluid_u, double bed_u, double* spacing) {
        const std::string text = R"({"name": "channel", "solver": "sph", "dim": 2, "particles": 2000, "gravity": [0, 0, 0],
          "domain": {"min": [0, 0, 0], "max": [1, 0.2, 1]}, "periodic": [1, 0, 0],
          "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.05, 1]}],
          "colliders": [{"type": "box", "center": [0.5, -0.5, 0.5], "half": [2, 0.5, 1],
                         "motion": {"velocity": [)" + std::to_string(bed_u) + R"(, 0, 0]}}],
          "sph": {"sound_speed": 20, "h_ratio": 1.3, "alpha": 0, "nu": 1e-6, "wall_friction": true}})";
        const auto sol = one_step_at(text, fluid_u);
        *spacing = sol->spacing();
        const auto v = sol->view();
        double ax = 0;
        for (std::size_t i = 0; i < v.n; ++i) ax += (double(v.v[2 * i]) - fluid_u) / sol->last_dt();
        return ax / double(v.n);
    };
    double spacing = 0;
    const double sliding = mean_acceleration(u, 0, &spacing), dragged = mean_acceleration(0, -u, &spacing);
    const double lo = detail::friction_velocity(u, 2 * 1.3 * spacing, 1e-6), hi = detail::friction_velocity(u, spacing / 2, 1e-6);
    std::printf("[ wall friction ] -a depth: layer sliding %.5f, bed moving %.5f m^2/s^2 (law: %.5f to %.5f)\n",
                -sliding * depth, -dragged * depth, lo * lo, hi * hi);
    EXPECT_GT(-sliding * depth, lo * lo);
    EXPECT_LT(-sliding * depth, hi * hi);
    EXPECT_NEAR(dragged, sliding, 1e-3 * std::abs(sliding));
}
