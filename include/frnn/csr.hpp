// Compressed sparse rows: the result type of neighbor-list queries.
// Row i holds indices[offsets[i] .. offsets[i+1]) and, when requested, their distances.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "frnn/buffer.hpp"

namespace frnn {

template <class T>
struct csr {
    buffer<std::uint64_t> offsets{0};  ///< rows() + 1 entries, offsets[0] == 0
    buffer<std::uint32_t> indices;     ///< neighbor indices, row after row
    buffer<T> distances;               ///< same length as indices, or empty

    std::size_t rows() const { return offsets.size() - 1; }
    std::size_t size() const { return indices.size(); }
    std::span<const std::uint32_t> row(std::size_t i) const {
        return {indices.data() + offsets[i], indices.data() + offsets[i + 1]};
    }
    std::span<const T> row_distances(std::size_t i) const {
        return {distances.data() + offsets[i], distances.data() + offsets[i + 1]};
    }
};

}  // namespace frnn
