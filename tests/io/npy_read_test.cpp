// The npy point reader: dtypes, shapes, orders, versions, and every malformed header or body.
#include <cmath>
#include <random>

#include "frnn/io/read.hpp"
#include "frnn/io/write.hpp"
#include "io/test_files.hpp"

namespace frnn::test {
namespace {

template <class T>
std::vector<T> random_values(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-100, 100);
    std::vector<T> v(n);
    for (auto& x : v) x = T(u(rng));
    return v;
}

template <class T>
std::string raw(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <class T>
void round_trip(int dim) {
    const auto dir = fresh_dir();
    const auto coords = random_values<T>(17 * std::size_t(dim), 7);
    const std::uint64_t shape[2] = {17, std::uint64_t(dim)};
    io::write_npy<T>(dir / "p.npy", coords, shape);
    const io::point_set p = io::read_points(dir / "p.npy");
    EXPECT_EQ(p.dimension, dim);
    EXPECT_EQ(p.size(), 17u);
    EXPECT_EQ(p.type(), sizeof(T) == 4 ? io::precision::f32 : io::precision::f64);
    EXPECT_EQ(std::get<std::vector<T>>(p.coords), coords);
}

TEST(npy_read, round_trip_float_2d) { round_trip<float>(2); }
TEST(npy_read, round_trip_float_3d) { round_trip<float>(3); }
TEST(npy_read, round_trip_double_2d) { round_trip<double>(2); }
TEST(npy_read, round_trip_double_3d) { round_trip<double>(3); }

TEST(npy_read, fortran_order_is_transposed) {
    const auto dir = fresh_dir();
    const std::vector<double> columns = {0, 1, 2, 3, 10, 11, 12, 13, 20, 21, 22, 23};  // x..., y..., z...
    write_bytes(dir / "f.npy",
                npy_bytes("{'descr': '<f8', 'fortran_order': True, 'shape': (4, 3), }", raw(columns)));
    const io::point_set p = io::read_points(dir / "f.npy");
    ASSERT_EQ(p.size(), 4u);
    const auto& c = std::get<std::vector<double>>(p.coords);
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t a = 0; a < 3; ++a) EXPECT_EQ(c[i * 3 + a], columns[a * 4 + i]);
}

// The slices of MPI ranks: consecutive, nearly equal, together the whole file, in C and
// Fortran order; a NaN is named by its index in the file.
TEST(npy_read, slices_cover_the_file_in_both_orders) {
    const auto dir = fresh_dir();
    const std::vector<double> c = random_values<double>(7 * 3, 9);
    std::vector<double> columns(c.size());
    for (std::size_t i = 0; i < 7; ++i)
        for (std::size_t a = 0; a < 3; ++a) columns[a * 7 + i] = c[i * 3 + a];
    write_bytes(dir / "c.npy", npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (7, 3), }", raw(c)));
    write_bytes(dir / "f.npy", npy_bytes("{'descr': '<f8', 'fortran_order': True, 'shape': (7, 3), }", raw(columns)));
    for (const char* file : {"c.npy", "f.npy"})
        for (std::uint64_t parts : {1, 2, 3, 4, 9}) {
            std::vector<double> joined;
            for (std::uint64_t k = 0; k < parts; ++k) {
                const io::point_slice s = io::read_npy_slice(dir / file, k, parts);
                EXPECT_EQ(s.total, 7u);
                EXPECT_EQ(s.first, 7 * k / parts);
                EXPECT_EQ(s.points.size(), 7 * (k + 1) / parts - 7 * k / parts);
                const auto& v = std::get<std::vector<double>>(s.points.coords);
                joined.insert(joined.end(), v.begin(), v.end());
            }
            EXPECT_EQ(joined, c) << file << " in " << parts << " slices";
        }
    std::vector<double> bad = c;
    bad[5 * 3 + 1] = std::nan("");
    write_bytes(dir / "n.npy", npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (7, 3), }", raw(bad)));
    EXPECT_NO_THROW((void)io::read_npy_slice(dir / "n.npy", 0, 2));
    expect_error([&] { (void)io::read_npy_slice(dir / "n.npy", 1, 2); }, {"n.npy", "point 5 has a non-finite coordinate"});
}

TEST(npy_read, version_2_header_and_double_quotes) {
    const auto dir = fresh_dir();
    const std::vector<float> v = {1, 2, 3, 4};
    std::string dict = "{\"descr\": \"<f4\", \"shape\": (2, 2), \"fortran_order\": False}";
    dict += std::string(64 - (12 + dict.size() + 1) % 64, ' ') + "\n";
    std::string bytes = "\x93NUMPY";
    bytes += char(2);
    bytes += char(0);
    put(bytes, std::uint32_t(dict.size()));
    write_bytes(dir / "v2.npy", bytes + dict + raw(v));
    const io::point_set p = io::read_points(dir / "v2.npy");
    EXPECT_EQ(p.dimension, 2);
    EXPECT_EQ(std::get<std::vector<float>>(p.coords), v);
}

TEST(npy_read, files_written_by_numpy) {
    const std::string python = python_with("numpy");
    if (python.empty()) GTEST_SKIP() << "python3 with numpy not available";
    const auto dir = fresh_dir();
    // Value of point i, axis a: i + a / 4 (exact in float and double).
    const std::string script = python + " -c \"import numpy as np,sys; d=sys.argv[1]; "
        "v=lambda n,k: np.arange(n)[:,None]+np.arange(k)[None,:]/4; "
        "np.save(d+'/c.npy', v(5,3).astype(np.float32)); "
        "np.save(d+'/f.npy', np.asfortranarray(v(4,2))); "
        "np.save(d+'/e.npy', np.zeros((0,2)))\" '" + dir.string() + "'";
    ASSERT_EQ(std::system(script.c_str()), 0);
    const io::point_set c = io::read_points(dir / "c.npy"), f = io::read_points(dir / "f.npy");
    ASSERT_EQ(c.type(), io::precision::f32);
    ASSERT_EQ(f.type(), io::precision::f64);
    ASSERT_EQ(c.size(), 5u);
    ASSERT_EQ(f.size(), 4u);
    for (std::size_t i = 0; i < 5; ++i)
        for (std::size_t a = 0; a < 3; ++a) EXPECT_EQ(std::get<std::vector<float>>(c.coords)[i * 3 + a], i + a / 4.f);
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t a = 0; a < 2; ++a) EXPECT_EQ(std::get<std::vector<double>>(f.coords)[i * 2 + a], i + a / 4.);
    EXPECT_EQ(io::read_points(dir / "e.npy").size(), 0u);
}

