// Periodic boxes in the simulation (scene key "periodic"): a lattice filling the box keeps
// every particle's neighbor count and stays at rest; a uniform flow stays uniform while its
// particles cross the box's faces and are wrapped back; 1 and 2 threads agree bit for bit;
// a box periodic on some axes wraps those only; a box too short for the kernel is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/profiler.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

using namespace frnn::sim;

namespace {

// A box of side 1 filled by a lattice of `per_axis` particles per axis, moving at `velocity`,
// no gravity, no collider.
scene filled_box(solver_kind solver, int dim, int per_axis, const std::string& velocity) {
    const std::string text = R"({"name": "box", "dim": )" + std::to_string(dim) + R"(, "particles": )" +
                             std::to_string(int(std::pow(per_axis, dim))) + R"(, "gravity": [0, 0, 0],
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, 1, 1],
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "velocity": )" + velocity + "}]}";
    scene s = parse_scene(text, "box");
    scene_overrides o;
    o.solver = solver;
    apply(s, o);
    return s;
}

struct solver_case {
    solver_kind solver;
    int dim;
};
const solver_case cases[] = {{solver_kind::sph, 2}, {solver_kind::sph, 3}, {solver_kind::viscoelastic, 2},
                             {solver_kind::viscoelastic, 3}};
std::string name_of(const solver_case& c) { return to_string(c.solver) + " " + std::to_string(c.dim) + "D"; }

}  // namespace

TEST(SimPeriodic, LatticeFillingTheBoxStaysAtRestWithEqualNeighborCounts) {
    for (const auto& c : cases) {
        auto sol = make_solver(filled_box(c.solver, c.dim, c.dim == 2 ? 20 : 10, "[0, 0, 0]"), 2);
        profiler prof;
        const particle_view start = sol->view();
        const std::vector<float> x0(start.x, start.x + start.n * c.dim);
        for (int s = 0; s < 50; ++s) sol->step(prof);
        const particle_view v = sol->view();
        // In a periodic lattice every particle has the same neighbors, at the faces too. (The
        // viscoelastic radius, 2 spacings, puts lattice neighbors at exactly h, where rounding
        // decides: they weigh (1 - q)^2 = 0 there, but the counts may differ.)
        if (c.solver == solver_kind::sph) {
            for (std::size_t i = 0; i < v.n; ++i)
                ASSERT_EQ(sol->neighbor_count(i), sol->neighbor_count(0)) << name_of(c) << " particle " << i;
        }
        EXPECT_GT(sol->neighbor_count(0), 4u) << name_of(c);
        double fastest = 0, moved = 0;
        for (std::size_t i = 0; i < v.n; ++i)
            for (int a = 0; a < c.dim; ++a) {
                fastest = std::max(fastest, double(std::abs(v.v[i * c.dim + a])));
                moved = std::max(moved, double(std::abs(v.x[i * c.dim + a] - x0[v.id[i] * c.dim + a])));
            }
        EXPECT_LT(fastest, 1e-4) << name_of(c);
        EXPECT_LT(moved, 1e-4) << name_of(c);
    }
}

TEST(SimPeriodic, UniformFlowStaysUniformAcrossTheFaces) {
    const double u[3] = {0.6, -0.3, 0.2};
    for (const auto& c : cases) {
        auto sol = make_solver(filled_box(c.solver, c.dim, c.dim == 2 ? 20 : 10, "[0.6, -0.3, 0.2]"), 2);
        profiler prof;
        const particle_view start = sol->view();
        const std::vector<float> x0(start.x, start.x + start.n * c.dim);
        while (sol->time() < 0.25) sol->step(prof);  // 0.15 of the box along x: faces crossed
        const particle_view v = sol->view();
        const double t = sol->time();
        double speed_error = 0, place_error = 0;
        for (std::size_t i = 0; i < v.n; ++i)
            for (int a = 0; a < c.dim; ++a) {
                const double x = v.x[i * c.dim + a];
                ASSERT_TRUE(x >= 0 && x < 1) << name_of(c) << ": particle " << v.id[i] << " at " << x;
                speed_error = std::max(speed_error, std::abs(v.v[i * c.dim + a] - u[a]));
                // Where the start position moved by u t lands after wrapping (distance on the circle).
                double d = x - (x0[v.id[i] * c.dim + a] + u[a] * t);
                d -= std::nearbyint(d);
                place_error = std::max(place_error, std::abs(d));
            }
        EXPECT_LT(speed_error, 1e-3) << name_of(c);
        EXPECT_LT(place_error, 1e-3) << name_of(c);
    }
}

