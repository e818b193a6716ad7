// This level's vectors: copies of runs in whole vectors, the lanes of T with their loads,
// comparisons and masks, and the compressed store of a row's hits.
// Included by sweep_impl.hpp inside the instruction-set level's namespace (see there).

template <class T>
void grow(std::vector<T>& v, std::size_t n) {
    if (v.size() < n) v.resize(n + n / 2);
}

/// Runs are short (a few dozen points), so they are copied in whole vectors rather than by
/// library calls. Copies n values, reading and writing up to one vector past n: the grid pads
/// its coordinate arrays and the block has that much slack.
template <class U>
void copy_padded(U* __restrict dst, const U* __restrict src, std::uint32_t n) {
    for (std::uint32_t j = 0; j < n; j += FRNN_SWEEP_BYTES / sizeof(U)) std::memcpy(dst + j, src + j, FRNN_SWEEP_BYTES);
}
/// The same for an unpadded source: whole vectors, then the tail (by a masked load at the
/// AVX-512 level, which reads nothing past n; one by one at the others).
inline void copy_ids(std::uint32_t* __restrict dst, const std::uint32_t* __restrict src, std::uint32_t n) {
    constexpr std::uint32_t w = FRNN_SWEEP_BYTES / 4;
    std::uint32_t j = 0;
    for (; j + w <= n; j += w) std::memcpy(dst + j, src + j, FRNN_SWEEP_BYTES);
#if FRNN_SWEEP_BYTES == 64
    if (j < n) _mm512_storeu_si512(dst + j, _mm512_maskz_loadu_epi32(__mmask16(~(~0u << (n - j))), src + j));
#else
    for (; j < n; ++j) dst[j] = src[j];
#endif
}
/// dst[j] = first + j for j < n, writing up to one vector past n.
inline void count_up(std::uint32_t* __restrict dst, std::uint32_t first, std::uint32_t n) {
    constexpr std::uint32_t w = FRNN_SWEEP_BYTES / 4;
    typedef std::uint32_t uvec __attribute__((vector_size(FRNN_SWEEP_BYTES)));
    // A constant plus a splat: GCC fills a vector lane by lane otherwise.
    static constexpr std::uint32_t lanes[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    uvec v;
    std::memcpy(&v, lanes, sizeof v);
    v += first;
    for (std::uint32_t j = 0; j < n; j += w, v += w) std::memcpy(dst + j, &v, FRNN_SWEEP_BYTES);
}

/// Vector operations of this level on T.
template <class T>
struct lanes_of {
    static constexpr int n = FRNN_SWEEP_BYTES / int(sizeof(T));
    typedef T vec __attribute__((vector_size(FRNN_SWEEP_BYTES)));

    static vec load(const T* p) {
        vec v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    /// x in every lane. (x - 0 is x for every x, so GCC drops the subtraction; 0 + x is not
    /// for x = -0, and GCC adds, an extra operation in inner loops.)
    static vec splat(T x) { return x - vec{}; }
    /// Each lane rounded to the nearest integer, ties to even: std::nearbyint in the default
    /// rounding mode, which the other query paths use for the minimum image.
    static vec round_even(vec a) {
#if FRNN_SWEEP_BYTES == 64
        constexpr int mode = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
        // (The masked forms: GCC 12 warns about the plain ones' undefined pass-through operand.)
        if constexpr (sizeof(T) == 4)
            return reinterpret_cast<vec>(_mm512_maskz_roundscale_ps(__mmask16(0xFFFF), reinterpret_cast<__m512>(a), mode));
        else
            return reinterpret_cast<vec>(_mm512_maskz_roundscale_pd(__mmask8(0xFF), reinterpret_cast<__m512d>(a), mode));
#elif FRNN_SWEEP_BYTES == 32
        constexpr int mode = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
        if constexpr (sizeof(T) == 4) return reinterpret_cast<vec>(_mm256_round_ps(reinterpret_cast<__m256>(a), mode));
        else return reinterpret_cast<vec>(_mm256_round_pd(reinterpret_cast<__m256d>(a), mode));
#else
        for (int l = 0; l < n; ++l) a[l] = std::nearbyint(a[l]);
        return a;
#endif
    }
    /// Bit l set when a[l] <= b[l].
    static std::uint32_t le_bits(vec a, vec b) {
#if FRNN_SWEEP_BYTES == 64
        if constexpr (sizeof(T) == 4)
            return _mm512_cmp_ps_mask(reinterpret_cast<__m512>(a), reinterpret_cast<__m512>(b), _CMP_LE_OQ);
        else
            return _mm512_cmp_pd_mask(reinterpret_cast<__m512d>(a), reinterpret_cast<__m512d>(b), _CMP_LE_OQ);
#elif FRNN_SWEEP_BYTES == 32
        if constexpr (sizeof(T) == 4)
            return std::uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b), _CMP_LE_OQ)));
        else
            return std::uint32_t(_mm256_movemask_pd(_mm256_cmp_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b), _CMP_LE_OQ)));
