// `frnn view` runs the viewer beside the tool; a scene saved from the viewer, with a parameter
// changed live, runs in `frnn sim` and keeps that parameter.
#include <gtest/gtest.h>

#include "frnn/sim/parameters.hpp"
#include "frnn/sim/scene.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;

TEST(ViewerSceneFile, SavedSceneRunsInFrnnSim) {
    const scratch_dir dir("viewer_save_scene");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 1, "do": "set", "name": "viscoelastic.beta", "value": 0.375},
        {"frame": 1, "do": "gravity", "value": [0, -5, 0]},
        {"frame": 2, "do": "save_scene", "path": "saved.json"}]})");
    const auto v = run_viewer(dir, "--scene droplet --dim 2 --particles 300 --script script.json --frames 4");
    ASSERT_EQ(v.code, 0) << v.err;
    const frnn::sim::scene s = frnn::sim::load_scene((dir / "saved.json").string());
    EXPECT_EQ(s.viscoelastic.beta, 0.375);
    EXPECT_EQ(s.gravity[1], -5);
    EXPECT_EQ(s.dim, 2);
    const auto r = run_tool(dir, "sim saved.json --steps 5 --quiet --out run");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "run" / "summary.json"));
}

TEST(ViewerSceneFile, FrnnViewRunsTheViewer) {
    const scratch_dir dir("viewer_via_frnn");
    const auto r = run_in(dir, on_virtual_screen() + "'" FRNN_TOOL_PATH "' view --scene droplet --dim 2 --particles 200 --frames 3 --state s.json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_json(dir / "s.json").at("scene"), "droplet");
}
