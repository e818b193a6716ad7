// Colliders by hand: a scripted drag moves a sphere to the point under the pointer (computed
// here from the camera in the --state dump) and it pushes the fluid it sweeps; while held it
// moves at its displacement over the simulated time in between; Shift moves it along the view;
// a box turns about the view direction; add, delete and save scene round-trip; a click on
// empty space selects nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "projection.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;
using v3 = std::array<double, 3>;

namespace {

// A ball in a tank, half full, and a tilted brick above; a fixed time step, 2 steps per frame,
// the camera set by the script.
const char* ball_scene = R"({"name": "ball", "dim": 3, "particles": 4000, "solver": "viscoelastic",
  "domain": {"min": [0, 0, 0], "max": [1, 0.6, 0.5]},
  "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.3, 0.5]}],
  "colliders": [{"name": "ball", "type": "sphere", "center": [0.25, 0.15, 0.25], "radius": 0.1},
                {"name": "tank", "type": "box", "inside": true, "center": [0.5, 0.3, 0.25], "half": [0.5, 0.3, 0.25]},
                {"name": "brick", "type": "box", "center": [0.75, 0.42, 0.25], "half": [0.08, 0.04, 0.06],
                 "axis": [1, 1, 0], "angle": 20}],
  "viscoelastic": {"dt": 0.002, "cfl": 0}})";
const std::string camera = R"({"frame": 0, "do": "camera", "target": [0.5, 0.2, 0.25], "distance": 1.6, "yaw": 0, "pitch": 30, "fov": 45})";

/// Runs a scene (the ball's) with these actions after a first one (the camera's) for `frames`
/// frames.
nlohmann::json run_ball(const scratch_dir& dir, const std::string& actions, int frames, const std::string& scene = ball_scene,
                        const std::string& first = camera) {
    write_text(dir / "ball.json", scene);
    write_text(dir / "script.json", R"({"steps_per_frame": 2, "actions": [)" + first + actions + "]}");
    const auto r = run_viewer(dir, "ball.json --script script.json --frames " + std::to_string(frames) + " --state state.json");
    EXPECT_EQ(r.code, 0) << r.err;
    return read_json(dir / "state.json");
}

std::string at(const pixel_xy& p) {
    char text[64];
    std::snprintf(text, sizeof text, "[%.3f, %.3f]", p.x, p.y);
    return text;
}
std::string click(int frame, const pixel_xy& p) {
    return R"(, {"frame": )" + std::to_string(frame) + R"(, "do": "click", "x": )" + std::to_string(p.x) + R"(, "y": )" +
           std::to_string(p.y) + "}";
}

double distance(const v3& a, const v3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }
v3 particle(const nlohmann::json& state, std::size_t k) {
    const auto& x = state.at("x");
    return {x[k * 3], x[k * 3 + 1], x[k * 3 + 2]};
}

