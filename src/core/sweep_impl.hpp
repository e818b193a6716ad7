// The cell sweep of sweep.hpp, for one instruction-set level. Included by sweep_<level>.cpp,
// which first includes every header this file needs, then opens the target region and defines
// FRNN_SWEEP_NS (the level's namespace) and FRNN_SWEEP_BYTES (vector width in bytes). Everything
// here lives in that namespace, so the levels never share a symbol.
//
// Distances are (dx*dx + dy*dy) + dz*dz with dx = candidate - point, rounded per operation
// (the library is built without contraction into fused multiply-adds), so every level, the
// brute-force oracle and the other query paths agree bit for bit.

namespace frnn::detail::FRNN_SWEEP_NS {

/// The block is padded to a multiple of this many values: the widest vector of floats.
constexpr std::uint32_t block_multiple = 16;
/// How many points ahead a fill sweep fetches the lines of a scattered output row.
constexpr std::uint32_t row_prefetch_distance = 8;
/// Id of no point: padding lanes and "no id to skip". Grids hold at most 2^32 - 2 points.
constexpr std::uint32_t no_id = 0xFFFFFFFFu;

#include "core/sort_ids_impl.hpp"

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

/// The candidates of one cell's stencil, contiguous: coordinates per axis and output ids.
/// Padding lanes hold +infinity, so their distance never passes the test and the kernels need
/// no tail handling.
template <class T, int D>
struct candidate_block {
    std::vector<T> c[D];
    std::vector<std::uint32_t> id;
    /// Periodic box, from gather_shifts: what the minimum image subtracts from candidate -
    /// point per axis, image * L, at each position.
    std::vector<T> shift[D];
    std::uint32_t size = 0;
    std::uint32_t padded = 0;

    /// Copies the runs' points in order; their ids are ids[point] or, without ids, the sorted
    /// index, unless with_ids is false: then the id array is left as it was.
    void gather(const grid<T, D>& g, const candidate_run* runs, std::size_t nruns, const std::uint32_t* ids,
                bool with_ids = true) {
        std::size_t total = 0;
        for (std::size_t k = 0; k < nruns; ++k) total += runs[k].end - runs[k].begin;
        for (auto& axis : c) grow(axis, total + 2 * block_multiple);
        T* __restrict dst[D];
        for (int a = 0; a < D; ++a) dst[a] = c[a].data();
        std::uint32_t m = 0;
        for (std::size_t k = 0; k < nruns; ++k) {
            const std::uint32_t len = runs[k].end - runs[k].begin;
            for (int a = 0; a < D; ++a) copy_padded(dst[a] + m, grid_access::search_coords(g, a) + runs[k].begin, len);
            m += len;
        }
        size = m;
        padded = padded_size(m);
        for (std::uint32_t j = m; j < padded; ++j)
            for (int a = 0; a < D; ++a) c[a][j] = T(INFINITY);
        if (with_ids) gather_ids(runs, nruns, ids);
    }

    /// The shifts of the runs' positions (after gather): image[a] * box[a] per axis.
    void gather_shifts(const candidate_run* runs, const run_image* images, std::size_t nruns, const T* box) {
        for (auto& axis : shift) grow(axis, padded + 2 * block_multiple);
        for (int a = 0; a < D; ++a) {
            T* __restrict dst = shift[a].data();
            std::uint32_t m = 0;
            for (std::size_t k = 0; k < nruns; ++k) {
                // Whole vectors, like copy_padded: the next run or the padding overwrites the rest.
                typedef T vec __attribute__((vector_size(FRNN_SWEEP_BYTES)));
                const vec v = T(images[k][a]) * box[a] - vec{};
                const std::uint32_t len = runs[k].end - runs[k].begin;
                for (std::uint32_t j = 0; j < len; j += FRNN_SWEEP_BYTES / sizeof(T)) std::memcpy(dst + m + j, &v, sizeof v);
                m += len;
            }
            std::fill(dst + m, dst + padded, T(0));
        }
    }

    /// Only the ids and the size of the block that gather would make.
    void gather_ids(const candidate_run* runs, std::size_t nruns, const std::uint32_t* ids) {
        std::uint32_t total = 0;
        for (std::size_t k = 0; k < nruns; ++k) total += runs[k].end - runs[k].begin;
        grow(id, total + 2 * block_multiple);
        std::uint32_t* __restrict dst_id = id.data();
        std::uint32_t m = 0;
        for (std::size_t k = 0; k < nruns; ++k) {
            const std::uint32_t len = runs[k].end - runs[k].begin;
            if (ids) copy_ids(dst_id + m, ids + runs[k].begin, len);
            else count_up(dst_id + m, runs[k].begin, len);
            m += len;
        }
        size = m;
        padded = padded_size(m);
        for (std::uint32_t j = m; j < padded; ++j) id[j] = no_id;
    }

    static std::uint32_t padded_size(std::uint32_t n) { return (n + block_multiple - 1) / block_multiple * block_multiple; }
};

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

/// Which candidates of a block enter a point's row: those at block positions from `from` on,
/// except position `skip` (the point itself), and, where the kernel is asked to, with id >= lo.
struct candidate_filter {
    std::uint32_t from = 0;
    std::uint32_t skip = no_id;
    std::uint32_t lo = 0;
};

/// How a periodic box's differences d = candidate - point are wrapped: not at all (the caller
/// knows every correction is zero), by the candidates' shifts (image * L, grid::images_exact),
/// or by the minimum image, d -= L * nearbyint(d / L) per axis, as
/// grid::distance_squared_sorted computes it. The three give the same values where they apply.
enum class wrap_mode { none, shift, min_image };

/// One point against a candidate block, its differences wrapped as `Wrap` says.
template <class T, int D, wrap_mode Wrap>
struct point_kernel {
    using L = lanes_of<T>;
    using vec = typename L::vec;
    vec x[D];
    vec box[D];
    vec limit;

    point_kernel(const T* point, T r2, const T* box_lengths) : limit(L::splat(r2)) {
        for (int a = 0; a < D; ++a) x[a] = L::splat(point[a]);
        for (int a = 0; a < D; ++a) box[a] = L::splat(box_lengths[a]);
    }

