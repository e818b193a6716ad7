// The order in which half-stencil sweeps (count_pairs) visit the cell layers of a uniform
// grid. A sweep of a slab of layers adds to the counts of points up to `reach` layers past the
// slab (in a periodic box, past the last layer into the first ones), so two slabs swept at the
// same time must never be neighbors.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace frnn::detail {

/// Layers [begin, end) of the grid's last axis.
struct layer_slab {
    std::size_t begin, end;
};

/// Rounds of slabs: the slabs of one round may be swept at the same time, the rounds one
/// after the other. Slabs are at least `reach` layers thick (the last takes the rest), about
/// 32 per thread: even slabs in the first round, odd ones in the second. In a periodic box the
/// last slab reaches into the first, so with an odd number of slabs it makes a third round.
inline std::vector<std::vector<layer_slab>> slab_rounds(std::size_t layers, std::size_t reach, int threads,
                                                        bool periodic) {
    const std::size_t want = std::max<std::size_t>(1, std::size_t(std::max(threads, 1)) * 32);
    const std::size_t thick = std::max<std::size_t>({std::size_t(1), reach, (layers + want - 1) / want});
    const std::size_t slabs = std::max<std::size_t>(1, layers / thick);
    auto slab = [&](std::size_t k) { return layer_slab{k * thick, k + 1 == slabs ? layers : (k + 1) * thick}; };
    const bool last_alone = periodic && slabs > 1 && slabs % 2 == 1;
    const std::size_t paired = last_alone ? slabs - 1 : slabs;
    std::vector<std::vector<layer_slab>> rounds(2);
    for (std::size_t k = 0; k < paired; ++k) rounds[k % 2].push_back(slab(k));
    if (last_alone) rounds.push_back({slab(slabs - 1)});
    if (rounds[1].empty()) rounds.pop_back();
    return rounds;
}

}  // namespace frnn::detail
