// Distance tests of one point against a contiguous run of sorted points, several candidates
// per instruction. GCC's vector extensions compile to AVX when the target has it and to pairs
// of SSE operations otherwise; the comparison becomes a bit mask so that only the hits (about
// one candidate in seven in 3D) are touched. Loads may read up to `lanes - 1` values past the
// run: the grid pads its coordinate arrays for that, and the extra lanes are masked off.
#pragma once
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace frnn::detail {

#if defined(__AVX__)
inline constexpr int vector_bytes = 32;
#else
inline constexpr int vector_bytes = 16;
#endif

template <class T>
struct simd {
    static constexpr int lanes = vector_bytes / sizeof(T);
    typedef T vec __attribute__((vector_size(vector_bytes)));
    using ivec_elem = std::conditional_t<sizeof(T) == 4, std::int32_t, std::int64_t>;
    typedef ivec_elem ivec __attribute__((vector_size(vector_bytes)));

    static vec load(const T* p) {
        vec v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    static vec splat(T x) { return vec{} + x; }

    /// Bit l set when lane l of the comparison result is true.
    static std::uint32_t bits(ivec m) {
#if defined(__AVX__)
        if constexpr (sizeof(T) == 4) return std::uint32_t(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
        else return std::uint32_t(_mm256_movemask_pd(reinterpret_cast<__m256d>(m)));
#elif defined(__SSE2__)
        if constexpr (sizeof(T) == 4) return std::uint32_t(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
        else return std::uint32_t(_mm_movemask_pd(reinterpret_cast<__m128d>(m)));
#else
        std::uint32_t b = 0;
        for (int l = 0; l < lanes; ++l) b |= std::uint32_t(m[l] != 0) << l;
        return b;
#endif
    }
};

/// Bits set in a lane mask (at most 8 bits), without a library call on CPUs lacking popcnt.
inline std::uint32_t popcount8(std::uint32_t x) {
    x = x - ((x >> 1) & 0x55u);
    x = (x & 0x33u) + ((x >> 2) & 0x33u);
    return (x + (x >> 4)) & 0x0Fu;
}

/// Squared distances (dx^2 + dy^2) + dz^2 from x to `lanes` points starting at j.
template <class T, int D>
inline typename simd<T>::vec d2_lanes(const T* const* p, const typename simd<T>::vec* x, std::uint32_t j) {
    using S = simd<T>;
    const auto dx = S::load(p[0] + j) - x[0];
    const auto dy = S::load(p[1] + j) - x[1];
    auto d2 = dx * dx;
    d2 += dy * dy;
    if constexpr (D == 3) {
        const auto dz = S::load(p[2] + j) - x[2];
        d2 += dz * dz;
    }
    return d2;
}

/// Number of points of [b, e) within r of x (r2 = r*r).
template <class T, int D>
inline std::uint32_t count_run(const T* const* p, const T* x, std::uint32_t b, std::uint32_t e, T r2) {
    using S = simd<T>;
    typename S::vec xv[D];
    for (int a = 0; a < D; ++a) xv[a] = S::splat(x[a]);
    const auto limit = S::splat(r2);
    typename S::ivec total{};
    std::uint32_t j = b;
    for (; j + S::lanes <= e; j += S::lanes) total -= d2_lanes<T, D>(p, xv, j) <= limit;  // true lanes are -1
    std::uint32_t c = 0;
    for (int l = 0; l < S::lanes; ++l) c += std::uint32_t(total[l]);
    if (j < e) {
        const std::uint32_t tail = S::bits(d2_lanes<T, D>(p, xv, j) <= limit) & ((1u << (e - j)) - 1);
        c += popcount8(tail);
    }
    return c;
}

/// Calls hit(j, d2) for every point j of [b, e) within r of x, in increasing j.
template <class T, int D, class Hit>
inline void hits_in_run(const T* const* p, const T* x, std::uint32_t b, std::uint32_t e, T r2, Hit&& hit) {
    using S = simd<T>;
    typename S::vec xv[D];
    for (int a = 0; a < D; ++a) xv[a] = S::splat(x[a]);
    const auto limit = S::splat(r2);
    for (std::uint32_t j = b; j < e; j += S::lanes) {
        const auto d2 = d2_lanes<T, D>(p, xv, j);
        std::uint32_t m = S::bits(d2 <= limit);
        if (e - j < std::uint32_t(S::lanes)) m &= (1u << (e - j)) - 1;
        for (; m; m &= m - 1) {
            const int l = __builtin_ctz(m);
            hit(j + std::uint32_t(l), d2[l]);
        }
    }
}

}  // namespace frnn::detail