    /// A block's coordinate and shift columns.
    struct columns {
        const T* c[D];
        const T* shift[D];
        explicit columns(const candidate_block<T, D>& b) {
            for (int a = 0; a < D; ++a) c[a] = b.c[a].data(), shift[a] = b.shift[a].data();
        }
    };

    // Inlined by force: GCC otherwise calls d2 from some of the kernels' loops (W8 half
    // lists spent a sixth of their time in the calls).
    [[gnu::always_inline]] vec delta(const columns& c, std::uint32_t k, int a) const {
        vec d = L::load(c.c[a] + k) - x[a];
        // Padding lanes (+infinity) stay infinite or become NaN, which fails every comparison.
        if constexpr (Wrap == wrap_mode::shift) d -= L::load(c.shift[a] + k);
        if constexpr (Wrap == wrap_mode::min_image) d -= box[a] * L::round_even(d / box[a]);
        return d;
    }

    [[gnu::always_inline]] vec d2(const columns& c, std::uint32_t k) const {
        const vec dx = delta(c, k, 0);
        const vec dy = delta(c, k, 1);
        vec d = dx * dx;
        d += dy * dy;
        if constexpr (D == 3) {
            const vec dz = delta(c, k, D - 1);
            d += dz * dz;
        }
        return d;
    }

    /// Candidates within r, the point itself included.
    std::uint32_t count_all(const candidate_block<T, D>& b) const {
        const columns c(b);
        const std::uint32_t padded = b.padded;
        std::uint32_t hits = 0;
        for (std::uint32_t k = 0; k < padded; k += L::n) hits += std::uint32_t(__builtin_popcount(L::le_bits(d2(c, k), limit)));
        return hits;
    }

    /// The candidates within r that `f` lets into the row (ById: f.lo applies; the block
    /// needs its ids then): returns how many and writes the bits of the hits of each vector
    /// of the block, one word per vector, to bits (zero for vectors wholly before f.from).
    template <bool ById, class Word>
    std::uint32_t keep_hits(const candidate_block<T, D>& b, const candidate_filter& f, Word* __restrict bits) const {
        const columns c(b);
        const std::uint32_t padded = b.padded;
        const std::uint32_t first = f.from / L::n * L::n;
        for (std::uint32_t k = 0; k < first; k += L::n) bits[k / L::n] = 0;
        std::uint32_t n = 0;
        // The filter's positions are cleared after the loop, which then needs no check per
        // vector.
        for (std::uint32_t k = first; k < padded; k += L::n) {
            std::uint32_t m = L::le_bits(d2(c, k), limit);
            if constexpr (ById) m &= ids_at_least(b.id.data() + k, f.lo);
            bits[k / L::n] = Word(m);
            n += std::uint32_t(__builtin_popcount(m));
        }
        auto clear = [&](std::uint32_t vector, std::uint32_t drop) {
            const std::uint32_t m = bits[vector];
            n -= std::uint32_t(__builtin_popcount(m & drop));
            bits[vector] = Word(m & ~drop);
        };
        if (f.from > first && first < padded) clear(first / L::n, ~(~0u << (f.from - first)));
        if (f.skip >= f.from && f.skip < padded) clear(f.skip / L::n, 1u << (f.skip % L::n));
        return n;
    }

    /// Bits of the lanes of a vector of ids that are at least lo.
    static std::uint32_t ids_at_least(const std::uint32_t* ids, std::uint32_t lo) {
#if FRNN_SWEEP_BYTES == 64
        if constexpr (L::n == 16) return _mm512_cmpge_epu32_mask(_mm512_loadu_si512(ids), _mm512_set1_epi32(int(lo)));
        if constexpr (L::n == 8)
            return _mm256_cmpge_epu32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(ids)), _mm256_set1_epi32(int(lo)));
#endif
        std::uint32_t m = 0;
        for (int l = 0; l < L::n; ++l) m |= std::uint32_t(ids[l] >= lo) << l;
        return m;
    }

    /// Writes the ids (and squared distances) of the candidates within r that `f` lets into
    /// the row, in block order, to out (and out_d2); returns how many. Writes nothing else.
    /// ById: f.lo applies (half rows whose block is not in id order need it).
    template <bool WithD2, bool CountOnly = false, bool ById = false>
    std::uint32_t emit(const candidate_block<T, D>& b, const candidate_filter& f, std::uint32_t* __restrict out,
                       T* __restrict out_d2) const {
        const columns c(b);
        const std::uint32_t* __restrict block_ids = b.id.data();
        const std::uint32_t padded = b.padded;
        const std::uint32_t skip_vector = f.skip == no_id ? no_id : f.skip / L::n * L::n;
        const std::uint32_t keep_at_skip = f.skip == no_id ? ~0u : ~(1u << (f.skip % L::n));
        std::uint32_t n = 0;
        // Vectors wholly before f.from hold no candidate of the row.
        for (std::uint32_t k = f.from / L::n * L::n; k < padded; k += L::n) {
            const vec d = d2(c, k);
            std::uint32_t m = L::le_bits(d, limit);
            if (k < f.from) m &= ~0u << (f.from - k);
            if (k == skip_vector) m &= keep_at_skip;
#if FRNN_SWEEP_BYTES == 64
            if constexpr (sizeof(T) == 4) {
                if constexpr (ById) m &= _mm512_cmpge_epu32_mask(_mm512_loadu_si512(block_ids + k), _mm512_set1_epi32(int(f.lo)));
                if constexpr (!CountOnly) {
                    store_hits<16>(out + n, m, block_ids + k);
                    if constexpr (WithD2)
                        _mm512_mask_storeu_ps(out_d2 + n, __mmask16((1u << __builtin_popcount(m)) - 1),
                                              _mm512_maskz_compress_ps(__mmask16(m), reinterpret_cast<__m512>(d)));
                }
            } else {
                if constexpr (ById)
                    m &= _mm256_cmpge_epu32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(block_ids + k)),
                                                 _mm256_set1_epi32(int(f.lo)));
                if constexpr (!CountOnly) {
                    store_hits<8>(out + n, m, block_ids + k);
                    if constexpr (WithD2)
                        _mm512_mask_storeu_pd(out_d2 + n, __mmask8((1u << __builtin_popcount(m)) - 1),
                                              _mm512_maskz_compress_pd(__mmask8(m), reinterpret_cast<__m512d>(d)));
                }
            }
            n += std::uint32_t(__builtin_popcount(m));
