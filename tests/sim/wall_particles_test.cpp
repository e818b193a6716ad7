// Where the wall particles lie (sim/src/wall_particles.hpp): each face of an axis-aligned box
// half a spacing in front of its first layer, also where the box's sides are no multiple of
// the fluid's spacing, so the wall the fluid meets is the collider's at every resolution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "frnn/sim/scene.hpp"
#include "wall_particles.hpp"

namespace {

using frnn::sim::detail::wall_particles;

// A tank 5.366 long and 3 high around a fluid box 2 x 1, as in frnn validate's wall-pressure
// case, at fluid spacing 1/k.
frnn::sim::scene tank() {
    return frnn::sim::parse_scene(R"({"name": "tank", "solver": "sph", "dim": 2, "particles": 200,
      "domain": {"min": [0, 0, 0], "max": [5.366, 3, 1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [2, 1, 1]}],
      "colliders": [{"type": "box", "inside": true, "center": [2.683, 1.5, 0.5], "half": [2.683, 1.5, 0.5]}],
      "sph": {"wall_particles": true}})",
                                  "tank");
}

TEST(SimWallParticles, EachBoxFaceLiesHalfASpacingInFrontOfItsFirstLayer) {
    const auto s = tank();
    for (const int k : {10, 20, 40}) {
        const double spacing = 1.0 / k, support = 2.6 * spacing;
        wall_particles<2> walls;
        walls.seed(s, s.colliders, spacing, support, 1, std::size_t(2 * k * k));
        ASSERT_FALSE(walls.empty());
        // Beyond each face, the nearest layer's distance from it, over the wall particles
        // facing the fluid along that axis.
        double left = INFINITY, right = INFINITY, floor = INFINITY;
        const float* x = walls.positions();
        for (std::size_t w = 0; w < walls.size(); ++w) {
            const double px = x[2 * w], py = x[2 * w + 1];
            if (py > 0 && py < 3) {
                if (px < 0) left = std::min(left, -px);
                if (px > 5.366) right = std::min(right, px - 5.366);
            }
            if (px > 0 && px < 5.366 && py < 0) floor = std::min(floor, -py);
        }
        // The box's own spacing divides 5.366 into round(5.366 k) steps: within 0.1% of 1/k.
        const double step = 5.366 / std::round(5.366 * k);
        EXPECT_NEAR(left, step / 2, 1e-6) << "k = " << k;
        EXPECT_NEAR(right, step / 2, 1e-6) << "k = " << k;
        EXPECT_NEAR(floor, spacing / 2, 1e-6) << "k = " << k;
        // As deep as the kernel's support behind the far face: layers up to `support` deep.
        double deepest = 0;
        for (std::size_t w = 0; w < walls.size(); ++w)
            if (x[2 * w] > 5.366 && x[2 * w + 1] > 0 && x[2 * w + 1] < 3) deepest = std::max(deepest, x[2 * w] - 5.366);
        EXPECT_GT(deepest, support - step) << "k = " << k;
        EXPECT_LT(deepest, support + 1e-6) << "k = " << k;
    }
}

// A solid plate far thinner than the spacing gets a lattice of its own across its thickness
// (one layer at its middle) and is searched over its own box, so a large domain around it is
// seeded, not refused for the lattice points of the whole domain at the plate's step.
TEST(SimWallParticles, AThinPlateGetsALayerInALargeDomain) {
    const auto s = frnn::sim::parse_scene(R"({"name": "plate", "solver": "sph", "dim": 2, "particles": 200,
      "domain": {"min": [0, 0, 0], "max": [100, 1, 1]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.5, 0.5, 1]}],
      "colliders": [{"type": "box", "center": [1.2, 0.3, 0.5], "half": [0.0001, 0.3, 0.5]}],
      "sph": {"wall_particles": true}})",
                                          "plate");
    const double spacing = 0.05;
    wall_particles<2> walls;
    walls.seed(s, s.colliders, spacing, 2.6 * spacing, 1, 200);
    ASSERT_EQ(walls.size(), 12u);  // 0.6 / 0.05 rows, one column
    for (std::size_t w = 0; w < walls.size(); ++w) EXPECT_NEAR(walls.positions()[2 * w], 1.2, 1e-6);
}

}  // namespace
