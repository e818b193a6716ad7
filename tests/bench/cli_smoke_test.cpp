// Smoke runs of `frnn bench` at tiny N with --baselines: the CSV has the documented header and
// well-formed rows, every method and thread count found the same number of pairs (which also
// equals the brute-force oracle's), and the Markdown and plot files appear; --precision, --kind,
// --cell and --space each change what they must and keep the oracle's pairs. No timing is checked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "frnn/bench/brute_baseline.hpp"
#include "frnn/brute_force.hpp"
#include "frnn/bench/report.hpp"
#include "frnn/bench/results.hpp"
#include "frnn/bench/workloads.hpp"
#include "scratch_dir.hpp"

#ifdef FRNN_TOOL_PATH
#include "bench/tool.hpp"

namespace fb = frnn::bench;
using frnn::test::run;
using frnn::test::scratch_dir;
using frnn::test::slurp;
using frnn::test::split;

namespace {

std::uint64_t oracle_pairs(const std::string& id, std::size_t n) {
    const auto& w = fb::find_workload(id);
    const auto p = fb::generate<float>(w, n);
    if (w.dim == 2) return fb::brute_neighbor_lists<float, 2>(p, float(w.radius)).size();
    return fb::brute_neighbor_lists<float, 3>(p, float(w.radius)).size();
}

// Runs one smoke configuration at `n` points and checks its CSV.
void smoke(const std::string& workloads, std::size_t n, const std::string& tag) {
    const scratch_dir dir("bench_smoke_" + tag);
    const std::string csv = (dir / "smoke.csv").string(), md = (dir / "smoke.md").string();
    ASSERT_EQ(run("bench --workload " + workloads + " --n " + std::to_string(n) +
                  " --threads 1,2 --repeat 1 --baselines --csv '" + csv + "' --markdown '" + md +
                  "' > /dev/null"),
              0);
    std::istringstream in(slurp(csv));
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "workload,n,threads,method,phase,ms,ns_per_particle,pairs,contended_ms,load_pairs");
    const std::set<std::string> methods(fb::methods.begin(), fb::methods.end());
    const std::set<std::string> phases(fb::phases.begin(), fb::phases.end());
    std::map<std::string, std::set<std::uint64_t>> pairs;          // workload -> pair counts
    std::map<std::string, std::set<std::string>> seen;             // workload -> method/phase/t
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        ASSERT_NE(line.rfind("# VOID", 0), 0u) << line;
        const auto f = split(line, ',');
        ASSERT_EQ(f.size(), 10u) << line;
        const std::string& w = f[0];
        EXPECT_EQ(std::stoull(f[1]), fb::point_count(fb::find_workload(w), n)) << line;  // real count
        EXPECT_TRUE(f[2] == "1" || f[2] == "2") << line;
        EXPECT_TRUE(methods.count(f[3])) << line;
        EXPECT_TRUE(phases.count(f[4])) << line;
        EXPECT_GE(std::stod(f[5]), 0.0) << line;
        EXPECT_GE(std::stod(f[6]), 0.0) << line;
        const bool searches = f[4] != "build" && f[4] != "update";
        EXPECT_EQ(!f[7].empty(), searches) << line;
        if (searches) pairs[w].insert(std::stoull(f[7]));
        EXPECT_TRUE(f[8].empty() && f[9].empty()) << "figures under load without a load: " << line;
        seen[w].insert(f[3] + "/" + f[4] + "/" + f[2]);
        ++rows;
    }
    for (const auto& id : fb::parse_workload_list(workloads)) {
        SCOPED_TRACE(id);
        ASSERT_EQ(pairs[id].size(), 1u) << "methods disagree on the pair count";
        EXPECT_EQ(*pairs[id].begin(), oracle_pairs(id, n));
        EXPECT_GT(*pairs[id].begin(), 0u);
        for (const char* key : {"frnn/build/1", "frnn/count/2", "frnn/list/1", "frnn/build+list/2",
                                "frnn/update/2", "nanoflann/build+list/2", "brute/build+list/1"})
            EXPECT_TRUE(seen[id].count(key)) << key;
        if (id != "W5" && id != "W3") {
            EXPECT_TRUE(seen[id].count("cell-list/build+list/1"));
        }
    }
    EXPECT_GT(rows, 0u);
    const std::string markdown = slurp(md);
    EXPECT_NE(markdown.find("| method | threads | phase | ms | ns/particle | pairs |"), std::string::npos);
    EXPECT_NE(markdown.find("vs nanoflann"), std::string::npos);
    EXPECT_EQ(markdown.find("VOID"), std::string::npos);
}

}  // namespace

