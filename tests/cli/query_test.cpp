// `frnn query` end to end: its output files against the brute-force oracle, for every input
// format, output format and option.
#include <chrono>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>

#include "cli/run_tool.hpp"
#include "frnn/bench/workloads.hpp"

namespace frnn::test {
namespace {

constexpr double radius = 1.0;

// Runs the tool on `input` and checks out.npy against brute force over `xyz` (i < j pairs).
template <class T, int D>
void expect_half_pairs(const std::filesystem::path& dir, const std::string& input, const std::vector<T>& xyz,
                       const std::string& options = "") {
    const tool_result r = run_tool(dir, "query " + input + " --radius 1 -o out.npy " + options);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto expected = pairs_of(brute_force_lists<T, D>(xyz, xyz, T(radius), true), true);
    ASSERT_GT(expected.size(), 100u);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected) << input << " " << options;
    EXPECT_NE(r.out.find("pairs      " + std::to_string(expected.size() / 2)), std::string::npos) << r.out;
}

TEST(cli_query, every_input_format_double) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(300, 5.0, 1);
    for (const char* name : {"p.npy", "p.csv", "p.txt", "p.xyz", "p.ply"}) {
        write_points<double, 3>(dir / name, xyz);
        expect_half_pairs<double, 3>(dir, name, xyz);
    }
    write_points<double, 3>(dir / "b.ply", xyz, true);
    expect_half_pairs<double, 3>(dir, "b.ply", xyz);
}

TEST(cli_query, float_inputs_search_in_float) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<float, 3>(300, 5.0, 2);
    write_points<float, 3>(dir / "p.npy", xyz);
    expect_half_pairs<float, 3>(dir, "p.npy", xyz);
    write_points<float, 3>(dir / "p.ply", xyz, true);
    expect_half_pairs<float, 3>(dir, "p.ply", xyz);
    const auto j = nlohmann::json::parse(run_tool(dir, "query p.ply -r 1 --json").out);
    EXPECT_EQ(j["precision"], "float");
}

TEST(cli_query, two_dimensional) {
    const auto dir = fresh_dir();
    const auto xy = random_points<double, 2>(300, 10.0, 3);
    write_points<double, 2>(dir / "p.csv", xy);
    expect_half_pairs<double, 2>(dir, "p.csv", xy);
}

TEST(cli_query, grid_kinds_cell_sizes_and_threads_agree) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(400, 6.0, 4);
    write_points<double, 3>(dir / "p.npy", xyz);
    std::string first;
    for (const char* options : {"--grid uniform", "--grid hash", "--grid auto --cell-size 0.5",
                                "--grid hash --cell-size 0.34", "--threads 1", "--threads 2", "--threads 4"}) {
        expect_half_pairs<double, 3>(dir, "p.npy", xyz, options);
        const std::string bytes = read_bytes(dir / "out.npy");
        if (first.empty()) first = bytes;
        EXPECT_EQ(bytes, first) << options;  // bit-identical files
    }
}

TEST(cli_query, self_pairs) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(200, 4.0, 5);
    write_points<double, 3>(dir / "p.npy", xyz);
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 --self -o out.npy").code, 0);
    const auto expected = pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, false), true);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
}

TEST(cli_query, csv_output_has_distances_in_input_precision) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<float, 3>(200, 4.0, 6);
    write_points<float, 3>(dir / "p.npy", xyz);
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 -o out.csv").code, 0);
    const csr<float> lists = brute_force_lists<float, 3>(xyz, xyz, 1.0f, true);
    const csv_pairs<float> read = parse_csv_pairs<float>(read_bytes(dir / "out.csv"));
    EXPECT_EQ(read.pairs, pairs_of(lists, true));
    const std::vector<float> expected = distances_of(lists, true);
    ASSERT_EQ(read.distances.size(), expected.size());
    ASSERT_GT(expected.size(), 100u);
    for (std::size_t k = 0; k < expected.size(); ++k)
        EXPECT_NEAR(read.distances[k], expected[k], 1e-6f);  // float arithmetic, not double
}

