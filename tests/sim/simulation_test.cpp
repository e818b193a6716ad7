// frnn::sim::simulation: one step at a time, live and restarting parameter changes, snapshots
// in id order with every field of the same step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "expect_error.hpp"
#include "frnn/sim/run.hpp"
#include "frnn/sim/simulation.hpp"
#include "scratch_dir.hpp"

using namespace frnn::sim;

namespace {
scene droplet_2d() {
    scene s = builtin_scene("droplet");
    scene_overrides o;
    o.dim = 2;
    o.particles = 400;
    apply(s, o);
    return s;
}
}  // namespace

TEST(SimSimulation, StepsMatchTheSolverBitForBit) {
    const scene s = droplet_2d();
    simulation sim(s, 2);
    auto solver = make_solver(s, 1);
    profiler prof;
    for (int k = 0; k < 20; ++k) {
        sim.step();
        solver->step(prof);
    }
    EXPECT_EQ(sim.steps(), 20u);
    particle_snapshot snap;
    sim.snapshot(snap);
    const particle_view v = solver->view();
    ASSERT_EQ(snap.n, v.n);
    for (std::size_t i = 0; i < v.n; ++i)
        for (int a = 0; a < 2; ++a) ASSERT_EQ(snap.x[v.id[i] * 3 + std::size_t(a)], v.x[i * 2 + std::size_t(a)]) << i;
}

TEST(SimSimulation, SnapshotIsInIdOrderWithFieldsOfOneStep) {
    simulation sim(droplet_2d(), 1);
    particle_snapshot snap;
    sim.snapshot(snap);
    EXPECT_EQ(snap.step, 0u);
    const seeded_particles seeded = seed(sim.current_scene());
    ASSERT_EQ(snap.n, seeded.count);
    for (std::size_t k = 0; k < snap.n; ++k) {
        EXPECT_EQ(snap.x[k * 3], seeded.x[k * 2]);
        EXPECT_EQ(snap.x[k * 3 + 1], seeded.x[k * 2 + 1]);
        EXPECT_EQ(snap.x[k * 3 + 2], 0.f);
        EXPECT_EQ(snap.neighbors[k], 0u);  // no lists before the first step
    }
    sim.step();
    sim.snapshot(snap);
    EXPECT_EQ(snap.step, 1u);
    EXPECT_GT(snap.time, 0);
    const particle_view v = sim.state().view();
    std::size_t with_neighbors = 0;
    for (std::size_t i = 0; i < v.n; ++i) {
        const std::size_t k = v.id[i];
        EXPECT_EQ(snap.density[k], v.rho[i]);
        EXPECT_EQ(snap.pressure[k], v.p[i]);
        EXPECT_FLOAT_EQ(snap.speed[k], std::hypot(v.v[i * 2], v.v[i * 2 + 1]));
        EXPECT_EQ(snap.neighbors[k], sim.state().neighbor_count(i));
        with_neighbors += snap.neighbors[k] > 0;
    }
    EXPECT_GT(with_neighbors, v.n / 2);
}

TEST(SimSimulation, LiveParameterKeepsTheRunAndChangesTheNextStep) {
    simulation a(droplet_2d(), 1), b(droplet_2d(), 1);
    for (int k = 0; k < 5; ++k) a.step(), b.step();
    const parameter& stiffness = *find_parameter("viscoelastic.stiffness");
    EXPECT_FALSE(a.set_parameter(stiffness, 0.4));
    EXPECT_EQ(a.steps(), 5u);
    EXPECT_EQ(a.current_scene().viscoelastic.stiffness, 0.4);
    a.step(), b.step();
    particle_snapshot sa, sb;
    a.snapshot(sa), b.snapshot(sb);
    EXPECT_NE(sa.x, sb.x);
}

TEST(SimSimulation, NonLiveParameterRestartsTheScene) {
    simulation sim(droplet_2d(), 1);
    const double radius = sim.state().radius();
    for (int k = 0; k < 3; ++k) sim.step();
    EXPECT_TRUE(sim.set_parameter(*find_parameter("viscoelastic.h_ratio"), 2.5));
    EXPECT_EQ(sim.steps(), 0u);
    EXPECT_DOUBLE_EQ(sim.state().radius(), radius * 2.5 / 2.0);
    // The other solver's parameter is kept for a switch, the run goes on.
    sim.step();
    EXPECT_FALSE(sim.set_parameter(*find_parameter("sph.h_ratio"), 1.4));
    EXPECT_EQ(sim.steps(), 1u);
    EXPECT_EQ(sim.current_scene().sph.h_ratio, 1.4);
}

