// `frnn query` failures: exit code 2 for usage errors and 1 for bad input, one line on stderr
// naming the file and line or index, and never a partial or clobbered output file.
#include "cli/run_tool.hpp"

namespace frnn::test {
namespace {

// Runs the tool and expects `code`, a one-line message holding every part, no new files.
void expect_failure(const std::filesystem::path& dir, const std::string& args, int code,
                    std::initializer_list<std::string_view> parts) {
    std::vector<std::filesystem::path> before;
    for (const auto& e : std::filesystem::directory_iterator(dir)) before.push_back(e.path());
    const tool_result r = run_tool(dir, args);
    EXPECT_EQ(r.code, code) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    ASSERT_FALSE(r.err.empty()) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (std::string_view p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << "stderr '" << r.err << "' lacks '" << p << "'";
    std::vector<std::filesystem::path> after;
    for (const auto& e : std::filesystem::directory_iterator(dir)) after.push_back(e.path());
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    EXPECT_EQ(after, before) << args << ": files were created";
}

class cli_errors : public ::testing::Test {
protected:
    void SetUp() override {
        write_points<double, 3>(dir / "p.npy", random_points<double, 3>(50, 3.0, 1));
        write_points<double, 2>(dir / "flat.csv", random_points<double, 2>(20, 3.0, 2));
    }
    const scratch_dir dir = fresh_dir();
};

TEST_F(cli_errors, usage_errors_exit_2) {
    expect_failure(dir, "query p.npy", 2, {"radius"});
    expect_failure(dir, "query p.npy --radius -1", 2, {"radius"});
    expect_failure(dir, "query p.npy --radius abc", 2, {"radius"});
    expect_failure(dir, "query p.npy --radius inf", 2, {"radius"});
    expect_failure(dir, "query p.npy -r 1 --grid octree", 2, {"grid"});
    expect_failure(dir, "query p.npy -r 1 --frobnicate", 2, {"frobnicate"});
    expect_failure(dir, "query p.npy -r 1 -o out.txt", 2, {"out.txt", "extension"});
    expect_failure(dir, "query p.dat -r 1", 2, {"p.dat", "extension"});
    expect_failure(dir, "query -r 1", 2, {"--generate"});
    expect_failure(dir, "query p.npy --generate lattice:4 -r 1", 2, {"--generate"});
    expect_failure(dir, "query --generate cubes:4 -r 1", 2, {"cubes:4"});
    expect_failure(dir, "query --generate lattice:x -r 1", 2, {"lattice:x"});
    expect_failure(dir, "query p.npy -r 1 --cell-size 2", 2, {"--cell-size"});
    expect_failure(dir, "query p.npy -r 1 --cell-size 0.1", 2, {"--cell-size"});
    expect_failure(dir, "query p.npy -r 1 --knn 0", 2, {"knn"});
    expect_failure(dir, "query p.npy -r 1 --threads -2", 2, {"threads"});
    expect_failure(dir, "query p.npy -r 1 --self --queries flat.csv", 2, {"--self"});
    expect_failure(dir, "query p.npy -r 1 --periodic 4,4", 2, {"--periodic", "3 box lengths", "got 2"});
    expect_failure(dir, "query p.npy -r 1 --periodic 4,x,4", 2, {"--periodic", "'x'"});
    expect_failure(dir, "query p.npy -r 1 --periodic 4,1,4", 2, {"--periodic", "2 * radius", "axis 1"});
    expect_failure(dir, "query p.npy -r 1 --periodic 4,0,1", 2, {"--periodic", "2 * radius", "axis 2"});
    expect_failure(dir, "query p.npy -r 1 --periodic 4,-1,4", 2, {"--periodic", "'-1'"});
    expect_failure(dir, "query p.npy -r radii.txt", 2, {"--radius", "radii.txt"});
    expect_failure(dir, "query p.npy -r r.npy --backend vulkan", 2, {"--backend", "one radius"});
    expect_failure(dir, "query p.npy -r r.npy --queries flat.csv", 2, {"--queries", "radius per point"});
    expect_failure(dir, "query p.npy -r r.npy --rule both", 2, {"--rule"});
    expect_failure(dir, "", 2, {});
}

// A launcher's variables without mpirun (the tool may be built without MPI): commands other
// than query refuse several ranks: rank 0 prints the message and exits 1, the others end quietly.
TEST_F(cli_errors, several_launcher_ranks_are_refused_outside_query) {
    const auto first = run_command(dir, "OMPI_COMM_WORLD_SIZE=4 OMPI_COMM_WORLD_RANK=0 '" FRNN_TOOL_PATH
                                        "' bench --workload W1");
    EXPECT_EQ(first.code, 1);
    EXPECT_EQ(first.err.rfind("frnn: bench runs in one process, but an MPI launcher started 4 ranks (each would run "
                              "its own copy): run it without mpirun; only `frnn query`",
                              0),
              0u)
        << first.err;
    const auto other = run_command(dir, "PMI_SIZE=2 PMI_RANK=1 '" FRNN_TOOL_PATH "' validate --quick");
    EXPECT_EQ(other.code, 0) << "rank 0 alone fails the job";
    EXPECT_TRUE(other.err.empty()) << "only rank 0 speaks: " << other.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "run"));
}

TEST_F(cli_errors, bad_text_line_names_file_and_line) {
    write_bytes(dir / "bad.csv", "x,y,z\n1,2,3\n4,five,6\n");
    expect_failure(dir, "query bad.csv -r 1 -o out.npy", 1, {"bad.csv", "line 3", "'five'"});
    write_bytes(dir / "wide.txt", "1 2 3 4\n");
    expect_failure(dir, "query wide.txt -r 1 -o out.npy", 1, {"wide.txt", "line 1", "4 columns"});
    write_bytes(dir / "nan.xyz", "1 2 3\n4 5 nan\n");
    expect_failure(dir, "query nan.xyz -r 1 -o out.npz", 1, {"nan.xyz", "line 2", "point 1"});
}

TEST_F(cli_errors, bad_binary_files_name_the_problem) {
    const std::string npy = read_bytes(dir / "p.npy");
    write_bytes(dir / "short.npy", npy.substr(0, npy.size() - 8));
    expect_failure(dir, "query short.npy -r 1 -o out.npy", 1, {"short.npy", "truncated"});
    write_bytes(dir / "cut.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                 "property float y\nend_header\n12345678");
    expect_failure(dir, "query cut.ply -r 1 -o out.csv", 1, {"cut.ply", "truncated", "item 1 of 3"});
    expect_failure(dir, "query missing.npy -r 1 -o out.npy", 1, {"missing.npy", "cannot open"});
    expect_failure(dir, "query p.npy --queries missing.csv -r 1", 1, {"missing.csv"});
}

TEST_F(cli_errors, query_dimension_mismatch) {
    expect_failure(dir, "query p.npy --queries flat.csv -r 1 -o out.npy", 1, {"flat.csv", "2-D", "3-D"});
}

TEST_F(cli_errors, failed_write_leaves_no_file) {
    expect_failure(dir, "query p.npy -r 1 -o no/such/folder/out.npy", 1, {"no/such/folder/out.npy"});
}

TEST_F(cli_errors, failure_keeps_the_previous_output) {
    write_bytes(dir / "out.npy", "previous result");
    write_bytes(dir / "bad.csv", "1,2,3\n4,5\n");
    expect_failure(dir, "query bad.csv -r 1 -o out.npy", 1, {"bad.csv", "line 2"});
    EXPECT_EQ(read_bytes(dir / "out.npy"), "previous result");
}

TEST_F(cli_errors, help_exits_0) {
    const tool_result r = run_tool(dir, "query --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("--radius"), std::string::npos);
}

}  // namespace
}  // namespace frnn::test
