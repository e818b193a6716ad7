// Scene keys by path: a key set as a scene file would set it, the parser's checks the only
// rules, a changed type carrying its block's or collider's geometry over.
#include <gtest/gtest.h>

#include <string>

#include "expect_error.hpp"
#include "frnn/sim/parameters.hpp"
#include "frnn/sim/scene_keys.hpp"
#include "small_scene.hpp"

using namespace frnn::sim;

TEST(SimSceneKeys, SetsTheKeyAndNothingElse) {
    const scene s = builtin_scene("block-drop");
    const scene d = with_scene_key(s, "domain.max", "[2, 1.5, 1.25]", "t");
    EXPECT_EQ(d.domain_max, (vec3{2, 1.5, 1.25}));
    const scene c = with_scene_key(d, "colliders[1].radius", "0.25", "t");
    EXPECT_EQ(c.colliders[1].radius, 0.25);
    const scene m = with_scene_key(c, "colliders[3].motion.frequency", "2", "t");
    EXPECT_EQ(m.colliders[3].path.frequency, 2);
    const scene p = with_scene_key(m, "particles.2d", "123", "t");
    EXPECT_EQ(p.particles_2d, 123u);
    EXPECT_EQ(p.particles_3d, s.particles_3d);
    const scene a = with_scene_key(p, "sph.eos", "\"ideal\"", "t");
    EXPECT_EQ(a.sph.eos, sph_params::eos_t::ideal);
    const scene n = with_scene_key(a, "description", "\"edited\"", "t");
    EXPECT_EQ(n.description, "edited");
    scene expected = s;
    expected.domain_max = {2, 1.5, 1.25};
    expected.colliders[1].radius = 0.25;
    expected.colliders[3].path.frequency = 2;
    expected.particles_2d = 123;
    expected.sph.eos = sph_params::eos_t::ideal;
    expected.description = "edited";
    EXPECT_EQ(scene_to_json(n), scene_to_json(expected));
}

TEST(SimSceneKeys, WholeObjectsAndTwoDimensionalScenes) {
    const scene s = builtin_scene("droplet");
    const scene f = with_scene_key(s, "fluid[0]", R"({"type": "box", "min": [0, 0, 0], "max": [0.5, 0.25, 1]})", "t");
    EXPECT_EQ(f.fluid[0].max, (vec3{0.5, 0.25, 1}));
    const scene flat = frnn::test::small_scene("droplet", solver_kind::viscoelastic, 2, 500);
    // A 2D scene stays flat: its colliders keep z = 0 whatever the value says.
    const scene c = with_scene_key(flat, "colliders[0].center", "[0.5, 0.25, 0.75]", "t");
    EXPECT_EQ(c.colliders[0].center, (vec3{0.5, 0.25, 0}));
}

TEST(SimSceneKeys, ChangedTypeKeepsPlaceAndSize) {
    const scene s = builtin_scene("droplet");
    const scene sphere = with_scene_key(s, "fluid[0].type", "\"sphere\"", "t");
    EXPECT_EQ(sphere.fluid[0].kind, fluid_block::kind_t::sphere);
    EXPECT_EQ(sphere.fluid[0].center, (vec3{0.5, 0.1, 0.5}));
    EXPECT_EQ(sphere.fluid[0].radius, 0.1);  // inscribed: half the shortest side
    const scene box = with_scene_key(s, "fluid[1].type", "\"box\"", "t");
    EXPECT_EQ(box.fluid[1].kind, fluid_block::kind_t::box);
    EXPECT_NEAR(box.fluid[1].min[1], 0.5, 1e-15);
    EXPECT_NEAR(box.fluid[1].max[1], 0.8, 1e-15);
    EXPECT_EQ(box.fluid[1].velocity, s.fluid[1].velocity);

    const scene b = builtin_scene("block-drop");
    const scene ball = with_scene_key(b, "colliders[1].type", "\"box\"", "t");
    EXPECT_EQ(ball.colliders[1].kind, shape::box);
    EXPECT_EQ(ball.colliders[1].half, (vec3{0.12, 0.12, 0.12}));
    const scene tank = with_scene_key(b, "colliders[0].type", "\"plane\"", "t");
    EXPECT_EQ(tank.colliders[0].kind, shape::plane);
    EXPECT_FALSE(tank.colliders[0].inside);
    EXPECT_EQ(tank.colliders[0].center, b.colliders[0].center);
    const scene paddle = with_scene_key(b, "colliders[3].type", "\"sphere\"", "t");
    EXPECT_EQ(paddle.colliders[3].radius, 0.02);  // inscribed in the box
}

TEST(SimSceneKeys, BadPathsAndValuesNameTheKey) {
    const scene s = builtin_scene("dam-break");
    for (const char* path : {"domain.maximum", "colliders[1].center", "fluid.min", "domain..max", "domain.max.", "[0]", "", "fluid[0]min"})
        frnn::test::expect_error([&] { with_scene_key(s, path, "1", "edit"); }, {"edit: no key '" + std::string(path) + "' in the scene"});
    frnn::test::expect_error([&] { with_scene_key(s, "domain.max", "[0, 0, 0]", "edit"); },
                             {"edit: key 'domain.max': expected max > min on every axis"});
    frnn::test::expect_error([&] { with_scene_key(s, "sph.gamma", "12", "edit"); },
                             {"edit: key 'sph.gamma': expected a number in [1, 10], got 12"});
    frnn::test::expect_error([&] { with_scene_key(s, "colliders[0].type", "\"cone\"", "edit"); },
                             {"edit: key 'colliders[0].type': expected one of \"plane\", \"sphere\", \"box\", got \"cone\""});
    frnn::test::expect_error([&] { with_scene_key(s, "name", "[1", "edit"); }, {"edit: key 'name': the value is not JSON: [1"});
}

TEST(SimSceneKeys, ChoicesAreThoseTheParserAccepts) {
    EXPECT_EQ(scene_key_choices("solver"), solver_names());
    EXPECT_EQ(scene_key_choices("fluid[3].type"), fluid_block_types());
    EXPECT_EQ(scene_key_choices("colliders[0].type"), collider_types());
    EXPECT_EQ(scene_key_choices("sph.integrator"), find_parameter("sph.integrator")->choices);
    EXPECT_TRUE(scene_key_choices("domain.max").empty());
    EXPECT_TRUE(scene_key_choices("name").empty());
    EXPECT_TRUE(scene_key_choices("colliders[0].name").empty());
}
