// Stepping in the viewer: pause holds the state bit for bit, a single step advances exactly
// one step, N lockstep steps equal `frnn sim` after N steps, in decoupled mode frames keep
// coming while slowed steps run (many frames per step shown), --timing's medians, and a saved
// state loads back bit for bit.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "viewer_run.hpp"

using namespace frnn::test;

namespace {

/// The positions of a VTK frame written by `frnn sim` (Points: base64 of a UInt32 byte count
/// and the float32 data), in particle-id order.
std::vector<float> vtp_points(const std::string& vtp) {
    const auto name = vtp.find("Name=\"Points\"");
    const auto begin = vtp.find('>', name) + 1, end = vtp.find('<', begin);
    std::string bytes;
    std::uint32_t acc = 0;
    int bits = 0;
    for (std::size_t i = begin; i < end; ++i) {
        const char c = vtp[i];
        int v = -1;
        if (c >= 'A' && c <= 'Z') v = c - 'A';
        else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
        else if (c >= '0' && c <= '9') v = c - '0' + 52;
        else if (c == '+') v = 62;
        else if (c == '/') v = 63;
        if (v < 0) continue;  // whitespace, padding
        acc = acc << 6 | std::uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            bytes += char(acc >> bits & 0xff);
        }
    }
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data(), 4);
    std::vector<float> x(count / 4);
    std::memcpy(x.data(), bytes.data() + 4, count);
    return x;
}

std::vector<float> positions(const nlohmann::json& state) { return state.at("x").get<std::vector<float>>(); }

}  // namespace

TEST(ViewerStepping, PauseHoldsTheStateBitForBit) {
    const scratch_dir dir("viewer_pause");
    // The panel's Pause button, clicked at frame 5 (released at 6): frames 0 to 6 step.
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 5, "do": "button", "label": "Pause"}]})");
    const std::string scene = "--scene droplet --dim 2 --particles 400 --script script.json ";
    const auto a = run_viewer(dir, scene + "--frames 9 --state a.json");
    ASSERT_EQ(a.code, 0) << a.err;
    const auto b = run_viewer(dir, scene + "--frames 30 --state b.json");
    ASSERT_EQ(b.code, 0) << b.err;
    const auto sa = read_json(dir / "a.json"), sb = read_json(dir / "b.json");
    EXPECT_EQ(sa.at("step"), 7);
    EXPECT_EQ(sb.at("step"), 7);
    EXPECT_FALSE(sb.at("playing").get<bool>());
    EXPECT_EQ(positions(sa), positions(sb));
    EXPECT_EQ(sa.at("speed"), sb.at("speed"));
    EXPECT_EQ(sa.at("density"), sb.at("density"));
}

TEST(ViewerStepping, SingleStepAdvancesExactlyOneStep) {
    const scratch_dir dir("viewer_step");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 0, "do": "pause"}, {"frame": 3, "do": "key", "key": "s"}]})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 400 --script script.json --frames 8 --state s.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto s = read_json(dir / "s.json");
    EXPECT_EQ(s.at("step"), 1);
    EXPECT_GT(s.at("time").get<double>(), 0);
    EXPECT_FALSE(s.at("playing").get<bool>());
}

TEST(ViewerStepping, LockstepStepsEqualFrnnSimBitForBit) {
    const scratch_dir dir("viewer_vs_sim");
    for (const char* solver : {"viscoelastic", "sph"}) {
        const std::string scene = std::string("--scene dam-break --dim 2 --particles 500 --solver ") + solver;
        // 4 frames of 3 steps: 12 steps.
        write_text(dir / "script.json", R"({"steps_per_frame": 3, "actions": []})");
        const auto v = run_viewer(dir, scene + " --script script.json --frames 4 --state v.json");
        ASSERT_EQ(v.code, 0) << v.err;
        const auto s = run_tool(dir, "sim " + scene + " --steps 12 --every 12 --quiet --out run");
        ASSERT_EQ(s.code, 0) << s.err;
        const auto state = read_json(dir / "v.json");
        EXPECT_EQ(state.at("step"), 12) << solver;
        const std::vector<float> sim_x = vtp_points(slurp(dir / "run" / "frames" / "frame_00001.vtp"));
        ASSERT_EQ(sim_x.size(), positions(state).size()) << solver;
        EXPECT_EQ(std::memcmp(sim_x.data(), positions(state).data(), sim_x.size() * sizeof(float)), 0) << solver;
        std::filesystem::remove_all(dir / "run");
    }
}

TEST(ViewerStepping, DecoupledFramesKeepComingDuringASlowStep) {
    const scratch_dir dir("viewer_decoupled");
    // Every step sleeps 1.5 s first; drawing a frame takes milliseconds. A window that waited
    // for the steps would show a new step in about every frame. Decoupled, its 40 frames show at
    // most one step per 1.5 s of drawing: fewer steps than half the frames unless the frames
    // took 0.75 s each. No time is measured: the test's timeout is the only limit.
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 300 --slow-step-ms 1500 --frames 40 --state s.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto s = read_json(dir / "s.json");
    const long frames = s.at("frames").get<long>(), steps = s.at("step").get<long>();
    EXPECT_EQ(frames, 40);
    EXPECT_LT(2 * steps, frames) << "the last frame showed step " << steps;
}

TEST(ViewerStepping, TimingGivesTheMedianFrameAndStep) {
    const scratch_dir dir("viewer_timing");
    // Lockstep, one step of at least 80 ms per frame: both medians at least that.
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": []})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 300 --slow-step-ms 80 --script script.json --frames 6 --timing");
    ASSERT_EQ(r.code, 0) << r.err;
    double frame = 0, step = 0;
    int frames = 0;
    const auto at = r.out.find("median frame");
    ASSERT_NE(at, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + at, "median frame %lf ms (%d frames), median step %lf ms", &frame, &frames, &step), 3) << r.out;
    EXPECT_EQ(frames, 6);
    EXPECT_GE(step, 80);
    EXPECT_GE(frame, step);
}

TEST(ViewerStepping, SavedStateLoadsBackBitForBit) {
    const scratch_dir dir("viewer_checkpoint");
    // Run A: 6 steps, pause, save the state, then 4 more steps.
    write_text(dir / "a.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 6, "do": "pause"}, {"frame": 7, "do": "save_state", "path": "six.bin"},
        {"frame": 8, "do": "play"}]})");
    const std::string scene = "--scene droplet --dim 2 --particles 400 --solver sph ";
    const auto a = run_viewer(dir, scene + "--script a.json --frames 12 --state a.json.out");
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_EQ(read_json(dir / "a.json.out").at("step"), 10);
    // Run B, another scene: loads the state, then 4 steps: the same as A's end.
    write_text(dir / "b.json", R"({"steps_per_frame": 1, "actions": [
        {"frame": 0, "do": "pause"}, {"frame": 1, "do": "load_state", "path": "six.bin"}, {"frame": 2, "do": "play"}]})");
    const auto b = run_viewer(dir, "--scene block-drop --script b.json --frames 6 --state b.json.out");
    ASSERT_EQ(b.code, 0) << b.err;
    const auto sa = read_json(dir / "a.json.out"), sb = read_json(dir / "b.json.out");
    EXPECT_EQ(sb.at("step"), 10);
    EXPECT_EQ(sb.at("scene"), "droplet");
    EXPECT_EQ(sb.at("solver"), "sph");
    EXPECT_EQ(positions(sa), positions(sb));
    // (frnn sim --resume continuing such a checkpoint: tests/sim/simulation_test.cpp)
}