// 512 points: W1 8^3, W4 23^2 = 529, W5 8^3 + 1.
TEST(BenchCli, LatticeWorkloadsAgreeAcrossMethods) { smoke("W1,W4,W5", 512, "lattice"); }

TEST(BenchCli, PointCountWorkloadsAgreeAcrossMethods) { smoke("W2,W3", 3000, "points"); }

// Directed pairs within r of the md workload by brute force with the minimum image.
std::uint64_t periodic_oracle_pairs(std::size_t n) {
    const auto& w = fb::find_workload("W8");
    const auto p = fb::generate<double>(w, n);
    const double box = fb::periodic_box(w, n), r2 = w.radius * w.radius;
    std::uint64_t pairs = 0;
    for (std::size_t i = 0; i < p.size() / 3; ++i)
        for (std::size_t j = i + 1; j < p.size() / 3; ++j) {
            double d2 = 0;
            for (int a = 0; a < 3; ++a) {
                double d = p[3 * j + a] - p[3 * i + a];
                d -= box * std::nearbyint(d / box);
                d2 += d * d;
            }
            pairs += d2 <= r2 ? 2 : 0;
        }
    return pairs;
}

// The md workload: its half-list phases (pairs counted twice) agree with the full lists and
// the minimum-image oracle, and LAMMPS either joins with the same count or is said to be
// missing. 2,916 atoms: 9^3 fcc cells, a box of 5 cells of r per axis.
TEST(BenchCli, MdWorkloadHalfListsAndLammps) {
    const scratch_dir dir("bench_md");
    const std::string csv = (dir / "md.csv").string(), md = (dir / "md.md").string();
    ASSERT_EQ(run("bench --workload W8 --n 2916 --threads 1,2 --repeat 1 --baselines --csv '" + csv +
                  "' --markdown '" + md + "' > /dev/null 2>&1"),
              0);
    std::istringstream in(slurp(csv));
    std::string line;
    std::getline(in, line);
    std::set<std::string> seen;
    std::set<std::uint64_t> pairs;
    while (std::getline(in, line)) {
        ASSERT_NE(line.rfind("# VOID", 0), 0u) << line;
        const auto f = split(line, ',');
        ASSERT_EQ(f.size(), 10u) << line;
        EXPECT_EQ(f[1], "2916") << line;
        seen.insert(f[3] + "/" + f[4] + "/" + f[2]);
        if (!f[7].empty()) pairs.insert(std::stoull(f[7]));
    }
    for (const char* t : {"1", "2"})
        for (const char* phase : {"count", "list", "half", "half sorted-space", "half by-index", "build+half by-index"})
            EXPECT_TRUE(seen.count(std::string("frnn/") + phase + "/" + t)) << phase << " at " << t;
    ASSERT_EQ(pairs.size(), 1u) << "phases disagree on the pair count";
    EXPECT_EQ(*pairs.begin(), periodic_oracle_pairs(2916));
    const std::string markdown = slurp(md);
    const bool lammps = std::system("command -v lmp > /dev/null 2>&1") == 0;
    EXPECT_EQ(seen.count("lammps/build+half/1"), lammps ? 1u : 0u);
    EXPECT_NE(markdown.find(lammps ? "| LAMMPS / frnn |" : "LAMMPS skipped: no `lmp` on PATH"), std::string::npos);
    EXPECT_EQ(markdown.find("nanoflann"), std::string::npos);  // no periodic boxes there
}

