// Small helpers shared by the readers and writers: file slurping, messages, number parsing.
#pragma once
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "frnn/error.hpp"

namespace frnn::io::detail {

/// Throws frnn::error "<name>: <what>".
[[noreturn]] void fail(std::string_view name, const std::string& what);
/// The whole file as bytes; throws naming the file when it cannot be opened or read.
std::string read_file(const std::filesystem::path& file);
/// The extension, lower case, with its dot (".npy").
std::string lower_extension(const std::filesystem::path& file);

/// Parses a whole token as a number (a leading '+' allowed); false when it is not one.
/// "nan" and "inf" parse: the caller rejects them with the point index.
inline bool parse_number(std::string_view token, double& out) {
    if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
    const char* end = token.data() + token.size();
    const auto r = std::from_chars(token.data(), end, out);
    return r.ec == std::errc() && r.ptr == end;
}

/// Index of the first non-finite value of `values`, or values.size().
template <class T>
std::size_t first_non_finite(std::span<const T> values) {
    for (std::size_t k = 0; k < values.size(); ++k)
        if (!std::isfinite(values[k])) return k;
    return values.size();
}

/// Throws naming the point index when a coordinate is not finite; `first_point` is the index of
/// the first point of `coords` in its file.
template <class T>
void check_finite(std::span<const T> coords, int dimension, std::string_view name, std::uint64_t first_point = 0) {
    const std::size_t k = first_non_finite(coords);
    if (k == coords.size()) return;
    fail(name, "point " + std::to_string(first_point + k / std::size_t(dimension)) +
                   " has a non-finite coordinate (" + std::to_string(coords[k]) + ")");
}

}  // namespace frnn::io::detail
