// One point against the candidates of its cell's stencil: the candidate block they are
// gathered into, which of them enter the row, how periodic differences are wrapped, and the
// kernel that counts or stores the hits.
// Included by sweep_impl.hpp inside the instruction-set level's namespace (see there).

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
    /// Symmetric radius per point, from gather_r2: the candidates' squared radii.
    std::vector<T> r2;
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

    /// The squared radii of the runs' points (after gather), from the grid's point_r2.
    void gather_r2(const grid<T, D>& g, const candidate_run* runs, std::size_t nruns) {
        grow(r2, padded + 2 * block_multiple);
        const T* src = grid_access::point_r2(g);
        std::uint32_t m = 0;
        for (std::size_t k = 0; k < nruns; ++k) {
            const std::uint32_t len = runs[k].end - runs[k].begin;
            copy_padded(r2.data() + m, src + runs[k].begin, len);
            m += len;
        }
        std::fill(r2.data() + m, r2.data() + padded, T(0));
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

/// Which candidates of a block enter a point's row: those at block positions from `from` on,
/// except position `skip` (the point itself), and, where the kernel is asked to, with id >= lo.
struct candidate_filter {
    std::uint32_t from = 0;
    std::uint32_t skip = no_id;
    std::uint32_t lo = 0;
};

/// How a periodic box's differences d = candidate - point are wrapped: not at all (the caller
/// knows every correction is zero), by the candidates' shifts (image * L, grid::images_exact),
/// or by the minimum image, d -= L * nearbyint(d / L) on each periodic axis (L > 0), as
/// grid::distance_squared_sorted computes it. The three give the same values where they apply.
enum class wrap_mode { none, shift, min_image };

/// One point against a candidate block, its differences wrapped as `Wrap` says. A candidate
/// is a hit when d2 <= the point's limit, or, ByCandidate (symmetric radius per point), when
/// d2 <= max(limit, the candidate's squared radius).
template <class T, int D, wrap_mode Wrap, bool ByCandidate = false>
struct point_kernel {
    using L = lanes_of<T>;
    using vec = typename L::vec;
    vec x[D];
    vec box[D];
    bool wraps[D];  ///< periodic axes (box length > 0); the others are open
    vec limit;

    point_kernel(const T* point, T r2, const T* box_lengths) : limit(L::splat(r2)) {
        for (int a = 0; a < D; ++a) x[a] = L::splat(point[a]);
        for (int a = 0; a < D; ++a) box[a] = L::splat(box_lengths[a]), wraps[a] = box_lengths[a] > T(0);
    }

    /// A block's coordinate, shift and radius columns.
    struct columns {
        const T* c[D];
        const T* shift[D];
        const T* r2;
        explicit columns(const candidate_block<T, D>& b) : r2(b.r2.data()) {
            for (int a = 0; a < D; ++a) c[a] = b.c[a].data(), shift[a] = b.shift[a].data();
        }
    };

    /// The hit limit of the candidates at positions [k, k + L::n).
    [[gnu::always_inline]] vec limit_at(const columns& c, std::uint32_t k) const {
        if constexpr (!ByCandidate) return limit;
        const vec theirs = L::load(c.r2 + k);
        return limit > theirs ? limit : theirs;
    }

    // Inlined by force: GCC otherwise calls d2 from some of the kernels' loops (W8 half
    // lists spent a sixth of their time in the calls).
    [[gnu::always_inline]] vec delta(const columns& c, std::uint32_t k, int a) const {
        vec d = L::load(c.c[a] + k) - x[a];
        // Padding lanes (+infinity) stay infinite or become NaN, which fails every comparison.
        if constexpr (Wrap == wrap_mode::shift) d -= L::load(c.shift[a] + k);
        if constexpr (Wrap == wrap_mode::min_image) {
            if (wraps[a]) d -= box[a] * L::round_even(d / box[a]);
        }
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
        for (std::uint32_t k = 0; k < padded; k += L::n)
            hits += std::uint32_t(__builtin_popcount(L::le_bits(d2(c, k), limit_at(c, k))));
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
            std::uint32_t m = L::le_bits(d2(c, k), limit_at(c, k));
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
            std::uint32_t m = L::le_bits(d, limit_at(c, k));
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
