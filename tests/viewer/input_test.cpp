// Mouse input as scripts drive it: a drag over the scene orbits the camera, a right drag pans,
// the wheel zooms, a drag that starts on the panel leaves the camera alone, and `c` resets it.
#include <gtest/gtest.h>

#include <cmath>

#include "projection.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;

namespace {

nlohmann::json camera_after(const scratch_dir& dir, const std::string& actions) {
    write_text(dir / "script.json", R"({"steps_per_frame": 0, "actions": [)" + actions + "]}");
    const auto r = run_viewer(dir, "--scene droplet --particles 300 --script script.json --frames 20 --state s.json");
    EXPECT_EQ(r.code, 0) << r.err;
    return read_json(dir / "s.json").at("camera");
}

double distance(const nlohmann::json& a, const nlohmann::json& b) {
    double s = 0;
    for (int i = 0; i < 3; ++i) s += std::pow(a[i].get<double>() - b[i].get<double>(), 2);
    return std::sqrt(s);
}

}  // namespace

TEST(ViewerInput, DragsAndWheelMoveTheCameraOnlyOverTheScene) {
    const scratch_dir dir("viewer_input");
    const auto home = camera_after(dir, "");
    // The window is 960 x 600 with the panel on its right 380 pixels (text at its top).
    const auto orbit = camera_after(dir, R"({"frame": 2, "do": "drag", "from": [200, 300], "to": [320, 300], "frames": 5})");
    EXPECT_EQ(orbit.at("target"), home.at("target"));  // orbiting keeps the target
    // 120 pixels to the right turn the view 36 degrees (0.3 a pixel) from the home yaw of 30
    // degrees, at the home pitch of 20 and the home distance.
    const std::array<double, 3> target = home.at("target");
    const double d = distance(home.at("eye"), home.at("target"));
    const auto expected = orbit_eye(target, d, 30 - 36, 20);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(orbit.at("eye")[a].get<double>(), expected[std::size_t(a)], 1e-4) << a;
    const auto pan = camera_after(dir, R"({"frame": 2, "do": "drag", "from": [200, 300], "to": [260, 340], "button": "right"})");
    EXPECT_GT(distance(pan.at("target"), home.at("target")), 0.01);
    const auto zoom = camera_after(dir, R"({"frame": 2, "do": "scroll", "x": 200, "y": 300, "steps": 3})");
    EXPECT_LT(distance(zoom.at("eye"), zoom.at("target")), 0.8 * distance(home.at("eye"), home.at("target")));
    const auto on_panel = camera_after(dir, R"({"frame": 2, "do": "drag", "from": [700, 45], "to": [820, 45], "frames": 5})");
    EXPECT_EQ(on_panel.at("eye"), home.at("eye"));
    const auto reset = camera_after(dir, R"({"frame": 2, "do": "drag", "from": [200, 300], "to": [320, 300], "frames": 5},
                                           {"frame": 12, "do": "key", "key": "c"})");
    EXPECT_EQ(reset.at("eye"), home.at("eye"));
}
