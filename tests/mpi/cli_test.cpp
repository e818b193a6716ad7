// `mpirun -np P frnn query`: the output file is byte-identical to the single-process tool's at
// P = 1..4 (rank_counts()) on every oracle set and through every reading path (.npy slices in C
// and Fortran order, text files read in parts, binary .ply in slices, ascii .ply read on rank 0
// and scattered); the --json summary adds up; bad input
// stops every rank with one clear message and no file; a killed rank ends the job instead of
// leaving the others waiting.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "cli/run_tool.hpp"
#include "oracle/point_sets.hpp"
#include "scratch_dir.hpp"
#ifdef FRNN_SIM_AVAILABLE
#include "frnn/sim/run.hpp"
#include "frnn/sim/scene.hpp"
#endif

namespace frnn::test {
namespace {

const std::string mpirun = "'" FRNN_MPIEXEC "' --oversubscribe --allow-run-as-root";
const std::string tool = "'" FRNN_TOOL_PATH "'";

/// `mpirun -np P frnn <args>` in `dir`, one thread per rank.
command_result run_mpi(const std::filesystem::path& dir, int ranks, const std::string& args) {
    return run_command(dir, "FRNN_NUM_THREADS=1 OMP_NUM_THREADS=1 " + mpirun + " -np " + std::to_string(ranks) +
                                " " + tool + " " + args);
}

/// The rank counts the byte-identity checks run at: 1 to 4, or those listed in
/// FRNN_MPI_CLI_RANKS (the sanitizer tree runs 1 and 3, tests/mpi/CMakeLists.txt).
std::vector<int> rank_counts() {
    const char* listed = std::getenv("FRNN_MPI_CLI_RANKS");
    if (!listed) return {1, 2, 3, 4};
    std::vector<int> counts;
    for (const char* p = listed; *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p || n < 1 || n > 64) {
            ADD_FAILURE() << "FRNN_MPI_CLI_RANKS=" << listed << ": expected rank counts such as 1,3";
            return {1, 2, 3, 4};
        }
        counts.push_back(int(n));
        p = *end == ',' ? end + 1 : end;
    }
    return counts;
}

/// The names in `dir`, sorted: what a failed run must leave is only what was there before.
std::vector<std::string> listing(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

/// Writes `points` as `input`, runs the serial tool and mpirun at rank_counts() with `options`,
/// and compares the output files byte for byte.
template <class T, int D>
void expect_same_files(const char* name, const std::vector<T>& points, const std::string& input, const std::string& output,
                       const std::string& options, bool fortran_order = false, bool binary = false) {
    SCOPED_TRACE(name);
    const scratch_dir dir(std::string("mpi_cli_") + name);
    if (fortran_order) {
        // All x, then all y (then all z): each rank reads its rows from D places.
        const std::size_t n = points.size() / D;
        std::string columns;
        for (std::size_t a = 0; a < D; ++a)
            for (std::size_t i = 0; i < n; ++i) put(columns, points[i * D + a]);
        write_bytes(dir / input, npy_bytes(std::string("{'descr': '") + (sizeof(T) == 4 ? "<f4" : "<f8") +
                                               "', 'fortran_order': True, 'shape': (" + std::to_string(n) + ", " +
                                               std::to_string(D) + "), }",
                                           columns));
    } else {
        write_points<T, D>(dir / input, points, binary);
    }
    const tool_result serial = run_tool(dir, "query " + input + " " + options + " -o serial" + output);
    ASSERT_EQ(serial.code, 0) << serial.err;
    const std::string expected = read_bytes(dir / ("serial" + output));
    for (int ranks : rank_counts()) {
        const std::string file = "mpi" + std::to_string(ranks) + output;
        const command_result r = run_mpi(dir, ranks, "query " + input + " " + options + " -o " + file);
        ASSERT_EQ(r.code, 0) << ranks << " ranks: " << r.err;
        const std::string found = read_bytes(dir / file);
        EXPECT_TRUE(found == expected) << ranks << " ranks: " << file << " (" << found.size()
                                       << " bytes) differs from the single-process file (" << expected.size() << " bytes)";
    }
}

TEST(MpiCli, OutputIsTheSingleProcessFileOnEveryOracleSet) {
    expect_same_files<float, 3>("random", uniform_points<float, 3>(3000, 0, 12, 61), "in.npy", ".npy", "-r 1");
    expect_same_files<double, 2>("clustered", clustered_points<double, 2>(2000, 6, 0.4, 0, 10, 62), "in.csv", ".csv",
                                 "-r 0.25");
    std::vector<double> box_points = uniform_points<double, 3>(1500, 0, 1, 63);
    const double box[3] = {8, 6, 7};
    for (std::size_t i = 0; i < box_points.size(); ++i) box_points[i] = std::min(box_points[i] * box[i % 3], box[i % 3] * 0.999999);
    expect_same_files<double, 3>("periodic", box_points, "in.npy", ".npz", "-r 1.1 --periodic 8,6,7");
    expect_same_files<double, 3>("periodic_on_x_and_z", box_points, "in.npy", ".npz", "-r 1.1 --periodic 8,0,7");
    // Points outside the box, a few boxes and 10^6 boxes out: wrapped as the single process does.
    std::vector<float> outside(box_points.begin(), box_points.end());
    for (std::size_t i = 0; i < 300; ++i) outside[i] += float(box[i % 3] * (i < 30 ? 1e6 : double(int(i % 7) - 3)));
    expect_same_files<float, 3>("periodic_points_outside", outside, "in.npy", ".npz", "-r 1.1 --periodic 8,6,7");
    std::vector<double> outliers = uniform_points<double, 3>(600, 0, 5, 64);
    append_point<double, 3>(outliers, 1e6);
    append_point<double, 3>(outliers, -1e6);
    append_point<double, 3>(outliers, 1e6 + 0.25);
    expect_same_files<double, 3>("outliers", outliers, "in.ply", ".csv", "-r 0.5");
    // Binary .ply: every rank reads its own slice of vertices.
    expect_same_files<float, 3>("binary_ply", uniform_points<float, 3>(2000, 0, 10, 69), "in.ply", ".npy", "-r 0.8",
                                false, true);
    expect_same_files<float, 2>("duplicates", with_duplicates(uniform_points<float, 2>(250, 0, 4, 65), 2, 3), "in.npy",
                                ".npz", "-r 0.5");
    expect_same_files<double, 3>("lattice", lattice_points<double, 3>(8, 1.0), "in.xyz", ".csv", "-r 1");
    expect_same_files<double, 2>("periodic_lattice", lattice_points<double, 2>(12, 1.0), "in.npy", ".npy",
                                 "-r 1 --periodic 12,12");
    expect_same_files<double, 2>("fortran_order", uniform_points<double, 2>(1000, 0, 10, 68), "in.npy", ".csv", "-r 0.6",
                                 true);
}

TEST(MpiCli, JsonSummaryAddsUp) {
    const scratch_dir dir("mpi_cli_json");
    const tool_result serial = run_tool(dir, "query --generate lattice:12 -r 2 --json");
    ASSERT_EQ(serial.code, 0) << serial.err;
    const auto start = std::chrono::steady_clock::now();
    const command_result r = run_mpi(dir, 3, "query --generate lattice:12 -r 2 --json -o pairs.npy");
    const double run_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(r.code, 0) << r.err;
    // One document, from rank 0 only.
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["ranks"], 3);
    EXPECT_EQ(j["points"], 1728);
    EXPECT_EQ(j["pairs"], nlohmann::json::parse(serial.out)["pairs"]);
    EXPECT_EQ(j["output"], "pairs.npy");
    ASSERT_EQ(j["per_rank"].size(), 3u);
    // A time, checked to be a number (a NaN or an infinity would print as null).
    auto ms = [](const nlohmann::json& times, const char* name) {
        const bool number = times.contains(name) && times[name].is_number();
        EXPECT_TRUE(number) << name << ": " << times.dump();
        return number ? times[name].get<double>() : 0.0;
    };
    std::uint64_t particles = 0, pairs = 0;
    std::vector<double> rank_ms;
    for (int k = 0; k < 3; ++k) {
        const nlohmann::json& rank = j["per_rank"][std::size_t(k)];
        EXPECT_EQ(rank["rank"], k);
        particles += rank["particles"].get<std::uint64_t>();
        pairs += rank["pairs"].get<std::uint64_t>();
        EXPECT_GT(rank["ghosts"].get<std::uint64_t>(), 0u);
        EXPECT_GT(rank["bytes_sent"]["halo"].get<std::uint64_t>(), 0u);
        // The rank's search: its phases, added in the tool's order.
        const nlohmann::json &exchange = rank.at("exchange_ms"), &local = rank.at("local_ms");
        rank_ms.push_back(ms(exchange, "decompose") + ms(exchange, "migrate") + ms(exchange, "halo") +
                          ms(local, "grid") + ms(local, "lists"));
    }
    EXPECT_EQ(particles, 1728u);
    EXPECT_EQ(pairs, j["pairs"].get<std::uint64_t>());
    // The summary's search time is the slowest rank's. Rank 0's read, search and write are laps
    // of one clock within its process: together no longer than mpirun's run as this test timed
    // it, however loaded the machine.
    const nlohmann::json& times = j.at("time_ms");
    EXPECT_DOUBLE_EQ(ms(times, "search"), *std::max_element(rank_ms.begin(), rank_ms.end())) << r.out;
    EXPECT_LE(ms(times, "read") + rank_ms[0] + ms(times, "write"), run_ms) << r.out;
}

/// A run that must fail with exit code `code` and `message` printed once.
void expect_failure(const command_result& r, int code, const std::string& message) {
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_EQ(occurrences(r.err, message), 1u) << "stderr:\n" << r.err;
}

TEST(MpiCli, BadInputStopsEveryRankWithOneMessage) {
    const scratch_dir dir("mpi_cli_errors");
    std::vector<double> points = uniform_points<double, 3>(30, 0, 4, 66);
    write_points<double, 3>(dir / "in.npy", points);
    points[25 * 3 + 1] = std::numeric_limits<double>::quiet_NaN();
    write_points<double, 3>(dir / "nan.npy", points);
    write_points<double, 3>(dir / "three.npy", uniform_points<double, 3>(3, 0, 4, 67));
    write_bytes(dir / "bad.csv", "x,y,z\n1,2,3\n1,two,3\n");
    std::string rows = "x,y,z\n";
    for (int k = 0; k < 30; ++k) rows += "1,2,3\n";
    write_bytes(dir / "columns.csv", rows + "4,5\n");
    write_bytes(dir / "nan.csv", rows + "1,nan,3\n");
    const std::vector<std::string> before = listing(dir);

    // A NaN in the last rank's slice: that rank finds it, every rank stops.
    expect_failure(run_mpi(dir, 3, "query nan.npy -r 1 -o out.npy"), 1,
                   "frnn: error: rank 2: nan.npy: point 25 has a non-finite coordinate");
    expect_failure(run_mpi(dir, 4, "query three.npy -r 1 -o out.npy"), 1,
                   "frnn: error: more ranks (4) than particles (3)");
    // Each rank reads its part of a text file; line and point numbers are the whole file's, and
    // the columns of a later part are checked against the first data line's.
    expect_failure(run_mpi(dir, 2, "query bad.csv -r 1 -o out.npy"), 1, "frnn: error: rank 1: bad.csv: line 3");
    expect_failure(run_mpi(dir, 3, "query columns.csv -r 1 -o out.npy"), 1,
                   "frnn: error: rank 2: columns.csv: line 32: 2 columns, but line 2 has 3");
    expect_failure(run_mpi(dir, 3, "query nan.csv -r 1 -o out.npy"), 1,
                   "frnn: error: rank 2: nan.csv: line 32: point 30 has a non-finite coordinate (nan)");
    // Ranks started with different options (an MPMD launch).
    auto two = [&](const std::string& first, const std::string& second) {
        return run_command(dir, "FRNN_NUM_THREADS=1 " + mpirun + " -np 1 " + tool + " query in.npy " + first + " : -np 1 " +
                                    tool + " query in.npy " + second);
    };
    expect_failure(two("-r 1 -o out.npy", "-r 2 -o out.npy"), 1,
                   "frnn: error: rank 1: radius, skin, imbalance threshold and periodic box (2.000000");
    expect_failure(two("-r 1 -o a.npy", "-r 1 -o b.npy"), 1,
                   "frnn: error: rank 1: INPUT, --output, --generate, --dim, --seed or --json differ from rank 0's");
    expect_failure(two("-r 1 --periodic 5,5,5", "-r 1 --periodic 5,5,6"), 1,
                   "frnn: error: rank 1: radius, skin, imbalance threshold and periodic box");
    // What the distributed path does not do, and a write that fails on rank 0.
    expect_failure(run_mpi(dir, 2, "query in.npy -r 1 --knn 3 -o out.npy"), 2,
                   "frnn: --knn: is not supported under mpirun");
    expect_failure(run_mpi(dir, 2, "query in.npy -r 1 --self"), 2, "frnn: --self: is not supported under mpirun");
    expect_failure(run_mpi(dir, 2, "query in.npy -r 1 --cell 4,0,0,0,4,0,0,0,4 -o out.npy"), 2,
                   "frnn: --cell: is not supported under mpirun");
    expect_failure(run_mpi(dir, 2, "query in.npy -r 1 -o missing/out.npy"), 1, "frnn: error: rank 0: missing/out.npy: cannot create");
    EXPECT_EQ(listing(dir), before) << "a failed run left files";
}

// Every command but query runs in one process: under mpirun with several ranks it refuses
// with one message and writes nothing, instead of running one copy per rank.
TEST(MpiCli, SingleProcessCommandsRefuseSeveralRanks) {
    const scratch_dir dir("mpi_cli_single");
    const std::vector<std::string> before = listing(dir);
    expect_failure(run_mpi(dir, 2, "view --scene droplet"), 1, "frnn: view runs in one process, but an MPI launcher started 2 ranks");
    expect_failure(run_mpi(dir, 3, "validate --quick"), 1, "frnn: validate runs in one process, but an MPI launcher started 3");
    expect_failure(run_mpi(dir, 2, "bench --workload W1 --n 1000"), 1, "frnn: bench runs in one process");
    EXPECT_EQ(listing(dir), before) << "a refused run left files";
    // One rank is one process: it runs.
    const auto one = run_mpi(dir, 1, "sim --particles 300 --steps 2 --quiet --out run");
    EXPECT_EQ(one.code, 0) << one.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "run" / "summary.json"));
}

