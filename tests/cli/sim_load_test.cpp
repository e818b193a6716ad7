// `frnn sim --contend K` and `--contend-process K`: the table gains the columns quiet ms/step,
// contended ms/step and contended/quiet under a line naming the load, summary.json the same
// figures; a run too short for 5 blocks of each kind says so in that line, shows dashes and
// still succeeds; giving both options is a usage error. No timing or ratio is compared.
#include "cli/run_tool.hpp"

#ifdef FRNN_TOOL_HAS_SIM
#include <nlohmann/json.hpp>

#include "text_lines.hpp"

namespace frnn::test {
namespace {

// A small 2D dam break (about 300 particles) for `steps` steps into `out`, under `load`.
tool_result small_sim(const scratch_dir& dir, int steps, const std::string& load) {
    return run_tool(dir, "sim --scene dam-break --dim 2 --particles 300 --steps " + std::to_string(steps) +
                             " --every 1000 --threads 2 --quiet --out out " + load);
}

nlohmann::json under_load(const scratch_dir& dir) {
    std::ifstream in(dir / "out" / "summary.json");
    return nlohmann::json::parse(in).at("under_load");
}

TEST(cli_sim_load, busy_thread_adds_quiet_and_contended_columns) {
    const auto dir = fresh_dir();
    // 120 steps: warm-up block, then quiet blocks 1, 3, .., 11 and contended 2, .., 10.
    const tool_result r = small_sim(dir, 120, "--contend 1");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("under load (1 busy thread in this process; kernel autogroup scheduling: "), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("medians over 6 quiet and 5 contended blocks"), std::string::npos) << r.out;
    const std::string header = line_starting(r.out, "stage ");
    for (const char* column : {"quiet ms/step", "contended ms/step", "contended/quiet"})
        EXPECT_NE(header.find(column), std::string::npos) << header;
    const std::string step = line_starting(r.out, "step (without output)");
    EXPECT_EQ(step.find('-'), std::string::npos) << "the step has figures: " << step;
    const auto load = under_load(dir);
    EXPECT_TRUE(load.at("enough_blocks").get<bool>());
    EXPECT_GT(load.at("quiet_ms_per_step").at("step without output").get<double>(), 0.0);
    EXPECT_GT(load.at("contended_ms_per_step").at("step without output").get<double>(), 0.0);
}

TEST(cli_sim_load, too_short_run_says_so) {
    const auto dir = fresh_dir();
    const tool_result r = small_sim(dir, 40, "--contend-process 1");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string line = line_starting(r.out, "under load (1 busy child process;");
    EXPECT_NE(line.find("TOO SHORT TO COMPARE: 2 quiet and 1 contended blocks"), std::string::npos) << r.out;
    EXPECT_NE(line.find("run at least 110 steps"), std::string::npos) << line;
    const std::string step = line_starting(r.out, "step (without output)");
    EXPECT_NE(step.find(" -"), std::string::npos) << step;
    EXPECT_FALSE(under_load(dir).at("enough_blocks").get<bool>());
}

TEST(cli_sim_load, one_load_option_in_range) {
    const auto dir = fresh_dir();
    for (const char* load : {"--contend 1 --contend-process 1", "--contend 0", "--contend-process 65"}) {
        const tool_result r = small_sim(dir, 5, load);
        EXPECT_EQ(r.code, 2) << load;
        EXPECT_NE(r.err.find("--contend"), std::string::npos) << load << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "out")) << load;
    }
}

}  // namespace
}  // namespace frnn::test

#endif  // FRNN_TOOL_HAS_SIM