// The radii workload: every method's phases agree on the pairs of their own search, and those
// of the radii per point are the brute-force counts of the same points and radii.
TEST(BenchCli, RadiiWorkloadAgreesWithBruteForce) {
    const scratch_dir dir("bench_radii");
    const std::string csv = (dir / "w7.csv").string();
    ASSERT_EQ(run("bench --workload W7 --n 3000 --threads 1,2 --repeat 1 --csv '" + csv + "' > /dev/null 2>&1"), 0);
    const auto& w7 = frnn::bench::find_workload("W7");
    const auto pts = frnn::bench::generate<float>(w7, 3000);
    std::map<std::string, std::set<std::uint64_t>> pairs;
    std::istringstream in(slurp(csv));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        ASSERT_NE(line.rfind("# VOID", 0), 0u) << line;
        const auto f = split(line, ',');
        if (!f[7].empty()) pairs[f[3]].insert(std::stoull(f[7]));
    }
    for (double low : {0.5, 0.2}) {
        const auto radii = frnn::bench::point_radii<float>(3000, low, 2.0, 44);
        for (auto rule : {frnn::radius_rule::gather, frnn::radius_rule::symmetric}) {
            char method[64];
            std::snprintf(method, sizeof method, "frnn %s %g-2", std::string(frnn::to_string(rule)).c_str(), low);
            const auto lists = frnn::brute_force_lists<float, 3>(pts, radii, pts, radii, rule, 2.0f, true);
            ASSERT_EQ(pairs[method].size(), 1u) << method;
            EXPECT_EQ(*pairs[method].begin(), lists.size()) << method;
        }
    }
    EXPECT_EQ(pairs["frnn r=2"].size(), 1u);
    EXPECT_EQ(pairs["frnn r=1.25"].size(), 1u);
}

TEST(BenchCli, OneSizePerWorkloadAsPointsOrSide) {
    const scratch_dir dir("bench_sizes");
    const std::string csv = (dir / "sizes.csv").string();
    ASSERT_EQ(run("bench --workload W1,W2,W4 --n W1=120,W2=200 --side W4=3 --threads 1 --repeat 1 --csv '" +
                  csv + "' > /dev/null 2>&1"),
              0);
    const std::string text = slurp(csv);
    EXPECT_NE(text.find("\nW1,125,1,frnn,count,"), std::string::npos);  // 120 rounds to 5^3
    EXPECT_NE(text.find("\nW2,200,1,frnn,count,"), std::string::npos);
    EXPECT_NE(text.find("\nW4,9,1,frnn,count,"), std::string::npos);  // side 3: 3^2
    EXPECT_EQ(text.find("\nW4,1000000,"), std::string::npos);  // --side replaced the default
}

TEST(BenchCli, MarkdownNamesTheLatticeSide) {
    const scratch_dir dir("bench_side");
    const std::string md = (dir / "side.md").string();
    ASSERT_EQ(run("bench --workload W1 --side 6 --threads 1 --repeat 1 --markdown '" + md + "' > /dev/null 2>&1"), 0);
    EXPECT_NE(slurp(md).find("## W1 lattice: N = 216 (lattice side 6), 3D"), std::string::npos);
    EXPECT_NE(slurp(md).find("--side 6"), std::string::npos);  // the recorded command line
}

namespace {

// One W2 run of 2,000 points on 1 thread with `options`, and what an option must show in it:
// the Markdown's settings line, the pair counts of every searching row, and frnn's structure
// bytes per particle from the memory table.
struct option_run {
    std::string settings;
    std::set<std::uint64_t> pairs;
    double frnn_bytes = -1;
};

option_run run_with(const std::string& options, const std::string& tag) {
    const scratch_dir dir("bench_option_" + tag);
    const std::string csv = (dir / "w2.csv").string(), md = (dir / "w2.md").string();
    option_run out;
    EXPECT_EQ(run("bench --workload W2 --n 2000 --threads 1 --repeat 1 " + options + " --csv '" + csv +
                  "' --markdown '" + md + "' > /dev/null 2>&1"),
              0)
        << options;
    std::istringstream in(slurp(csv));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        const auto f = split(line, ',');
        EXPECT_EQ(f.size(), 10u) << options << ": " << line;
        if (f.size() == 10 && !f[7].empty()) out.pairs.insert(std::stoull(f[7]));
    }
    std::istringstream text(slurp(md));
    bool memory = false;
    while (std::getline(text, line)) {
        if (line.rfind("- settings: ", 0) == 0) out.settings = line.substr(12);
        if (line.find("| structure bytes/particle |") != std::string::npos) memory = true;
        if (memory && line.rfind("| frnn | 1 | ", 0) == 0) {
            out.frnn_bytes = std::stod(line.substr(13));
            memory = false;
        }
    }
    EXPECT_GT(out.frnn_bytes, 0.0) << options << ": no memory row for frnn";
    return out;
}