/// The camera of a dump, and where it draws a point / what lies under a pixel.
struct view {
    v3 eye, target;
    double fov;
    std::array<int, 4> viewport;
    int height;
    explicit view(const nlohmann::json& state) {
        const auto& c = state.at("camera");
        eye = c.at("eye"), target = c.at("target"), fov = c.at("fov"), viewport = c.at("viewport"), height = c.at("height");
    }
    pixel_xy pixel(const v3& p) const { return project(p, eye, target, fov, viewport, height); }
    v3 under(const pixel_xy& p, const v3& depth_of) const { return unproject(p, depth_of, eye, target, fov, viewport, height); }
    v3 forward() const {
        const v3 d{target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
        const double l = std::hypot(d[0], d[1], d[2]);
        return {d[0] / l, d[1] / l, d[2] / l};
    }
};

/// R(axis, degrees) m, by Rodrigues' formula.
std::array<v3, 3> turn(const v3& axis, double degrees, const std::array<v3, 3>& m) {
    const double th = degrees * 3.14159265358979323846 / 180, c = std::cos(th), s = std::sin(th);
    const double l = std::hypot(axis[0], axis[1], axis[2]);
    const v3 k{axis[0] / l, axis[1] / l, axis[2] / l};
    const double kx[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    std::array<v3, 3> out{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int n = 0; n < 3; ++n) out[i][j] += ((i == n ? c : 0) + (1 - c) * k[i] * k[n] + s * kx[i][n]) * m[n][j];
    return out;
}
std::array<v3, 3> rotation(const nlohmann::json& collider) { return collider.at("rotation").get<std::array<v3, 3>>(); }

}  // namespace

TEST(ViewerColliders, DragPutsTheSphereUnderThePointerAndSweepsTheFluid) {
    const scratch_dir dir("viewer_collider_drag");
    const int frames = 40;
    const auto still = run_ball(dir, "", frames);
    const view cam(still);
    const v3 center0 = still.at("colliders")[0].at("center");
    const double radius = still.at("colliders")[0].at("radius"), spacing = still.at("spacing");
    const pixel_xy a = cam.pixel(center0), b{a.x + 200, a.y - 10};
    const v3 expected = cam.under(b, center0);
    ASSERT_GT(distance(expected, center0), 3 * radius);  // a sweep through the fluid, not a nudge

    const std::string drag = R"(, {"frame": 3, "do": "drag", "from": )" + at(a) + R"(, "to": )" + at(b) + R"(, "frames": 16})";
    const auto moved = run_ball(dir, drag, frames);
    const auto& ball = moved.at("colliders")[0];
    EXPECT_LT(distance(ball.at("center"), expected), 0.5 * spacing) << ball.dump();
    EXPECT_EQ(moved.at("selected_collider"), 0);
    EXPECT_EQ(distance(ball.at("velocity"), {0, 0, 0}), 0) << "released: at rest";

    // The particles where the ball now is, had it stayed, were pushed out of it.
    std::size_t swept = 0;
    double shift = 0;
    for (std::size_t k = 0; k < still.at("particles").get<std::size_t>(); ++k) {
        if (distance(particle(still, k), expected) >= radius) continue;
        ++swept;
        EXPECT_GE(distance(particle(moved, k), expected), radius * (1 - 1e-3)) << "particle " << k;
        shift += distance(particle(moved, k), particle(still, k));
    }
    ASSERT_GE(swept, 20u);
    EXPECT_GT(shift / double(swept), spacing);
}

TEST(ViewerColliders, PlaneViewDragMovesABoxInTheXyPlane) {
    const scratch_dir dir("viewer_collider_drag_2d");
    const std::string scene = R"({"name": "block", "dim": 2, "particles": 1500, "solver": "viscoelastic",
      "domain": {"min": [0, 0, 0], "max": [1, 0.6, 1]}, "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.25, 1]}],
      "colliders": [{"name": "block", "type": "box", "center": [0.3, 0.45, 0], "half": [0.06, 0.04, 0.06]}],
      "viscoelastic": {"dt": 0.002, "cfl": 0}})";
    const std::string play = R"({"frame": 0, "do": "play"})";  // the plane view as it opens
    const auto still = run_ball(dir, "", 2, scene, play);
    // The plane view: the target at the viewport's center, vp[3] / (2 half_height) pixels a unit.
    const auto& cam = still.at("camera");
    const std::array<int, 4> vp = cam.at("viewport");
    const v3 view_target = cam.at("target");
    const double scale = vp[3] / (2 * cam.at("half_height").get<double>());
    const int height = cam.at("height");
    const auto pixel = [&](double x, double y) {
        return pixel_xy{vp[0] + 0.5 * vp[2] + (x - view_target[0]) * scale, height - (vp[1] + 0.5 * vp[3] + (y - view_target[1]) * scale)};
    };
    const pixel_xy a = pixel(0.3, 0.45), b{a.x + 150, a.y + 40};
    const v3 expected{0.3 + 150 / scale, 0.45 - 40 / scale, 0};
    const auto moved = run_ball(dir, R"(, {"frame": 3, "do": "drag", "from": )" + at(a) + R"(, "to": )" + at(b) + R"(, "frames": 8})", 16,
                                scene, play);
    EXPECT_EQ(moved.at("selected_collider"), 0);
    EXPECT_LT(distance(moved.at("colliders")[0].at("center"), expected), 0.5 * moved.at("spacing").get<double>())
        << moved.at("colliders")[0].dump();
}

TEST(ViewerColliders, HeldSphereMovesAtItsDisplacementOverTheStepsInBetween) {
    const scratch_dir dir("viewer_collider_velocity");
    const auto still = run_ball(dir, "", 2);
    const view cam(still);
    const v3 center0 = still.at("colliders")[0].at("center");
    const double spacing = still.at("spacing");
    const pixel_xy a = cam.pixel(center0), b{a.x + 160, a.y};
    // The drag presses at frame 3 and moves 1/16 of the way each frame after; the run ends
    // holding it at frame 10, 7/16 of the way.
    const std::string drag = R"(, {"frame": 3, "do": "drag", "from": )" + at(a) + R"(, "to": )" + at(b) + R"(, "frames": 16})";
    const auto held = run_ball(dir, drag, 11);
    const auto& ball = held.at("colliders")[0];
    const v3 a3 = cam.under(a, center0), b3 = cam.under(b, center0);
    v3 expected{}, velocity{};
    const double dt = held.at("time").get<double>() / held.at("step").get<double>();  // a fixed time step
    for (int k = 0; k < 3; ++k) {
        expected[k] = a3[k] + 7.0 / 16 * (b3[k] - a3[k]);
        velocity[k] = (b3[k] - a3[k]) / 16 / (2 * dt);  // one frame's displacement over its 2 steps
    }
    EXPECT_LT(distance(ball.at("center"), expected), 0.5 * spacing) << ball.dump();
    EXPECT_LT(distance(ball.at("velocity"), velocity), 1e-3 * std::hypot(velocity[0], velocity[1], velocity[2])) << ball.dump();
}

