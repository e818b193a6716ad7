// frnn-view --threads: results never depend on the thread count. The same lockstep frames on 1
// and on 2 simulation threads end in the same state (--state), field for field; only the
// timings may differ.
#include <gtest/gtest.h>

#include "viewer_run.hpp"

using namespace frnn::test;

namespace {

/// The end state without what measures time.
nlohmann::json without_timings(nlohmann::json state) {
    state.erase("profile");
    state.erase("max_frames_in_one_step");
    return state;
}

/// 4 lockstep frames of 3 steps of a 2D dam break by `solver`, at 1 and at 2 threads. 2,000
/// particles: the solvers' loops stay on one thread below 1,024 items.
void expect_same_state_at_1_and_2_threads(const std::string& solver) {
    const scratch_dir dir("viewer_threads_" + solver);
    write_text(dir / "script.json", R"({"steps_per_frame": 3, "actions": []})");
    const std::string scene = "--scene dam-break --dim 2 --particles 2000 --solver " + solver + " --script script.json --frames 4 ";
    const auto one = run_viewer(dir, scene + "--threads 1 --state one.json");
    ASSERT_EQ(one.code, 0) << one.err;
    const auto two = run_viewer(dir, scene + "--threads 2 --state two.json");
    ASSERT_EQ(two.code, 0) << two.err;
    const auto a = read_json(dir / "one.json"), b = read_json(dir / "two.json");
    EXPECT_EQ(a.at("step"), 12);
    EXPECT_GE(a.at("particles").get<int>(), 1024);
    // The fields one by one first, for a readable failure.
    for (const char* field : {"step", "time", "particles", "x", "speed", "density", "pressure", "neighbors"})
        EXPECT_TRUE(a.at(field) == b.at(field)) << field << " differs between 1 and 2 threads";
    EXPECT_TRUE(without_timings(a) == without_timings(b)) << "the end states differ between 1 and 2 threads";
}

}  // namespace

TEST(ViewerThreads, ViscoelasticEndsAlikeOnOneAndTwoThreads) { expect_same_state_at_1_and_2_threads("viscoelastic"); }

TEST(ViewerThreads, SphEndsAlikeOnOneAndTwoThreads) { expect_same_state_at_1_and_2_threads("sph"); }