TEST(npy_read, zero_points) {
    const auto dir = fresh_dir();
    write_bytes(dir / "e.npy", npy_bytes("{'descr': '<f8', 'fortran_order': False, 'shape': (0, 3), }", ""));
    const io::point_set p = io::read_points(dir / "e.npy");
    EXPECT_EQ(p.size(), 0u);
    EXPECT_EQ(p.dimension, 3);
}

// Writes an npy file with `dict` and `data`, and expects the reader to fail naming the file
// and every part.
void expect_bad(const std::string& dict, std::string_view data, std::initializer_list<std::string_view> parts,
                std::string_view whole = {}) {
    const auto dir = fresh_dir();
    const auto file = dir / "bad.npy";
    write_bytes(file, whole.empty() ? npy_bytes(dict, data) : whole);
    expect_error([&] { io::read_points(file); }, parts);
    expect_error([&] { io::read_points(file); }, {file.string()});
}

const std::string f8_3 = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";

TEST(npy_read, truncated_data) {
    expect_bad(f8_3, std::string(40, '\0'), {"truncated", "needs 48 bytes", "has 40"});
}
TEST(npy_read, trailing_bytes) { expect_bad(f8_3, std::string(49, '\0'), {"1 unexpected bytes after the data"}); }
TEST(npy_read, bad_magic) { expect_bad("", "", {"byte 0", "not an npy file"}, "PK\x03\x04 not numpy at all"); }
TEST(npy_read, empty_file) {
    const auto dir = fresh_dir();
    const auto file = dir / "empty.npy";
    write_bytes(file, "");
    expect_error([&] { io::read_points(file); }, {file.string(), "not an npy file"});
}
TEST(npy_read, truncated_header) {
    expect_bad("", "", {"header truncated"}, npy_bytes(f8_3, "").substr(0, 40));
}
TEST(npy_read, unsupported_version) {
    std::string bytes = npy_bytes(f8_3, std::string(48, '\0'));
    bytes[6] = 9;
    expect_bad("", "", {"byte 6", "version 9"}, bytes);
}
TEST(npy_read, header_not_a_dict) { expect_bad("[1, 2]", "", {"npy header", "expected '{'"}); }
TEST(npy_read, header_missing_key) {
    expect_bad("{'descr': '<f8', 'shape': (2, 3), }", std::string(48, '\0'), {"missing key 'fortran_order'"});
}
TEST(npy_read, header_unknown_key) {
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), 'x': 1}", "", {"unexpected key 'x'"});
}
TEST(npy_read, header_bad_shape) {
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (2, -3), }", "", {"byte", "non-negative integer"});
}
TEST(npy_read, header_bad_bool) {
    expect_bad("{'descr': '<f8', 'fortran_order': 0, 'shape': (2, 3), }", "", {"True or False"});
}
TEST(npy_read, header_unterminated_string) { expect_bad("{'descr: 1", "", {"unterminated string"}); }
TEST(npy_read, one_dimensional_shape) {
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (6,), }", std::string(48, '\0'),
               {"shape (6,) is not (N, 2) or (N, 3)"});
}
TEST(npy_read, four_columns) {
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4), }", std::string(64, '\0'),
               {"shape (2, 4)"});
}
TEST(npy_read, three_dimensional_shape) {
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2, 3), }", std::string(48, '\0'),
               {"shape (1, 2, 3)"});
}
TEST(npy_read, integer_dtype) {
    expect_bad("{'descr': '<i8', 'fortran_order': False, 'shape': (2, 3), }", std::string(48, '\0'),
               {"dtype '<i8' is not supported"});
}
TEST(npy_read, big_endian_dtype) {
    expect_bad("{'descr': '>f8', 'fortran_order': False, 'shape': (2, 3), }", std::string(48, '\0'),
               {"'>f8'", "big-endian"});
}
TEST(npy_read, nan_names_the_point) {
    std::vector<double> v(12, 1.0);
    v[10] = std::nan("");
    expect_bad("{'descr': '<f8', 'fortran_order': False, 'shape': (4, 3), }", raw(v), {"point 3", "non-finite"});
}
TEST(npy_read, infinity_in_fortran_order_names_the_point) {
    std::vector<float> v(8, 1.0f);
    v[5] = INFINITY;  // column y, row 1
    expect_bad("{'descr': '<f4', 'fortran_order': True, 'shape': (4, 2), }", raw(v), {"point 1", "non-finite"});
}
TEST(npy_read, missing_file) {
    expect_error([] { io::read_points("/nonexistent/frnn/points.npy"); },
                 {"/nonexistent/frnn/points.npy", "cannot open"});
}
TEST(npy_read, unknown_extension) {
    expect_error([] { io::read_points("points.dat"); }, {"points.dat", "unknown point file extension"});
    EXPECT_FALSE(io::is_point_file("points.dat"));
    EXPECT_TRUE(io::is_point_file("POINTS.NPY"));
}

}  // namespace
}  // namespace frnn::test