#else
            for (; m; m &= m - 1) {
                const int l = __builtin_ctz(m);
                const std::uint32_t j = block_ids[k + std::uint32_t(l)];
                if (ById && j < f.lo) continue;
                if constexpr (!CountOnly) {
                    out[n] = j;
                    if constexpr (WithD2) out_d2[n] = d[l];
                }
                ++n;
            }
#endif
        }
        return n;
    }
};

#if FRNN_SWEEP_BYTES == 64
/// The intrinsics' vector of `Lanes` 32-bit integers.
template <int Lanes>
struct int_lanes;
template <>
struct int_lanes<16> {
    using type = __m512i;
};
template <>
struct int_lanes<8> {
    using type = __m256i;
};
template <>
struct int_lanes<4> {
    using type = __m128i;
};
#endif

/// Vectors of `Lanes` values of T for pair_counter: this level's full vector or, at the AVX-512
/// level, half of one (on AMD's Zen 4 a half vector takes half the time). Comparisons come as
/// bit masks under a mask of lanes to keep; `tally` holds an unsigned count per lane.
template <class T, int Lanes>
struct tally_lanes {
    typedef T vec __attribute__((vector_size(Lanes * sizeof(T))));
    static constexpr std::uint32_t all = ~0u >> (32 - Lanes);

    static vec load(const T* p) {
        vec v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    static vec splat(T x) { return x - vec{}; }  // see lanes_of::splat

#if FRNN_SWEEP_BYTES == 64
    static constexpr int bytes = Lanes * int(sizeof(T));
    using tally = typename int_lanes<Lanes>::type;

    static vec round_even(vec a) {
        constexpr int mode = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
        if constexpr (bytes == 64) return lanes_of<T>::round_even(a);
        else if constexpr (sizeof(T) == 4) return reinterpret_cast<vec>(_mm256_round_ps(reinterpret_cast<__m256>(a), mode));
        else return reinterpret_cast<vec>(_mm256_round_pd(reinterpret_cast<__m256d>(a), mode));
    }
    /// Bits of the lanes in `keep` where a <= b. The result stays in a mask register.
    static std::uint32_t le(std::uint32_t keep, vec a, vec b) {
        constexpr int le_oq = _CMP_LE_OQ;
        if constexpr (bytes == 64 && sizeof(T) == 4)
            return _mm512_mask_cmp_ps_mask(__mmask16(keep), reinterpret_cast<__m512>(a), reinterpret_cast<__m512>(b), le_oq);
        else if constexpr (bytes == 64)
            return _mm512_mask_cmp_pd_mask(__mmask8(keep), reinterpret_cast<__m512d>(a), reinterpret_cast<__m512d>(b), le_oq);
        else if constexpr (sizeof(T) == 4)
            return _mm256_mask_cmp_ps_mask(__mmask8(keep), reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b), le_oq);
        else
            return _mm256_mask_cmp_pd_mask(__mmask8(keep), reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b), le_oq);
    }
    /// Adds one in the lanes of m.
    static tally add_ones(tally t, std::uint32_t m) {
        if constexpr (Lanes == 16) return _mm512_mask_sub_epi32(t, __mmask16(m), t, _mm512_set1_epi32(-1));
        else if constexpr (Lanes == 8) return _mm256_mask_sub_epi32(t, __mmask8(m), t, _mm256_set1_epi32(-1));
        else return _mm_mask_sub_epi32(t, __mmask8(m), t, _mm_set1_epi32(-1));
    }
    /// dst[l] += t[l] for the lanes l of m; the others are not touched.
    static void add_to(std::uint32_t* dst, std::uint32_t m, tally t) {
        if constexpr (Lanes == 16)
            _mm512_mask_storeu_epi32(dst, __mmask16(m), _mm512_add_epi32(_mm512_maskz_loadu_epi32(__mmask16(m), dst), t));
        else if constexpr (Lanes == 8)
            _mm256_mask_storeu_epi32(dst, __mmask8(m), _mm256_add_epi32(_mm256_maskz_loadu_epi32(__mmask8(m), dst), t));
        else
            _mm_mask_storeu_epi32(dst, __mmask8(m), _mm_add_epi32(_mm_maskz_loadu_epi32(__mmask8(m), dst), t));
    }
#else
    struct tally {
        std::uint32_t v[Lanes] = {};
    };
    static vec round_even(vec a) { return lanes_of<T>::round_even(a); }
    static std::uint32_t le(std::uint32_t keep, vec a, vec b) { return lanes_of<T>::le_bits(a, b) & keep; }
    static tally add_ones(tally t, std::uint32_t m) {
        for (; m; m &= m - 1) ++t.v[__builtin_ctz(m)];
        return t;
    }
    static void add_to(std::uint32_t* dst, std::uint32_t m, const tally& t) {
        for (; m; m &= m - 1) dst[__builtin_ctz(m)] += t.v[__builtin_ctz(m)];
    }
#endif
};

/// Where a sweep of [b, e) adds the counts of partner point j: own[j] inside the range,
/// after[j - e] past it, before[j] before it. A run of candidates lies in one row of cells, so
/// in one layer: wholly in one of the three when [b, e) holds whole layers.
struct partner_sink {
    std::uint32_t* own;
    std::uint32_t* after = nullptr;
    std::uint32_t* before = nullptr;
    std::size_t b = 0, e = SIZE_MAX;
    std::uint32_t* at(std::size_t j) const { return j >= e ? after + (j - e) : j < b ? before + j : own + j; }
};

/// For a sweep that meets each pair once: the points of one group against the runs of their
/// forward half-stencil, read where the grid keeps them (no candidate block). The first run
/// starts with the group's cells, and a point meets only the candidates after it there. Adds
/// each point's hits to its count and each candidate's hits to its partner count.
///
/// The candidate vectors are the outer loop, so that their partner counts stay in a register.
/// Counted point by point into a gathered block, they went through memory once per point and
/// vector, and the gather took a fifth of the time (at 1M points, 1 thread: W1 counts 26.7 ->
/// 18.9 ms, W2 41.7 -> 24.3).
template <class T, int D, bool Periodic>
struct pair_counter {
    static constexpr int lanes = lanes_of<T>::n;
    // A run's last vector reads up to lanes - 1 values past it, at most into the padding.
    static_assert(coordinate_padding >= std::size_t(lanes));
    const grid<T, D>& g;
    T r2;
    const T* box;
    /// Half rows: each pair is counted once, for the point of the smaller id, the caller's
    /// (ids[sorted point]) or, without ids, the sorted index.
    bool half = false;
    const std::uint32_t* ids = nullptr;

