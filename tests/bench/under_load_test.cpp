// `frnn bench --contend K` and `--contend-process K`: every row gets a median under load from
// max(--repeat, 5) pairs of runs, the Markdown has the table "Under load" under a line naming
// the load and the kernel's autogroup setting, the CSV fills its two trailing columns, the
// recorded command line keeps the option, and giving both options is a usage error. The figures
// are checked for form only: no timing and no ratio is compared.
#include <gtest/gtest.h>

#include <set>
#include <sstream>

#include "frnn/bench/contention.hpp"
#include "frnn/bench/report.hpp"
#include "frnn/bench/results.hpp"
#include "scratch_dir.hpp"

namespace fb = frnn::bench;

namespace {

// The cells of the Markdown table that follows the first line starting with `heading`.
std::vector<std::vector<std::string>> table_after(const std::string& md, const std::string& heading) {
    std::istringstream in(md);
    std::string line;
    while (std::getline(in, line) && line.rfind(heading, 0) != 0) {
    }
    std::vector<std::vector<std::string>> rows;
    while (std::getline(in, line) && (line.empty() || line[0] == '|')) {
        if (line.empty()) {
            if (rows.empty()) continue;  // the blank line between heading and table
            break;
        }
        std::vector<std::string> cells;
        std::istringstream cols(line.substr(1));
        std::string cell;
        while (std::getline(cols, cell, '|')) cells.push_back(cell.substr(1, cell.size() - 2));
        rows.push_back(cells);
    }
    return rows;
}

TEST(BenchResults, UnderLoadTableGivesBothMediansAndTheirRatio) {
    fb::report rep;
    rep.load = "1 busy thread in this process";
    rep.autogroup = "off";
    fb::case_info c;
    c.workload = "W2";
    c.n = 10;
    rep.cases.push_back(c);
    rep.rows = {{"W2", 10, 2, "frnn", "build", 2, 200, std::nullopt, 3, 5},
                {"W2", 10, 2, "frnn", "count", 4, 400, 36, 5, 6}};
    const std::string md = fb::to_markdown(rep);
    const auto rows = table_after(md, "Under load: 1 busy thread in this process; kernel autogroup scheduling: off.");
    ASSERT_EQ(rows.size(), 4u) << md;  // header, rule, two rows
    EXPECT_EQ(rows[0], (std::vector<std::string>{"method", "threads", "phase", "quiet ms", "contended ms",
                                                 "contended/quiet", "pairs of runs"}));
    EXPECT_EQ(rows[2], (std::vector<std::string>{"frnn", "2", "build", "2.000", "3.000", "1.50", "5"}));
    EXPECT_EQ(rows[3], (std::vector<std::string>{"frnn", "2", "count", "4.000", "5.000", "1.25", "6"}));
    const std::string csv = fb::to_csv(rep);
    EXPECT_NE(csv.find("\nW2,10,2,frnn,build,2,200,,3,5\n"), std::string::npos) << csv;
    EXPECT_NE(csv.find("\nW2,10,2,frnn,count,4,400,36,5,6\n"), std::string::npos) << csv;
}

}  // namespace

#ifdef FRNN_TOOL_PATH
#include "bench/tool.hpp"

using frnn::test::run;
using frnn::test::scratch_dir;
using frnn::test::slurp;
using frnn::test::split;

namespace {

// One run of W2 at 2,000 points and 2 threads under `option`, expecting `pairs` pairs of runs.
void check_under_load(const std::string& option, int repeat, int pairs, const std::string& load) {
    const scratch_dir dir("bench_under_load");
    const std::string csv = (dir / "load.csv").string(), md = (dir / "load.md").string();
    const std::string out = (dir / "stdout.md").string(), err = (dir / "stderr.txt").string();
    const std::string args = "--workload W2 --n 2000 --threads 2 --repeat " + std::to_string(repeat) + " " + option;
    ASSERT_EQ(run("bench " + args + " --csv '" + csv + "' --markdown '" + md + "' > '" + out + "' 2> '" + err + "'"), 0)
        << slurp(err);
    const std::string markdown = slurp(md);
    EXPECT_EQ(slurp(out), markdown);
    EXPECT_NE(markdown.find("- command: `frnn bench " + args + "`"), std::string::npos) << markdown;
    EXPECT_EQ(markdown.find("VOID"), std::string::npos) << markdown;

    const auto rows = table_after(markdown, "Under load: " + load + "; kernel autogroup scheduling: " +
                                                fb::autogroup_scheduling() + ".");
    ASSERT_GE(rows.size(), 2u) << markdown;
    EXPECT_EQ(rows[0][3], "quiet ms");
    std::set<std::string> phases;
    for (std::size_t k = 2; k < rows.size(); ++k) {
        const auto& r = rows[k];
        ASSERT_EQ(r.size(), 7u);
        EXPECT_EQ(r[0], "frnn");
        EXPECT_EQ(r[1], "2");
        EXPECT_GE(std::stod(r[3]), 0.0);
        EXPECT_GE(std::stod(r[4]), 0.0);
        EXPECT_EQ(r[6], std::to_string(pairs));
        phases.insert(r[2]);
    }
    EXPECT_EQ(phases, (std::set<std::string>{"build", "count", "list", "build+list", "update"}));

    std::istringstream lines(slurp(csv));
    std::string line;
    ASSERT_TRUE(std::getline(lines, line));
    std::size_t measured = 0;
    while (std::getline(lines, line)) {
        const auto f = split(line, ',');
        ASSERT_EQ(f.size(), 10u) << line;
        ASSERT_FALSE(f[8].empty()) << "no median under load: " << line;
        EXPECT_GE(std::stod(f[8]), 0.0) << line;
        EXPECT_EQ(f[9], std::to_string(pairs)) << line;
        ++measured;
    }
    EXPECT_EQ(measured, 5u);  // the five phases of frnn at 2 threads
}

TEST(BenchUnderLoad, BusyThreadPairsEveryRun) {
    check_under_load("--contend 1", 5, 5, "1 busy thread in this process");
}

TEST(BenchUnderLoad, BusyChildProcessPairsAtLeastFiveRuns) {
    check_under_load("--contend-process 1", 2, 5, "1 busy child process");  // max(--repeat, 5)
}

TEST(BenchUnderLoad, OneLoadOptionInRange) {
    const scratch_dir dir("bench_load_usage");
    const std::string err = (dir / "stderr.txt").string();
    for (const char* option : {"--contend 1 --contend-process 1", "--contend 0", "--contend-process 65"}) {
        EXPECT_EQ(run(std::string("bench --workload W2 --n 100 --threads 1 --repeat 1 ") + option + " > /dev/null 2> '" +
                      err + "'"),
                  2)
            << option;
        EXPECT_NE(slurp(err).find("--contend"), std::string::npos) << option << ": " << slurp(err);
    }
}

}  // namespace

#endif  // FRNN_TOOL_PATH