TEST(SimSimulation, SolverRefusesALiveChangeOfARestartParameter) {
    scene s = droplet_2d();
    auto solver = make_solver(s, 1);
    s.viscoelastic.h_ratio = 3;
    frnn::test::expect_error([&] { solver->set_parameters(s); }, {"viscoelastic.h_ratio", "restart"});
}

TEST(SimSimulation, GravityChangesLive) {
    simulation down(droplet_2d(), 1), up(droplet_2d(), 1);
    up.set_gravity({0, 9.81, 0});
    EXPECT_EQ(up.current_scene().gravity[1], 9.81);
    down.step(), up.step();
    particle_snapshot a, b;
    down.snapshot(a), up.snapshot(b);
    double rise = 0;  // of the particles under upward gravity, against those under downward
    for (std::size_t k = 0; k < a.n; ++k) rise += b.x[k * 3 + 1] - a.x[k * 3 + 1];
    EXPECT_GT(rise / double(a.n), 0.5 * 9.81 * 0.004 * 0.004);
}

TEST(SimSimulation, CollidersChangeLiveAndAMovingOnePushesWithItsVelocity) {
    simulation still(droplet_2d(), 1), moving(droplet_2d(), 1);
    for (int k = 0; k < 5; ++k) still.step(), moving.step();
    particle_snapshot a;
    still.snapshot(a);
    double cx = 0, cy = 0;  // a sphere dropped into the middle of the drop
    for (std::size_t k = 0; k < a.n; ++k) cx += a.x[k * 3] / double(a.n), cy += a.x[k * 3 + 1] / double(a.n);
    collider ball;
    ball.kind = shape::sphere;
    ball.radius = 3 * a.spacing;
    ball.center = {cx, cy, 0.3};  // flattened: z = 0 in a 2D scene
    std::vector<collider> list = still.current_scene().colliders;
    list.push_back(ball);
    still.set_colliders(list);
    // The same place now, moving right at 1 m/s: center(t) = center + velocity t.
    list.back().path.velocity = {1, 0, 0};
    list.back().center[0] -= moving.time();
    moving.set_colliders(list);
    EXPECT_EQ(still.steps(), 5u);  // no restart
    EXPECT_EQ(still.current_scene().colliders.back().center[2], 0);
    std::size_t inside = 0;
    for (std::size_t k = 0; k < a.n; ++k) inside += std::hypot(a.x[k * 3] - cx, a.x[k * 3 + 1] - cy) < ball.radius;
    ASSERT_GT(inside, 5u);
    still.step(), moving.step();
    particle_snapshot b, c;
    still.snapshot(b), moving.snapshot(c);
    // Out of the ball after one step; those it touches leave faster when it moves (they take
    // its velocity along the normal).
    double still_speed = 0, moving_speed = 0;
    for (std::size_t k = 0; k < b.n; ++k) {
        const double d = std::hypot(b.x[k * 3] - cx, b.x[k * 3 + 1] - cy);
        EXPECT_GE(d, ball.radius) << "particle " << k;
        if (d < ball.radius + a.spacing) still_speed += b.speed[k], moving_speed += c.speed[k];
    }
    EXPECT_GT(moving_speed, still_speed + 0.1 * double(inside));
}

TEST(SimSimulation, ParameterOutsideItsRangeIsRefused) {
    simulation sim(droplet_2d(), 1);
    frnn::test::expect_error([&] { sim.set_parameter(*find_parameter("sph.gamma"), 12); }, {"sph.gamma", "[1, 10]", "12"});
    frnn::test::expect_error([&] { sim.set_parameter(*find_parameter("sph.eos"), 2); }, {"sph.eos", "index from 0 to 1"});
    frnn::test::expect_error([&] { sim.set_parameter(*find_parameter("viscoelastic.springs"), 0.5); }, {"viscoelastic.springs", "0 or 1"});
    EXPECT_EQ(sim.current_scene().sph.gamma, 7);
}