// The tool's .npz output holds `lists` (rows sorted by index), distances within `tolerance`.
void expect_npz_lists(const std::filesystem::path& file, const csr<double>& lists, double tolerance) {
    const auto members = read_zip(read_bytes(file));
    ASSERT_EQ(members.size(), 3u);
    const auto offsets = npy_values<std::int64_t>(members.at("offsets.npy"), "<i8", {lists.rows() + 1});
    const auto indices = npy_values<std::int64_t>(members.at("indices.npy"), "<i8", {lists.size()});
    const auto distances = npy_values<double>(members.at("distances.npy"), "<f8", {lists.size()});
    EXPECT_TRUE(std::equal(offsets.begin(), offsets.end(), lists.offsets.begin(), lists.offsets.end()));
    EXPECT_TRUE(std::equal(indices.begin(), indices.end(), lists.indices.begin(), lists.indices.end()));
    for (std::size_t k = 0; k < std::min(distances.size(), lists.size()); ++k)
        EXPECT_NEAR(distances[k], lists.distances[k], tolerance) << k;
}

TEST(cli_query, npz_holds_full_sorted_lists) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(250, 4.0, 7);
    write_points<double, 3>(dir / "p.npy", xyz);
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 -o out.npz").code, 0);
    expect_npz_lists(dir / "out.npz", brute_force_lists<double, 3>(xyz, xyz, 1.0, true), 1e-12);
}

TEST(cli_query, queries_from_another_file) {
    const auto dir = fresh_dir();
    const auto data = random_points<double, 3>(300, 5.0, 8);
    const auto queries = random_points<double, 3>(60, 5.0, 9);
    write_points<double, 3>(dir / "data.npy", data);
    write_points<double, 3>(dir / "q.csv", queries);
    const tool_result r = run_tool(dir, "query data.npy --queries q.csv -r 1 -o out.npy --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto expected = pairs_of(brute_force_lists<double, 3>(queries, data, 1.0, false), false);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["query_points"], 60);
    EXPECT_EQ(j["pairs"], expected.size() / 2);
}

TEST(cli_query, float_data_with_double_queries_searches_in_float) {
    const auto dir = fresh_dir();
    const auto data = random_points<float, 2>(300, 8.0, 10);
    const auto queries = random_points<double, 2>(50, 8.0, 11);
    write_points<float, 2>(dir / "data.npy", data);
    write_points<double, 2>(dir / "q.npy", queries);
    ASSERT_EQ(run_tool(dir, "query data.npy --queries q.npy -r 1 -o out.npy").code, 0);
    const std::vector<float> qf(queries.begin(), queries.end());
    const auto expected = pairs_of(brute_force_lists<float, 2>(qf, data, 1.0f, false), false);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
}

TEST(cli_query, knn_keeps_the_nearest_listed_by_index) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(300, 4.0, 12);
    write_points<double, 3>(dir / "p.npy", xyz);
    for (bool self : {false, true}) {
        ASSERT_EQ(run_tool(dir, std::string("query p.npy -r 1 --knn 4 -o out.npy") + (self ? " --self" : "")).code, 0);
        const auto expected = pairs_of(keep_nearest(brute_force_lists<double, 3>(xyz, xyz, 1.0, !self), 4), false);
        EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected) << self;
    }
    const auto queries = random_points<double, 3>(40, 4.0, 13);
    write_points<double, 3>(dir / "q.npy", queries);
    ASSERT_EQ(run_tool(dir, "query p.npy --queries q.npy -r 1 --knn 3 -o out.npy").code, 0);
    const auto expected = pairs_of(keep_nearest(brute_force_lists<double, 3>(queries, xyz, 1.0, false), 3), false);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
}

TEST(cli_query, periodic_box) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(300, 5.0, 14);
    write_points<double, 3>(dir / "p.npy", xyz);
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 --periodic 5,5,5 -o out.npy").code, 0);
    const double box[3] = {5, 5, 5};
    const auto expected = pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, true, box), true);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
    // The box adds pairs across the faces.
    EXPECT_GT(expected.size(), pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, true), true).size());
}

// A box with an open axis: 0 on y, pairs wrap across x and z only.
TEST(cli_query, periodic_on_some_axes) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(300, 5.0, 16);
    write_points<double, 3>(dir / "p.npy", xyz);
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 --periodic 5,0,5 -o out.npy").code, 0);
    const double box[3] = {5, 0, 5};
    const auto expected = pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, true, box), true);
    EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected);
    const double all[3] = {5, 5, 5};
    const auto wrapped_everywhere = pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, true, all), true);
    const auto open = pairs_of(brute_force_lists<double, 3>(xyz, xyz, 1.0, true), true);
    EXPECT_GT(expected.size(), open.size());
    EXPECT_LT(expected.size(), wrapped_everywhere.size());
}

