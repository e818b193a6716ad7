// Picking: a click on a particle selects it (its id in the state), a click on the background
// selects none, in 3D and in the plane view.
#include <gtest/gtest.h>

#include "projection.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;

namespace {
const char* layer_scene = R"({"name": "layer", "dim": %d, "particles": 16, "gravity": [0, 0, 0],
  "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
  "fluid": [{"type": "box", "min": [0.3, 0.3, 0.45], "max": [0.7, 0.7, 0.55]}]})";

std::string scene_text(int dim) {
    char text[512];
    std::snprintf(text, sizeof text, layer_scene, dim);
    return text;
}

/// Runs the scene paused with the camera of `camera` (JSON, may be empty) and clicks at (x, y).
nlohmann::json click(const scratch_dir& dir, int dim, const std::string& camera, double x, double y) {
    write_text(dir / "layer.json", scene_text(dim));
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 0, "do": "pause"}, )" + camera +
                                        R"({"frame": 2, "do": "click", "x": )" + std::to_string(x) + R"(, "y": )" +
                                        std::to_string(y) + "}]}");
    const auto r = run_viewer(dir, "layer.json --script script.json --frames 5 --state state.json");
    EXPECT_EQ(r.code, 0) << r.err;
    return read_json(dir / "state.json");
}

/// The state of a paused run with no click: where the particles are and how the camera looks.
nlohmann::json look(const scratch_dir& dir, int dim, const std::string& camera) { return click(dir, dim, camera, 2, 2); }
}  // namespace

TEST(ViewerPicking, ClickSelectsTheParticleUnderThePointer) {
    const scratch_dir dir("viewer_picking");
    const std::string camera = R"({"frame": 0, "do": "camera", "target": [0.5, 0.5, 0.5], "distance": 1.2, "yaw": 25, "pitch": 20, "fov": 40}, )";
    const auto before = look(dir, 3, camera);
    EXPECT_TRUE(before.at("picked").is_null());  // a click at (2, 2) hits nothing
    const std::array<int, 4> vp = before.at("camera").at("viewport");
    const int height = before.at("camera").at("height");
    const auto eye = orbit_eye({0.5, 0.5, 0.5}, 1.2, 25, 20);
    const auto& x = before.at("x");
    const std::size_t n = before.at("particles");
    ASSERT_GE(n, 9u);
    for (std::size_t k : {std::size_t(0), n / 2, n - 1}) {
        const pixel_xy at = project({x[k * 3], x[k * 3 + 1], x[k * 3 + 2]}, eye, {0.5, 0.5, 0.5}, 40, vp, height);
        const auto after = click(dir, 3, camera, at.x, at.y);
        EXPECT_EQ(after.at("picked"), k);
    }
}

TEST(ViewerPicking, PlaneViewPicksToo) {
    const scratch_dir dir("viewer_picking_2d");
    const auto before = look(dir, 2, "");
    const auto& cam = before.at("camera");
    const std::array<int, 4> vp = cam.at("viewport");
    const std::array<double, 3> target = cam.at("target");
    const double scale = vp[3] / (2 * cam.at("half_height").get<double>());
    const int height = cam.at("height");
    const auto& x = before.at("x");
    const std::size_t k = 5;
    const double px = vp[0] + 0.5 * vp[2] + (x[k * 3].get<double>() - target[0]) * scale;
    const double py = height - (vp[1] + 0.5 * vp[3] + (x[k * 3 + 1].get<double>() - target[1]) * scale);
    EXPECT_EQ(click(dir, 2, "", px, py).at("picked"), k);
}
