// How half-stencil sweeps (count_pairs) of a uniform grid cut its cell layers into slabs that
// run at the same time. A sweep of a slab adds to the counts of points up to `reach` layers past
// it (in a periodic box, past the last layer into the first ones): those it keeps apart, in a
// spill of its own, which the next slab's owner adds in afterwards.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace frnn::detail {

/// Layers [begin, end) of the grid's last axis.
struct layer_slab {
    std::size_t begin, end;
};

/// Consecutive slabs covering [0, layers): one for one thread, else about 32 per thread, each
/// at least `reach` layers thick (the last takes the rest), so that a slab's spill lies wholly
/// in the next slab (the last one's, in a periodic box, in the first).
inline std::vector<layer_slab> layer_slabs(std::size_t layers, std::size_t reach, int threads) {
    const std::size_t want = threads <= 1 ? 1 : std::size_t(threads) * 32;
    const std::size_t thick = std::max<std::size_t>({std::size_t(1), reach, (layers + want - 1) / want});
    const std::size_t slabs = std::max<std::size_t>(1, layers / thick);
    std::vector<layer_slab> out;
    for (std::size_t k = 0; k < slabs; ++k) out.push_back({k * thick, k + 1 == slabs ? layers : (k + 1) * thick});
    return out;
}

}  // namespace frnn::detail