// --radius FILE.npy: a radius per point, gather pairs (i, j) as rows give them, symmetric pairs
// once (i < j).
TEST(cli_query, radius_per_point) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(400, 5.0, 17);
    write_points<double, 3>(dir / "p.npy", xyz);
    std::vector<double> radii(400);
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.2 + 0.8 * double((i * 7919) % 400) / 400.0;
    io::write_npy<double>(dir / "r.npy", radii);
    for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
        const std::string name(to_string(rule));
        ASSERT_EQ(run_tool(dir, "query p.npy -r r.npy --rule " + name + " -o out.npy").code, 0) << name;
        const auto expected = pairs_of(brute_force_lists<double, 3>(xyz, radii, xyz, radii, rule, 1.0, true),
                                       rule == radius_rule::symmetric);
        EXPECT_EQ(read_pairs(dir / "out.npy", expected.size() / 2), expected) << name;
    }
    // A bad radius names the file and the index; a wrong count, the counts.
    radii[9] = -1;
    io::write_npy<double>(dir / "bad.npy", radii);
    const tool_result bad = run_tool(dir, "query p.npy -r bad.npy");
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("bad.npy: radius 9"), std::string::npos) << bad.err;
    radii.pop_back();
    io::write_npy<double>(dir / "short.npy", radii);
    const tool_result short_file = run_tool(dir, "query p.npy -r short.npy");
    EXPECT_NE(short_file.err.find("399 radii for 400 points"), std::string::npos) << short_file.err;
}

TEST(cli_query, empty_input_gives_no_pairs) {
    const auto dir = fresh_dir();
    write_bytes(dir / "e.csv", "x,y,z\n");
    const tool_result r = run_tool(dir, "query e.csv -r 1 -o out.npy --json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(read_pairs(dir / "out.npy", 0).empty());
    EXPECT_EQ(nlohmann::json::parse(r.out)["pairs"], 0);
}

TEST(cli_query, json_summary_parses_and_agrees) {
    const auto dir = fresh_dir();
    const auto xyz = random_points<double, 3>(300, 5.0, 15);
    write_points<double, 3>(dir / "p.npy", xyz);
    const auto start = std::chrono::steady_clock::now();
    const tool_result r = run_tool(dir, "query p.npy -r 1 --json --grid hash");
    const double run_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);  // throws (fails the test) when not one JSON object
    const csr<double> full = brute_force_lists<double, 3>(xyz, xyz, 1.0, true);
    std::size_t max_row = 0;
    for (std::size_t i = 0; i < full.rows(); ++i) max_row = std::max(max_row, full.row(i).size());
    EXPECT_EQ(j["points"], 300);
    EXPECT_EQ(j["dimension"], 3);
    EXPECT_EQ(j["precision"], "double");
    EXPECT_EQ(j["pairs"], full.size() / 2);
    EXPECT_DOUBLE_EQ(j["mean_neighbors"].get<double>(), double(full.size()) / 300);
    EXPECT_EQ(j["max_neighbors"], max_row);
    EXPECT_EQ(j["grid"], "hash");
    EXPECT_GE(j["slots"].get<std::size_t>(), j["occupied_slots"].get<std::size_t>());
    EXPECT_GT(j["occupied_slots"].get<std::size_t>(), 0u);
    // The stage times are numbers (a NaN or an infinity would print as null) and laps of one clock
    // within the tool's run: together no longer than the run as this test timed it, however
    // loaded the machine (milliseconds, not microseconds).
    const auto& times = j.at("time_ms");
    EXPECT_EQ(times.size(), 4u) << times.dump();
    double stages_ms = 0;
    for (const char* stage : {"read", "build", "query", "write"}) {
        ASSERT_TRUE(times.contains(stage) && times[stage].is_number()) << stage << ": " << times.dump();
        stages_ms += times[stage].get<double>();
    }
    EXPECT_LE(stages_ms, run_ms) << times.dump();
}

