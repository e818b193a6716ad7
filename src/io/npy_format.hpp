// The .npy container shared by the npy reader and the npy/npz writers.
#pragma once
#include <cstdint>
#include <span>
#include <type_traits>
#include <string>
#include <string_view>

namespace frnn::io::detail {

/// Magic, version 1.0, header dictionary padded with spaces and '\n' to a multiple of 64 bytes.
std::string make_npy_header(std::string_view descr, std::span<const std::uint64_t> shape);

/// The little-endian descr of T ("<f8", "<i8", ...).
template <class T>
constexpr std::string_view npy_descr() {
    if constexpr (std::is_same_v<T, float>) return "<f4";
    else if constexpr (std::is_same_v<T, double>) return "<f8";
    else if constexpr (std::is_same_v<T, std::int32_t>) return "<i4";
    else if constexpr (std::is_same_v<T, std::int64_t>) return "<i8";
    else if constexpr (std::is_same_v<T, std::uint32_t>) return "<u4";
    else {
        static_assert(std::is_same_v<T, std::uint64_t>, "no npy type for T");
        return "<u8";
    }
}

}  // namespace frnn::io::detail
