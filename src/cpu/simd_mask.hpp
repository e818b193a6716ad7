// Bit masks of "d2[k] <= limit" over short blocks, with SSE/AVX where the compiler targets
// them. Turning comparisons into masks lets the list kernels touch only the hits (about one
// candidate in seven in 3D), instead of a store per candidate.
#pragma once
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace frnn::detail {

/// Bit k set when d2[k] <= limit, for k < len <= 64.
inline std::uint64_t le_mask(const float* d2, std::uint32_t len, float limit) {
    std::uint64_t mask = 0;
    std::uint32_t k = 0;
#if defined(__AVX__)
    const __m256 l8 = _mm256_set1_ps(limit);
    for (; k + 8 <= len; k += 8)
        mask |= std::uint64_t(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(d2 + k), l8, _CMP_LE_OQ))) << k;
#elif defined(__SSE2__)
    const __m128 l4 = _mm_set1_ps(limit);
    for (; k + 4 <= len; k += 4)
        mask |= std::uint64_t(_mm_movemask_ps(_mm_cmple_ps(_mm_loadu_ps(d2 + k), l4))) << k;
#endif
    for (; k < len; ++k) mask |= std::uint64_t(d2[k] <= limit) << k;
    return mask;
}

inline std::uint64_t le_mask(const double* d2, std::uint32_t len, double limit) {
    std::uint64_t mask = 0;
    std::uint32_t k = 0;
#if defined(__AVX__)
    const __m256d l4 = _mm256_set1_pd(limit);
    for (; k + 4 <= len; k += 4)
        mask |= std::uint64_t(_mm256_movemask_pd(_mm256_cmp_pd(_mm256_loadu_pd(d2 + k), l4, _CMP_LE_OQ))) << k;
#elif defined(__SSE2__)
    const __m128d l2 = _mm_set1_pd(limit);
    for (; k + 2 <= len; k += 2)
        mask |= std::uint64_t(_mm_movemask_pd(_mm_cmple_pd(_mm_loadu_pd(d2 + k), l2))) << k;
#endif
    for (; k < len; ++k) mask |= std::uint64_t(d2[k] <= limit) << k;
    return mask;
}

}  // namespace frnn::detail