TEST(SimSimulation, CheckpointRestoresTheStateBitForBit) {
    const frnn::test::scratch_dir dir("sim_checkpoint");
    simulation a(droplet_2d(), 1);
    for (int k = 0; k < 5; ++k) a.step();
    a.set_parameter(*find_parameter("viscoelastic.beta"), 0.45);
    a.save_checkpoint((dir / "state.bin").string());
    simulation b(builtin_scene("dam-break"), 1);  // another scene entirely
    b.load_checkpoint((dir / "state.bin").string());
    EXPECT_EQ(b.steps(), 5u);
    EXPECT_EQ(b.current_scene().viscoelastic.beta, 0.45);
    EXPECT_EQ(b.current_scene().dim, 2);
    for (int k = 0; k < 3; ++k) a.step(), b.step();
    particle_snapshot sa, sb;
    a.snapshot(sa), b.snapshot(sb);
    EXPECT_EQ(sa.x, sb.x);
    EXPECT_EQ(sa.density, sb.density);
}

TEST(SimSimulation, FrnnSimResumesASavedCheckpoint) {
    const frnn::test::scratch_dir dir("sim_checkpoint_resume");
    scene s = droplet_2d();
    s.steps = 8;
    simulation a(s, 1), whole(s, 1);
    for (int k = 0; k < 5; ++k) a.step();
    std::filesystem::create_directories(dir / "run");
    a.save_checkpoint((dir / "run" / "checkpoint.bin").string());
    run_options o;
    o.progress = false;
    o.print_table = false;
    const run_result r = resume((dir / "run").string(), o);  // to the scene's 8 steps
    EXPECT_TRUE(r.finished);
    EXPECT_EQ(r.steps, 8u);
    for (int k = 0; k < 8; ++k) whole.step();
    simulation after(s, 1);
    after.load_checkpoint((dir / "run" / "checkpoint.bin").string());  // the run's final checkpoint
    particle_snapshot sw, sa;
    whole.snapshot(sw), after.snapshot(sa);
    EXPECT_EQ(sa.step, 8u);
    EXPECT_EQ(sw.x, sa.x);
}

TEST(SimSimulation, LoadingANonCheckpointNamesTheFileAndKeepsTheRun) {
    const frnn::test::scratch_dir dir("sim_checkpoint_bad");
    std::ofstream(dir / "not.bin") << "hello, world";
    simulation sim(droplet_2d(), 1);
    sim.step();
    frnn::test::expect_error([&] { sim.load_checkpoint((dir / "not.bin").string()); }, {"not.bin", "not a frnn sim checkpoint"});
    frnn::test::expect_error([&] { sim.load_checkpoint((dir / "missing.bin").string()); }, {"cannot open checkpoint", "missing.bin"});
    EXPECT_EQ(sim.steps(), 1u);
}

