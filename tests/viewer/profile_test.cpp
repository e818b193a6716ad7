// Profiling: "capture profile" writes a Chrome trace of exactly the next N steps, a span per
// solver stage per step; the state has the live per-stage times of the panel's bar.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "viewer_run.hpp"

using namespace frnn::test;

TEST(ViewerProfile, CaptureWritesAChromeTraceOfTheNextSteps) {
    const scratch_dir dir("viewer_profile");
    // 2 steps per frame from frame 0; the capture starts after frame 2's steps (steps 4 on).
    write_text(dir / "script.json", R"({"steps_per_frame": 2, "actions": [
        {"frame": 3, "do": "capture_profile", "steps": 5, "path": "trace.json"}]})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 600 --script script.json --frames 8 --state state.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto trace = nlohmann::json::parse(slurp(dir / "trace.json"));  // throws unless valid JSON
    std::map<std::uint64_t, std::set<std::string>> stages;                 // names by step
    for (const auto& e : trace.at("traceEvents")) {
        if (e.at("ph") != "X") continue;
        EXPECT_GE(e.at("dur").get<double>(), 0);
        EXPECT_GE(e.at("ts").get<double>(), 0);
        stages[e.at("args").at("step").get<std::uint64_t>()].insert(e.at("name").get<std::string>());
    }
    ASSERT_EQ(stages.size(), 5u);
    EXPECT_EQ(stages.begin()->first, 6u);  // frames 0 to 2 ran steps 0 to 5
    EXPECT_EQ(stages.rbegin()->first, 10u);
    for (const auto& [step, names] : stages)
        for (const char* stage : {"grid build + reorder", "neighbor lists", "viscosity", "density relaxation", "integration"})
            EXPECT_TRUE(names.count(stage)) << "step " << step << ": no " << stage;
    const auto state = read_json(dir / "state.json");
    const auto& profile = state.at("profile");
    EXPECT_EQ(profile.at("capture"), "profile written to trace.json");
    EXPECT_GT(profile.at("stage_ms").at("grid build + reorder").get<double>(), 0);
    EXPECT_GT(profile.at("stage_ms").at("neighbor lists").get<double>(), 0);
    EXPECT_GT(profile.at("drawing_ms").get<double>(), 0);
}
