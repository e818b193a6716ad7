// Steps under an outside load switched in blocks (run_options::load): the profiler's block
// medians and table columns, the order in which a run switches the load, the blocks it keeps
// (an incomplete last one is dropped), and what the summary holds, for long and too-short runs.
// The figures are checked for form; no timing and no ratio of timings is asserted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "frnn/sim/profiler.hpp"
#include "frnn/sim/run.hpp"
#include "scratch_dir.hpp"
#include "text_lines.hpp"

using namespace frnn::sim;
using frnn::test::line_starting;
using frnn::test::scratch_dir;

namespace {

// Two steps in a block of one kind, `ms` per step in the grid stage and 5 ms once in output.
void block_of(profiler& p, bool busy, double ms) {
    p.start_block(busy);
    p.add(stage::grid, 2 * ms / 1e3);
    p.add(stage::output, 5e-3);
    p.end_step();
    p.end_step();
    p.end_block();
}

TEST(SimLoadBlocks, ProfilerKeepsMediansPerKindOfBlock) {
    profiler p;
    p.start_block(true);
    p.end_block();  // no steps: not kept
    for (int k = 1; k <= 4; ++k) {
        block_of(p, false, k);      // quiet: 1, 2, 3, 4 ms per step
        block_of(p, true, 10 * k);  // busy: 10, 20, 30, 40
    }
    p.start_block(false);
    p.end_step();  // a block never ended is dropped by the next start
    EXPECT_EQ(p.blocks(false), 4u);
    EXPECT_EQ(p.blocks(true), 4u);
    EXPECT_FALSE(p.enough_blocks());
    EXPECT_NEAR(p.block_median_ms(false, stage::grid), 2.5, 1e-9);
    EXPECT_NEAR(p.block_median_ms(true, stage::grid), 25, 1e-9);
    EXPECT_NEAR(p.block_median_step_ms(true), 25, 1e-9);  // output is not part of the step
    const std::string short_table = p.table(true);
    EXPECT_NE(short_table.find("contended/quiet"), std::string::npos);
    EXPECT_EQ(line_starting(short_table, "grid build + reorder").find("2.500"), std::string::npos) << "too few blocks";

    block_of(p, false, 5);
    block_of(p, true, 50);
    EXPECT_TRUE(p.enough_blocks());
    const std::string table = p.table(true);
    const std::string grid = line_starting(table, "grid build + reorder");
    EXPECT_NE(grid.find(" 3.000 "), std::string::npos) << grid;  // quiet median of 1..5
    EXPECT_NE(grid.find(" 30.000 "), std::string::npos) << grid;
    EXPECT_NE(grid.find(" 10.00"), std::string::npos) << grid;  // contended / quiet
    EXPECT_NE(line_starting(table, "output").find(" -"), std::string::npos) << table;
    EXPECT_EQ(p.table().find("quiet ms/step"), std::string::npos);  // no load: the plain table
}

run_options quiet_run(const scratch_dir& dir) {
    run_options o;
    o.out_dir = dir.string();
    o.progress = false;
    o.print_table = false;
    o.write_frames = false;
    o.threads = 2;
    return o;
}

scene_overrides small(std::uint64_t steps) {
    scene_overrides ov;
    ov.dim = 2;
    ov.particles = 300;
    ov.steps = steps;
    ov.every = 1000;
    return ov;
}

nlohmann::json summary_of(const scratch_dir& dir) {
    std::ifstream in(dir / "summary.json");
    return nlohmann::json::parse(in);
}

TEST(SimLoadBlocks, RunSwitchesTheLoadByBlocks) {
    const scratch_dir dir("sim_load_blocks");
    run_options o = quiet_run(dir);
    std::vector<bool> calls;
    o.load = {[&](bool busy) { calls.push_back(busy); }, 2, "a test load"};
    // 23 steps in blocks of 2: warm-up (block 0), then quiet 1, 3, .., 9 and busy 2, .., 10;
    // block 11 (quiet) has one step only and is dropped; the load is off at the end.
    const run_result r = run(builtin_scene_text("dam-break"), "dam-break", small(23), o);
    EXPECT_EQ(calls, (std::vector<bool>{false, true, false, true, false, true, false, true, false, true, false, false}));
    EXPECT_EQ(r.quiet_blocks, 5u);
    EXPECT_EQ(r.contended_blocks, 5u);
    EXPECT_GT(r.quiet_step_ms, 0.0);
    EXPECT_GT(r.contended_step_ms, 0.0);

    const auto load = summary_of(dir).at("under_load");
    EXPECT_EQ(load.at("load"), "a test load");
    EXPECT_EQ(load.at("block_steps"), 2);
    EXPECT_EQ(load.at("quiet_blocks"), 5);
    EXPECT_EQ(load.at("contended_blocks"), 5);
    EXPECT_TRUE(load.at("enough_blocks").get<bool>());
    for (const char* key : {"quiet_ms_per_step", "contended_ms_per_step", "contended_over_quiet"}) {
        SCOPED_TRACE(key);
        EXPECT_TRUE(load.at(key).contains("step without output"));
        EXPECT_TRUE(load.at(key).contains("neighbor lists"));
        EXPECT_FALSE(load.at(key).contains("output"));
    }
    EXPECT_NEAR(load["contended_over_quiet"]["step without output"].get<double>(),
                r.contended_step_ms / r.quiet_step_ms, 1e-9);
}

TEST(SimLoadBlocks, TooShortRunHasNoFigures) {
    const scratch_dir dir("sim_load_short");
    run_options o = quiet_run(dir);
    o.load = {[](bool) {}, 2, "a test load"};
    const run_result r = run(builtin_scene_text("dam-break"), "dam-break", small(10), o);
    EXPECT_EQ(r.quiet_blocks, 2u);
    EXPECT_EQ(r.contended_blocks, 2u);
    EXPECT_EQ(r.quiet_step_ms, 0.0);
    const auto load = summary_of(dir).at("under_load");
    EXPECT_FALSE(load.at("enough_blocks").get<bool>());
    EXPECT_FALSE(load.contains("quiet_ms_per_step"));
}

TEST(SimLoadBlocks, NoLoadNoBlocks) {
    const scratch_dir dir("sim_load_none");
    const run_result r = run(builtin_scene_text("dam-break"), "dam-break", small(4), quiet_run(dir));
    EXPECT_EQ(r.quiet_blocks + r.contended_blocks, 0u);
    EXPECT_FALSE(summary_of(dir).contains("under_load"));
}

}  // namespace