// Every searching row of `r` found the brute-force pairs of W2's 2,000 points in `precision`.
void expect_oracle_pairs(const option_run& r, bool double_precision, const std::string& what) {
    ASSERT_EQ(r.pairs.size(), 1u) << what << ": phases disagree on the pair count";
    const auto& w2 = fb::find_workload("W2");
    const std::uint64_t want = double_precision
                                   ? fb::brute_neighbor_lists<double, 3>(fb::generate<double>(w2, 2000), 2.0).size()
                                   : oracle_pairs("W2", 2000);
    EXPECT_EQ(*r.pairs.begin(), want) << what;
}

}  // namespace

// --precision double: the points are searched as doubles (the brute-force pairs of the double
// points; the grid's copy of the points takes 3 x 4 bytes more per point).
TEST(BenchCli, PrecisionDoubleSearchesDoubleCoordinates) {
    const option_run f = run_with("--kind uniform", "float"), d = run_with("--kind uniform --precision double", "double");
    EXPECT_EQ(f.settings.rfind("float coordinates", 0), 0u) << f.settings;
    EXPECT_EQ(d.settings.rfind("double coordinates", 0), 0u) << d.settings;
    expect_oracle_pairs(f, false, "float");
    expect_oracle_pairs(d, true, "double");
    EXPECT_GE(d.frnn_bytes, f.frnn_bytes + 11.9);
}

// --kind hash: the hashed grid (a table sized from N, not one slot per cell: other memory)
// finds the pairs of the uniform grid.
TEST(BenchCli, KindHashFindsTheUniformGridsPairs) {
    const option_run u = run_with("--kind uniform", "uniform"), h = run_with("--kind hash", "hash");
    EXPECT_NE(u.settings.find("grid kind uniform;"), std::string::npos) << u.settings;
    EXPECT_NE(h.settings.find("grid kind hash;"), std::string::npos) << h.settings;
    expect_oracle_pairs(u, false, "uniform");
    expect_oracle_pairs(h, false, "hash");
    EXPECT_NE(h.frnn_bytes, u.frnn_bytes);
}

// --cell 0.5: cells of r/2, eight times as many slots in the uniform grid, the same pairs.
TEST(BenchCli, HalfCellsFindTheSamePairs) {
    const option_run whole = run_with("--kind uniform", "cell_r"), half = run_with("--kind uniform --cell 0.5", "cell_half");
    EXPECT_NE(whole.settings.find("cell size default;"), std::string::npos) << whole.settings;
    EXPECT_NE(half.settings.find("cell size 0.5"), std::string::npos) << half.settings;
    expect_oracle_pairs(whole, false, "cells of r");
    expect_oracle_pairs(half, false, "cells of r/2");
    EXPECT_GT(half.frnn_bytes, whole.frnn_bytes);
}

// --space sorted: lists in the grid's numbering hold the same pairs.
TEST(BenchCli, SortedSpaceListsTheSamePairs) {
    const option_run original = run_with("", "space_original"), sorted = run_with("--space sorted", "space_sorted");
    EXPECT_NE(original.settings.find("frnn lists in the caller's order"), std::string::npos) << original.settings;
    EXPECT_NE(sorted.settings.find("frnn lists in sorted (cell) order"), std::string::npos) << sorted.settings;
    expect_oracle_pairs(original, false, "original");
    expect_oracle_pairs(sorted, false, "sorted");
}

TEST(BenchCli, PlotIsAPngOrSaysWhyNot) {
    const scratch_dir dir("bench_plot");
    const std::string png = (dir / "smoke.png").string(), log = (dir / "plot.log").string();
    ASSERT_EQ(run("bench --workload W1 --n 125,216 --threads 1 --repeat 1 --plot '" + png +
                  "' > /dev/null 2> '" + log + "'"),
              0);
    if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
        const std::string data = slurp(png);
        ASSERT_GE(data.size(), 8u);
        EXPECT_EQ(data.substr(1, 3), "PNG");
    } else {
        EXPECT_NE(slurp(log).find("gnuplot not found"), std::string::npos);
    }
}