TEST(ViewerColliders, ShiftDragMovesAlongTheViewDirection) {
    const scratch_dir dir("viewer_collider_shift");
    const auto still = run_ball(dir, "", 2);
    const view cam(still);
    const v3 center0 = still.at("colliders")[0].at("center");
    const pixel_xy a = cam.pixel(center0), b{a.x, a.y - 60};
    const std::string drag = R"(, {"frame": 3, "do": "drag", "from": )" + at(a) + R"(, "to": )" + at(b) +
                             R"(, "frames": 6, "modifier": "shift"})";
    const auto moved = run_ball(dir, drag, 14);
    // Up the screen is away from the eye, by the pixels' size at the ball's depth.
    const v3 f = cam.forward();
    const double depth = (center0[0] - cam.eye[0]) * f[0] + (center0[1] - cam.eye[1]) * f[1] + (center0[2] - cam.eye[2]) * f[2];
    const double pixel = 2 * depth * std::tan(cam.fov * 3.14159265358979 / 360) / cam.viewport[3];
    v3 expected{};
    for (int k = 0; k < 3; ++k) expected[k] = center0[k] + 60 * pixel * f[k];
    EXPECT_LT(distance(moved.at("colliders")[0].at("center"), expected), 0.5 * moved.at("spacing").get<double>())
        << moved.at("colliders")[0].dump();
}

TEST(ViewerColliders, RotateTurnsTheSelectedBoxAboutTheViewDirection) {
    const scratch_dir dir("viewer_collider_rotate");
    const auto still = run_ball(dir, "", 2);
    const view cam(still);
    const auto& brick0 = still.at("colliders")[2];
    const pixel_xy on_brick = cam.pixel(brick0.at("center"));
    // 40 degrees counterclockwise by the action, then 15 back by the key ']'.
    const auto turned = run_ball(dir, click(2, on_brick) + R"(, {"frame": 4, "do": "rotate_collider", "degrees": 40},
        {"frame": 5, "do": "key", "key": "]"})", 8);
    EXPECT_EQ(turned.at("selected_collider"), 2);
    const v3 back{cam.eye[0] - cam.target[0], cam.eye[1] - cam.target[1], cam.eye[2] - cam.target[2]};
    const auto expected = turn(back, 25, rotation(brick0)), got = rotation(turned.at("colliders")[2]);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(got[i][j], expected[i][j], 1e-5) << i << ", " << j;
    EXPECT_EQ(turned.at("colliders")[2].at("center"), brick0.at("center"));
}