    /// Points [gb, ge) against runs; counts are indexed by sorted point. With `wrap`, by the
    /// runs' images if given (grid::images_exact), else by the minimum image.
    void count(std::uint32_t gb, std::uint32_t ge, const candidate_run* runs, const run_image* images, std::size_t nruns,
               bool wrap, std::uint32_t* counts, const partner_sink& partners) const {
        if (half) return count_as<true>(gb, ge, runs, images, nruns, wrap, counts, partners);
        count_as<false>(gb, ge, runs, images, nruns, wrap, counts, partners);
    }

  private:
    template <bool Half>
    void count_as(std::uint32_t gb, std::uint32_t ge, const candidate_run* runs, const run_image* images, std::size_t nruns,
                  bool wrap, std::uint32_t* counts, const partner_sink& partners) const {
        if (Periodic && wrap && images) sweep<wrap_mode::shift, Half>(gb, ge, runs, images, nruns, counts, partners);
        else if (Periodic && wrap) sweep<wrap_mode::min_image, Half>(gb, ge, runs, images, nruns, counts, partners);
        else sweep<wrap_mode::none, Half>(gb, ge, runs, images, nruns, counts, partners);
    }

    /// Where one run's candidates are and which of them the group's points meet.
    struct run_view {
        const T* c[D];         // the run's coordinates
        T shift[D];            // wrap_mode::shift: image * L per axis
        std::uint32_t begin;   // its first sorted point
        std::uint32_t len;     // its length
        std::uint32_t pos0;    // the first run: the first point's position in it
        bool first;            // whether this is the first run
    };

    // counts and partners may be one array (the uniform grid's): no __restrict on them.
    template <wrap_mode Wrap, bool Half>
    void sweep(std::uint32_t gb, std::uint32_t ge, const candidate_run* runs, const run_image* images, std::size_t nruns,
               std::uint32_t* counts, const partner_sink& partners) const {
        const T* x[D];
        for (int a = 0; a < D; ++a) x[a] = grid_access::search_coords(g, a) + gb;
        // Half: the ids of the group's points.
        std::uint32_t point_ids[Half ? 64 : 1];
        if constexpr (Half) {
            if (ge - gb > 64) return sweep_in_parts<Wrap>(gb, ge, runs, images, nruns, counts, partners);
            for (std::uint32_t j = 0; j < ge - gb; ++j) point_ids[j] = ids ? ids[gb + j] : gb + j;
        }
        for (std::size_t r = 0; r < nruns; ++r) {
            run_view v;
            for (int a = 0; a < D; ++a) v.c[a] = grid_access::search_coords(g, a) + runs[r].begin;
            if constexpr (Wrap == wrap_mode::shift)
                for (int a = 0; a < D; ++a) v.shift[a] = T(images[r][a]) * box[a];
            v.begin = runs[r].begin;
            v.len = runs[r].end - runs[r].begin;
            v.first = r == 0;
            v.pos0 = v.first ? gb - runs[r].begin : 0;
            std::uint32_t* run_partners = partners.at(runs[r].begin);
            // Vectors wholly at or before the first point hold no candidate of the group.
            std::uint32_t k = v.first ? (v.pos0 + 1) / lanes * lanes : 0;
            for (; k < v.len; k += lanes) {
#if FRNN_SWEEP_BYTES == 64
                if (v.len - k <= lanes / 2) {  // the rest fits half a vector
                    test_vector<Wrap, Half, lanes / 2>(x, point_ids, ge - gb, v, k, counts + gb, run_partners);
                    break;
                }
#endif
                test_vector<Wrap, Half, lanes>(x, point_ids, ge - gb, v, k, counts + gb, run_partners);
            }
        }
    }

    /// Half counts of a group of more than 64 points (cells that dense are rare): the
    /// group's points one by one, each against the runs from its own position on.
    template <wrap_mode Wrap>
    void sweep_in_parts(std::uint32_t gb, std::uint32_t ge, const candidate_run* runs, const run_image* images,
                        std::size_t nruns, std::uint32_t* counts, const partner_sink& partners) const {
        for (std::uint32_t s = gb; s < ge; ++s) sweep<Wrap, true>(s, s + 1, runs, images, nruns, counts, partners);
    }

    /// Lanes whose id exceeds `me`.
    template <int Lanes>
    static std::uint32_t greater(const std::uint32_t* lane_ids, std::uint32_t me) {
#if FRNN_SWEEP_BYTES == 64
        if constexpr (Lanes == 16) return _mm512_cmpgt_epu32_mask(_mm512_loadu_si512(lane_ids), _mm512_set1_epi32(int(me)));
        if constexpr (Lanes == 8)
            return _mm256_cmpgt_epu32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(lane_ids)), _mm256_set1_epi32(int(me)));
        if constexpr (Lanes == 4)
            return _mm_cmpgt_epu32_mask(_mm_loadu_si128(reinterpret_cast<const __m128i*>(lane_ids)), _mm_set1_epi32(int(me)));
