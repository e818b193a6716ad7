// Counting each pair once: a group's points against the runs of their forward half-stencil,
// with per-lane tallies, adding the partners' counts where the sweep says.
// Included by sweep_impl.hpp inside the instruction-set level's namespace (see there).

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
            if constexpr (Wrap == wrap_mode::min_image) {
                if (box[a] > T(0)) d -= box_v[a] * V::round_even(d / box_v[a]);  // a periodic axis
            }
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
