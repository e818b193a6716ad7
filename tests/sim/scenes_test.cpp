// Scene files: the shipped ones parse and seed the advertised counts; bad ones fail with a
// message naming the key and what was expected.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/scene.hpp"

using namespace frnn::sim;

namespace {
std::string error_of(const std::string& json) {
    try {
        parse_scene(json, "bad.json");
    } catch (const frnn::error& e) {
        return e.what();
    }
    return "no error";
}
const char* minimal = R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "fluid": [{"type": "box", "min": [0,0,0], "max": [0.5,0.5,0.5]}]})";
}  // namespace

TEST(SimScenes, ShippedScenesParseAndSeed) {
    const auto names = builtin_scene_names();
    ASSERT_GE(names.size(), 3u);
    for (const auto& n : names) {
        scene s = builtin_scene(n);
        EXPECT_EQ(s.name, n);
        EXPECT_FALSE(s.fluid.empty());
        for (int dim : {2, 3}) {
            scene t = s;
            scene_overrides o;
            o.dim = dim;
            o.particles = 500;
            apply(t, o);
            const auto p = seed(t);
            EXPECT_GT(p.count, 250u) << n << " " << dim << "D";
            EXPECT_LT(p.count, 1000u) << n << " " << dim << "D";
            EXPECT_EQ(p.x.size(), p.count * std::size_t(dim));
        }
    }
    EXPECT_THROW(builtin_scene("no-such-scene"), frnn::error);
}

TEST(SimScenes, DefaultDamBreakHasExactly32768Particles) {
    const scene s = builtin_scene("dam-break");
    EXPECT_EQ(s.dim, 3);
    EXPECT_EQ(s.solver, solver_kind::viscoelastic);
    EXPECT_EQ(seed(s).count, 32768u);
}

TEST(SimScenes, ErrorsNameTheKeyAndTheExpectation) {
    EXPECT_NE(error_of("{").find("not valid JSON"), std::string::npos);
    EXPECT_NE(error_of(R"({"fluid": []})").find("key 'domain'"), std::string::npos);
    std::string e = error_of(R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "fluid": [{"type": "box", "min": [0,0], "max": "x"}]})");
    EXPECT_NE(e.find("bad.json: key 'fluid[0].max'"), std::string::npos) << e;
    EXPECT_NE(e.find("expected an array of 2 or 3 numbers"), std::string::npos) << e;
    std::string j = minimal;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "solver": "flip"})");
    EXPECT_NE(e.find("key 'solver'"), std::string::npos) << e;
    EXPECT_NE(e.find("\"viscoelastic\", \"sph\""), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "viscoelastic": {"stifness": 1}})");
    EXPECT_NE(e.find("key 'viscoelastic.stifness': unknown key"), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "dim": 4})");
    EXPECT_NE(e.find("key 'dim': expected an integer in [2, 3], got 4"), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "colliders": [{"type": "box", "half": [1, -1, 1]}]})");
    EXPECT_NE(e.find("key 'colliders[0].half': expected positive half extents"), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "sph": {"cfl": "fast"}})");
    EXPECT_NE(e.find("key 'sph.cfl': expected a number, got string"), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "sph": {"density": "kernel"}})");
    EXPECT_NE(e.find("key 'sph.density'"), std::string::npos) << e;
    EXPECT_NE(e.find("\"summation\", \"continuity\""), std::string::npos) << e;
    e = error_of(j.substr(0, j.size() - 1) + R"(, "sph": {"density_diffusion": 2}})");
    EXPECT_NE(e.find("key 'sph.density_diffusion': expected a number in [0, 1], got 2"), std::string::npos) << e;
    EXPECT_EQ(error_of(minimal), "no error");
}

TEST(SimScenes, TwoDimensionalOverrideFlattens) {
    scene s = builtin_scene("block-drop");
    scene_overrides o;
    o.dim = 2;
    o.particles = 300;
    o.solver = solver_kind::sph;
    apply(s, o);
    EXPECT_EQ(s.dim, 2);
    EXPECT_EQ(s.solver, solver_kind::sph);
    for (const auto& c : s.colliders) EXPECT_EQ(c.center[2], 0);
    const auto p = seed(s);
    EXPECT_EQ(p.x.size(), 2 * p.count);
}

TEST(SimScenes, JitterMovesEachCoordinateWithinItsShareOfTheLatticeStep) {
    for (int dim : {2, 3}) {
        const std::string d = std::to_string(dim);
        const auto scene_with = [&](const std::string& jitter) {
            return parse_scene(R"({"dim": )" + d + R"(, "particles": 1000, "domain": {"min": [0,0,0], "max": [1,1,1]},
                "fluid": [{"type": "box", "min": [0,0,0], "max": [0.5,0.4,0.3])" + jitter + "}]}", "jitter.json");
        };
        const scene lattice_scene = scene_with(""), jittered_scene = scene_with(R"(, "jitter": 0.3)");
        const seeded_particles lattice = seed(lattice_scene), jittered = seed(jittered_scene);
        ASSERT_EQ(jittered.count, lattice.count);
        ASSERT_GT(lattice.count, 500u);
        // The box's lattice step per axis: its width over its particle count along it.
        double step[3] = {0, 0, 0};
        const double width[3] = {0.5, 0.4, 0.3};
        for (int a = 0; a < dim; ++a) step[a] = width[a] / std::round(width[a] / lattice.spacing);
        double largest = 0, sum = 0;
        for (std::size_t i = 0; i < lattice.count; ++i)
            for (int a = 0; a < dim; ++a) {
                const std::size_t k = i * std::size_t(dim) + std::size_t(a);
                const double moved = (double(jittered.x[k]) - lattice.x[k]) / step[a];
                ASSERT_LE(std::abs(moved), 0.3 + 1e-5) << dim << "D particle " << i << " axis " << a;
                largest = std::max(largest, std::abs(moved));
                sum += moved;
            }
        // Uniform in [-0.3, 0.3]: the extremes are reached and the mean is near 0.
        EXPECT_GT(largest, 0.29) << dim << "D";
        EXPECT_LT(std::abs(sum / double(lattice.count * std::size_t(dim))), 0.02) << dim << "D";
        // The same positions in every run and after the scene is written and read back.
        EXPECT_EQ(seed(jittered_scene).x, jittered.x);
        EXPECT_EQ(seed(parse_scene(scene_to_json(jittered_scene), "back.json")).x, jittered.x);
        EXPECT_EQ(lattice_scene.fluid[0].jitter, 0);
    }
    std::string j = minimal;
    const std::string e = error_of(j.substr(0, j.size() - 3) + R"(, "jitter": 0.6}]})");
    EXPECT_NE(e.find("key 'fluid[0].jitter': expected a number in [0, 0.5], got 0.6"), std::string::npos) << e;
}