/// summary.json without what may differ between runs: timings, threads and the ranks.
nlohmann::json summary_without_timings(const std::filesystem::path& file) {
    nlohmann::json j = nlohmann::json::parse(read_bytes(file));
    for (const char* key : {"wall_seconds", "mean_ms_per_step", "mean_process_cpu_ms_per_step", "step_ms_without_output",
                            "threads", "ranks"})
        j.erase(key);
    return j;
}

// One simulation across ranks (WCSPH or viscoelastic) writes the one-process run's frames and
// checkpoint, byte for byte, at any rank and thread count; each rank holds a part of the particles.
TEST(MpiCli, SimAcrossRanksIsTheOneProcessRun) {
    const scratch_dir dir("mpi_cli_sim");
    // A dam break in an open tank (walls by the kernel's integral, no wall particles): the
    // column runs along the cut axis, so particles move between ranks every few steps.
    write_bytes(dir / "open-dam-break.json", R"({"name": "open-dam-break", "solver": "sph", "dim": 2,
        "particles": {"2d": 1500, "3d": 4000}, "duration": 1, "gravity": [0, -9.81, 0],
        "domain": {"min": [0, 0, 0], "max": [2, 1, 1]},
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.25, 0.5, 1]}],
        "colliders": [{"name": "tank", "type": "box", "inside": true, "center": [1, 0.5, 0.5], "half": [1, 0.5, 0.5]}],
        "sph": {"alpha": 0.3, "cfl": 0.4}, "front": {"a": 0.25, "origin": 0, "axis": 0, "every_T": 0.02}})");
    // A layer falling and flowing through a box periodic on both axes, stirred by a sphere.
    write_bytes(dir / "periodic-box.json", R"({"name": "periodic-box", "solver": "sph", "dim": 2,
        "particles": {"2d": 1200, "3d": 4000}, "duration": 1, "gravity": [0, -9.81, 0],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, 1, 0],
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.4, 1], "velocity": [1.5, -1, 0]}],
        "colliders": [{"name": "stone", "type": "sphere", "center": [0.5, 0.6, 0.5], "radius": 0.1}],
        "sph": {"alpha": 0.3}})");
    // A channel periodic along x only: a layer flowing over a bed past a stone.
    write_bytes(dir / "channel.json", R"({"name": "channel", "solver": "sph", "dim": 2,
        "particles": {"2d": 1200, "3d": 4000}, "duration": 1, "gravity": [0, -9.81, 0],
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "periodic": [1, 0, 0],
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [1, 0.3, 1], "velocity": [1.5, 0, 0]}],
        "colliders": [{"name": "bed", "type": "box", "center": [0.5, -0.5, 0.5], "half": [2, 0.5, 1]},
                      {"name": "stone", "type": "sphere", "center": [0.5, 0.3, 0.5], "radius": 0.1}],
        "sph": {"alpha": 0.3}})");
    // The shipped dam break's walls with the continuity equation: the density moves with its particle.
    write_bytes(dir / "continuity-dam-break.json", R"({"name": "continuity-dam-break", "solver": "sph", "dim": 2,
        "particles": {"2d": 1250, "3d": 4000}, "duration": 1, "gravity": [0, -9.81, 0],
        "domain": {"min": [0, 0, 0], "max": [2, 1, 1]},
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.25, 0.5, 1]}],
        "colliders": [{"name": "tank", "type": "box", "inside": true, "center": [1, 0.5, 0.5], "half": [1, 0.5, 0.5]}],
        "sph": {"h_ratio": 1.3, "alpha": 0.02, "wall_particles": true, "density": "continuity", "density_diffusion": 0.1},
        "front": {"a": 0.25, "origin": 0, "axis": 0, "every_T": 0.02}})");
    // The same walls with the bulk viscosity (a pair pass after the density, whose sums the
    // ghosts take from their owners) and the walls' friction.
    write_bytes(dir / "bulk-dam-break.json", R"({"name": "bulk-dam-break", "solver": "sph", "dim": 2,
        "particles": {"2d": 1250, "3d": 4000}, "duration": 1, "gravity": [0, -9.81, 0],
        "domain": {"min": [0, 0, 0], "max": [2, 1, 1]},
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.25, 0.5, 1]}],
        "colliders": [{"name": "tank", "type": "box", "inside": true, "center": [1, 0.5, 0.5], "half": [1, 0.5, 0.5]}],
        "sph": {"h_ratio": 1.3, "viscosity": "laminar", "wall_particles": true, "free_slip": true, "bulk_viscosity": 0.3,
                "wall_friction": true},
        "front": {"a": 0.25, "origin": 0, "axis": 0, "every_T": 0.02}})");
    struct scene_case {
        const char* options;
        std::size_t frames;  // the first, then one every `--every` steps
        std::vector<std::pair<int, int>> ranks_threads;
        bool rebalances = false;  // the fluid moves enough that a new cut follows it
        bool empty_ranks = false;  // fewer particles than ranks: some ranks hold none
    };
    const std::vector<scene_case> cases = {
        {"open-dam-break.json --steps 400 --every 100", 5, {{2, 2}, {3, 1}, {4, 1}}, true},
        // With PNG pictures, drawn on rank 0 from the gathered particles: the same bytes.
        {"--scene droplet --solver sph --dim 3 --particles 2000 --steps 24 --every 12 --png", 3, {{2, 1}}},
        // Wall particles: ghosts two radii deep.
        {"--scene dam-break --solver sph --dim 2 --particles 1250 --steps 400 --every 100", 5, {{2, 1}, {3, 2}}, true},
        // Periodic: particles and ghosts cross the box's faces.
        {"periodic-box.json --steps 300 --every 100", 4, {{2, 1}, {3, 1}}},
        // Periodic on one axis: the open one spans the scene's domain on every rank.
        {"channel.json --steps 300 --every 100", 4, {{2, 1}, {4, 1}}},
        // The shipped scene with a scripted collider (a paddle sweeping the floor).
        {"--scene block-drop --solver sph --dim 2 --particles 1500 --steps 300 --every 100", 4, {{2, 1}, {4, 1}}},
        // The viscoelastic solver: its springs (block-drop) reach partners beyond the ghosts,
        // which are fetched by id.
        {"--scene block-drop --dim 2 --particles 1500 --steps 400 --every 100", 5, {{2, 1}, {3, 2}, {4, 1}}, true},
        {"--scene block-drop --dim 3 --particles 3000 --steps 200 --every 100", 3, {{4, 1}}, true},
        {"--scene dam-break --dim 2 --particles 1500 --steps 200 --every 100", 3, {{2, 1}, {4, 1}}},
        {"--scene droplet --dim 3 --particles 2000 --steps 100 --every 50", 3, {{2, 1}}},
        {"periodic-box.json --solver viscoelastic --steps 200 --every 100", 3, {{2, 1}, {4, 1}}},
        {"channel.json --solver viscoelastic --steps 200 --every 100", 3, {{3, 1}}},
        // 2 particles: ranks without particles, and without a share of a frame's ids.
        {"--scene dam-break --solver sph --dim 2 --particles 2 --steps 40 --every 20", 3, {{3, 1}, {4, 1}}, false, true},
        // The continuity density: rho is state that moves with its particle.
        {"continuity-dam-break.json --steps 300 --every 100", 4, {{2, 1}, {3, 1}}},
        {"bulk-dam-break.json --steps 300 --every 100", 4, {{2, 1}, {3, 1}}},
    };
    // The release tree runs every case at 1 to 4 ranks of one thread, and the variants listed
    // with more threads. The sanitizer tree (rank counts 1 and 3) runs only the listed variants
    // at its counts: each path (springs, channels, periodic boxes, walls) has one at 3.
    const std::vector<int> counts = rank_counts();
    const bool every_count = counts.size() >= 4;
    for (const auto& c : cases) {
        SCOPED_TRACE(c.options);
        std::vector<std::pair<int, int>> runs;
        if (every_count)
            for (int ranks : counts) runs.emplace_back(ranks, 1);
        for (const auto& rt : c.ranks_threads)
            if ((every_count && rt.second > 1) || (!every_count && std::find(counts.begin(), counts.end(), rt.first) != counts.end()))
                runs.push_back(rt);
        if (runs.empty()) continue;
        const std::string common = std::string("sim ") + c.options + " --quiet";
        const auto one = run_command(dir, tool + " " + common + " --threads 1 --out one");
        ASSERT_EQ(one.code, 0) << one.err;
        if (std::string(c.options).find("dam-break") != std::string::npos) {
            ASSERT_TRUE(std::filesystem::exists(dir / "one" / "front.csv"));
        }
        const std::size_t particles = summary_without_timings(dir / "one" / "summary.json")["particles"].get<std::size_t>();
        std::size_t rebalances = 0;
        for (const auto& [ranks, threads] : runs) {
            SCOPED_TRACE(std::to_string(ranks) + " ranks of " + std::to_string(threads) + " threads");
            const std::string out = "ranks" + std::to_string(ranks);
            const auto r = run_mpi(dir, ranks, common + " --threads " + std::to_string(threads) + " --out " + out);
            ASSERT_EQ(r.code, 0) << r.err;
            std::size_t frames = 0;
            for (const auto& e : std::filesystem::directory_iterator(dir / "one" / "frames")) {
                const auto name = e.path().filename();
                EXPECT_TRUE(read_bytes(e.path()) == read_bytes(dir / out / "frames" / name)) << name << " differs";
                ++frames;
            }
            EXPECT_EQ(frames, c.frames);
            if (std::string(c.options).find("--png") != std::string::npos) {
                std::size_t pictures = 0;
                for (const auto& e : std::filesystem::directory_iterator(dir / "one" / "png")) {
                    EXPECT_TRUE(read_bytes(e.path()) == read_bytes(dir / out / "png" / e.path().filename()))
                        << e.path().filename() << " differs";
                    ++pictures;
                }
                EXPECT_EQ(pictures, c.frames);
            }
            for (const char* file : {"checkpoint.bin", "particles.pvd", "front.csv"})
                EXPECT_TRUE(read_bytes(dir / "one" / file) == read_bytes(dir / out / file)) << file << " differs";
            EXPECT_EQ(summary_without_timings(dir / "one" / "summary.json"), summary_without_timings(dir / out / "summary.json"));
            const nlohmann::json summary = nlohmann::json::parse(read_bytes(dir / out / "summary.json"));
            if (ranks == 1) {  // one rank runs as one process: no ranks section
                EXPECT_FALSE(summary.contains("ranks")) << summary.dump();
                continue;
            }
            ASSERT_EQ(summary["ranks"]["per_rank"].size(), std::size_t(ranks)) << summary.dump();
            std::size_t sum = 0;
            for (const auto& rank : summary["ranks"]["per_rank"]) {
                if (!c.empty_ranks) {
                    EXPECT_GT(rank["particles"].get<std::size_t>(), 0u) << summary.dump();
                    EXPECT_GT(rank["ghosts"].get<std::size_t>(), 0u) << summary.dump();
                }
                for (const char* ms : {"exchange_ms_per_step", "waiting_ms_per_step", "local_ms_per_step"})
                    EXPECT_GT(rank[ms].get<double>(), 0.0) << ms << ": " << summary.dump();
                EXPECT_LE(rank["waiting_ms_per_step"].get<double>(), rank["exchange_ms_per_step"].get<double>());
                sum += rank["particles"].get<std::size_t>();
            }
            EXPECT_EQ(sum, particles);
            const nlohmann::json& balance = summary["ranks"]["balance"];
            // Every 20 steps after the first (one grid per step).
            EXPECT_EQ(balance["checks"], (summary["steps"].get<std::size_t>() - 1) / 20) << balance.dump();
            EXPECT_GE(balance["largest_imbalance"].get<double>(), 1.0) << balance.dump();
            rebalances += balance["rebalances"].get<std::size_t>();
        }
        if (c.rebalances && (every_count || runs.size() == c.ranks_threads.size())) {
            EXPECT_GT(rebalances, 0u) << "no rank count cut the domain anew";
        }
    }
}

