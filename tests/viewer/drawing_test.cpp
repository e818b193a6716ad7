// What the viewer draws: each particle at its projected pixel, in the legend's color for its
// field value (3D perspective and 2D plane view), and the colliders' outlines where they are.
// The projection is computed here from the camera the script sets (not from the viewer's
// matrices), and the expected colors are read from the legend in the same picture.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "projection.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;

namespace {

// One layer of particles facing the camera, no gravity: they stay where they were seeded.
const char* layer_scene = R"({"name": "layer", "dim": 3, "particles": 16, "gravity": [0, 0, 0],
  "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
  "fluid": [{"type": "box", "min": [0.2, 0.2, 0.45], "max": [0.8, 0.8, 0.55]}]})";

/// Each particle k of the state, colored by id over [0, n - 1], shows the legend's color for k
/// at the pixel `at(position)`: the centroid of the pixels of that color near it lies within
/// 2 px, and the pixel itself has that color.
template <class Projection>
void expect_particles_at(const nlohmann::json& state, const frnn::sim::image& img, Projection at_of) {
    const std::size_t n = state.at("particles");
    const double top = double(n - 1);
    const std::array<double, 4> legend = state.at("legend").at("rect");
    const auto& x = state.at("x");
    for (std::size_t k = 0; k < n; ++k) {
        const pixel_xy at = at_of({x[k * 3], x[k * 3 + 1], x[k * 3 + 2]});
        // The legend's color for value k of the range [0, n - 1].
        const double lx = legend[0] + double(k) / top * (legend[2] - legend[0]), ly = 0.5 * (legend[1] + legend[3]);
        const rgb expected = pixel(img, int(std::lround(std::clamp(lx, legend[0] + 1, legend[2] - 2))), int(ly));
        // Pixels of that color near the projection: their centroid is the sphere's center.
        double sx = 0, sy = 0;
        int count = 0;
        for (int y = int(at.y) - 15; y <= int(at.y) + 15; ++y)
            for (int xx = int(at.x) - 15; xx <= int(at.x) + 15; ++xx)
                if (xx >= 0 && y >= 0 && xx < img.width && y < img.height && color_distance(pixel(img, xx, y), expected) <= 6)
                    sx += xx + 0.5, sy += y + 0.5, ++count;
        ASSERT_GE(count, 5) << "particle " << k << ": no pixel of the legend's color near (" << at.x << ", " << at.y << ")";
        EXPECT_NEAR(sx / count, at.x, 2.0) << "particle " << k;
        EXPECT_NEAR(sy / count, at.y, 2.0) << "particle " << k;
        EXPECT_LE(color_distance(pixel(img, int(at.x), int(at.y)), expected), 8) << "particle " << k;
    }
}

}  // namespace

TEST(ViewerDrawing, ParticlesAtTheirProjectedPixelsInTheLegendsColors) {
    const scratch_dir dir("viewer_drawing");
    write_text(dir / "layer.json", layer_scene);
    // Camera: target (0.5, 0.5, 0.5), 1.3 away, yawed 20 and pitched 15 degrees, fov 40.
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 0, "do": "pause"},
        {"frame": 0, "do": "camera", "target": [0.5, 0.5, 0.5], "distance": 1.3, "yaw": 20, "pitch": 15, "fov": 40},
        {"frame": 0, "do": "color", "field": "id", "range": [0, 24]}]})");
    const auto r = run_viewer(dir, "layer.json --script script.json --frames 3 --screenshot shot.png --state state.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto state = read_json(dir / "state.json");
    const frnn::sim::image img = frnn::sim::decode_png(slurp(dir / "shot.png"));
    ASSERT_EQ(state.at("step"), 0);
    const std::size_t n = state.at("particles");
    ASSERT_EQ(n, 25u);  // a 5 x 5 layer
    const auto& cam = state.at("camera");
    const std::array<int, 4> vp = cam.at("viewport");
    ASSERT_EQ(img.height, int(cam.at("height")));
    const std::array<double, 3> target{0.5, 0.5, 0.5}, eye = orbit_eye(target, 1.3, 20, 15);
    expect_particles_at(state, img, [&](const std::array<double, 3>& p) { return project(p, eye, target, 40, vp, img.height); });
}

