// The ply point reader: ascii and binary, vertex property types, skipped elements, bad files.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <random>

#include "frnn/io/read.hpp"
#include "io/test_files.hpp"

namespace frnn::test {
namespace {

const std::vector<double> expected3 = {1.5, -2, 3.25, 4, 5.5, -6, 0.125, 8, 9};

TEST(ply_read, ascii_float_xyz_with_other_properties_and_elements) {
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment made by hand\nobj_info test\n"
        "element camera 2\nproperty list uchar int tags\nproperty float k\n"
        "element vertex 3\nproperty uchar red\nproperty float x\nproperty float y\nproperty float z\n"
        "property list uchar float extra\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "3 10 11 12 0.5\n0 1e3\n"
        "255 1.5 -2 3.25 2 7 7\n0 4 5.5 -6 0\n12 0.125 8 9 1 0.5\n"
        "3 0 1 2\n";
    const io::point_set p = io::parse_ply_points(ply, "a.ply");
    EXPECT_EQ(p.dimension, 3);
    ASSERT_EQ(p.type(), io::precision::f32);
    const auto& c = std::get<std::vector<float>>(p.coords);
    ASSERT_EQ(c.size(), 9u);
    for (std::size_t k = 0; k < 9; ++k) EXPECT_EQ(c[k], float(expected3[k]));
}

TEST(ply_read, ascii_double_two_dimensional_with_crlf) {
    const std::string ply =
        "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty double y\r\nproperty double x\r\nend_header\r\n"
        "1 2\r\n3 4\r\n";
    const io::point_set p = io::parse_ply_points(ply, "b.ply");
    EXPECT_EQ(p.dimension, 2);
    EXPECT_EQ(std::get<std::vector<double>>(p.coords), (std::vector<double>{2, 1, 4, 3}));
}

TEST(ply_read, integer_and_mixed_properties_read_as_double) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty int x\nproperty short y\nproperty float z\nend_header\n"
        "1 -2 0.5\n-30000 7 1\n";
    const io::point_set p = io::parse_ply_points(ply, "c.ply");
    EXPECT_EQ(std::get<std::vector<double>>(p.coords), (std::vector<double>{1, -2, 0.5, -30000, 7, 1}));
}

TEST(ply_read, zero_vertices) {
    const io::point_set p = io::parse_ply_points(
        "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n", "d.ply");
    EXPECT_EQ(p.size(), 0u);
}

// A binary ply: a leading element with a list, then vertices of (uchar tag, double x, float y,
// int16 z, list of uint16), then faces.
std::string binary_ply(bool big) {
    auto put_any = [big](std::string& s, auto v) {
        put(s, v);
        if (big) std::reverse(s.end() - sizeof v, s.end());
    };
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement meta 2\nproperty list uint8 int32 ids\nproperty double w\n"
                    "element vertex 3\nproperty uchar tag\nproperty double x\nproperty float y\n"
                    "property int16 z\nproperty list uint8 uint16 more\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int m = 0; m < 2; ++m) {
        put_any(s, std::uint8_t(m + 1));
        for (int k = 0; k <= m; ++k) put_any(s, std::int32_t(k));
        put_any(s, 0.5);
    }
    const double xs[3] = {1.5, 4, 0.125};
    const float ys[3] = {-2, 5.5, 8};
    const std::int16_t zs[3] = {3, -6, 9};
    for (int v = 0; v < 3; ++v) {
        put_any(s, std::uint8_t(v));
        put_any(s, xs[v]);
        put_any(s, ys[v]);
        put_any(s, zs[v]);
        put_any(s, std::uint8_t(v));
        for (int k = 0; k < v; ++k) put_any(s, std::uint16_t(k));
    }
    put_any(s, std::uint8_t(3));
    for (int k = 0; k < 3; ++k) put_any(s, std::int32_t(k));
    return s;
}

TEST(ply_read, binary_little_endian) {
    const io::point_set p = io::parse_ply_points(binary_ply(false), "e.ply");
    ASSERT_EQ(p.type(), io::precision::f64);
    EXPECT_EQ(std::get<std::vector<double>>(p.coords), (std::vector<double>{1.5, -2, 3, 4, 5.5, -6, 0.125, 8, 9}));
}

TEST(ply_read, binary_big_endian) {
    const io::point_set p = io::parse_ply_points(binary_ply(true), "f.ply");
    EXPECT_EQ(std::get<std::vector<double>>(p.coords), (std::vector<double>{1.5, -2, 3, 4, 5.5, -6, 0.125, 8, 9}));
}

TEST(ply_read, binary_float_file_reads_as_float) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n";
    for (float v : {1.f, 2.f, 3.f, 4.f, 5.f, 6.f}) put(s, v);
    const auto dir = fresh_dir();
    const auto file = dir / "g.ply";
    write_bytes(file, s);
    const io::point_set p = io::read_points(file);
    EXPECT_EQ(std::get<std::vector<float>>(p.coords), (std::vector<float>{1, 2, 3, 4, 5, 6}));
}

