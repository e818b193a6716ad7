// Walks the pairs a pair_filter keeps from neighbor lists, in row order.
#pragma once
#include <cstdint>

#include "frnn/io/write.hpp"

namespace frnn::io::detail {

/// Calls f(row, neighbor, entry) for each kept entry; `entry` indexes lists.indices.
template <class T, class F>
void for_each_pair(const csr<T>& lists, pair_filter filter, F&& f) {
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            if (filter == pair_filter::all || lists.indices[k] >= i) f(i, lists.indices[k], k);
}

}  // namespace frnn::io::detail