#ifdef FRNN_SIM_AVAILABLE
// A one-process run stopped after its checkpoint at step 100 and continued across ranks ends
// as the uninterrupted run, byte for byte.
TEST(MpiCli, SimResumedAcrossRanksIsTheOneProcessRun) {
    struct resume_case {
        const char* scene;
        sim::solver_kind solver;
        const char* solver_name;
    };
    // WCSPH with wall particles, and the viscoelastic solver with its springs.
    for (const resume_case& c : {resume_case{"dam-break", sim::solver_kind::sph, "sph"},
                                 resume_case{"block-drop", sim::solver_kind::viscoelastic, "viscoelastic"}}) {
        SCOPED_TRACE(c.scene);
        const scratch_dir dir("mpi_cli_sim_resume");
        const auto whole = run_command(dir, tool + " sim --scene " + c.scene + " --solver " + c.solver_name +
                                                   " --dim 2 --particles 1250 --steps 200 --every 20 --quiet --threads 1 --out whole");
        ASSERT_EQ(whole.code, 0) << whole.err;
        sim::scene_overrides ov;  // the same options, as `frnn sim` gives them
        ov.solver = c.solver;
        ov.dim = 2;
        ov.particles = 1250;
        ov.steps = 200;
        ov.every = 20;
        sim::run_options o;
        o.out_dir = (dir / "cut").string();
        o.threads = 1;
        o.progress = o.print_table = false;
        o.stop_after = 130;  // the scenes checkpoint every 5 frames: at step 100
        ASSERT_FALSE(sim::run(sim::builtin_scene_text(c.scene), std::string("scene ") + c.scene, ov, o).finished);
        const auto resumed = run_mpi(dir, 3, "sim --resume cut --quiet");
        ASSERT_EQ(resumed.code, 0) << resumed.err;
        std::size_t frames = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir / "whole" / "frames")) {
            EXPECT_TRUE(read_bytes(e.path()) == read_bytes(dir / "cut" / "frames" / e.path().filename())) << e.path().filename();
            ++frames;
        }
        EXPECT_EQ(frames, 11u);
        for (const char* file : {"checkpoint.bin", "particles.pvd", "front.csv"}) {
            if (!std::filesystem::exists(dir / "whole" / file)) continue;  // block-drop records no front
            EXPECT_TRUE(read_bytes(dir / "whole" / file) == read_bytes(dir / "cut" / file)) << file << " differs";
        }
    }
}
#endif