void expect_bad(std::string_view bytes, std::initializer_list<std::string_view> parts) {
    expect_error([&] { io::parse_ply_points(bytes, "bad.ply"); }, parts);
    expect_error([&] { io::parse_ply_points(bytes, "bad.ply"); }, {"bad.ply: "});
}

const std::string ascii_head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                               "property float z\nend_header\n";

TEST(ply_read, truncated_binary) {
    const std::string whole = binary_ply(false);
    expect_bad(whole.substr(0, whole.size() - 20), {"data truncated", "element 'vertex' item 2 of 3"});
    expect_bad(whole.substr(0, whole.find("end_header") + 11 + 6), {"element 'meta' item 0 of 2"});
}
TEST(ply_read, missing_vertex_property) {
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\nend_header\n1 2\n",
               {"line 3", "no property 'y'"});
}
TEST(ply_read, vertex_coordinate_is_a_list) {
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\nend_header\n",
               {"line 3", "'x' is a list"});
}
TEST(ply_read, no_vertex_element) {
    expect_bad("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int v\nend_header\n", {"no 'vertex' element"});
}
TEST(ply_read, ascii_bad_number) {
    expect_bad(ascii_head + "1 2 3\n4 five 6\n", {"line 9", "item 1 of 2", "property 'y'", "'five'"});
}
TEST(ply_read, ascii_end_of_file) { expect_bad(ascii_head + "1 2 3\n4 5\n", {"item 1 of 2", "property 'z'", "end of file"}); }
TEST(ply_read, ascii_nan) { expect_bad(ascii_head + "1 2 3\n4 nan 6\n", {"vertex 1", "non-finite"}); }
// A float property's ascii value beyond float's range (found by the points fuzzer: it read as inf).
TEST(ply_read, ascii_value_beyond_float) {
    expect_bad(ascii_head + "1 2 3\n4 1e39 6\n", {"vertex 1", "1e+39", "beyond the range"});
    expect_bad(ascii_head + "1 -3.5e38 3\n4 5 6\n", {"vertex 0", "beyond the range"});
}
TEST(ply_read, not_a_ply) { expect_bad("solid stl\n", {"line 1", "not a ply file"}); }
TEST(ply_read, empty) { expect_bad("", {"line 1", "not a ply file"}); }
TEST(ply_read, no_end_header) { expect_bad("ply\nformat ascii 1.0\nelement vertex 0\n", {"line 4", "without 'end_header'"}); }
TEST(ply_read, unknown_format) { expect_bad("ply\nformat binary_middle_endian 1.0\nend_header\n", {"line 2", "unknown format"}); }
TEST(ply_read, missing_format) { expect_bad("ply\nelement vertex 0\nend_header\n", {"missing 'format'"}); }
TEST(ply_read, unknown_type) {
    expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", {"line 4", "property <type> <name>"});
}
TEST(ply_read, property_before_element) {
    expect_bad("ply\nformat ascii 1.0\nproperty float x\nend_header\n", {"line 3", "before any element"});
}
TEST(ply_read, bad_element_count) {
    expect_bad("ply\nformat ascii 1.0\nelement vertex -4\nend_header\n", {"line 3", "element <name> <count>"});
}
TEST(ply_read, unknown_keyword) { expect_bad("ply\nformat ascii 1.0\nvertices 3\nend_header\n", {"line 3", "'vertices'"}); }
TEST(ply_read, bad_list_length) {
    expect_bad("ply\nformat ascii 1.0\nelement a 1\nproperty list int int v\nelement vertex 0\nproperty float x\n"
               "property float y\nend_header\n-2\n",
               {"element 'a' item 0", "bad list length"});
}
TEST(ply_read, ascii_integers_must_fit_their_type) {
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 1\nproperty uchar x\nproperty short y\nend_header\n";
    expect_bad(head + "300 1\n", {"line 7", "property 'x'", "'300' is not a uchar"});
    expect_bad(head + "3 1.5\n", {"line 7", "property 'y'", "'1.5' is not a short"});
    expect_bad(head + "3 -40000\n", {"'-40000' is not a short"});
    expect_bad(head + "-1 2\n", {"'-1' is not a uchar"});
    expect_bad(head + "nan 2\n", {"'nan' is not a uchar"});
    // A list count far beyond 2^64 (found by the fuzzer: its conversion was undefined).
    expect_bad("ply\nformat ascii 1.0\nelement a 1\nproperty list uchar int v\nelement vertex 0\nproperty float x\n"
               "property float y\nend_header\n" + std::string(58, '4') + " 1 2\n",
               {"element 'a' item 0", "property 'v'", "is not a uchar"});
}

// Read in slices of vertices (one per MPI rank): the points and the first error of the whole.