#endif
        std::uint32_t m = 0;
        for (int l = 0; l < Lanes; ++l) m |= std::uint32_t(lane_ids[l] > me) << l;
        return m;
    }

    /// The group's points (coordinates x) against the candidates at run positions [k, k + Lanes).
    template <wrap_mode Wrap, bool Half, int Lanes>
    void test_vector(const T* const* x, const std::uint32_t* point_ids, std::uint32_t points, const run_view& v,
                     std::uint32_t k, std::uint32_t* counts, std::uint32_t* partners) const {
        using V = tally_lanes<T, Lanes>;
        using vec = typename V::vec;
        // Lanes past the run hold other points (or the arrays' padding): never hits.
        const std::uint32_t in_run = v.len - k >= std::uint32_t(Lanes) ? V::all : ~(~0u << (v.len - k));
        // In the first run, points at positions k + Lanes - 1 or later have no candidate here.
        const std::uint32_t last = k + Lanes - 1;
        const std::uint32_t active = v.first ? std::min(points, last > v.pos0 ? last - v.pos0 : 0u) : points;
        vec c[D], box_v[D], shift_v[D];
        for (int a = 0; a < D; ++a) c[a] = V::load(v.c[a] + k), box_v[a] = V::splat(box[a]);
        if constexpr (Wrap == wrap_mode::shift)
            for (int a = 0; a < D; ++a) shift_v[a] = V::splat(v.shift[a]);
        const vec limit = V::splat(r2);
        auto delta = [&](int a, std::uint32_t j) {
            vec d = c[a] - V::splat(x[a][j]);
            if constexpr (Wrap == wrap_mode::shift) d -= shift_v[a];
            if constexpr (Wrap == wrap_mode::min_image) d -= box_v[a] * V::round_even(d / box_v[a]);
            return d;
        };
        // Half: the ids of the vector's candidates (0 past the run, where no lane hits).
        std::uint32_t cand_ids[Half ? Lanes : 1] = {};
        if constexpr (Half) {
            const std::uint32_t n = std::min<std::uint32_t>(std::uint32_t(Lanes), v.len - k);
            for (std::uint32_t l = 0; l < n; ++l) cand_ids[l] = ids ? ids[v.begin + k + l] : v.begin + k + l;
        }
        typename V::tally partner{};
        for (std::uint32_t j = 0; j < active; ++j) {
            const vec dx = delta(0, j);
            const vec dy = delta(1, j);
            vec d = dx * dx;
            d += dy * dy;
            if constexpr (D == 3) {
                const vec dz = delta(D - 1, j);
                d += dz * dz;
            }
            const std::uint32_t p = v.pos0 + j;
            const std::uint32_t keep = v.first && p + 1 > k ? in_run & (~0u << (p + 1 - k)) : in_run;
            const std::uint32_t m = V::le(keep, d, limit);
            if constexpr (Half) {
                const std::uint32_t mine = m & greater<Lanes>(cand_ids, point_ids[j]);
                partner = V::add_ones(partner, m & ~mine);
                counts[j] += std::uint32_t(__builtin_popcount(mine));
            } else {
                partner = V::add_ones(partner, m);
                counts[j] += std::uint32_t(__builtin_popcount(m));
            }
        }
        // Only the run's lanes are written: the points past it may be another thread's.
        V::add_to(partners + k, in_run, partner);
    }
};

/// Calls f(begin, end, cell, width) for each run of sorted points in [b, e) that share one
/// candidate block: the points of `width` consecutive cells of an x row from `cell` on (the
/// uniform grid with open boundaries groups up to `group_width` cells), or of one cell.
template <class T, int D, class F>
void for_each_cell_group(const grid<T, D>& g, std::size_t b, std::size_t e, std::int64_t group_width, F&& f) {
    if (b >= e) return;
    std::array<T, D> x;
    for (int a = 0; a < D; ++a) x[a] = grid_access::search_coord(g, b, a);
    auto cell = g.geometry().cell_of(x);
    if (g.kind() == grid_kind::uniform) {
        // Walk the cells in order from the first point's: no cell computation per group.
        const auto starts = grid_access::cell_starts(g);
        const auto dims = g.geometry().dims;
        std::size_t slot = g.geometry().slot_of_cell(cell);
        for (std::size_t s = b; s < e;) {
            const std::int64_t width = std::min(group_width, dims[0] - cell[0]);
            const std::size_t end = std::min<std::size_t>(starts[slot + std::size_t(width)], e);
            if (end > s) {
                f(std::uint32_t(s), std::uint32_t(end), cell, width);
                s = end;
            }
            slot += std::size_t(width);
            if ((cell[0] += width) == dims[0]) {
                cell[0] = 0;
                if (++cell[1] == dims[1]) cell[1] = 0, ++cell[2];
            }
        }
        return;
    }
    for (std::size_t s = b; s < e;) {
        for (int a = 0; a < D; ++a) x[a] = grid_access::search_coord(g, s, a);
        const std::size_t end = std::min<std::size_t>(grid_access::cell_group_end(g, std::uint32_t(s)), e);
        f(std::uint32_t(s), std::uint32_t(end), g.geometry().cell_of(x), std::int64_t(1));
        s = end;
    }
}

/// Cells per candidate block along x: sparse grids share one block between neighboring cells,
/// since a block of a few points costs more to gather than to test.
template <class T, int D>
std::int64_t group_width_for(const grid<T, D>& g) {
    if (g.kind() != grid_kind::uniform || g.periodic() || g.nonempty_cells() == 0) return 1;
    // Measured on lattices: 8 points per cell (W1) are best one cell at a time, 4 per cell
    // (W4) three at a time (lists 25% faster, counts 30%).
    const double per_cell = double(g.size()) / double(g.nonempty_cells());
    return std::clamp<std::int64_t>(std::int64_t(12.0 / per_cell), 1, 4);
}

/// The sweeps over the cells of a grid; `Periodic` for a periodic box.
template <class T, int D, bool Periodic>
struct sweeper {
    using kernel = point_kernel<T, D, wrap_mode::none>;
    const grid<T, D>& g;
    const sweep_job<T>& job;
    T box[D] = {};
    candidate_block<T, D> block;
    candidate_run runs[max_runs];
    run_image images[max_runs];
    std::size_t nruns = 0;
    T r2;
    std::int64_t group_width;
    /// Periodic box: grid points wrap by their runs' images, without a division.
    bool shifts = false;

    sweeper(const grid<T, D>& gr, const sweep_job<T>& j)
        : g(gr), job(j), r2(gr.search_radius() * gr.search_radius()), group_width(group_width_for(gr)) {
        if constexpr (Periodic) {
            for (int a = 0; a < D; ++a) box[a] = gr.geometry().box[a];
            shifts = !job.queries && grid_access::images_exact(gr);
        }
    }

    std::array<T, D> point(std::uint32_t s) const {
        std::array<T, D> x;
        if (job.queries) {
            const T* q = job.queries + std::size_t(job.query_order[s]) * D;
            for (int a = 0; a < D; ++a) x[a] = q[a];
        } else {
            for (int a = 0; a < D; ++a) x[a] = grid_access::search_coord(g, s, a);
        }
        return x;
    }
    /// The id of point s, which is also its output row.
    std::uint32_t id(std::uint32_t s) const {
        if (job.queries) return job.query_order[s];
        return job.ids ? job.ids[s] : s;
    }

