// The law of the wall behind "wall_friction" (sim/src/wall_friction.hpp): the friction
// velocity solves the sublayer's or the log layer's equation, and is continuous where they meet.
#include <gtest/gtest.h>

#include <cmath>

#include "wall_friction.hpp"

namespace frnn::sim::detail {
namespace {

constexpr double water = 1e-6;

TEST(WallFriction, TheCrossoverIsWhereBothLawsGiveTheSameVelocity) {
    const double y = log_law_crossover();
    EXPECT_NEAR(y, std::log(log_law_e * y) / log_law_kappa, 1e-12);
    EXPECT_GT(y, 11.0);
    EXPECT_LT(y, 12.0);
}

TEST(WallFriction, ViscousSublayerCloseToTheWall) {
    // u = 0.01 m/s at 0.1 mm: y+ about 1.
    const double u = 0.01, y = 1e-4, t = friction_velocity(u, y, water);
    EXPECT_NEAR(u / t, y * t / water, 1e-12 * u / t);
    EXPECT_NEAR(t, std::sqrt(water * u / y), 1e-15);
}

TEST(WallFriction, LogLawFurtherOut) {
    for (double u : {0.1, 1.0, 3.0, 30.0})
        for (double y : {1e-4, 7.5e-4, 1e-2, 1.0}) {
            const double t = friction_velocity(u, y, water), y_plus = y * t / water;
            if (y_plus <= log_law_crossover()) continue;
            EXPECT_NEAR(u / t, std::log(log_law_e * y_plus) / log_law_kappa, 1e-9 * u / t) << "u " << u << ", y " << y;
        }
    // Water at 2 m/s, 0.75 mm from the wall: y+ far in the log layer.
    EXPECT_GT(7.5e-4 * friction_velocity(2, 7.5e-4, water) / water, 30);
}

TEST(WallFriction, ContinuousAndRisingWithTheSpeed) {
    // Across the crossover: u+ = y+ = y+_c at u = y+_c^2 nu / y.
    const double y = 1e-3, yc = log_law_crossover(), u_c = yc * yc * water / y;
    const double below = friction_velocity(u_c * (1 - 1e-9), y, water), above = friction_velocity(u_c * (1 + 1e-9), y, water);
    EXPECT_NEAR(below, above, 1e-7 * above);
    double last = 0;
    for (double u = 1e-4; u < 100; u *= 1.3) {
        const double t = friction_velocity(u, y, water);
        EXPECT_GT(t, last) << u;
        last = t;
    }
    EXPECT_EQ(friction_velocity(0, y, water), 0);
}

}  // namespace
}  // namespace frnn::sim::detail