/// Appends v's bytes, in big-endian order when asked.
template <class V>
void put(std::string& out, V v, bool big) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if (big) std::reverse(b, b + sizeof v);
    out.append(b, sizeof v);
}

/// A random binary .ply: an element before the vertices (scalars, or with a list: not
/// sliceable), vertices with x, y, maybe z of float, double or int among other properties, an
/// element after them; now and then a NaN coordinate or a file cut short.
std::string random_binary_ply(std::mt19937& rng, bool& sliceable) {
    auto pick = [&](int n) { return int(rng() % unsigned(n)); };
    const bool big = pick(2) == 1;
    const bool list_before = pick(5) == 0;
    sliceable = !list_before;
    const int before = pick(3), n = pick(40), dim = 2 + pick(2);
    const char* types[] = {"float", "double", "int"};
    const int coord_type = pick(3);
    std::string ply = std::string("ply\nformat binary_") + (big ? "big" : "little") + "_endian 1.0\n";
    ply += "element meta " + std::to_string(before) + "\nproperty uchar a\n";
    if (list_before) ply += "property list uchar int l\n";
    ply += "property double b\nelement vertex " + std::to_string(n) + "\nproperty uchar red\n";
    for (int a = 0; a < dim; ++a) ply += std::string("property ") + types[coord_type] + " " + "xyz"[a] + "\n";
    ply += "property int id\nelement face 1\nproperty list uchar int v\nend_header\n";
    for (int k = 0; k < before; ++k) {
        put(ply, std::uint8_t(k), big);
        if (list_before) {
            put(ply, std::uint8_t(2), big);
            put(ply, std::int32_t(7), big);
            put(ply, std::int32_t(8), big);
        }
        put(ply, 0.5 * k, big);
    }
    const int nan_at = pick(4) == 0 && coord_type != 2 ? pick(n + 1) : -1;
    for (int k = 0; k < n; ++k) {
        put(ply, std::uint8_t(k), big);
        for (int a = 0; a < dim; ++a) {
            const double x = k == nan_at && a == dim - 1 ? NAN : pick(2001) - 1000 + 0.25 * pick(4);
            if (coord_type == 0) put(ply, float(x), big);
            else if (coord_type == 1) put(ply, x, big);
            else put(ply, std::int32_t(x), big);
        }
        put(ply, std::int32_t(k), big);
    }
    put(ply, std::uint8_t(0), big);  // the face: an empty list
    if (pick(4) == 0) ply.resize(ply.size() - std::size_t(pick(int(std::min<std::size_t>(ply.size(), 60)))));
    return ply;
}

TEST(ply_read, slices_give_the_points_and_the_first_error_of_the_whole) {
    const auto dir = fresh_dir();
    const auto file = dir / "p.ply";
    std::mt19937 rng(9);
    int failing = 0, sliced = 0;
    for (int trial = 0; trial < 300; ++trial) {
        bool sliceable = false;
        write_bytes(file, random_binary_ply(rng, sliceable));
        std::string whole_error;
        io::point_set whole;
        try {
            whole = io::read_points(file);
        } catch (const error& e) {
            whole_error = e.what();
        }
        failing += !whole_error.empty();
        for (std::uint64_t parts : {1, 2, 3, 5}) {
            std::string error_message;
            io::point_set joined;
            bool any_slice = false;
            for (std::uint64_t k = 0; k < parts && error_message.empty(); ++k) {
                try {
                    const std::optional<io::point_slice> s = io::read_ply_slice(file, k, parts);
                    if (!s) break;
                    any_slice = true;
                    ASSERT_EQ(s->first, io::slice_start(s->total, k, parts));
                    joined.dimension = s->points.dimension;
                    std::visit([&](const auto& v) {
                        using V = std::decay_t<decltype(v)>;
                        if (k == 0) joined.coords = V{};
                        auto& to = std::get<V>(joined.coords);
                        to.insert(to.end(), v.begin(), v.end());
                    }, s->points.coords);
                } catch (const error& e) {
                    error_message = e.what();
                    any_slice = true;
                }
            }
            // A truncated header or the data before the vertices cut short is read whole too.
            if (!any_slice) continue;
            ASSERT_TRUE(sliceable) << "a file with a list before its vertices was sliced";
            sliced += parts == 2;
            ASSERT_EQ(error_message, whole_error) << "parts " << parts << " trial " << trial;
            if (!whole_error.empty()) continue;
            ASSERT_EQ(joined.dimension, whole.dimension);
            ASSERT_TRUE(joined.coords == whole.coords) << "parts " << parts << " trial " << trial;
        }
    }
    EXPECT_GT(failing, 30);
    EXPECT_GT(sliced, 150);
    // Ascii files are read whole.
    write_bytes(file, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n");
    EXPECT_FALSE(io::read_ply_slice(file, 0, 2).has_value());
    expect_error([&] { io::read_ply_slice(dir / "missing.ply", 0, 2); }, {"missing.ply", "cannot open"});
}

}  // namespace
}  // namespace frnn::test
