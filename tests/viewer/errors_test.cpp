// Bad input to the viewer, and `frnn view` where there is no viewer: one line on stderr
// naming what and where, and a non-zero exit code; never a crash.
#include <gtest/gtest.h>

#include "viewer_run.hpp"

using namespace frnn::test;

TEST(ViewerErrors, BrokenSceneFileNamesTheFile) {
    const scratch_dir dir("viewer_broken_scene");
    write_text(dir / "broken.json", "{\"domain\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"fluid\": [");
    const auto r = run_viewer(dir, "broken.json --frames 2");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("frnn-view: error: broken.json: not valid JSON"), std::string::npos) << r.err;
    write_text(dir / "bad_key.json", R"({"domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}], "sph": {"gamma": 40}})");
    const auto k = run_viewer(dir, "bad_key.json --frames 2");
    EXPECT_EQ(k.code, 1);
    EXPECT_EQ(lines(k.err), 1) << k.err;
    EXPECT_NE(k.err.find("bad_key.json: key 'sph.gamma'"), std::string::npos) << k.err;
}

TEST(ViewerErrors, NoDisplay) {
    const scratch_dir dir("viewer_no_display");
    const auto r = run_in(dir, "env -u DISPLAY -u WAYLAND_DISPLAY '" FRNN_VIEW_PATH "' --scene droplet --dim 2 --particles 200 --frames 2");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("frnn-view: error: cannot open a window"), std::string::npos) << r.err;
}

// Under a launcher of several ranks (its variables, without mpirun): rank 0 refuses with one
// line, the other ranks end quietly; no window opens.
TEST(ViewerErrors, SeveralLauncherRanksAreRefused) {
    const scratch_dir dir("viewer_launcher_ranks");
    const auto first = run_in(dir, "OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 '" FRNN_VIEW_PATH "' --scene droplet --frames 2");
    EXPECT_EQ(first.code, 1);
    EXPECT_EQ(lines(first.err), 1) << first.err;
    EXPECT_NE(first.err.find("frnn-view: the viewer runs in one process, but an MPI launcher started 2 ranks"),
              std::string::npos)
        << first.err;
    const auto other = run_in(dir, "PMI_SIZE=3 PMI_RANK=2 '" FRNN_VIEW_PATH "' --scene droplet --frames 2");
    EXPECT_EQ(other.code, 0);
    EXPECT_TRUE(other.err.empty()) << other.err;
}

TEST(ViewerErrors, BadScriptNamesTheAction) {
    const scratch_dir dir("viewer_bad_script");
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "play"}, {"frame": 2, "do": "jump"}]})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 200 --script script.json --frames 3");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("script.json: actions[1]: unknown action 'jump'"), std::string::npos) << r.err;
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "set", "name": "sph.no_such", "value": 1}]})");
    const auto p = run_viewer(dir, "--scene droplet --dim 2 --particles 200 --script script.json --frames 3");
    EXPECT_EQ(p.code, 1);
    EXPECT_EQ(lines(p.err), 1) << p.err;
    EXPECT_NE(p.err.find("no parameter 'sph.no_such'"), std::string::npos) << p.err;
    write_text(dir / "script.json", R"({"actions": [{"frame": 1, "do": "set", "name": "sph.gamma", "value": 40}]})");
    const auto g = run_viewer(dir, "--scene droplet --dim 2 --particles 200 --script script.json --frames 3");
    EXPECT_EQ(g.code, 1);
    EXPECT_EQ(lines(g.err), 1) << g.err;
    EXPECT_NE(g.err.find("script.json: frame 1: parameter sph.gamma: expected a number in [1, 10], got 40"), std::string::npos) << g.err;
}

TEST(ViewerErrors, BadSceneKeyNamesTheActionKeyAndValue) {
    const scratch_dir dir("viewer_bad_scene_key");
    // The script's actions fail with one line holding `message`, and exit code 1.
    const auto fails = [&](const std::string& actions, const std::string& message) {
        write_text(dir / "script.json", R"({"actions": [)" + actions + "]}");
        const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 200 --paused --script script.json --frames 3");
        EXPECT_EQ(r.code, 1);
        EXPECT_EQ(lines(r.err), 1) << r.err;
        EXPECT_NE(r.err.find("frnn-view: error: script.json: " + message), std::string::npos) << r.err;
    };
    fails(R"({"frame": 1, "do": "play"}, {"frame": 2, "do": "set_scene", "key": "domain.maximum", "value": [2, 1, 1]})",
          "actions[1] (frame 2): set_scene domain.maximum = [2,1,1]: scene 'droplet': no key 'domain.maximum' in the scene");
    fails(R"({"frame": 1, "do": "set_scene", "key": "colliders[0].half", "value": [0.5, -1, 0.5]})",
          "actions[0] (frame 1): set_scene colliders[0].half = [0.5,-1,0.5]: scene 'droplet': key 'colliders[0].half': "
          "expected positive half extents");
    fails(R"({"frame": 1, "do": "set_scene", "key": "duration"})", "actions[0]: missing key 'value'");
}

TEST(ViewerErrors, FrnnViewWithoutTheViewerSaysWhatItNeeds) {
    const scratch_dir dir("viewer_not_built");
    // The frnn tool alone in a folder: no frnn-view beside it.
    std::filesystem::copy_file(FRNN_TOOL_PATH, dir / "frnn");
    const auto r = run_in(dir, "./frnn view --scene droplet");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "frnn: error: viewer not built (needs libglfw3-dev, libimgui-dev)\n");
}