// A rank killed mid-run ends the job (the only time limit is `timeout`'s). What was written
// before is complete: the frames are the uninterrupted run's, and the last checkpoint resumes,
// in one process, to the uninterrupted run's end.
TEST(MpiCli, SimWithAKilledRankEndsAndItsCheckpointResumes) {
    const scratch_dir dir("mpi_cli_sim_killed");
    const std::string options = "sim --scene dam-break --solver sph --dim 2 --particles 1250 --steps 200 --every 20 --quiet "
                                "--threads 1";
    const auto whole = run_command(dir, tool + " " + options + " --out whole");
    ASSERT_EQ(whole.code, 0) << whole.err;
    // Three exchanges a step: rank 1 dies in step 130 (frames every 20 steps, the checkpoint
    // at step 100).
    const auto r = run_command(dir, "FRNN_TEST_KILL_RANK=1 FRNN_TEST_KILL_EXCHANGE=390 FRNN_NUM_THREADS=1 timeout 60 " +
                                        mpirun + " -np 2 " + tool + " " + options + " --out cut");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.code, 124) << "mpirun still ran after 60 s: rank 0 was left waiting";
    EXPECT_NE(r.err.find("exited on signal 9"), std::string::npos) << r.err;
    std::vector<std::string> frames;
    for (const auto& e : std::filesystem::directory_iterator(dir / "cut" / "frames")) {
        frames.push_back(e.path().filename().string());
        EXPECT_TRUE(read_bytes(e.path()) == read_bytes(dir / "whole" / "frames" / e.path().filename()))
            << e.path().filename() << " differs from the uninterrupted run's";
    }
    EXPECT_EQ(frames.size(), 7u) << "the frames of steps 0 to 120";
    const auto resumed = run_command(dir, tool + " sim --resume cut --quiet --threads 1");
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    for (const auto& e : std::filesystem::directory_iterator(dir / "whole" / "frames"))
        EXPECT_TRUE(read_bytes(e.path()) == read_bytes(dir / "cut" / "frames" / e.path().filename())) << e.path().filename();
    for (const char* file : {"checkpoint.bin", "particles.pvd", "front.csv"})
        EXPECT_TRUE(read_bytes(dir / "whole" / file) == read_bytes(dir / "cut" / file)) << file << " differs";
}