TEST(ViewerColliders, AddDeleteAndSaveSceneRoundTrip) {
    const scratch_dir dir("viewer_collider_save");
    const auto still = run_ball(dir, "", 2);
    const view cam(still);
    // Paused: add a sphere and a box (each selected), delete the box, select the ball by a
    // click and delete it too, then save.
    const auto edited = run_ball(dir, R"(, {"frame": 1, "do": "pause"}, {"frame": 2, "do": "add_collider", "type": "sphere"},
        {"frame": 3, "do": "add_collider", "type": "box"}, {"frame": 4, "do": "delete_collider"})" +
                                          click(5, cam.pixel(still.at("colliders")[0].at("center"))) +
                                          R"(, {"frame": 7, "do": "delete_collider"}, {"frame": 8, "do": "save_scene", "path": "saved.json"})",
                                 10);
    EXPECT_TRUE(edited.at("selected_collider").is_null());
    const auto& c = edited.at("colliders");
    ASSERT_EQ(c.size(), 3u) << c.dump();  // tank, brick, the new sphere
    EXPECT_EQ(c[0].at("name"), "tank");
    EXPECT_EQ(c[1].at("name"), "brick");
    EXPECT_EQ(c[2].at("type"), "sphere");
    // Its radius a tenth of the domain's smallest side (0.5), inside the domain, with a
    // particle spacing of room around it (the particles have not moved since: paused).
    const double radius = c[2].at("radius"), spacing = edited.at("spacing");
    EXPECT_EQ(radius, 0.05);
    const v3 center = c[2].at("center"), hi{1, 0.6, 0.5};
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(center[a], radius - 1e-9);
        EXPECT_LE(center[a], hi[a] - radius + 1e-9);
    }
    for (std::size_t k = 0; k < edited.at("particles").get<std::size_t>(); ++k)
        ASSERT_GE(distance(particle(edited, k), center), radius + spacing) << "particle " << k;

    // The saved scene, run again, has the same colliders.
    write_text(dir / "script.json", R"({"steps_per_frame": 0, "actions": []})");
    const auto r = run_viewer(dir, "saved.json --script script.json --frames 1 --state reloaded.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto reloaded = read_json(dir / "reloaded.json").at("colliders");
    ASSERT_EQ(reloaded.size(), c.size());
    for (std::size_t k = 0; k < c.size(); ++k) {
        EXPECT_EQ(reloaded[k].at("name"), c[k].at("name"));
        EXPECT_EQ(reloaded[k].at("type"), c[k].at("type"));
        EXPECT_LT(distance(reloaded[k].at("center"), c[k].at("center")), 1e-9);
        for (const char* size : {"radius", "half"})
            if (c[k].contains(size)) {
                EXPECT_EQ(reloaded[k].at(size), c[k].at(size));
            }
        const auto r0 = rotation(reloaded[k]), r1 = rotation(c[k]);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) EXPECT_NEAR(r0[i][j], r1[i][j], 1e-9);
    }
}

TEST(ViewerColliders, ClickOnEmptySpaceSelectsNothing) {
    const scratch_dir dir("viewer_collider_select");
    const auto still = run_ball(dir, "", 2);
    const view cam(still);
    const pixel_xy on_ball = cam.pixel(still.at("colliders")[0].at("center"));
    // Inside the tank (a container: picked by its outline only), far from its edges and the
    // other colliders.
    const pixel_xy inside = cam.pixel({0.5, 0.45, 0.25});
    const v3 lo{0, 0, 0}, hi{1, 0.6, 0.5};
    const auto corner = [&](int e) { return cam.pixel({e & 1 ? hi[0] : lo[0], e & 2 ? hi[1] : lo[1], e & 4 ? hi[2] : lo[2]}); };
    for (int e = 0; e < 8; ++e)
        for (int bit = 1; bit < 8; bit *= 2) {  // the edges from corner e to its neighbors
            const pixel_xy p = corner(e), q = corner(e ^ bit);
            const double dx = q.x - p.x, dy = q.y - p.y;
            const double u = std::clamp(((inside.x - p.x) * dx + (inside.y - p.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
            ASSERT_GT(std::hypot(p.x + u * dx - inside.x, p.y + u * dy - inside.y), 20) << "a tank edge near the test's pixel";
        }
    EXPECT_EQ(run_ball(dir, click(2, on_ball), 5).at("selected_collider"), 0);
    EXPECT_TRUE(run_ball(dir, click(2, on_ball) + click(4, inside), 7).at("selected_collider").is_null());
    EXPECT_TRUE(run_ball(dir, click(2, inside), 5).at("selected_collider").is_null());
    EXPECT_TRUE(run_ball(dir, click(2, {2, 2}), 5).at("selected_collider").is_null());
}

TEST(ViewerColliders, BadCollidersActionsNameTheAction) {
    const scratch_dir dir("viewer_collider_errors");
    write_text(dir / "ball.json", ball_scene);
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "delete_collider"}]})");
    const auto r = run_viewer(dir, "ball.json --script script.json --frames 3");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("script.json: actions[0] (frame 1): delete_collider: no collider is selected"), std::string::npos) << r.err;
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "drag", "from": [1, 1], "to": [5, 5], "modifier": "alt"}]})");
    const auto m = run_viewer(dir, "ball.json --script script.json --frames 3");
    EXPECT_EQ(m.code, 1);
    EXPECT_EQ(lines(m.err), 1) << m.err;
    EXPECT_NE(m.err.find("script.json: actions[0]: key 'modifier': expected \"shift\", got \"alt\""), std::string::npos) << m.err;
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "add_collider", "type": "cone"}]})");
    const auto t = run_viewer(dir, "ball.json --script script.json --frames 3");
    EXPECT_EQ(t.code, 1);
    EXPECT_NE(t.err.find("script.json: actions[0]: key 'type': expected \"sphere\" or \"box\", got \"cone\""), std::string::npos) << t.err;
}
