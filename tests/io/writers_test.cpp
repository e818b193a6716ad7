// The writers: generic npy arrays, pairs as npy and csv, CSR lists as npz (read back by an
// independent zip reader, and by Python when available), files assembled from separately
// encoded row blocks (as the ranks of a distributed query write them), and the all-or-nothing
// output file.
#include <cstdlib>

#include "frnn/brute_force.hpp"
#include "frnn/io/write.hpp"
#include "io/test_files.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/io/neighbor_file.hpp"

namespace frnn::test {
namespace {

// Neighbor lists of a small random set, from the brute-force oracle (full, sorted by index).
template <class T>
csr<T> sample_lists(bool self = false) {
    std::vector<T> xyz;
    std::uint32_t state = 12345;
    for (int k = 0; k < 3 * 40; ++k) {
        state = state * 1664525u + 1013904223u;
        xyz.push_back(T(state >> 8) / T(1 << 24) * 3);
    }
    csr<T> lists = brute_force_lists<T, 3>(xyz, xyz, T(0.8), !self);
    EXPECT_GT(lists.size(), 40u);
    return lists;
}

template <class U>
void npy_round_trip(std::string_view descr) {
    const auto dir = fresh_dir();
    const std::vector<U> v = {U(1), U(2), U(3), U(4), U(5), U(7)};
    const std::uint64_t shape[2] = {3, 2};
    io::write_npy<U>(dir / "a.npy", v, shape);
    EXPECT_EQ(npy_values<U>(read_bytes(dir / "a.npy"), descr, {3, 2}), v);
    io::write_npy<U>(dir / "b.npy", v);
    EXPECT_EQ(npy_values<U>(read_bytes(dir / "b.npy"), descr, {6}), v);
}

TEST(npy_write, float32) { npy_round_trip<float>("<f4"); }
TEST(npy_write, float64) { npy_round_trip<double>("<f8"); }
TEST(npy_write, int32) { npy_round_trip<std::int32_t>("<i4"); }
TEST(npy_write, int64) { npy_round_trip<std::int64_t>("<i8"); }
TEST(npy_write, uint32) { npy_round_trip<std::uint32_t>("<u4"); }
TEST(npy_write, uint64) { npy_round_trip<std::uint64_t>("<u8"); }

TEST(npy_write, empty_array) {
    const auto dir = fresh_dir();
    const auto file = dir / "e.npy";
    io::write_npy<double>(file, std::span<const double>{});
    EXPECT_TRUE(npy_values<double>(read_bytes(file), "<f8", {0}).empty());
}

TEST(npy_write, shape_mismatch_is_an_error_and_writes_nothing) {
    const auto dir = fresh_dir();
    const std::vector<double> v(5);
    const std::uint64_t shape[2] = {2, 3};
    expect_error([&] { io::write_npy<double>(dir / "x.npy", v, shape); }, {"x.npy", "shape holds 6 values"});
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(pairs_write, npy_upper_and_all) {
    const auto dir = fresh_dir();
    for (bool self : {false, true}) {
        const csr<double> lists = sample_lists<double>(self);
        for (bool upper : {true, false}) {
            const auto filter = upper ? io::pair_filter::upper : io::pair_filter::all;
            const auto expected = pairs_of(lists, upper);
            EXPECT_EQ(io::count_pairs(lists, filter), expected.size() / 2);
            io::write_neighbors(dir / "p.npy", lists, filter);
            EXPECT_EQ(npy_values<std::int64_t>(read_bytes(dir / "p.npy"), "<i8", {expected.size() / 2, 2}), expected);
        }
    }
}

template <class T>
void csv_round_trip() {
    const auto dir = fresh_dir();
    const auto file = dir / "p.csv";
    const csr<T> lists = sample_lists<T>();
    io::write_neighbors(file, lists, io::pair_filter::upper);
    const csv_pairs<T> read = parse_csv_pairs<T>(read_bytes(file));
    EXPECT_EQ(read.pairs, pairs_of(lists, true));
    EXPECT_EQ(read.distances, distances_of(lists, true));  // shortest round-trip text: exact
    EXPECT_EQ(read.distances.size(), io::count_pairs(lists, io::pair_filter::upper));
}

TEST(pairs_write, csv_float_round_trips_exactly) { csv_round_trip<float>(); }
TEST(pairs_write, csv_double_round_trips_exactly) { csv_round_trip<double>(); }

TEST(pairs_write, csv_and_npz_need_distances) {
    const auto dir = fresh_dir();
    csr<double> lists = sample_lists<double>();
    lists.distances.clear();
    expect_error([&] { io::write_neighbors(dir / "p.csv", lists, io::pair_filter::all); }, {"p.csv", "distances"});
    expect_error([&] { io::write_neighbors(dir / "p.npz", lists, io::pair_filter::all); }, {"p.npz", "distances"});
    expect_error([&] { io::write_neighbors(dir / "p.txt", lists, io::pair_filter::all); }, {"p.txt", "unknown output"});
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

template <class T>
void npz_round_trip() {
    const auto dir = fresh_dir();
    const auto file = dir / "lists.npz";
    const csr<T> lists = sample_lists<T>(true);
    io::write_csr_npz(file, lists);
    const auto members = read_zip(read_bytes(file));
    ASSERT_EQ(members.size(), 3u);
    const std::uint64_t n = lists.rows(), m = lists.size();
    const auto offsets = npy_values<std::int64_t>(members.at("offsets.npy"), "<i8", {n + 1});
    const auto indices = npy_values<std::int64_t>(members.at("indices.npy"), "<i8", {m});
    const auto distances = npy_values<double>(members.at("distances.npy"), "<f8", {m});
    EXPECT_TRUE(std::equal(offsets.begin(), offsets.end(), lists.offsets.begin(), lists.offsets.end()));
    EXPECT_TRUE(std::equal(indices.begin(), indices.end(), lists.indices.begin(), lists.indices.end()));
    for (std::size_t k = 0; k < m; ++k) EXPECT_EQ(distances[k], double(lists.distances[k]));
}

TEST(npz_write, float_lists_read_back) { npz_round_trip<float>(); }
TEST(npz_write, double_lists_read_back) { npz_round_trip<double>(); }

TEST(npz_write, empty_lists) {
    const auto dir = fresh_dir();
    const auto file = dir / "empty.npz";
    io::write_csr_npz(file, csr<double>{});
    const auto members = read_zip(read_bytes(file));
    ASSERT_EQ(members.size(), 3u);
    EXPECT_EQ(npy_values<std::int64_t>(members.at("offsets.npy"), "<i8", {1}), std::vector<std::int64_t>{0});
    EXPECT_TRUE(npy_values<std::int64_t>(members.at("indices.npy"), "<i8", {0}).empty());
}

TEST(npz_write, python_zipfile_accepts_the_archive) {
    const std::string python = python_with("zipfile");
    if (python.empty()) GTEST_SKIP() << "python3 not available";
    const auto dir = fresh_dir();
    const auto file = dir / "lists.npz";
    io::write_csr_npz(file, sample_lists<double>());
    const std::string check = python + " -c \"import zipfile,sys; z=zipfile.ZipFile(sys.argv[1]); "
                              "assert z.testzip() is None; "
                              "assert sorted(z.namelist())==['distances.npy','indices.npy','offsets.npy']\" '" +
                              file.string() + "'";
    EXPECT_EQ(std::system(check.c_str()), 0);
}

TEST(npz_write, numpy_loads_the_archive) {
    const std::string python = python_with("numpy");
    if (python.empty()) GTEST_SKIP() << "python3 with numpy not available";
    const auto dir = fresh_dir();
    const csr<double> lists = sample_lists<double>();
    io::write_csr_npz(dir / "lists.npz", lists);
    // numpy rebuilds the full pair list, which must match the C++ lists written as npy.
    io::write_neighbors(dir / "pairs.npy", lists, io::pair_filter::all);
    const std::string check =
        python + " -c \"import numpy as np,sys; z=np.load(sys.argv[1]); p=np.load(sys.argv[2]); "
        "o,i,d=z['offsets'],z['indices'],z['distances']; "
        "assert o.dtype==np.int64 and i.dtype==np.int64 and d.dtype==np.float64; "
        "rows=np.repeat(np.arange(len(o)-1),np.diff(o)); "
        "assert (np.stack([rows,i],1)==p).all()\" '" +
        (dir / "lists.npz").string() + "' '" + (dir / "pairs.npy").string() + "'";
    EXPECT_EQ(std::system(check.c_str()), 0);
}

/// Rows [b, e) of `lists` as lists of their own (offsets from 0), as one rank holds them.
template <class T>
csr<T> row_block(const csr<T>& lists, std::size_t b, std::size_t e) {
    csr<T> block;
    block.offsets.resize(e - b + 1);
    for (std::size_t i = b; i <= e; ++i) block.offsets[i - b] = lists.offsets[i] - lists.offsets[b];
    for (std::uint64_t k = lists.offsets[b]; k < lists.offsets[e]; ++k) {
        block.indices.push_back(lists.indices[k]);
        if (!lists.distances.empty()) block.distances.push_back(lists.distances[k]);
    }
    return block;
}

/// The file of `lists` assembled from blocks cut at `cuts` (each encoded alone, with its rows'
/// numbering, its bodies' CRCs combined), as the distributed writer assembles it.
template <class T>
std::string assembled(io::neighbor_format f, const csr<T>& lists, const std::vector<std::size_t>& cuts, io::pair_filter filter) {
    std::vector<csr<T>> blocks;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) blocks.push_back(row_block(lists, cuts[k], cuts[k + 1]));
    std::vector<std::string> bodies(3);
    std::vector<std::uint32_t> crcs;
    for (int m = 0; m < io::member_count(f); ++m) {
        io::checksum sum;
        for (std::size_t k = 0; k < blocks.size(); ++k) {
            const io::row_numbering at{cuts[k], lists.offsets[cuts[k]]};
            std::string bytes = "left from before";
            const bool closes = k + 1 == blocks.size();
            io::encode_rows(bytes, f, m, blocks[k], 0, blocks[k].rows(), at, filter, closes);
            // Every entry of .npz is written: its sizes follow from the block's rows and entries.
            if (f == io::neighbor_format::lists_npz) {
                EXPECT_EQ(io::encoded_size(f, m, blocks[k].rows(), blocks[k].size(), 0, closes), bytes.size()) << "member " << m;
            }
            sum = io::concatenate(sum, io::checksum_of(bytes));
            bodies[std::size_t(m)] += bytes;
        }
        EXPECT_EQ(sum.crc, io::checksum_of(bodies[std::size_t(m)]).crc) << "member " << m;
        crcs.push_back(sum.crc);
    }
    const std::uint64_t entries = f == io::neighbor_format::lists_npz ? lists.size() : io::count_pairs(lists, filter);
    for (int m = 0; m < io::member_count(f); ++m) {
        const auto size = io::encoded_size(f, m, lists.rows(), lists.size(), io::count_pairs(lists, filter), true);
        if (f == io::neighbor_format::pairs_csv) {
            EXPECT_FALSE(size.has_value());
        } else {
            EXPECT_EQ(size, bodies[std::size_t(m)].size()) << "member " << m;
        }
    }
    const io::neighbor_frame frame = io::frame_of(f, "assembled", lists.rows(), entries, crcs);
    std::string file;
    for (int m = 0; m < io::member_count(f); ++m) file += frame.before[std::size_t(m)] + bodies[std::size_t(m)];
    return file + frame.after;
}

TEST(neighbor_file, blocks_encoded_apart_make_the_written_file) {
    const auto dir = fresh_dir();
    const csr<float> lists = sample_lists<float>();
    const std::size_t n = lists.rows();
    // One block; even cuts; empty blocks at the start, inside and at the end; single rows.
    const std::vector<std::vector<std::size_t>> cuttings = {
        {0, n}, {0, n / 3, 2 * n / 3, n}, {0, 0, 5, 5, 6, n - 1, n, n}, {0, 1, 2, 3, n}};
    for (const char* name : {"out.npy", "out.csv", "out.npz"}) {
        for (io::pair_filter filter : {io::pair_filter::upper, io::pair_filter::all}) {
            io::write_neighbors(dir / name, lists, filter);
            const std::string written = read_bytes(dir / name);
            for (const auto& cuts : cuttings)
                EXPECT_TRUE(assembled(io::neighbor_format_of(name), lists, cuts, filter) == written)
                    << name << " cut into " << cuts.size() - 1 << " blocks";
        }
    }
    csr<float> none;
    io::write_csr_npz(dir / "none.npz", none);
    EXPECT_TRUE(assembled(io::neighbor_format::lists_npz, none, {0, 0, 0}, io::pair_filter::all) == read_bytes(dir / "none.npz"));
}

TEST(neighbor_file, unknown_extension_names_the_file) {
    expect_error([] { io::neighbor_format_of("out.txt"); }, {"out.txt", "unknown output extension '.txt'"});
}

TEST(output_file, commit_renames_and_abandon_leaves_nothing) {
    const auto dir = fresh_dir();
    const auto target = dir / "out.bin";
    {
        io::output_file out(target);
        out.write("partial");
        EXPECT_FALSE(std::filesystem::exists(target));
    }  // destroyed without commit, as after an exception
    EXPECT_TRUE(std::filesystem::is_empty(dir));

    write_bytes(target, "old");
    {
        io::output_file out(target);
        out.write("new data");
    }
    EXPECT_EQ(read_bytes(target), "old");  // a failed write keeps the previous file
    {
        io::output_file out(target);
        out.write("new data");
        out.patch(0, "N", 1);
        out.write("!");
        out.commit();
    }
    EXPECT_EQ(read_bytes(target), "New data!");
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
}

TEST(output_file, missing_folder_names_the_target) {
    expect_error([] { io::output_file out("/nonexistent/frnn/out.npy"); },
                 {"/nonexistent/frnn/out.npy", "cannot create"});
}

}  // namespace
}  // namespace frnn::test
