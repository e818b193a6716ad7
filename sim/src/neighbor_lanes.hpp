// A particle's neighbors taken 8 at a time as the lanes of float vectors (GCC vector
// extensions: two SSE registers on the base x86-64 level, one AVX register in the AVX2 build,
// which also loads the neighbors' values with gather instructions), so a pair pass runs
// without a branch per pair. Lane l of a sum adds the neighbors l, l + 8, l + 16, ... in list
// order and the lanes are added in one fixed order: a particle's sum depends on its neighbor
// list alone, never on the thread count, the loop's split or the instruction-set level (no
// fused multiply-add; square root and division are correctly rounded on every level).
//
// Included once per level by viscoelastic_pairs_impl.hpp, which opens namespace FRNN_SIM_NS
// after every other header (the level's source file includes <cmath>, <cstring> and
// <immintrin.h> first, so nothing else is compiled for the level). FRNN_SIM_AVX2 selects the
// AVX2 loads.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace frnn::sim::detail::FRNN_SIM_NS {

inline constexpr int lane_count = 8;
using lanes = float __attribute__((vector_size(lane_count * sizeof(float))));
using lane_mask = std::int32_t __attribute__((vector_size(lane_count * sizeof(std::int32_t))));

/// Lane-wise square root, correctly rounded like std::sqrt.
inline lanes sqrt_lanes(lanes x) {
#if defined(FRNN_SIM_AVX2)
    return lanes(_mm256_sqrt_ps(__m256(x)));
#elif defined(__SSE__)
    __m128 half[2];
    std::memcpy(half, &x, sizeof x);
    half[0] = _mm_sqrt_ps(half[0]);
    half[1] = _mm_sqrt_ps(half[1]);
    std::memcpy(&x, half, sizeof x);
    return x;
#else
    for (int l = 0; l < lane_count; ++l) x[l] = std::sqrt(x[l]);
    return x;
#endif
}

/// a where the mask is set, else 0 (a may be inf or NaN in the cleared lanes).
inline lanes select(lane_mask m, lanes a) {
    lane_mask bits;
    std::memcpy(&bits, &a, sizeof a);
    bits &= m;
    std::memcpy(&a, &bits, sizeof a);
    return a;
}

/// a where the mask is set, else b.
inline lanes blend(lane_mask m, lanes a, lanes b) {
    lane_mask bits_a, bits_b;
    std::memcpy(&bits_a, &a, sizeof a);
    std::memcpy(&bits_b, &b, sizeof b);
    bits_a = (bits_a & m) | (bits_b & ~m);
    std::memcpy(&a, &bits_a, sizeof a);
    return a;
}

/// The lanes' sum, always in the same order.
inline float sum_lanes(lanes v) { return ((v[0] + v[4]) + (v[2] + v[6])) + ((v[1] + v[5]) + (v[3] + v[7])); }