TEST(ViewerDrawing, PlaneViewOfA2DScene) {
    const scratch_dir dir("viewer_drawing_2d");
    write_text(dir / "layer.json", R"({"name": "layer2d", "dim": 2, "particles": 16, "gravity": [0, 0, 0],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "fluid": [{"type": "box", "min": [0.3, 0.3, 0], "max": [0.7, 0.7, 0]}]})");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 0, "do": "pause"}, {"frame": 0, "do": "color", "field": "id", "range": [0, 15]}]})");
    const auto r = run_viewer(dir, "layer.json --script script.json --frames 3 --screenshot shot.png --state state.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto state = read_json(dir / "state.json");
    const frnn::sim::image img = frnn::sim::decode_png(slurp(dir / "shot.png"));
    ASSERT_EQ(state.at("particles"), 16);
    const auto& cam = state.at("camera");
    ASSERT_TRUE(cam.at("plane_view").get<bool>());
    const std::array<int, 4> vp = cam.at("viewport");
    const std::array<double, 3> target = cam.at("target");
    const double half = cam.at("half_height");
    // Orthographic view of the xy plane: half_height scene units above and below the target.
    expect_particles_at(state, img, [&](const std::array<double, 3>& p) {
        const double scale = vp[3] / (2 * half);
        return pixel_xy{vp[0] + 0.5 * vp[2] + (p[0] - target[0]) * scale, img.height - (vp[1] + 0.5 * vp[3] + (p[1] - target[1]) * scale)};
    });
}

TEST(ViewerDrawing, CollidersAreOutlinedWhereTheyAre) {
    const scratch_dir dir("viewer_drawing_colliders");
    // A 2D scene: a box obstacle and a ball, fluid far from both, no gravity.
    write_text(dir / "scene.json", R"({"name": "outlines", "dim": 2, "particles": 16, "gravity": [0, 0, 0],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "fluid": [{"type": "box", "min": [0.05, 0.05, 0], "max": [0.15, 0.15, 0]}],
        "colliders": [{"type": "box", "center": [0.5, 0.4, 0], "half": [0.3, 0.1, 0.5]},
                      {"type": "sphere", "center": [0.6, 0.75, 0], "radius": 0.1}]})");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 0, "do": "pause"}]})");
    const auto r = run_viewer(dir, "scene.json --script script.json --frames 3 --screenshot shot.png --state state.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto state = read_json(dir / "state.json");
    const frnn::sim::image img = frnn::sim::decode_png(slurp(dir / "shot.png"));
    const auto& cam = state.at("camera");
    const std::array<int, 4> vp = cam.at("viewport");
    const std::array<double, 3> target = cam.at("target");
    const double scale = vp[3] / (2 * cam.at("half_height").get<double>());
    const auto px = [&](double x, double y) {
        return pixel_xy{vp[0] + 0.5 * vp[2] + (x - target[0]) * scale, img.height - (vp[1] + 0.5 * vp[3] + (y - target[1]) * scale)};
    };
    // The outline color (orange) within 1 px of a point of a collider's outline.
    const auto outlined = [&](double x, double y) {
        const pixel_xy p = px(x, y);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if (color_distance(pixel(img, int(p.x) + dx, int(p.y) + dy), {230, 153, 77}) <= 12) return true;
        return false;
    };
    for (double t : {0.1, 0.35, 0.6, 0.85}) {
        EXPECT_TRUE(outlined(0.2 + 0.6 * t, 0.3)) << "box bottom edge at " << t;
        EXPECT_TRUE(outlined(0.2 + 0.6 * t, 0.5)) << "box top edge at " << t;
        const double a = 6.2831853 * t;
        EXPECT_TRUE(outlined(0.6 + 0.1 * std::cos(a), 0.75 + 0.1 * std::sin(a))) << "circle at angle " << a;
    }
    EXPECT_FALSE(outlined(0.5, 0.4)) << "inside the box";
    EXPECT_FALSE(outlined(0.6, 0.75)) << "inside the ball";
}
