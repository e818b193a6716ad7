// Signed distances and projections of the colliders.
#include <gtest/gtest.h>

#include <cmath>

#include "frnn/sim/colliders.hpp"

using frnn::sim::collider;
using frnn::sim::posed_collider;
using frnn::sim::shape;
using frnn::sim::vec3;

TEST(SimColliders, PlaneSphereBoxDistances) {
    collider plane;
    plane.kind = shape::plane;
    plane.center = {0, 1, 0};
    plane.normal = {0, 2, 0};
    vec3 n;
    EXPECT_NEAR(posed_collider(plane, 0).phi({5, 3, 1}, n), 2.0, 1e-12);
    EXPECT_NEAR(n[1], 1.0, 1e-12);

    collider ball;
    ball.kind = shape::sphere;
    ball.center = {1, 1, 1};
    ball.radius = 0.5;
    EXPECT_NEAR(posed_collider(ball, 0).phi({1, 3, 1}, n), 1.5, 1e-12);
    ball.inside = true;
    EXPECT_NEAR(posed_collider(ball, 0).phi({1, 1.2, 1}, n), 0.3, 1e-12);
    EXPECT_NEAR(n[1], -1.0, 1e-12);  // toward the center from above: into the fluid

    collider box;
    box.kind = shape::box;
    box.half = {1, 2, 3};
    EXPECT_NEAR(posed_collider(box, 0).phi({2, 0, 0}, n), 1.0, 1e-12);
    EXPECT_NEAR(posed_collider(box, 0).phi({2, 3, 0}, n), std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(posed_collider(box, 0).phi({0.5, 0, 0}, n), -0.5, 1e-12);
    // Rotated by 90 degrees about z: the x half extent now lies along y.
    box.angle = 3.14159265358979323846 / 2;
    EXPECT_NEAR(posed_collider(box, 0).phi({0, 1.5, 0}, n), 0.5, 1e-12);
}

TEST(SimColliders, ContainerBoxKeepsParticlesInsideWithMargin) {
    collider tank;
    tank.kind = shape::box;
    tank.inside = true;
    tank.center = {1, 1, 1};
    tank.half = {1, 1, 1};
    tank.axis = {1, 1, 0};
    tank.angle = 0.3;
    const posed_collider c(tank, 0);
    const double margin = 0.05;
    for (double x = -1; x <= 3; x += 0.37)
        for (double y = -1; y <= 3; y += 0.41)
            for (double z = -1; z <= 3; z += 0.43) {
                vec3 p{x, y, z}, v{1, -2, 0.5}, n;
                c.resolve(p, v, margin);
                EXPECT_GE(c.phi(p, n), margin - 1e-9) << x << " " << y << " " << z;
            }
}

TEST(SimColliders, RestitutionAndFriction) {
    collider floor;
    floor.kind = shape::plane;
    floor.normal = {0, 1, 0};
    floor.restitution = 0.5;
    vec3 x{0, -0.1, 0}, v{2, -4, 0};
    EXPECT_TRUE(posed_collider(floor, 0).resolve(x, v, 0.01));
    EXPECT_NEAR(x[1], 0.01, 1e-12);
    EXPECT_NEAR(v[1], 2.0, 1e-12);  // -0.5 * -4
    EXPECT_NEAR(v[0], 2.0, 1e-12);  // no friction
    floor.friction = 0.1;
    x = {0, -0.1, 0}, v = {2, -4, 0};
    posed_collider(floor, 0).resolve(x, v, 0.01);
    EXPECT_NEAR(v[0], 2.0 - 0.1 * 6.0, 1e-12);  // tangential loss: friction * normal change
    // A particle above the floor is left alone.
    x = {0, 1, 0}, v = {0, -1, 0};
    EXPECT_FALSE(posed_collider(floor, 0).resolve(x, v, 0.01));
    EXPECT_EQ(v[1], -1);
}

TEST(SimColliders, ScriptedMotionMovesTheSurfaceAndDragsParticles) {
    collider paddle;
    paddle.kind = shape::box;
    paddle.half = {0.1, 0.1, 0.1};
    paddle.path.amplitude = {1, 0, 0};
    paddle.path.frequency = 0.25;  // quarter period at t = 1: center at x = 1, at rest
    vec3 n;
    EXPECT_NEAR(posed_collider(paddle, 1.0).phi({1, 0, 0}, n), -0.1, 1e-9);
    EXPECT_NEAR(posed_collider(paddle, 1.0).velocity_at({1, 0, 0})[0], 0, 1e-9);
    const double vx0 = posed_collider(paddle, 0).velocity_at({0, 0, 0})[0];
    EXPECT_NEAR(vx0, 2 * 3.14159265358979323846 * 0.25, 1e-9);
    // At t = 0 the paddle moves right at vx0: a particle at rest hit on its right face leaves
    // with the paddle's velocity (restitution 0).
    vec3 x{0.09, 0, 0}, v{0, 0, 0};
    posed_collider(paddle, 0).resolve(x, v, 0.0);
    EXPECT_NEAR(x[0], 0.1, 1e-9);
    EXPECT_NEAR(v[0], vx0, 1e-9);
    // A rotating plane: surface velocity omega x r.
    collider blade;
    blade.kind = shape::plane;
    blade.path.angular_velocity = 2;
    const vec3 u = posed_collider(blade, 0).velocity_at({1, 0, 0});
    EXPECT_NEAR(u[1], 2, 1e-12);
}
