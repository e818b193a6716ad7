// The slab schedule of half-stencil count sweeps: slabs swept at the same time never write the
// same counts, and every layer is swept once.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/slab_schedule.hpp"

namespace {

using frnn::detail::layer_slab;
using frnn::detail::slab_rounds;

// The layers whose counts a sweep of `s` adds to: its own and `reach` more, wrapping around
// in a periodic box.
std::set<std::size_t> written_layers(const layer_slab& s, std::size_t reach, std::size_t layers, bool periodic) {
    std::set<std::size_t> out;
    for (std::size_t z = s.begin; z < s.end + reach; ++z) {
        if (z < layers) out.insert(z);
        else if (periodic) out.insert(z % layers);
    }
    return out;
}

TEST(slab_schedule, concurrent_slabs_never_write_the_same_layer_and_every_layer_is_swept_once) {
    for (bool periodic : {false, true}) {
        for (std::size_t reach = 1; reach <= 4; ++reach) {
            // A periodic box is swept this way only with at least 2 reach + 1 layers.
            for (std::size_t layers = periodic ? 2 * reach + 1 : 1; layers <= 90; ++layers) {
                for (int threads : {1, 2, 3, 8}) {
                    const std::string what = "periodic=" + std::to_string(periodic) + " reach=" + std::to_string(reach) +
                                             " layers=" + std::to_string(layers) + " threads=" + std::to_string(threads);
                    const auto rounds = slab_rounds(layers, reach, threads, periodic);
                    std::size_t slabs = 0;
                    std::vector<int> swept(layers, 0);
                    for (const auto& round : rounds) {
                        ASSERT_FALSE(round.empty()) << what;
                        for (std::size_t a = 0; a < round.size(); ++a) {
                            ++slabs;
                            ASSERT_LT(round[a].begin, round[a].end) << what;
                            for (std::size_t z = round[a].begin; z < round[a].end; ++z) ++swept[z];
                            const auto wa = written_layers(round[a], reach, layers, periodic);
                            for (std::size_t b = a + 1; b < round.size(); ++b) {
                                for (auto z : written_layers(round[b], reach, layers, periodic))
                                    EXPECT_EQ(wa.count(z), 0u) << what << ": layer " << z << " written by two slabs of one round";
                            }
                        }
                    }
                    for (std::size_t z = 0; z < layers; ++z) EXPECT_EQ(swept[z], 1) << what << ": layer " << z;
                    if (slabs > 1) {
                        for (const auto& round : rounds)
                            for (const auto& s : round) EXPECT_GE(s.end - s.begin, reach) << what;
                    }
                }
            }
        }
    }
}

TEST(slab_schedule, odd_slab_counts_in_a_periodic_box_take_a_third_round) {
    // 3 slabs of 1 layer: the last reaches into the first, so it cannot go with it.
    const auto rounds = slab_rounds(3, 1, 1, true);
    ASSERT_EQ(rounds.size(), 3u);
    EXPECT_EQ(rounds[2].size(), 1u);
    EXPECT_EQ(rounds[2][0].begin, 2u);
    EXPECT_EQ(slab_rounds(3, 1, 1, false).size(), 2u);
}

}  // namespace
