// Test support shared by the io and cli tests: a fresh folder per test, byte files, error
// expectations, and independent readers of npy arrays and zip archives (with their own CRC).
#pragma once
#include <gtest/gtest.h>

#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/error.hpp"
#include "frnn/io/read.hpp"
#include "expect_error.hpp"
#include "scratch_dir.hpp"

namespace frnn::test {

/// An empty folder named after the running test, removed when the returned guard goes out of
/// scope (keep it in a variable: `const auto dir = fresh_dir();`).
inline scratch_dir fresh_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
        if (c == '/') c = '_';
    return scratch_dir(name);
}

inline void write_bytes(const std::filesystem::path& file, std::string_view bytes) {
    std::ofstream out(file, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    ASSERT_TRUE(out.good()) << file;
}

inline std::string read_bytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Appends the little-endian bytes of v.
template <class U>
void put(std::string& bytes, U v) {
    char b[sizeof(U)];
    std::memcpy(b, &v, sizeof v);
    bytes.append(b, sizeof b);
}

/// A version-1 npy file with the given dictionary text (not validated) and raw data.
inline std::string npy_bytes(const std::string& dict, std::string_view data) {
    std::string header = dict;
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::string out = "\x93NUMPY";
    out += char(1);
    out += char(0);
    put(out, std::uint16_t(header.size()));
    return out + header + std::string(data);
}

/// An npy array as stored: header fields and values of type U (checked against descr).
template <class U>
std::vector<U> npy_values(std::string_view bytes, std::string_view descr,
                          std::vector<std::uint64_t> shape) {
    const io::npy_header h = io::parse_npy_header(bytes, "test");
    EXPECT_EQ(h.descr, descr);
    EXPECT_EQ(h.shape, shape);
    EXPECT_FALSE(h.fortran_order);
    EXPECT_EQ(h.data_offset % 64, 0u);  // numpy's alignment
    std::vector<U> v(std::size_t(h.count()));
    EXPECT_EQ(bytes.size() - h.data_offset, v.size() * sizeof(U));
    if (!v.empty() && bytes.size() - h.data_offset == v.size() * sizeof(U))
        std::memcpy(v.data(), bytes.data() + h.data_offset, v.size() * sizeof(U));
    return v;
}

/// Pairs (row, neighbor) of lists, flattened, keeping neighbor >= row when `upper`.
template <class T>
std::vector<std::int64_t> pairs_of(const csr<T>& lists, bool upper) {
    std::vector<std::int64_t> pairs;
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint32_t j : lists.row(i))
            if (!upper || j >= i) {
                pairs.push_back(std::int64_t(i));
                pairs.push_back(j);
            }
    return pairs;
}

/// The distances of the same entries as pairs_of.
template <class T>
std::vector<T> distances_of(const csr<T>& lists, bool upper) {
    std::vector<T> d;
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            if (!upper || lists.indices[k] >= i) d.push_back(lists.distances[k]);
    return d;
}

/// A pair csv ("i,j,distance" header, then one line per pair) read back.
template <class T>
struct csv_pairs {
    std::vector<std::int64_t> pairs;
    std::vector<T> distances;
};
template <class T>
csv_pairs<T> parse_csv_pairs(std::string_view text) {
    csv_pairs<T> out;
    EXPECT_EQ(text.substr(0, 13), "i,j,distance\n");
    for (std::size_t pos = 13; pos < text.size();) {
        std::size_t eol = text.find('\n', pos);
        EXPECT_NE(eol, std::string_view::npos) << "last line without newline";
        if (eol == std::string_view::npos) eol = text.size();
        const char* end = text.data() + eol;
        std::int64_t i = -1, j = -1;
        T d = -1;
        const char* p = std::from_chars(text.data() + pos, end, i).ptr;
        if (p < end && *p == ',') p = std::from_chars(p + 1, end, j).ptr;
        if (p < end && *p == ',') p = std::from_chars(p + 1, end, d).ptr;
        EXPECT_EQ(p, end) << "bad line '" << text.substr(pos, eol - pos) << "'";
        out.pairs.push_back(i);
        out.pairs.push_back(j);
        out.distances.push_back(d);
        pos = eol + 1;
    }
    return out;
}

/// Bit-by-bit CRC-32, independent of the library's table version.
inline std::uint32_t slow_crc32(std::string_view s) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : s) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}

template <class U>
U get(std::string_view bytes, std::size_t at) {
    U v{};
    if (at + sizeof(U) <= bytes.size()) std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

/// Members of a stored (uncompressed) zip archive, found through its central directory;
/// checks signatures, sizes and checksums on the way.
inline std::map<std::string, std::string> read_zip(std::string_view zip) {
    std::map<std::string, std::string> members;
    EXPECT_GE(zip.size(), 22u);
    if (zip.size() < 22) return members;
    const std::size_t end = zip.size() - 22;  // no archive comment
    EXPECT_EQ(get<std::uint32_t>(zip, end), 0x06054b50u);
    const std::size_t entries = get<std::uint16_t>(zip, end + 10);
    std::size_t at = get<std::uint32_t>(zip, end + 16);
    EXPECT_EQ(at + get<std::uint32_t>(zip, end + 12), end);
    for (std::size_t e = 0; e < entries && at + 46 <= zip.size(); ++e) {
        EXPECT_EQ(get<std::uint32_t>(zip, at), 0x02014b50u);
        EXPECT_EQ(get<std::uint16_t>(zip, at + 10), 0u);  // stored
        const std::uint32_t crc = get<std::uint32_t>(zip, at + 16);
        const std::uint32_t size = get<std::uint32_t>(zip, at + 24);
        EXPECT_EQ(get<std::uint32_t>(zip, at + 20), size);
        const std::size_t name_length = get<std::uint16_t>(zip, at + 28);
        const std::size_t skip = name_length + get<std::uint16_t>(zip, at + 30) + get<std::uint16_t>(zip, at + 32);
        const std::string name(zip.substr(at + 46, name_length));
        const std::size_t local = get<std::uint32_t>(zip, at + 42);
        EXPECT_EQ(get<std::uint32_t>(zip, local), 0x04034b50u);
        EXPECT_EQ(get<std::uint32_t>(zip, local + 14), crc);
        EXPECT_EQ(get<std::uint32_t>(zip, local + 22), size);
        const std::size_t data = local + 30 + get<std::uint16_t>(zip, local + 26) + get<std::uint16_t>(zip, local + 28);
        EXPECT_EQ(zip.substr(local + 30, name_length), name);
        EXPECT_LE(data + size, zip.size());
        members[name] = std::string(zip.substr(data, size));
        EXPECT_EQ(slow_crc32(members[name]), crc) << name;
        at += 46 + skip;
    }
    return members;
}

/// A Python interpreter that can import `module` ("python3" first, then the system's, which
/// a virtual environment may hide), or "" when there is none: tests then skip.
inline std::string python_with(const std::string& module) {
    for (const char* python : {"python3", "/usr/bin/python3"})
        if (std::system((std::string(python) + " -c 'import " + module + "' >/dev/null 2>&1").c_str()) == 0)
            return python;
    return "";
}

}  // namespace frnn::test
