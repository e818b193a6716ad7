// The parameter table: it covers every solver key of the shipped scenes, the parser and the
// writer go through it, and every parameter at either end of its panel range keeps 100 steps
// finite; so do the colliders' coefficients at either end of the range the parser accepts (the
// viewer's Scene section offers any value the parser accepts).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/parameters.hpp"
#include "frnn/sim/scene_keys.hpp"
#include "frnn/sim/simulation.hpp"
#include "small_scene.hpp"

using namespace frnn::sim;

namespace {
bool all_finite(const particle_snapshot& p) {
    for (float v : p.x)
        if (!std::isfinite(v)) return false;
    for (const auto* f : {&p.speed, &p.density, &p.pressure})
        for (float v : *f)
            if (!std::isfinite(v)) return false;
    return true;
}
}  // namespace

TEST(SimParameters, TableIsConsistent) {
    std::set<std::string> names;
    for (const auto& p : parameters()) {
        EXPECT_TRUE(names.insert(p.name()).second) << "duplicate " << p.name();
        EXPECT_TRUE(p.section == "viscoelastic" || p.section == "sph") << p.name();
        EXPECT_FALSE(p.unit.empty()) << p.name();
        EXPECT_LE(p.min, p.ui_min) << p.name();
        EXPECT_LE(p.ui_min, p.ui_max) << p.name();
        EXPECT_LE(p.ui_max, p.max) << p.name();
        EXPECT_GE(p.default_value(), p.min) << p.name();
        EXPECT_LE(p.default_value(), p.max) << p.name();
        if (p.kind == parameter_kind::choice) {
            EXPECT_EQ(p.max, double(p.choices.size() - 1)) << p.name();
        }
        EXPECT_EQ(find_parameter(p.name()), &p);
    }
    EXPECT_EQ(find_parameter("viscoelastic.no_such_key"), nullptr);
}

TEST(SimParameters, EveryKeyOfEveryShippedSceneHasARow) {
    for (const auto& name : builtin_scene_names()) {
        const auto j = nlohmann::json::parse(builtin_scene_text(name));
        for (const char* section : {"viscoelastic", "sph"}) {
            if (!j.contains(section)) continue;
            for (auto it = j.at(section).begin(); it != j.at(section).end(); ++it)
                EXPECT_NE(find_parameter(std::string(section) + "." + it.key()), nullptr) << name << ": " << section << "." << it.key();
        }
    }
}

TEST(SimParameters, ParserReadsThroughTheTable) {
    const std::string base = R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "fluid": [{"type": "box", "min": [0,0,0], "max": [0.5,0.5,0.5]}], )";
    const scene s = parse_scene(base + R"("viscoelastic": {"stiffness": 0.3125, "springs": true}, "sph": {"eos": "ideal", "alpha": 0.75}})", "t.json");
    EXPECT_EQ(find_parameter("viscoelastic.stiffness")->get(s), 0.3125);
    EXPECT_EQ(find_parameter("viscoelastic.springs")->get(s), 1.0);
    EXPECT_EQ(find_parameter("sph.eos")->get(s), 1.0);
    EXPECT_EQ(s.sph.eos, sph_params::eos_t::ideal);
    EXPECT_EQ(s.sph.alpha, 0.75);
    try {
        parse_scene(base + R"("sph": {"gamma": 12}})", "t.json");
        ADD_FAILURE() << "gamma 12 accepted";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("t.json: key 'sph.gamma': expected a number in [1, 10], got 12"), std::string::npos) << e.what();
    }
}

TEST(SimParameters, SavedSceneParsesBackEqual) {
    for (const auto& name : builtin_scene_names())
        for (int dim : {2, 3}) {
            scene s = frnn::test::small_scene(name, solver_kind::sph, dim, 700);
            find_parameter("viscoelastic.beta")->set(s, 0.1 + 1.0 / 3);
            const std::string text = scene_to_json(s);
            const scene back = parse_scene(text, "saved.json");
            EXPECT_EQ(scene_to_json(back), text) << name << " " << dim << "D";
            for (const auto& p : parameters()) EXPECT_EQ(p.get(back), p.get(s)) << name << " " << p.name();
            EXPECT_EQ(back.solver, solver_kind::sph);
            EXPECT_EQ(back.dim, dim);
            EXPECT_EQ(back.target_particles(), 700u);
            EXPECT_EQ(back.colliders.size(), s.colliders.size());
            EXPECT_EQ(seed(back).x, seed(s).x) << name;
        }
}

// Each end of each panel range, 100 steps, on the scene where the parameter acts: the
// elastoplastic block for the viscoelastic rows (its springs are on), the dam break for SPH.
TEST(SimParameters, EveryParameterAtEachEndOfItsRangeStaysFinite) {
    for (const auto& p : parameters()) {
        const bool sph = p.section == "sph";
        const char* name = sph ? "dam-break" : "block-drop";
        const solver_kind solver = sph ? solver_kind::sph : solver_kind::viscoelastic;
        for (int dim : {2, 3}) {
            for (double value : {p.ui_min, p.ui_max}) {
                scene s = frnn::test::small_scene(name, solver, dim, 300);
                p.set(s, value);
                simulation sim(s, 1);
                try {
                    for (int k = 0; k < 100; ++k) sim.step();
                } catch (const frnn::error& e) {
                    ADD_FAILURE() << dim << "D, " << p.name() << " = " << value << ": " << e.what();
                    continue;
                }
                particle_snapshot snap;
                sim.snapshot(snap);
                EXPECT_EQ(snap.step, 100u);
                EXPECT_TRUE(all_finite(snap)) << dim << "D, " << p.name() << " = " << value;
            }
        }
    }
}

// The bounded scene keys that act on the particles: restitution in [0, 1] and friction in
// [0, 10], on every collider of the elastoplastic block's scene at once, both solvers.
TEST(SimParameters, ColliderCoefficientsAtEachEndOfTheirRangeStayFinite) {
    const struct {
        const char* key;
        double lo, hi;
    } keys[] = {{"restitution", 0, 1}, {"friction", 0, 10}};
    for (const auto& k : keys)
        for (const solver_kind solver : {solver_kind::viscoelastic, solver_kind::sph})
            for (int dim : {2, 3})
                for (double value : {k.lo, k.hi}) {
                    scene s = frnn::test::small_scene("block-drop", solver, dim, 300);
                    for (std::size_t c = 0; c < s.colliders.size(); ++c)
                        s = with_scene_key(s, "colliders[" + std::to_string(c) + "]." + k.key, std::to_string(value), "t");
                    const std::string what = to_string(solver) + " " + std::to_string(dim) + "D, " + k.key + " = " + std::to_string(value);
                    simulation sim(s, 1);
                    try {
                        for (int step = 0; step < 100; ++step) sim.step();
                    } catch (const frnn::error& e) {
                        ADD_FAILURE() << what << ": " << e.what();
                        continue;
                    }
                    particle_snapshot snap;
                    sim.snapshot(snap);
                    EXPECT_TRUE(all_finite(snap)) << what;
                }
}