// A corrupt checkpoint is refused before it is used: lengths beyond the file allocate nothing,
// and ids, which index the output and the springs, must be 0..n-1 each once (found by the
// checkpoint fuzzer, tests/fuzz/).
TEST(SimSimulation, CorruptCheckpointsAreRefused) {
    const frnn::test::scratch_dir dir("sim_checkpoint_corrupt");
    scene s = droplet_2d();
    s.solver = solver_kind::sph;
    simulation a(s, 1);
    a.step();
    const auto file = dir / "state.bin";
    a.save_checkpoint(file.string());
    std::string bytes;
    {
        std::ifstream in(file, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    auto load = [&](const std::string& changed) {
        std::ofstream(dir / "bad.bin", std::ios::binary) << changed;
        simulation b(s, 1);
        b.load_checkpoint((dir / "bad.bin").string());
    };
    load(bytes);  // unchanged: loads

    std::string huge = bytes;  // the scene's length, after the magic: 2^40 bytes
    const std::uint64_t length = std::uint64_t(1) << 40;
    std::memcpy(huge.data() + 8, &length, sizeof length);
    frnn::test::expect_error([&] { load(huge); }, {"checkpoint", "truncated", "1099511627776"});

    // The sph state ends with the ids (4 bytes each), then 2 arrays of n * 2 floats, a flag and
    // the wall particles' states (none here: a length of 0).
    particle_snapshot snap;
    a.snapshot(snap);
    const std::size_t n = snap.n;
    std::uint64_t walls = 1;
    std::memcpy(&walls, bytes.data() + bytes.size() - 8, 8);
    ASSERT_EQ(walls, 0u);
    const std::size_t ids = bytes.size() - 8 - 1 - 2 * (8 + 8 * n) - 4 * n;
    std::string twice = bytes;
    std::memcpy(twice.data() + ids + 4, twice.data() + ids, 4);  // slot 1 holds slot 0's id
    frnn::test::expect_error([&] { load(twice); }, {"checkpoint", "particle slot 1 holds id"});
    std::string beyond = bytes;
    const std::uint32_t far = std::uint32_t(n);
    std::memcpy(beyond.data() + ids, &far, 4);
    frnn::test::expect_error([&] { load(beyond); }, {"checkpoint", "particle slot 0 holds id " + std::to_string(n)});
}

// The viewer draws the cells a particle's search visits from the snapshot's geometry: after a
// step every pair within the snapshot's radius lies in those cells, and before it there are none.
TEST(SimSimulation, SnapshotCarriesTheRadiusAndTheGridTheSearchUsed) {
    simulation sim(droplet_2d(), 1);
    particle_snapshot snap;
    sim.snapshot(snap);
    EXPECT_EQ(snap.radius, sim.state().radius());
    EXPECT_EQ(snap.geometry.slots, 0u);
    sim.step();
    sim.snapshot(snap);
    EXPECT_EQ(snap.radius, sim.state().radius());
    ASSERT_GT(snap.geometry.slots, 0u);
    EXPECT_EQ(double(snap.geometry.search_radius), double(float(snap.radius)) * double(snap.geometry.scale));
    const auto& g = snap.geometry;
    const auto at = [&](std::size_t k) { return std::array<float, 2>{snap.x[k * 3] * g.scale, snap.x[k * 3 + 1] * g.scale}; };
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < snap.n; ++i) {
        const frnn::cell_range r = g.cells_within(at(i));
        for (std::size_t j = 0; j < snap.n; ++j) {
            const double dx = snap.x[i * 3] - snap.x[j * 3], dy = snap.x[i * 3 + 1] - snap.x[j * 3 + 1];
            if (j == i || std::sqrt(dx * dx + dy * dy) > snap.radius) continue;
            ++pairs;
            const frnn::cell_index c = g.cell_of(at(j));
            for (std::size_t a = 0; a < 2; ++a) ASSERT_TRUE(c[a] >= r.first[a] && c[a] <= r.last[a]) << i << " " << j;
        }
    }
    EXPECT_GT(pairs, snap.n);  // the droplet is dense: particles have neighbors
}

// The viewer's "capture profile": a tracing profiler set between steps traces the steps after
// it, one span per stage per step, numbered by the step.
TEST(SimSimulation, TracingProfilerSetBetweenStepsTracesTheStepsAfter) {
    simulation sim(droplet_2d(), 1);
    sim.step();
    sim.set_profiler(profiler(true, 1));
    for (int k = 0; k < 3; ++k) sim.step();
    EXPECT_EQ(sim.timings().steps(), 3u);
    const frnn::test::scratch_dir dir("sim_set_profiler");
    sim.timings().write_trace((dir / "trace.json").string());
    std::ifstream in(dir / "trace.json");
    const auto trace = nlohmann::json::parse(in);
    std::map<std::uint64_t, std::set<std::string>> stages;  // by step
    for (const auto& e : trace.at("traceEvents"))
        if (e.at("ph") == "X") stages[e.at("args").at("step").get<std::uint64_t>()].insert(e.at("name").get<std::string>());
    ASSERT_EQ(stages.size(), 3u);
    EXPECT_EQ(stages.begin()->first, 1u);  // the step before the profiler was set is not in it
    for (const auto& [step, names] : stages) {
        EXPECT_TRUE(names.count(to_string(stage::grid)) && names.count(to_string(stage::neighbors))) << step;
        EXPECT_EQ(names, stages.begin()->second) << step;
    }
    sim.reset();
    EXPECT_FALSE(sim.timings().tracing());
}

// A domain far taller than the fluid (its ceiling 10^6 times higher) would need more cells
// than a uniform grid may have: the solver then takes the hashed grid, and the droplet, far
// below the ceiling, steps as in its own domain (up to the order of its sums).
TEST(SimSimulation, DomainBeyondTheUniformGridsBudgetStepsOnTheHashedGrid) {
    const scene small = droplet_2d();
    scene large = small;
    large.domain_max[1] = small.domain_min[1] + 1e6 * (small.domain_max[1] - small.domain_min[1]);
    simulation a(small, 2), b(large, 2);
    for (int k = 0; k < 10; ++k) {
        a.step();
        b.step();
    }
    particle_snapshot sa, sb;
    a.snapshot(sa);
    b.snapshot(sb);
    ASSERT_EQ(sa.n, sb.n);
    const double extent = small.domain_max[0] - small.domain_min[0];
    for (std::size_t i = 0; i < sa.n * 3; ++i) ASSERT_NEAR(sa.x[i], sb.x[i], 1e-4 * extent) << i;
}