TEST(SimPeriodic, OneAndTwoThreadsAgreeBitForBit) {
    for (const auto& c : cases) {
        const scene s = filled_box(c.solver, c.dim, c.dim == 2 ? 16 : 8, "[0.6, -0.3, 0.2]");
        auto one = make_solver(s, 1), two = make_solver(s, 2);
        profiler p1, p2;
        for (int k = 0; k < 30; ++k) one->step(p1), two->step(p2);
        const particle_view a = one->view(), b = two->view();
        ASSERT_EQ(a.n, b.n);
        EXPECT_EQ(0, std::memcmp(a.x, b.x, a.n * c.dim * sizeof(float))) << name_of(c);
        EXPECT_EQ(0, std::memcmp(a.v, b.v, a.n * c.dim * sizeof(float))) << name_of(c);
    }
}

TEST(SimPeriodic, SavedSceneKeepsTheBox) {
    const scene s = filled_box(solver_kind::sph, 3, 6, "[0, 0, 0]");
    const scene back = parse_scene(scene_to_json(s), "saved");
    EXPECT_EQ(back.periodic, s.periodic);
    EXPECT_TRUE(back.is_periodic());
}

// Periodic in x only: a particle at the x face has the neighbors of one in the middle of its
// row, one at the open y face fewer; x positions stay in [0, 1) while y ones are not wrapped.
TEST(SimPeriodic, OpenAxisIsNotWrapped) {
    scene s = filled_box(solver_kind::sph, 2, 20, "[0.6, -0.3, 0]");
    s.periodic = {1, 0, 0};
    auto sol = make_solver(s, 2);
    profiler prof;
    sol->step(prof);
    const particle_view v = sol->view();
    auto nearest = [&](double x, double y) {
        std::size_t best = 0;
        double best_d = INFINITY;
        for (std::size_t i = 0; i < v.n; ++i) {
            const double d = std::hypot(v.x[2 * i] - x, v.x[2 * i + 1] - y);
            if (d < best_d) best_d = d, best = i;
        }
        return best;
    };
    const std::size_t middle = nearest(0.5, 0.5), x_face = nearest(0.0, 0.5), y_face = nearest(0.5, 0.0);
    EXPECT_EQ(sol->neighbor_count(x_face), sol->neighbor_count(middle));
    EXPECT_LT(sol->neighbor_count(y_face), sol->neighbor_count(middle));
    while (sol->time() < 0.25) sol->step(prof);
    const particle_view w = sol->view();
    double lowest_y = INFINITY;
    for (std::size_t i = 0; i < w.n; ++i) {
        ASSERT_TRUE(w.x[2 * i] >= 0 && w.x[2 * i] < 1) << "x of particle " << w.id[i] << ": " << w.x[2 * i];
        lowest_y = std::min(lowest_y, double(w.x[2 * i + 1]));
    }
    EXPECT_LT(lowest_y, -0.05);  // the flow carried the bottom rows below y = 0: not wrapped
}

TEST(SimPeriodic, ShortBoxAndNegativeLengthAreRefused) {
    scene s = filled_box(solver_kind::sph, 2, 10, "[0, 0, 0]");
    s.periodic = {1, 0.05, 0};  // shorter than twice the kernel's support
    auto sol = make_solver(s, 1);
    profiler prof;
    try {
        sol->step(prof);
        ADD_FAILURE() << "a box shorter than twice the radius was accepted";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("smaller than twice the radius"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parse_scene(R"({"name": "b", "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, -1],
                                 "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}]})",
                             "b"),
                 frnn::error);
}
