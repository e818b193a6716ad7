// The sweeps over the cells of a grid: which points share a candidate block, and the
// sweeper that runs counts, pair counts, fills and kept hits over a range of sorted points.
// Included by sweep_impl.hpp inside the instruction-set level's namespace (see there).

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
    if (g.kind() != grid_kind::uniform || g.periodic() || g.occupied_slots() == 0) return 1;
    // Measured on lattices: 8 points per cell (W1) are best one cell at a time, 4 per cell
    // (W4) three at a time (lists 25% faster, counts 30%).
    const double per_cell = double(g.size()) / double(g.occupied_slots());
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
    /// A radius per grid point: their squares (search space) by sorted index; else null.
    const T* own_r2 = nullptr;
    /// Symmetric radius per point: a candidate's own radius counts too.
    bool symmetric = false;

    sweeper(const grid<T, D>& gr, const sweep_job<T>& j)
        : g(gr), job(j), r2(gr.search_radius() * gr.search_radius()), group_width(group_width_for(gr)) {
        if constexpr (Periodic) {
            for (int a = 0; a < D; ++a) box[a] = gr.geometry().box[a];
            shifts = !job.of_queries() && grid_access::images_exact(gr);
        }
        own_r2 = grid_access::point_r2(gr);
        symmetric = own_r2 && gr.options().rule == radius_rule::symmetric;
    }

    /// The squared search radius of point s (search space).
    T limit(std::uint32_t s) const {
        if (job.of_queries()) return job.query_r2 ? job.query_r2[job.query_order[s]] : r2;
        return own_r2 ? own_r2[s] : r2;
    }

    std::array<T, D> point(std::uint32_t s) const {
        std::array<T, D> x;
        if (job.of_queries()) {
            const T* q = job.queries + std::size_t(job.query_order[s]) * D;
            for (int a = 0; a < D; ++a) x[a] = q[a];
        } else {
            for (int a = 0; a < D; ++a) x[a] = grid_access::search_coord(g, s, a);
        }
        return x;
    }
    /// The id of point s, which is also its output row.
    std::uint32_t id(std::uint32_t s) const {
        if (job.of_queries()) return job.query_order[s];
        return job.ids ? job.ids[s] : s;
    }
    /// Whether grid point s gets no row (list_options::rows).
    bool without_row(std::uint32_t s) const { return !job.of_queries() && id(s) >= job.row_limit; }

    /// Calls f(begin, end, cell, width) for the groups of points of [b, e) that share one
    /// candidate block: for_each_cell_group, or consecutive queries in one cell.
    template <class F>
    void for_each_group(std::size_t b, std::size_t e, F&& f) const {
        if (!job.of_queries()) return for_each_cell_group(g, b, e, group_width, f);
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
        if (group_wraps || !job.of_queries()) return group_wraps;
        for (int a = 0; a < D; ++a)
            if (box[a] > T(0) && !(x[a] >= T(0) && x[a] < box[a])) return true;
        return false;
    }

    /// f(kernel) with the kernel of point s at x, wrapping as wraps_at(group_wraps, x) says.
    template <class F>
    auto with_kernel(std::uint32_t s, const std::array<T, D>& x, bool group_wraps, F&& f) const {
        const T lim = limit(s);
        if (symmetric) return with_kernel_by<true>(x, lim, group_wraps, f);
        return with_kernel_by<false>(x, lim, group_wraps, f);
    }
    template <bool ByCandidate, class F>
    auto with_kernel_by(const std::array<T, D>& x, T lim, bool group_wraps, F&& f) const {
        if constexpr (Periodic) {
            if (wraps_at(group_wraps, x)) {
                if (shifts) return f(point_kernel<T, D, wrap_mode::shift, ByCandidate>(x.data(), lim, box));
                return f(point_kernel<T, D, wrap_mode::min_image, ByCandidate>(x.data(), lim, box));
            }
        }
        return f(point_kernel<T, D, wrap_mode::none, ByCandidate>(x.data(), lim, box));
    }

    /// Periodic box: whether the minimum image may differ from the plain difference for a
    /// point of `cell` and a candidate of its stencil. It cannot when the stencil does not wrap
    /// and the box spans at least 2k + 3 cells (points lie in the box, wrapped): then
    /// |d| < (k + 1) cells < box / 2 on every periodic axis, so nearbyint(d / box) = 0.
    bool wraps(const std::array<std::int64_t, 3>& cell) const {
        if constexpr (!Periodic) return false;
        const auto dims = g.geometry().dims;
        const int k = g.reach();
        for (int a = 0; a < D; ++a)
            if (box[a] > T(0) && (dims[a] < 2 * k + 3 || cell[a] < k || cell[a] + k >= dims[a])) return true;
        return false;
    }

    /// The cell's stencil into the block (without ids unless with_ids), with its shifts where
    /// grid points wrap by them and the candidates' radii when they count.
    void gather(const std::array<std::int64_t, 3>& cell, std::int64_t width, bool with_ids = true) {
        nruns = grid_access::stencil_runs(g, cell, runs, width, Periodic ? images : nullptr);
        block.gather(g, runs, nruns, job.ids, with_ids);
        if (shifts && wraps(cell)) block.gather_shifts(runs, images, nruns, box);
        if (symmetric) block.gather_r2(g, runs, nruns);
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
    bool filter_by_id() const { return job.half && !job.of_queries() && !positions_in_id_order(); }

    /// The candidates that enter the row of point s, at block position pos (grid points).
    candidate_filter filter(std::uint32_t s, std::uint32_t pos) const {
        candidate_filter f;
        if (job.of_queries()) return f;  // a query is no grid point: every candidate counts
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
            const std::uint32_t first = job.of_queries() ? 0 : block_position(gb);
            for (std::uint32_t s = gb; s < ge; ++s) {
                if (without_row(s)) {
                    job.counts[s] = 0;
                    continue;
                }
                const auto x = point(s);
                std::uint32_t c = with_kernel(s, x, wrap, [&](const auto& kern) {
                    if (!job.half)  // the point itself is always a candidate at distance 0
                        return kern.count_all(block) - (job.self ? 0 : 1);
                    const candidate_filter f = filter(s, first + (s - gb));
                    return filter_by_id() ? kern.template emit<false, true, true>(block, f, nullptr, nullptr)
                                          : kern.template emit<false, true>(block, f, nullptr, nullptr);
                });
                if (job.k_nearest > 0) c = std::uint32_t(std::min<std::size_t>(c, job.k_nearest));
                job.counts[job.of_queries() ? id(s) : s] = c;
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
        if (job.ids || job.of_queries()) {
            starts.resize(e - b);
            for (std::size_t s = b; s < e; ++s) starts[s - b] = job.offsets[id(std::uint32_t(s))];
        }
        return starts;
    }

    /// Where the row of point s starts; fetches the lines of a scattered row a few points
    /// before it is written.
    std::uint64_t row_start(const std::vector<std::uint64_t>& starts, std::uint32_t s, std::size_t b, std::size_t e) const {
        if (starts.empty()) return job.offsets[s];
        if (s + row_prefetch_distance < e && job.indices) {  // no pairs at all: no array (and null + k is undefined)
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
            const std::uint32_t first = job.of_queries() ? 0 : block_position(gb);
            if (job.k_nearest > 0) grow(row_ids, block.padded), grow(row_d2, block.padded);
            for (std::uint32_t s = gb; s < ge; ++s) {
                if (without_row(s)) continue;
                const auto x = point(s);
                const candidate_filter f = filter(s, first + (s - gb));
                const std::uint64_t dst = row_start(starts, s, b, e);
                std::uint32_t* ids = job.k_nearest > 0 ? row_ids.data() : job.indices + dst;
                T* d2 = job.k_nearest > 0 ? row_d2.data() : job.distances ? job.distances + dst : nullptr;
                if (need_d2 && !d2) {  // ordering by distance without returning distances
                    grow(row_d2, block.padded);
                    d2 = row_d2.data();
                }
                std::uint32_t n = with_kernel(s, x, wrap, [&](const auto& kern) {
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

    std::size_t hit_mask_bytes(std::size_t b, std::size_t e, std::size_t limit) {
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
    void count_keeping_masks(std::size_t b, std::size_t e) {
        auto* bits = reinterpret_cast<hit_word*>(job.hits);
        const bool by_id = filter_by_id();
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            gather(cell, width, by_id);
            const bool wrap = wraps(cell);
            const std::uint32_t first = job.of_queries() ? 0 : block_position(gb);
            const std::uint32_t vectors = block.padded / kernel::L::n;
            for (std::uint32_t s = gb; s < ge; ++s, bits += vectors) {
                if (without_row(s)) {
                    job.counts[s] = 0;
                    continue;
                }
                const auto x = point(s);
                const candidate_filter f = filter(s, first + (s - gb));
                job.counts[job.of_queries() ? id(s) : s] = with_kernel(s, x, wrap, [&](const auto& kern) {
                    return by_id ? kern.template keep_hits<true>(block, f, bits) : kern.template keep_hits<false>(block, f, bits);
                });
            }
        });
    }

    /// fill from the bits that count_keeping_masks kept: the ids they select, no distance computed.
    void fill_from_masks(std::size_t b, std::size_t e) {
        const auto* next = reinterpret_cast<const hit_word*>(job.hits);
        const std::vector<std::uint64_t> starts = scattered_row_starts(b, e);
        // Half rows in id order by block position: the vectors before the point's hold no hit.
        const bool from_position = job.half && !job.of_queries() && positions_in_id_order();
        for_each_group(b, e, [&](std::uint32_t gb, std::uint32_t ge, const auto& cell, std::int64_t width) {
            nruns = grid_access::stencil_runs(g, cell, runs, width);
            block.gather_ids(runs, nruns, job.ids);
            const std::uint32_t padded = block.padded;
            const std::uint32_t* __restrict ids = block.id.data();
            const std::uint32_t first = from_position ? block_position(gb) : 0;
            // A local cursor: a captured one would be reloaded after every store.
            const hit_word* __restrict bits = next;
            for (std::uint32_t s = gb; s < ge; ++s, bits += padded / kernel::L::n) {
                if (without_row(s)) continue;
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