    /// Calls f(begin, end, cell, width) for the groups of points of [b, e) that share one
    /// candidate block: for_each_cell_group, or consecutive queries in one cell.
    template <class F>
    void for_each_group(std::size_t b, std::size_t e, F&& f) const {
        if (!job.queries) return for_each_cell_group(g, b, e, group_width, f);
        for (std::size_t s = b; s < e;) {
            const auto cell = g.geometry().cell_of(point(std::uint32_t(s)));
            std::size_t end = s + 1;
            while (end < e && g.geometry().cell_of(point(std::uint32_t(end))) == cell) ++end;
            f(std::uint32_t(s), std::uint32_t(end), cell, std::int64_t(1));
            s = end;
        }
    }

    /// Whether point x needs the minimum image, given wraps() of its cell: a grid point never
    /// does when its cell does not; a query must lie inside the box as well.
    bool wraps_at(bool group_wraps, const std::array<T, D>& x) const {
        if constexpr (!Periodic) return false;
        if (group_wraps || !job.queries) return group_wraps;
        for (int a = 0; a < D; ++a)
            if (!(x[a] >= T(0) && x[a] < box[a])) return true;
        return false;
    }

    /// f(kernel) with the kernel of point x, wrapping as wraps_at(group_wraps, x) says.
    template <class F>
    auto with_kernel(const std::array<T, D>& x, bool group_wraps, F&& f) const {
        if constexpr (Periodic) {
            if (wraps_at(group_wraps, x)) {
                if (shifts) return f(point_kernel<T, D, wrap_mode::shift>(x.data(), r2, box));
                return f(point_kernel<T, D, wrap_mode::min_image>(x.data(), r2, box));
            }
        }
        return f(point_kernel<T, D, wrap_mode::none>(x.data(), r2, box));
    }

    /// Periodic box: whether the minimum image may differ from the plain difference for a
    /// point of `cell` and a candidate of its stencil. It cannot when every point lies inside
    /// the box, the stencil does not wrap, and the box spans at least 2k + 3 cells: then
    /// |d| < (k + 1) cells < box / 2 on every axis, so nearbyint(d / box) = 0.
    bool wraps(const std::array<std::int64_t, 3>& cell) const {
        if constexpr (!Periodic) return false;
        if (!grid_access::points_inside_box(g)) return true;
        const auto dims = g.geometry().dims;
        const int k = g.reach();
        for (int a = 0; a < D; ++a)
            if (dims[a] < 2 * k + 3 || cell[a] < k || cell[a] + k >= dims[a]) return true;
        return false;
    }

    /// The cell's stencil into the block (without ids unless with_ids), with its shifts
    /// where grid points wrap by them.
    void gather(const std::array<std::int64_t, 3>& cell, std::int64_t width, bool with_ids = true) {
        nruns = grid_access::stencil_runs(g, cell, runs, width, Periodic ? images : nullptr);
        block.gather(g, runs, nruns, job.ids, with_ids);
        if (shifts && wraps(cell)) block.gather_shifts(runs, images, nruns, box);
    }

    /// The block position of sorted point s, which lies in one of the gathered runs.
    std::uint32_t block_position(std::uint32_t s) const {
        std::uint32_t base = 0;
        for (std::size_t k = 0; k < nruns; ++k) {
            if (s >= runs[k].begin && s < runs[k].end) return base + (s - runs[k].begin);
            base += runs[k].end - runs[k].begin;
        }
        return no_id;
    }

    /// Whether block positions follow ids: the runs of a uniform grid come in slot order (a
    /// periodic one's too), and without caller ids a point's id is its sorted index.
    bool positions_in_id_order() const { return !job.ids && g.kind() == grid_kind::uniform; }
    /// Whether half rows must compare ids (the kernels' ById).
    bool filter_by_id() const { return job.half && !job.queries && !positions_in_id_order(); }

    /// The candidates that enter the row of point s, at block position pos (grid points).
    candidate_filter filter(std::uint32_t s, std::uint32_t pos) const {
        candidate_filter f;
        if (job.queries) return f;  // a query is no grid point: every candidate counts
        if (!job.half) {
            if (!job.self) f.skip = pos;
        } else if (positions_in_id_order()) {
            f.from = job.self ? pos : pos + 1;
        } else {
            f.lo = job.self ? id(s) : id(s) + 1;
        }
        return f;
    }