// `--generate` draws the points of `frnn bench`'s workloads (W1 is lattice:N, W4 lattice:N
// --dim 2, W2 uniform:N, at the default seed 42) and, at other seeds, of their generators: every
// pair and its distance agree bit for bit with brute force over those points.
TEST(cli_query, generated_point_sets_are_the_bench_workloads) {
    const auto dir = fresh_dir();
    namespace fb = frnn::bench;
    struct run {
        std::string spec;
        std::vector<double> xyz;
        int dim;
    };
    const run runs[] = {
        {"lattice:7", fb::generate<double>(fb::find_workload("W1"), 343), 3},
        {"lattice:12 --dim 2", fb::generate<double>(fb::find_workload("W4"), 144), 2},
        {"uniform:500", fb::generate<double>(fb::find_workload("W2"), 500), 3},
        {"lattice:9 --dim 2 --seed 3", fb::jittered_lattice<double>(9, 2, 3), 2},
        {"uniform:400 --dim 2 --seed 5", fb::uniform_cube<double>(400, 2, 5), 2},
    };
    for (const run& g : runs) {
        SCOPED_TRACE(g.spec);
        const tool_result r = run_tool(dir, "query --generate " + g.spec + " --radius 2 -o out.npz --json");
        ASSERT_EQ(r.code, 0) << r.err;
        expect_npz_lists(dir / "out.npz",
                         g.dim == 3 ? brute_force_lists<double, 3>(g.xyz, g.xyz, 2.0, true)
                                    : brute_force_lists<double, 2>(g.xyz, g.xyz, 2.0, true),
                         0.0);
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["points"], g.xyz.size() / std::size_t(g.dim));
        EXPECT_EQ(j["input"], g.spec.substr(0, g.spec.find(' ')));
    }
}

}  // namespace
}  // namespace frnn::test

namespace frnn::test {
namespace {

// The Vulkan backend (lavapipe in CI) writes the same files as the CPU for float input.
TEST(cli_query, vulkan_backend_writes_the_cpu_files) {
#ifndef FRNN_TOOL_HAS_VULKAN
    GTEST_SKIP() << "frnn was built without the Vulkan backend";
#else
    const auto dir = fresh_dir();
    const auto xyz = random_points<float, 3>(500, 6.0, 11);
    write_points<float, 3>(dir / "p.npy", xyz);
    for (const char* out : {"cpu.npy", "cpu.csv"}) {
        const tool_result r = run_tool(dir, std::string("query p.npy -r 1 -o ") + out);
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const tool_result gpu = run_tool(dir, "query p.npy -r 1 --backend vulkan -o gpu.npy");
    // Without a device the backend says so and the test skips, except under FRNN_STRICT=1 (CI).
    const char* strict = std::getenv("FRNN_STRICT");
    if (gpu.code != 0 && gpu.err.find("no Vulkan") != std::string::npos && !(strict && std::string(strict) == "1"))
        GTEST_SKIP() << "no Vulkan device: " << gpu.err;
    ASSERT_EQ(gpu.code, 0) << gpu.err;
    ASSERT_EQ(run_tool(dir, "query p.npy -r 1 --backend vulkan -o gpu.csv").code, 0);
    EXPECT_EQ(read_bytes(dir / "gpu.npy"), read_bytes(dir / "cpu.npy"));
    EXPECT_EQ(read_bytes(dir / "gpu.csv"), read_bytes(dir / "cpu.csv"));

    // Double input is decided in double on the device too: the same files as the CPU's.
    const auto xyz64 = random_points<double, 3>(500, 6.0, 12);
    write_points<double, 3>(dir / "d.npy", xyz64);
    ASSERT_EQ(run_tool(dir, "query d.npy -r 1 -o cpu64.csv").code, 0);
    const tool_result gpu64 = run_tool(dir, "query d.npy -r 1 --backend vulkan -o gpu64.csv");
    ASSERT_EQ(gpu64.code, 0) << gpu64.err;
    EXPECT_NE(gpu64.out.find("double"), std::string::npos) << gpu64.out;
    EXPECT_EQ(read_bytes(dir / "gpu64.csv"), read_bytes(dir / "cpu64.csv"));
#endif
}

// A radius beyond every distance (its square overflows double): every pair, no crash.
TEST(cli_query, radius_beyond_every_distance) {
    const auto dir = fresh_dir();
    write_points<double, 3>(dir / "three.xyz", {0, 0, 0, 1, 2, 3, -4, 5, 6});
    for (const char* r : {"1e200", "1e308"}) {
        const tool_result t = run_tool(dir, std::string("query three.xyz --radius ") + r + " -o out.npy");
        ASSERT_EQ(t.code, 0) << t.err;
        EXPECT_EQ(read_pairs(dir / "out.npy", 3), (std::vector<std::int64_t>{0, 1, 0, 2, 1, 2})) << r;
    }
}

}  // namespace
}  // namespace frnn::test