/// r - box round(r / box): the minimum image on a periodic axis (box > 0), as the grid and
/// particle_solver::offset compute it.
inline lanes minimum_image(lanes r, float box) {
#if defined(FRNN_SIM_AVX2)
    const __m256 k = _mm256_round_ps(__m256(r / box), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    return r - box * lanes(k);
#else
    for (int l = 0; l < lane_count; ++l) r[l] -= box * std::nearbyint(r[l] / box);
    return r;
#endif
}

/// One block of up to 8 neighbors j of particle i: their indices and r = x_j - x_i per axis.
/// Lanes past the end of the list hold j = i and r = (far, 0, 0), farther than any cutoff.
template <int D>
struct neighbor_block {
#if defined(FRNN_SIM_AVX2)
    __m256i j;
#else
    std::uint32_t j[lane_count];
#endif
    lanes r[D];
    lanes r2;  // |r|^2

    /// The indices of list[0, valid), then i in the other lanes.
    void load(const std::uint32_t* list, std::size_t valid, std::size_t i) {
#if defined(FRNN_SIM_AVX2)
        if (valid == lane_count) {
            j = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(list));
        } else {
            const __m256i in_list = _mm256_cmpgt_epi32(_mm256_set1_epi32(int(valid)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
            const __m256i loaded = _mm256_maskload_epi32(reinterpret_cast<const int*>(list), in_list);
            j = _mm256_blendv_epi8(_mm256_set1_epi32(int(i)), loaded, in_list);
        }
#else
        for (std::size_t l = 0; l < lane_count; ++l) j[l] = l < valid ? list[l] : std::uint32_t(i);
#endif
    }

    /// field[j * stride + a] per lane.
    lanes gather(const float* field, int stride, int a) const {
#if defined(FRNN_SIM_AVX2)
        const __m256i at = stride == 1 ? j : _mm256_mullo_epi32(j, _mm256_set1_epi32(stride));
        return lanes(_mm256_i32gather_ps(field + a, at, 4));
#else
        lanes out;
        for (int l = 0; l < lane_count; ++l) out[l] = field[std::size_t(j[l]) * std::size_t(stride) + std::size_t(a)];
        return out;
#endif
    }
};

/// Calls f(block) for the neighbors [begin, end) of particle i in blocks of 8; x holds D
/// coordinates per particle; box the periodic lengths per axis (0: open), or null. Inlined
/// into each pass, so the pass's sums stay in registers.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_neighbor_block(const float* x, const float* box, std::size_t i,
                                                           const std::uint32_t* begin, const std::uint32_t* end,
                                                           float far, F&& f) {
    neighbor_block<D> b;
    for (const std::uint32_t* it = begin; it < end; it += lane_count) {
        const std::size_t valid = std::size_t(end - it) < lane_count ? std::size_t(end - it) : lane_count;
        b.load(it, valid, i);
        b.r2 = lanes{};
        for (int a = 0; a < D; ++a) {
            b.r[a] = b.gather(x, D, a) - x[i * D + a];
            if (box && box[a] > 0) b.r[a] = minimum_image(b.r[a], box[a]);
            b.r2 += b.r[a] * b.r[a];
        }
        if (valid < lane_count) {
            const lane_mask in_list = lane_mask{0, 1, 2, 3, 4, 5, 6, 7} < int(valid);
            b.r[0] = blend(in_list, b.r[0], lanes{} + far);
            b.r2 = blend(in_list, b.r2, lanes{} + far * far);
        }
        f(b);
    }
}

/// One block of up to 8 neighbors read from records of 4 floats per particle ({x, y, z, extra}
/// in 3D, {x, y, unused, extra} in 2D): whole records are loaded and transposed, faster than
/// a gather per field. r = x_j - centre per axis, extra the records' fourth floats. Lanes past
/// the end of the list read the record of a valid index (pad) and hold r = (far, 0, 0).
template <int D>
struct record_block {
    std::uint32_t j[lane_count];
    lanes r[D];
    lanes r2;     // |r|^2
    lanes extra;  // the fourth float of the records read for r

    /// out[c][l] = records[4 j_l + c], for c < 4.
    void read(const float* records, lanes out[4]) const {
#if defined(FRNN_SIM_AVX2)
        __m256 row[4];
        for (int k = 0; k < 4; ++k)
            row[k] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(records + 4 * std::size_t(j[k]))),
                                          _mm_loadu_ps(records + 4 * std::size_t(j[k + 4])), 1);
        const __m256 t0 = _mm256_unpacklo_ps(row[0], row[1]), t1 = _mm256_unpackhi_ps(row[0], row[1]);
        const __m256 t2 = _mm256_unpacklo_ps(row[2], row[3]), t3 = _mm256_unpackhi_ps(row[2], row[3]);
        out[0] = lanes(_mm256_shuffle_ps(t0, t2, 0x44));
        out[1] = lanes(_mm256_shuffle_ps(t0, t2, 0xEE));
        out[2] = lanes(_mm256_shuffle_ps(t1, t3, 0x44));
        out[3] = lanes(_mm256_shuffle_ps(t1, t3, 0xEE));
#else
        for (int l = 0; l < lane_count; ++l)
            for (int c = 0; c < 4; ++c) out[c][l] = records[4 * std::size_t(j[l]) + std::size_t(c)];
#endif
    }
};

/// Calls f(block) for the neighbors [begin, end) of the point at centre (D coordinates) in
/// blocks of 8, the neighbors' positions and fourth floats read from records (see
/// record_block); pad an index for the lanes past the list's end; box the periodic lengths per
/// axis (0: open), or null.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_record_block(const float* records, const float* centre, std::size_t pad,
                                                         const float* box, const std::uint32_t* begin,
                                                         const std::uint32_t* end, float far, F&& f) {
    record_block<D> b;
    for (const std::uint32_t* it = begin; it < end; it += lane_count) {
        const std::size_t valid = std::size_t(end - it) < lane_count ? std::size_t(end - it) : lane_count;
        for (std::size_t l = 0; l < lane_count; ++l) b.j[l] = l < valid ? it[l] : std::uint32_t(pad);
        lanes field[4];
        b.read(records, field);
        b.r2 = lanes{};
        for (int a = 0; a < D; ++a) {
            b.r[a] = field[a] - centre[a];
            if (box && box[a] > 0) b.r[a] = minimum_image(b.r[a], box[a]);
            b.r2 += b.r[a] * b.r[a];
        }
        b.extra = field[3];
        if (valid < lane_count) {
            const lane_mask in_list = lane_mask{0, 1, 2, 3, 4, 5, 6, 7} < int(valid);
            b.r[0] = blend(in_list, b.r[0], lanes{} + far);
            b.r2 = blend(in_list, b.r2, lanes{} + far * far);
        }
        f(b);
    }
}

}  // namespace frnn::sim::detail::FRNN_SIM_NS
