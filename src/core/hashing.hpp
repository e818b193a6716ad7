// Hash of a row of cells (y, z) for the hashed grid. A cell (x, y, z) lives in slot
// (row_hash(y, z) + x) mod table size, so the cells of one stencil row sit in consecutive slots
// and their points form contiguous runs, as in the uniform grid.
#pragma once
#include <cstdint>

namespace frnn::detail {

inline std::uint64_t row_hash(std::int64_t y, std::int64_t z) {
    std::uint64_t h = std::uint64_t(y) * 0x9E3779B97F4A7C15ull + std::uint64_t(z) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return h;
}

}  // namespace frnn::detail
