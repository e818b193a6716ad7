// The row sort of the sweeps (core/sort_ids_impl.hpp) against std::sort, at the AVX-512 level
// (its sorting network, when this CPU has AVX-512) and at the base level, for every row
// length up to past the network's largest, with distinct and repeated ids.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq,avx2,popcnt,bmi,bmi2")
#define FRNN_SWEEP_BYTES 64
namespace sort_test_avx512 {
#include "core/sort_ids_impl.hpp"
}
#undef FRNN_SWEEP_BYTES
#pragma GCC pop_options

#define FRNN_SWEEP_BYTES 16
namespace sort_test_base {
#include "core/sort_ids_impl.hpp"
}
#undef FRNN_SWEEP_BYTES

namespace {

template <class Sort>
void check_against_std_sort(Sort sort) {
    std::mt19937_64 rng(7);
    for (std::uint32_t n = 0; n <= 200; ++n) {
        for (int trial = 0; trial < 20; ++trial) {
            // Odd trials repeat ids; even ones reach up to the largest id a grid can hold.
            const std::uint32_t top = trial % 2 ? 40u : 0xFFFFFFFEu;
            std::vector<std::uint32_t> ids(n);
            for (auto& v : ids) v = std::uint32_t(rng() % (std::uint64_t(top) + 1));
            auto want = ids;
            std::sort(want.begin(), want.end());
            sort(ids.data(), n);
            ASSERT_EQ(ids, want) << "n=" << n << " trial=" << trial;
        }
    }
}

TEST(sort_ids, base_level_matches_std_sort) { check_against_std_sort(sort_test_base::sort_ids); }

TEST(sort_ids, avx512_network_matches_std_sort) {
    if (!__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("avx512vl") ||
        !__builtin_cpu_supports("avx512bw") || !__builtin_cpu_supports("avx512dq"))
        GTEST_SKIP() << "this CPU has no AVX-512";
    check_against_std_sort(sort_test_avx512::sort_ids);
}

}  // namespace
