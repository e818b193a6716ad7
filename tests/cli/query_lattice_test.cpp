// `frnn query --cell`: pairs in a periodic cell of any shape, once per image with their shift.
// Counts come from crystallography (fcc: 12 first neighbors, 6 second; diamond: 4 bonds), the
// files from each other (.npy rows and .csv lines), and threads give the same bytes.
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

#include "cli/run_tool.hpp"

namespace frnn::test {
namespace {

TEST(cli_query_lattice, crystal_neighbor_counts) {
    const auto dir = fresh_dir();
    // fcc Cu, primitive cell of one atom (smaller than the cutoff): 12 neighbors within 3.0,
    // 18 within 4.0; each pair of atoms once per image, so half of that.
    write_points<double, 3>(dir / "cu.csv", std::vector<double>{0.2, -7.0, 0.5});
    const std::string fcc = "--cell 0,1.805,1.805,1.805,0,1.805,1.805,1.805,0";
    for (auto [cutoff, pairs] : {std::pair{"3.0", 6}, std::pair{"4.0", 9}}) {
        const auto r = run_tool(dir, std::string("query cu.csv --json -r ") + cutoff + " " + fcc);
        ASSERT_EQ(r.code, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["pairs"], pairs) << cutoff;
        EXPECT_GT(j["images"].get<int>(), 12);
    }
    // Diamond, cubic cell of 8 atoms, sheared description of the same lattice (c += a): 16 bonds.
    std::vector<double> diamond;
    const double a = 3.567;
    for (double f : {0., 0., 0., 0., .5, .5, .5, 0., .5, .5, .5, 0., .25, .25, .25, .25, .75, .75, .75, .25, .75,
                     .75, .75, .25})
        diamond.push_back(f * a);
    write_points<double, 3>(dir / "c.npy", diamond);
    for (const char* cell : {"3.567,0,0,0,3.567,0,0,0,3.567", "3.567,0,0,0,3.567,0,3.567,0,3.567"}) {
        const auto r = run_tool(dir, std::string("query c.npy -r 1.6 --json --cell ") + cell);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(nlohmann::json::parse(r.out)["pairs"], 16) << cell;
    }
    // Not periodic along c: the bonds that cross the c faces are gone, fewer pairs remain.
    const auto open = run_tool(dir, "query c.npy -r 1.6 --json --pbc 1,1,0 --cell 3.567,0,0,0,3.567,0,0,0,3.567");
    ASSERT_EQ(open.code, 0) << open.err;
    const int open_pairs = nlohmann::json::parse(open.out)["pairs"];
    EXPECT_GT(open_pairs, 0);
    EXPECT_LT(open_pairs, 16);
}

TEST(cli_query_lattice, npy_and_csv_agree_and_threads_give_the_same_bytes) {
    const auto dir = fresh_dir();
    write_points<double, 2>(dir / "p.npy", random_points<double, 2>(200, 9.0, 7));
    const std::string cell = " -r 1.5 --cell 3,0,1.2,2.5 --pbc 1,0";
    ASSERT_EQ(run_tool(dir, "query p.npy -o one.npy --threads 1" + cell).code, 0);
    ASSERT_EQ(run_tool(dir, "query p.npy -o two.npy --threads 2" + cell).code, 0);
    EXPECT_EQ(read_bytes(dir / "one.npy"), read_bytes(dir / "two.npy"));
    const auto r = run_tool(dir, "query p.npy -o p.csv" + cell);
    ASSERT_EQ(r.code, 0) << r.err;
    std::istringstream csv(read_bytes(dir / "p.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "i,j,S_a,S_b,distance");
    std::vector<std::int64_t> from_csv;
    while (std::getline(csv, line)) {
        std::istringstream fields(line);
        std::string field;
        for (int k = 0; k < 4 && std::getline(fields, field, ','); ++k) from_csv.push_back(std::stoll(field));
    }
    ASSERT_GT(from_csv.size(), 400u);
    const auto rows = from_csv.size() / 4;
    EXPECT_EQ(npy_values<std::int64_t>(read_bytes(dir / "one.npy"), "<i8", {rows, 4}), from_csv);
    for (std::size_t e = 0; e < rows; ++e) {
        EXPECT_EQ(from_csv[e * 4 + 3], 0) << "no shift along the open axis";
        const auto i = from_csv[e * 4], j = from_csv[e * 4 + 1];
        EXPECT_TRUE(j > i || (j == i && from_csv[e * 4 + 2] > 0)) << "each pair once per image";
    }
}

TEST(cli_query_lattice, bad_cells_and_options_say_what) {
    const auto dir = fresh_dir();
    write_points<double, 3>(dir / "p.npy", random_points<double, 3>(10, 3.0, 8));
    struct bad {
        const char* options;
        int code;
        const char* message;
    };
    for (const bad& b : {bad{"--cell 1,0,0,0,1,0", 2, "needs 9 numbers"},
                         bad{"--cell 1,0,0,0,1,0,0,0,x", 2, "'x' (number 9) is not a number"},
                         bad{"--cell 1,0,0,0,1,0,0,0,1 --pbc 1,1", 2, "needs 3 flags"},
                         bad{"--cell 1,0,0,0,1,0,0,0,1 --pbc 1,2,0", 2, "'2' is not 1, 0"},
                         bad{"--pbc 1,1,1", 2, "needs --cell"},
                         bad{"--cell 1,0,0,0,1,0,0,0,1 --periodic 4,4,4", 2, "--periodic: does not apply with --cell"},
                         bad{"--cell 1,0,0,0,1,0,0,0,1 -o out.npz", 2, "with --cell, .npy"},
                         bad{"--cell 1,0,0,2,0,0,0,0,1", 1, "do not span space"},
                         bad{"--cell 1,0,0,0,1,0,0,0,1 -r 5000", 1, "periodic images of the 10 atoms"}}) {
        const std::string options = b.options;
        const bool own_radius = options.find("-r ") != std::string::npos;
        const bool own_output = options.find("-o ") != std::string::npos;
        const auto r = run_tool(dir, "query p.npy " + std::string(own_output ? "" : "-o out.npy ") +
                                         (own_radius ? "" : "-r 1 ") + options);
        EXPECT_EQ(r.code, b.code) << b.options << ": " << r.err;
        EXPECT_NE(r.err.find(b.message), std::string::npos) << b.options << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "out.npy") || std::filesystem::exists(dir / "out.npz")) << b.options;
    }
}

}  // namespace
}  // namespace frnn::test