    void count(std::size_t b, std::size_t e) {
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            gather(cell, width);
            const bool wrap = wraps(cell);
            const std::uint32_t first = job.queries ? 0 : block_position(gb);
            for (std::uint32_t s = gb; s < ge; ++s) {
                const auto x = point(s);
                std::uint32_t c = with_kernel(x, wrap, [&](const auto& kern) {
                    if (!job.half)  // the point itself is always a candidate at distance 0
                        return kern.count_all(block) - (job.self ? 0 : 1);
                    const candidate_filter f = filter(s, first + (s - gb));
                    return filter_by_id() ? kern.template emit<false, true, true>(block, f, nullptr, nullptr)
                                          : kern.template emit<false, true>(block, f, nullptr, nullptr);
                });
                if (job.k_nearest > 0) c = std::uint32_t(std::min<std::size_t>(c, job.k_nearest));
                job.counts[job.queries ? id(s) : s] = c;
            }
        });
    }

    /// Counts every pair once (forward half-stencil) and adds it to both points' counts.
    /// Writes the counts of points in cells up to `reach` layers after [b, e): callers run
    /// sweeps of neighboring slabs one after the other.
    void count_pairs(std::size_t b, std::size_t e) {
        partner_sink partners{job.partner_counts ? job.partner_counts : job.counts};
        if (job.spill_after) partners.e = e, partners.after = job.spill_after;
        if (job.spill_before) partners.b = b, partners.before = job.spill_before;
        const pair_counter<T, D, Periodic> counter{g, r2, box, job.half, job.ids};
        for_each_cell_group(g, b, e, group_width, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            nruns = grid_access::forward_runs(g, cell, runs, width, shifts ? images : nullptr);
            counter.count(gb, ge, runs, shifts ? images : nullptr, nruns, wraps(cell), job.counts, partners);
        });
    }

    /// Rows by the caller's numbering or by query index start at scattered places. Their
    /// starts are read first, in one pass whose reads overlap: read between rows, each waited
    /// for memory (W2 lists at 1M points took 1.8x as long). Empty for rows in sorted order.
    std::vector<std::uint64_t> scattered_row_starts(std::size_t b, std::size_t e) const {
        std::vector<std::uint64_t> starts;
        if (job.ids || job.queries) {
            starts.resize(e - b);
            for (std::size_t s = b; s < e; ++s) starts[s - b] = job.offsets[id(std::uint32_t(s))];
        }
        return starts;
    }

    /// Where the row of point s starts; fetches the lines of a scattered row a few points
    /// before it is written.
    std::uint64_t row_start(const std::vector<std::uint64_t>& starts, std::uint32_t s, std::size_t b, std::size_t e) const {
        if (starts.empty()) return job.offsets[s];
        if (s + row_prefetch_distance < e) {
            const std::uint32_t* ahead = job.indices + starts[s + row_prefetch_distance - b];
            __builtin_prefetch(ahead, 1);
            __builtin_prefetch(ahead + 16, 1);
        }
        return starts[s - b];
    }

    void fill(std::size_t b, std::size_t e) {
        // Rows are written in place; only k-nearest rows, longer than their place, take a buffer.
        const bool need_d2 = job.distances || job.order == row_order::distance || job.k_nearest > 0;
        std::vector<std::uint32_t> row_ids;
        std::vector<T> row_d2;
        std::vector<std::pair<T, std::uint32_t>> pairs;
        const std::vector<std::uint64_t> starts = scattered_row_starts(b, e);
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            gather(cell, width);
            const bool wrap = wraps(cell);
            if (job.k_nearest > 0) grow(row_ids, block.padded), grow(row_d2, block.padded);
            const std::uint32_t first = job.queries ? 0 : block_position(gb);
            for (std::uint32_t s = gb; s < ge; ++s) {
                const auto x = point(s);
                const candidate_filter f = filter(s, first + (s - gb));
                const std::uint64_t dst = row_start(starts, s, b, e);
                std::uint32_t* ids = job.k_nearest > 0 ? row_ids.data() : job.indices + dst;
                T* d2 = job.k_nearest > 0 ? row_d2.data() : job.distances ? job.distances + dst : nullptr;
                if (need_d2 && !d2) {  // ordering by distance without returning distances
                    grow(row_d2, block.padded);
                    d2 = row_d2.data();
                }
                std::uint32_t n = with_kernel(x, wrap, [&](const auto& kern) {
                    if (filter_by_id())
                        return d2 ? kern.template emit<true, false, true>(block, f, ids, d2)
                                  : kern.template emit<false, false, true>(block, f, ids, nullptr);
                    return d2 ? kern.template emit<true>(block, f, ids, d2) : kern.template emit<false>(block, f, ids, nullptr);
                });
                if (job.k_nearest > 0 || job.order == row_order::distance ||
                    (job.order == row_order::index && !std::is_sorted(ids, ids + n))) {
                    if (d2) n = sort_row(n, ids, d2, pairs);
                    else sort_ids(ids, n);
                }
                if (job.k_nearest > 0 && n > 0) std::memcpy(job.indices + dst, ids, n * sizeof(std::uint32_t));
                if (job.distances) {
                    T* out = job.distances + dst;
                    for (std::uint32_t k = 0; k < n; ++k) out[k] = std::sqrt(d2[k]);
                }
            }
        });
    }

    /// One bit per candidate of a block, a word per vector.
    using hit_word = std::conditional_t<(kernel::L::n > 8), std::uint16_t, std::uint8_t>;

    std::size_t kept_hit_bytes(std::size_t b, std::size_t e, std::size_t limit) {
        std::size_t bytes = 0;
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            if (bytes > limit) return;  // the caller gives up: no more stencil lookups
            nruns = grid_access::stencil_runs(g, cell, runs, width);
            std::uint32_t total = 0;
            for (std::size_t k = 0; k < nruns; ++k) total += runs[k].end - runs[k].begin;
            bytes += std::size_t(ge - gb) * (candidate_block<T, D>::padded_size(total) / kernel::L::n) * sizeof(hit_word);
        });
        return bytes;
    }

    /// The count sweep of a list, keeping the hit bits of every vector in job.hits.
    void count_kept(std::size_t b, std::size_t e) {
        auto* bits = reinterpret_cast<hit_word*>(job.hits);
        const bool by_id = filter_by_id();
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            gather(cell, width, by_id);
            const bool wrap = wraps(cell);
            const std::uint32_t first = job.queries ? 0 : block_position(gb);
            const std::uint32_t vectors = block.padded / kernel::L::n;
            for (std::uint32_t s = gb; s < ge; ++s, bits += vectors) {
                const auto x = point(s);
                const candidate_filter f = filter(s, first + (s - gb));
                job.counts[job.queries ? id(s) : s] = with_kernel(x, wrap, [&](const auto& kern) {
                    return by_id ? kern.template keep_hits<true>(block, f, bits) : kern.template keep_hits<false>(block, f, bits);
                });
            }
        });
    }

    /// fill from the bits that count_kept kept: the ids they select, no distance computed.
    void fill_kept(std::size_t b, std::size_t e) {
        const auto* next = reinterpret_cast<const hit_word*>(job.hits);
        const std::vector<std::uint64_t> starts = scattered_row_starts(b, e);
        // Half rows in id order by block position: the vectors before the point's hold no hit.
        const bool from_position = job.half && !job.queries && positions_in_id_order();
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            nruns = grid_access::stencil_runs(g, cell, runs, width);
            block.gather_ids(runs, nruns, job.ids);
            const std::uint32_t padded = block.padded;
            const std::uint32_t* __restrict ids = block.id.data();
            const std::uint32_t first = from_position ? block_position(gb) : 0;
            // A local cursor: a captured one would be reloaded after every store.
            const hit_word* __restrict bits = next;
            for (std::uint32_t s = gb; s < ge; ++s, bits += padded / kernel::L::n) {
                std::uint32_t* __restrict out = job.indices + row_start(starts, s, b, e);
                std::uint32_t n = 0;
                const std::uint32_t from = from_position ? filter(s, first + (s - gb)).from / kernel::L::n * kernel::L::n : 0;
                constexpr std::uint32_t lanes = kernel::L::n;
                std::uint32_t k = from;
                for (; k + 2 * lanes <= padded; k += 2 * lanes)
                    n += store_hit_pair<lanes>(out + n, bits[k / lanes], bits[k / lanes + 1], ids + k);
                if (k < padded) n += store_hits<lanes>(out + n, bits[k / lanes], ids + k);
                if (job.order == row_order::index && !std::is_sorted(out, out + n)) sort_ids(out, n);
            }
            next = bits;
        });
    }

    /// Orders a row by distance (ties by id) or by id, keeping the k nearest when asked.
    std::uint32_t sort_row(std::uint32_t n, std::uint32_t* ids, T* d2, std::vector<std::pair<T, std::uint32_t>>& pairs) const {
        pairs.resize(n);
        for (std::uint32_t k = 0; k < n; ++k) pairs[k] = {d2[k], ids[k]};
        if (job.k_nearest > 0 && n > job.k_nearest) {
            std::nth_element(pairs.begin(), pairs.begin() + std::ptrdiff_t(job.k_nearest - 1), pairs.end());
            n = std::uint32_t(job.k_nearest);
            pairs.resize(n);
        }
        if (job.k_nearest > 0 || job.order == row_order::distance) {
            std::sort(pairs.begin(), pairs.end());
        } else {
            std::sort(pairs.begin(), pairs.end(), [](const auto& l, const auto& r) { return l.second < r.second; });
        }
        for (std::uint32_t k = 0; k < n; ++k) d2[k] = pairs[k].first, ids[k] = pairs[k].second;
        return n;
    }
};