TEST(BenchCli, BadArgumentsFailCleanly) {
    const scratch_dir dir("bench_bad");
    const std::string err = (dir / "stderr.txt").string();
    // Runs frnn bench with `args`, expects exit `code` and a message holding `part`.
    const auto fails = [&](const std::string& args, int code, const std::string& part) {
        EXPECT_EQ(run("bench " + args + " > /dev/null 2> '" + err + "'"), code) << args;
        EXPECT_NE(slurp(err).find(part), std::string::npos) << args << ": " << slurp(err);
    };
    fails("--workload W9 --n 4", 1, "unknown workload 'W9'");
    fails("--workload W1 --n 0", 1, "workload W1: N = 0 gives no points");
    fails("--workload W1 --n 4 --threads 0", 1, "--threads");
    fails("--workload W1 --n 4 --backend vulkan", 1, "backend 'vulkan'");
    fails("--workload W1 --n 4 --repeat 0", 2, "--repeat");
    fails("--workload W1 --n W2=1000", 1, "--n gives sizes for W2");  // W2 not selected
    fails("--workload W1 --n 4.5", 1, "--n: '4.5' is not a size (expected N or W2=N)");
    fails("--workload W1 --side 1e3", 1, "--side: '1e3' is not a size (expected S or W1=S)");
    fails("--workload W1,W2 --side W2=10", 1, "--side: W2 is not a lattice workload");
    fails("--workload W1 --side W4=10", 1, "--side gives sides for W4");
    fails("--workload W2 --side 10", 1, "--side needs a lattice workload");
    fails("--workload W1 --side 0", 1, "workload W1: lattice side 0 gives no points");
    fails("--workload W1 --side 2000", 1, "more than 2^32 - 2");
    fails("--workload W1 --n 4 --cell 2", 1, "--cell must lie in [0.25, 1]");
    fails("--workload W1 --n 4 --precision half", 2, "--precision");
    fails("--workload W1 --n 4 --kind octree", 2, "--kind");
    fails("--workload W1 --n 4 --space cells", 2, "--space");
    // An unwritable output fails with a message and leaves no file behind.
    fails("--workload W1 --n 4 --repeat 1 --csv /nonexistent-dir/x.csv", 1, "/nonexistent-dir/x.csv");
}

#endif  // FRNN_TOOL_PATH

TEST(BenchResults, DisagreeingPairCountsAreVoid) {
    std::vector<fb::row> rows{
        {"W1", 8, 1, "frnn", "count", 1, 1, 100, std::nullopt, 0},
        {"W1", 8, 2, "frnn", "list", 1, 1, 100, std::nullopt, 0},
        {"W1", 8, 1, "frnn", "build", 1, 1, std::nullopt, std::nullopt, 0},
        {"W1", 8, 1, "nanoflann", "list", 1, 1, 100, std::nullopt, 0},
        {"W2", 8, 1, "nanoflann", "list", 1, 1, 98, std::nullopt, 0},  // another case: not compared
    };
    EXPECT_TRUE(fb::disagreements(rows, "W1", 8).empty());
    rows.push_back({"W1", 8, 1, "cell-list", "list", 1, 1, 99, std::nullopt, 0});
    const auto v = fb::disagreements(rows, "W1", 8);
    ASSERT_EQ(v.size(), 1u);
    EXPECT_NE(v[0].find("VOID"), std::string::npos);
    EXPECT_NE(v[0].find("cell-list/list/t1"), std::string::npos);

    fb::report rep;
    fb::case_info c;
    c.workload = "W1";
    c.n = 8;
    c.voids = v;
    rep.cases.push_back(c);
    rep.rows = rows;
    EXPECT_TRUE(rep.void_comparison());
    const std::string csv = fb::to_csv(rep);
    EXPECT_EQ(csv.rfind(std::string(fb::csv_header) + "\n", 0), 0u);
    EXPECT_NE(csv.find("\n# VOID W1"), std::string::npos);
    EXPECT_NE(csv.find("W1,8,1,frnn,build,1,1,,,\n"), std::string::npos);  // no pairs for a build
    EXPECT_EQ(fb::to_markdown(rep).find("Under load"), std::string::npos);
    EXPECT_NE(fb::to_markdown(rep).find("**VOID W1"), std::string::npos);
}
