// Neighbor lists of one step, taken once from the grid in cell (sorted) order and reused by
// every neighbor loop of the step. The grid fills them in parallel, deterministically.
#pragma once
#include <cstdint>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/grid.hpp"
#include "parallel.hpp"

namespace frnn::sim::detail {

class neighbor_table {
public:
    template <int D>
    void build(const grid<float, D>& g, profiler& prof) {
        serial(prof, stage::neighbors, [&] {
            list_options o;
            o.space = index_space::sorted;
            g.neighbor_lists(lists_, o);  // reuses last step's arrays
        });
    }
    /// Neighbors of sorted particle i: [begin, end).
    const std::uint32_t* begin(std::size_t i) const { return lists_.indices.data() + lists_.offsets[i]; }
    const std::uint32_t* end(std::size_t i) const { return lists_.indices.data() + lists_.offsets[i + 1]; }
    std::size_t pairs() const { return lists_.size(); }
    /// Neighbors of sorted particle i; 0 before the first build.
    std::uint32_t count(std::size_t i) const {
        return i + 1 < lists_.offsets.size() ? std::uint32_t(lists_.offsets[i + 1] - lists_.offsets[i]) : 0;
    }

private:
    csr<float> lists_;
};

}  // namespace frnn::sim::detail