// An instability found on one rank (a ram hits the fluid at 40 m/s on the rank whose slab it
// reaches) stops every rank with the one-process message, printed once.
TEST(MpiCli, SimInstabilityStopsEveryRankWithTheOneProcessMessage) {
    const scratch_dir dir("mpi_cli_sim_unstable");
    write_bytes(dir / "ram.json", R"({"name": "ram", "solver": "sph", "dim": 2, "particles": {"2d": 800, "3d": 800},
        "duration": 1, "gravity": [0, -9.81, 0], "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
        "fluid": [{"type": "box", "min": [0.2, 0.2, 0], "max": [0.5, 0.5, 1], "velocity": [0, -0.5, 0]}],
        "colliders": [{"name": "tank", "type": "box", "inside": true, "center": [0.5, 0.5, 0.5], "half": [0.5, 0.5, 0.5]},
                      {"name": "ram", "type": "sphere", "center": [0.35, 0.9, 0.5], "radius": 0.1,
                       "motion": {"velocity": [0, -40, 0]}}],
        "sph": {"sound_speed": 1e-4, "cfl": 1, "max_dt": 1}})");
    const auto one = run_command(dir, tool + " sim ram.json --steps 100 --quiet --threads 1 --out one");
    ASSERT_EQ(one.code, 1) << one.err;
    const std::size_t at = one.err.find("frnn: error: simulation unstable at step");
    ASSERT_NE(at, std::string::npos) << one.err;
    const std::string message = one.err.substr(at, one.err.find('\n', at) - at);
    for (int ranks : rank_counts()) {
        if (ranks < 2) continue;
        SCOPED_TRACE(std::to_string(ranks) + " ranks");
        expect_failure(run_mpi(dir, ranks, "sim ram.json --steps 100 --quiet --out ranks" + std::to_string(ranks)), 1, message);
    }
}