/// f(sweeper) with the sweeper of g's kind of box.
template <class T, int D, class F>
auto with_sweeper(const grid<T, D>& g, const sweep_job<T>& job, F&& f) {
    if (g.periodic()) {
        sweeper<T, D, true> s(g, job);
        return f(s);
    }
    sweeper<T, D, false> s(g, job);
    return f(s);
}

template <class T, int D>
void count(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.count(b, e); });
}
template <class T, int D>
void count_pairs(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.count_pairs(b, e); });
}
template <class T, int D>
void fill(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.fill(b, e); });
}
template <class T, int D>
std::size_t kept_hit_bytes(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e, std::size_t limit) {
    return with_sweeper(g, job, [&](auto& s) { return s.kept_hit_bytes(b, e, limit); });
}
template <class T, int D>
void count_kept(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.count_kept(b, e); });
}
template <class T, int D>
void fill_kept(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.fill_kept(b, e); });
}

template <class T, int D>
void uniform_slots(const T* coords, std::size_t b, std::size_t e, const uniform_frame& f, std::uint32_t* out) {
    // grid_geometry's cell_of and slot_of_cell in 32-bit lanes (tests/unit/uniform_slots_test
    // checks that they agree); min/max rather than std::clamp, so that the loop is branch-free
    // and vectorizes.
    for (std::size_t i = b; i < e; ++i) {
        std::uint32_t cell[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a) {
            const double u = (double(coords[i * D + a]) - f.lo[a]) * f.inv[a];
            cell[a] = std::uint32_t(std::int32_t(std::min(std::max(u, 0.0), f.top[a])));
        }
        out[i - b] = cell[0] + f.stride1 * cell[1] + f.stride2 * cell[2];
    }
}

template <class T, int D>
void hashed_slots(const T* coords, std::size_t b, std::size_t e, const hashed_frame& f, std::uint32_t* out) {
    for (std::size_t i = b; i < e; ++i) {
        std::int64_t cell[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a)  // |v| < 2^52 cells is checked at build
            cell[a] = floor_to_int(double(coords[i * D + a]) * f.inv[a]);
        out[i - b] = std::uint32_t(hashed_slot(cell[0], cell[1], cell[2], f.mask));
    }
}

template <class T, int D>
void bounds(const T* coords, std::size_t b, std::size_t e, T* lo, T* hi, T* nonfinite) {
    // Over the interleaved values in blocks of 16 points, one accumulator per position: value
    // l of a block belongs to axis l % D, so the loop vectorizes without shuffles. v - v is 0
    // for a finite v and NaN otherwise.
    constexpr std::size_t w = 16 * D;
    T mn[w], mx[w], bad[w];
    for (std::size_t l = 0; l < w; ++l) mn[l] = T(INFINITY), mx[l] = -T(INFINITY), bad[l] = 0;
    const T* __restrict x = coords + b * D;
    const std::size_t total = (e - b) * D;
    auto take = [&](std::size_t l, T v) {
        mn[l] = v < mn[l] ? v : mn[l];
        mx[l] = v > mx[l] ? v : mx[l];
        bad[l] += v - v;
    };
    std::size_t i = 0;
    for (; i + w <= total; i += w)
        for (std::size_t l = 0; l < w; ++l) take(l, x[i + l]);
    for (; i < total; ++i) take(i % w, x[i]);
    for (int a = 0; a < D; ++a) lo[a] = T(INFINITY), hi[a] = -T(INFINITY), nonfinite[a] = 0;
    for (std::size_t l = 0; l < w; ++l) {
        const std::size_t a = l % D;
        lo[a] = std::min(lo[a], mn[l]);
        hi[a] = std::max(hi[a], mx[l]);
        nonfinite[a] += bad[l];
    }
}

template <class T, int D>
const sweep_kernels<T, D>& table() {
    static const sweep_kernels<T, D> t{&count<T, D>,         &count_pairs<T, D>, &fill<T, D>,
                                       &kept_hit_bytes<T, D>, &count_kept<T, D>,  &fill_kept<T, D>,
                                       &uniform_slots<T, D>,  &hashed_slots<T, D>, &bounds<T, D>};
    return t;
}

template const sweep_kernels<float, 2>& table<float, 2>();
template const sweep_kernels<float, 3>& table<float, 3>();
template const sweep_kernels<double, 2>& table<double, 2>();
template const sweep_kernels<double, 3>& table<double, 3>();

}  // namespace frnn::detail::FRNN_SWEEP_NS
