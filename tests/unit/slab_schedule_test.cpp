// The slabs of half-stencil count sweeps: they cover every layer once, in order, and the layers
// a slab adds to past its own (its spill) lie wholly in the next slab, or the last slab's in a
// periodic box in the first: the merge of the spills relies on both.
#include <gtest/gtest.h>

#include <string>

#include "core/slab_schedule.hpp"

namespace {

using frnn::detail::layer_slabs;

TEST(slab_schedule, slabs_cover_the_layers_in_order_and_each_spill_lies_in_the_next_slab) {
    for (bool periodic : {false, true}) {
        for (std::size_t reach = 1; reach <= 4; ++reach) {
            // A periodic box is swept this way only with at least 2 reach + 1 layers.
            for (std::size_t layers = periodic ? 2 * reach + 1 : 1; layers <= 300; ++layers) {
                for (int threads : {1, 2, 3, 8}) {
                    const std::string what = "periodic=" + std::to_string(periodic) + " reach=" + std::to_string(reach) +
                                             " layers=" + std::to_string(layers) + " threads=" + std::to_string(threads);
                    const auto slabs = layer_slabs(layers, reach, threads);
                    ASSERT_FALSE(slabs.empty()) << what;
                    EXPECT_LE(slabs.size(), threads <= 1 ? 1u : std::size_t(threads) * 32) << what;
                    EXPECT_EQ(slabs.front().begin, 0u) << what;
                    EXPECT_EQ(slabs.back().end, layers) << what;
                    for (std::size_t k = 0; k < slabs.size(); ++k) {
                        ASSERT_LT(slabs[k].begin, slabs[k].end) << what;
                        if (k > 0) {
                            EXPECT_EQ(slabs[k].begin, slabs[k - 1].end) << what;
                        }
                        if (slabs.size() == 1) continue;
                        const std::size_t spill_end = slabs[k].end + reach;
                        if (k + 1 < slabs.size()) {
                            EXPECT_LE(spill_end, slabs[k + 1].end) << what << " slab " << k;
                        } else if (periodic) {
                            EXPECT_LE(spill_end - layers, slabs[0].end) << what << ": the wrap";
                        }
                    }
                }
            }
        }
    }
}

TEST(slab_schedule, one_thread_sweeps_one_slab_and_more_threads_cut_more) {
    EXPECT_EQ(layer_slabs(100, 1, 1).size(), 1u);
    EXPECT_EQ(layer_slabs(100, 1, 2).size(), 50u);  // 64 wanted, at least 2 layers each
    EXPECT_EQ(layer_slabs(100, 3, 2).size(), 33u);  // 3 layers each, the last takes 4
    EXPECT_EQ(layer_slabs(100, 3, 2).back().begin, 96u);
}

}  // namespace
