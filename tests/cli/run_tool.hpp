// Runs the built frnn binary and collects its exit code, stdout and stderr; writes point files
// in each input format; reads the tool's outputs back.
#pragma once

#include <charconv>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/io/write.hpp"
#include "io/test_files.hpp"
#include "run_command.hpp"

namespace frnn::test {

using tool_result = command_result;

/// Runs `frnn <args>` (args already shell-quoted where needed) in folder `dir`.
inline tool_result run_tool(const std::filesystem::path& dir, const std::string& args) {
    return run_command(dir, "'" FRNN_TOOL_PATH "' " + args);
}

/// n points uniform in [0, side)^D.
template <class T, int D>
std::vector<T> random_points(std::size_t n, double side, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, side);
    std::vector<T> xyz(n * D);
    for (T& x : xyz) x = T(u(rng));
    return xyz;
}

template <class T>
std::string shortest(T v) {
    char buffer[64];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

/// Writes points as .npy, .csv/.txt/.xyz (exact decimal text) or .ply (ascii, or binary with
/// `binary`), chosen by the extension of `file`.
template <class T, int D>
void write_points(const std::filesystem::path& file, const std::vector<T>& xyz, bool binary = false) {
    const std::string ext = file.extension().string();
    const std::size_t n = xyz.size() / D;
    if (ext == ".npy") {
        const std::uint64_t shape[2] = {n, D};
        io::write_npy<T>(file, xyz, shape);
        return;
    }
    std::string s;
    if (ext == ".ply") {
        s = std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") +
            " 1.0\nelement vertex " + std::to_string(n) + "\n";
        for (int a = 0; a < D; ++a)
            s += std::string("property ") + (sizeof(T) == 4 ? "float " : "double ") + "xyz"[a] + "\n";
        s += "end_header\n";
    } else {
        s = D == 3 ? "x,y,z\n" : "x,y\n";
    }
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < D; ++a) {
            if (binary)
                put(s, xyz[i * D + a]);
            else
                s += shortest(xyz[i * D + a]) + (a + 1 < D ? (ext == ".csv" ? "," : " ") : "\n");
        }
    write_bytes(file, s);
}

/// The tool's .npy pair output.
inline std::vector<std::int64_t> read_pairs(const std::filesystem::path& file, std::uint64_t expected_rows) {
    return npy_values<std::int64_t>(read_bytes(file), "<i8", {expected_rows, 2});
}

/// The k nearest of each row (distance, then index), listed by index: the --knn contract.
template <class T>
csr<T> keep_nearest(const csr<T>& lists, std::size_t k) {
    csr<T> out;
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        std::vector<std::pair<T, std::uint32_t>> row;
        for (std::uint64_t e = lists.offsets[i]; e < lists.offsets[i + 1]; ++e)
            row.emplace_back(lists.distances[e], lists.indices[e]);
        std::sort(row.begin(), row.end());
        row.resize(std::min(row.size(), k));
        std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.second < b.second; });
        for (auto [d, j] : row) {
            out.indices.push_back(j);
            out.distances.push_back(d);
        }
        out.offsets.push_back(out.indices.size());
    }
    return out;
}

}  // namespace frnn::test