// What does not run across ranks yet stops every rank with one message, before any file.
TEST(MpiCli, SimAcrossRanksRefusesWhatItCannotRunYet) {
    const scratch_dir dir("mpi_cli_sim_refusals");
    const std::vector<std::string> before = listing(dir);
    // A domain so much larger than the fluid that the one-process run takes the hashed grid.
    write_bytes(dir / "vast.json", R"({"name": "vast", "solver": "sph", "dim": 2, "particles": {"2d": 400, "3d": 400},
        "duration": 1, "gravity": [0, -9.81, 0], "domain": {"min": [0, 0, 0], "max": [1e7, 1e7, 1]},
        "fluid": [{"type": "box", "min": [0, 0, 0], "max": [0.2, 0.2, 1]}]})");
    const std::vector<std::string> with_scenes = listing(dir);
    expect_failure(run_mpi(dir, 3, "sim vast.json --steps 2 --out run"), 1,
                   "frnn: error: a simulation across ranks needs the scene's uniform grid");
    EXPECT_EQ(listing(dir), with_scenes) << "a refused run left files";
    std::filesystem::remove(dir / "vast.json");
    expect_failure(run_mpi(dir, 2, "sim missing.json --out run"), 1, "frnn: error: cannot open scene file 'missing.json'");
    expect_failure(run_mpi(dir, 2, "sim --resume run"), 1, "frnn: error: --resume: no checkpoint in 'run'");
    expect_failure(run_mpi(dir, 2, "sim --scene droplet --bogus"), 2, "frnn: The following argument was not expected: --bogus");
    EXPECT_EQ(listing(dir), before) << "a refused run left files";
}