#elif defined(__SSE2__)
        if constexpr (sizeof(T) == 4)
            return std::uint32_t(_mm_movemask_ps(_mm_cmple_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b))));
        else
            return std::uint32_t(_mm_movemask_pd(_mm_cmple_pd(reinterpret_cast<__m128d>(a), reinterpret_cast<__m128d>(b))));
#else
        std::uint32_t bits = 0;
        for (int l = 0; l < n; ++l) bits |= std::uint32_t(a[l] <= b[l]) << l;
        return bits;
#endif
    }
};

/// Writes ids[l] for each bit l of `bits`, in lane order, to out[0, popcount(bits)) and
/// nothing else (rows of other points may follow); returns how many. `lanes` ids are read.
template <int Lanes>
std::uint32_t store_hits(std::uint32_t* __restrict out, std::uint32_t bits, const std::uint32_t* __restrict ids) {
    const auto n = std::uint32_t(__builtin_popcount(bits));
#if FRNN_SWEEP_BYTES == 64
    // Compressed to the front of a register and stored under a mask of the count.
    if constexpr (Lanes == 16) {
        _mm512_mask_storeu_epi32(out, __mmask16((1u << n) - 1), _mm512_maskz_compress_epi32(__mmask16(bits), _mm512_loadu_si512(ids)));
        return n;
    } else if constexpr (Lanes == 8) {
        _mm256_mask_storeu_epi32(out, __mmask8((1u << n) - 1),
                                 _mm256_maskz_compress_epi32(__mmask8(bits), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids))));
        return n;
    }
#endif
    std::uint32_t k = 0;
    for (; bits; bits &= bits - 1) out[k++] = ids[__builtin_ctz(bits)];
    return n;
}

/// store_hits of two consecutive vectors. Both are compressed before either is stored, so
/// that the second compress does not wait behind the first store.
template <int Lanes>
std::uint32_t store_hit_pair(std::uint32_t* __restrict out, std::uint32_t bits0, std::uint32_t bits1,
                             const std::uint32_t* __restrict ids) {
#if FRNN_SWEEP_BYTES == 64
    if constexpr (Lanes == 16) {
        const auto n0 = std::uint32_t(__builtin_popcount(bits0));
        const auto n1 = std::uint32_t(__builtin_popcount(bits1));
        const __m512i c0 = _mm512_maskz_compress_epi32(__mmask16(bits0), _mm512_loadu_si512(ids));
        const __m512i c1 = _mm512_maskz_compress_epi32(__mmask16(bits1), _mm512_loadu_si512(ids + 16));
        _mm512_mask_storeu_epi32(out, __mmask16((1u << n0) - 1), c0);
        _mm512_mask_storeu_epi32(out + n0, __mmask16((1u << n1) - 1), c1);
        return n0 + n1;
    }
#endif
    const std::uint32_t n0 = store_hits<Lanes>(out, bits0, ids);
    return n0 + store_hits<Lanes>(out + n0, bits1, ids + Lanes);
}