TEST(MpiCli, AKilledRankEndsTheJob) {
    // Rank k dies (SIGKILL) between the migration and the ghost exchange; the others wait for
    // it in a collective call until mpirun ends them. Rank 0 too: it would have written the file.
    // The only time limit is `timeout`'s: a job left waiting for the dead rank is ended by it
    // (exit 124), one ended by mpirun says which rank died.
    for (int killed : {1, 0}) {
        SCOPED_TRACE("rank " + std::to_string(killed) + " killed");
        const scratch_dir dir("mpi_cli_killed");
        const command_result r = run_command(dir, "FRNN_TEST_KILL_RANK=" + std::to_string(killed) +
                                                      " FRNN_NUM_THREADS=1 timeout 60 " + mpirun + " -np 3 " + tool +
                                                      " query --generate uniform:20000 -r 1 -o out.npy");
        EXPECT_NE(r.code, 0);
        EXPECT_NE(r.code, 124) << "mpirun still ran after 60 s: the other ranks were left waiting";
        EXPECT_NE(r.err.find("rank " + std::to_string(killed) + " with PID"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("exited on signal 9"), std::string::npos) << r.err;
        EXPECT_TRUE(listing(dir).empty()) << "no output file, no temporary";
    }
}

}  // namespace
}  // namespace frnn::test
