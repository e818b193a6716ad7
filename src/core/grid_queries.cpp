// Bulk queries: neighbor counts, CSR lists, k nearest within r, and queries from other points.
// Points are processed in chunks of cell order (grid points) or caller order (query points);
// each chunk fills its own buffer, and buffers are combined in chunk order, so the output does
// not depend on the thread count.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/sweep.hpp"
#include "cpu/parallel.hpp"
#include "cpu/run_kernels.hpp"
#include "cpu/simd_mask.hpp"
#include "frnn/grid.hpp"

namespace frnn {

namespace {

constexpr std::uint32_t no_index = std::numeric_limits<std::uint32_t>::max();

/// Distance tests against runs of sorted points, with raw pointers for the inner loops.
template <class T, int D>
struct distance_kernel {
    const grid<T, D>& g;
    const T* p[D];
    T box[D];
    T r2;
    bool periodic;

    explicit distance_kernel(const grid<T, D>& gr) : g(gr), r2(gr.radius() * gr.radius()), periodic(gr.periodic()) {
        for (int a = 0; a < D; ++a) p[a] = g.sorted_coords(a);
        for (int a = 0; a < D; ++a) box[a] = periodic ? T(g.options().periodic[a]) : T(0);
    }

    /// Squared distances from x to the sorted points [begin, begin + len), into out: one
    /// branch-free loop over contiguous coordinates that the compiler vectorizes.
    template <bool Periodic>
    void d2_block(const std::array<T, D>& x, std::uint32_t begin, std::uint32_t len, T* __restrict out) const {
        const T* __restrict px = p[0] + begin;
        const T* __restrict py = p[1] + begin;
        const T* __restrict pz = p[D - 1] + begin;
        const T x0 = x[0], x1 = x[1], x2 = x[D - 1];
        for (std::uint32_t k = 0; k < len; ++k) {
            T dx = px[k] - x0, dy = py[k] - x1;
            if constexpr (Periodic) {
                dx -= box[0] * std::nearbyint(dx / box[0]);
                dy -= box[1] * std::nearbyint(dy / box[1]);
            }
            T d2 = dx * dx;
            d2 += dy * dy;
            if constexpr (D == 3) {
                T dz = pz[k] - x2;
                if constexpr (Periodic) dz -= box[2] * std::nearbyint(dz / box[2]);
                d2 += dz * dz;
            }
            out[k] = d2;
        }
    }

    /// Calls hit(j, d2) for every point j >= first of the run within r of x, in increasing j.
    /// Open-boundary runs use the SIMD kernel; periodic runs take the general path.
    static constexpr std::uint32_t block_size = 64;
    template <bool Periodic, class Hit>
    void run_hits(const std::array<T, D>& x, const detail::candidate_run& run, std::uint32_t first, Hit&& hit) const {
        const std::uint32_t begin = std::max(run.begin, first);
        if (!Periodic) {
            detail::hits_in_run<T, D>(p, x.data(), begin, run.end, r2, hit);
            return;
        }
        alignas(64) T buf[block_size];
        for (std::uint32_t b = begin; b < run.end; b += block_size) {
            const std::uint32_t len = std::min(block_size, run.end - b);
            d2_block<Periodic>(x, b, len, buf);
            for (std::uint64_t m = detail::le_mask(buf, len, r2); m; m &= m - 1) {
                const std::uint32_t k = std::uint32_t(std::countr_zero(m));
                hit(b + k, buf[k]);
            }
        }
    }

    template <bool Periodic>
    std::uint32_t count(const std::array<T, D>& x, const detail::candidate_run* runs, std::size_t n) const {
        std::uint32_t c = 0;
        for (std::size_t k = 0; k < n; ++k) {
            if (!Periodic) {
                c += detail::count_run<T, D>(p, x.data(), runs[k].begin, runs[k].end, r2);
            } else {
                run_hits<Periodic>(x, runs[k], 0, [&](std::uint32_t, T) { ++c; });
            }
        }
        return c;
    }
};

/// Leaves new elements of a resized vector uninitialized: the chunk buffers grow ahead of
/// their writes, and zero-filling them cost as much as the writes themselves.
template <class U>
struct uninitialized_allocator : std::allocator<U> {
    template <class V>
    struct rebind {
        using other = uninitialized_allocator<V>;
    };
    template <class V>
    void construct(V* p) noexcept {
        ::new (static_cast<void*>(p)) V;
    }
    template <class V, class... Args>
    void construct(V* p, Args&&... args) {
        ::new (static_cast<void*>(p)) V(std::forward<Args>(args)...);
    }
};

/// Growable per-chunk output: neighbor index and squared distance per entry, count per row.
template <class T>
struct chunk_rows {
    std::vector<std::uint32_t, uninitialized_allocator<std::uint32_t>> index;
    std::vector<T, uninitialized_allocator<T>> d2;
    std::vector<std::uint32_t> row_count;
    std::size_t used = 0;
    bool keep_d2 = false;

    void reserve_more(std::size_t extra) {
        if (used + extra <= index.size()) return;
        const std::size_t cap = std::max(used + extra, index.size() * 2 + 1024);
        index.resize(cap);
        if (keep_d2) d2.resize(cap);
    }
};

/// Where the rows of a traversal go and how its indices are renumbered.
struct row_mapping {
    const std::uint32_t* row_of = nullptr;    // processing position -> output row; null: same
    const std::uint32_t* index_of = nullptr;  // sorted index -> output index; null: same
};

template <class T>
csr<T> assemble(std::vector<chunk_rows<T>>& chunks, std::size_t rows, std::size_t chunk_parts, int threads,
                row_mapping map, bool distances, row_order order) {
    csr<T> out;
    out.offsets.assign(rows + 1, 0);
    // Row sizes at their output rows, then offsets.
    detail::for_each_chunk(rows, chunk_parts, threads, [&](std::size_t c, std::size_t b, std::size_t) {
        const auto& ch = chunks[c];
        for (std::size_t k = 0; k < ch.row_count.size(); ++k) {
            const std::size_t p = b + k;
            out.offsets[map.row_of ? map.row_of[p] : p] = ch.row_count[k];
        }
    });
    const std::uint64_t total = detail::exclusive_scan(out.offsets.data(), rows + 1, threads);
    out.indices.resize(total);
    if (distances) out.distances.resize(total);
    detail::for_each_chunk(rows, chunk_parts, threads, [&](std::size_t c, std::size_t b, std::size_t) {
        const auto& ch = chunks[c];
        std::size_t src = 0;
        for (std::size_t k = 0; k < ch.row_count.size(); ++k) {
            const std::size_t p = b + k;
            const std::size_t row = map.row_of ? map.row_of[p] : p;
            std::uint64_t dst = out.offsets[row];
            for (std::uint32_t m = 0; m < ch.row_count[k]; ++m, ++src, ++dst) {
                const std::uint32_t j = ch.index[src];
                out.indices[dst] = map.index_of ? map.index_of[j] : j;
                if (distances) out.distances[dst] = std::sqrt(ch.d2[src]);
            }
        }
        chunks[c] = chunk_rows<T>{};  // release the chunk's memory early
    });
    if (order == row_order::none) return out;
    const std::size_t parts = detail::chunk_count(rows, threads, 4096);
    detail::for_each_chunk(rows, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
        std::vector<std::pair<T, std::uint32_t>> tmp;
        for (std::size_t r = b; r < e; ++r) {
            const std::uint64_t ob = out.offsets[r], oe = out.offsets[r + 1];
            if (!distances && order == row_order::index) {
                std::sort(out.indices.begin() + ob, out.indices.begin() + oe);
                continue;
            }
            tmp.clear();
            for (std::uint64_t m = ob; m < oe; ++m)
                tmp.emplace_back(distances ? out.distances[m] : T(0), out.indices[m]);
            if (order == row_order::index) {
                std::sort(tmp.begin(), tmp.end(), [](auto& l, auto& r2) { return l.second < r2.second; });
            } else {
                std::sort(tmp.begin(), tmp.end());
            }
            for (std::uint64_t m = ob; m < oe; ++m) {
                out.indices[m] = tmp[m - ob].second;
                if (distances) out.distances[m] = tmp[m - ob].first;
            }
        }
    });
    return out;
}

}  // namespace

namespace detail {

/// Runs the traversals of one grid; a friend-free home for the query code.
template <class T, int D>
struct query_engine {
    const grid<T, D>& g;
    int threads;

    explicit query_engine(const grid<T, D>& gr) : g(gr), threads(gr.threads()) {}

    /// Calls per_point(s, x, runs, nruns) for the sorted points [b, e), computing the candidate
    /// runs once per cell.
    template <class F>
    void walk_sorted(std::size_t b, std::size_t e, F&& per_point) const {
        candidate_run runs[max_runs];
        std::size_t s = b;
        while (s < e) {
            std::array<T, D> x;
            for (int a = 0; a < D; ++a) x[a] = g.sorted_coord(s, a);
            const std::size_t group_end = std::min<std::size_t>(g.cell_group_end(std::uint32_t(s)), e);
            const std::size_t n = g.candidate_runs(x, runs);
            for (; s < group_end; ++s) {
                for (int a = 0; a < D; ++a) x[a] = g.sorted_coord(s, a);
                per_point(std::uint32_t(s), x, runs, n);
            }
        }
    }

    /// Calls per_point(q, x, runs, nruns) for the query points [b, e).
    template <class F>
    void walk_queries(std::span<const T> queries, std::size_t b, std::size_t e, F&& per_point) const {
        candidate_run runs[max_runs];
        for (std::size_t q = b; q < e; ++q) {
            std::array<T, D> x;
            for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
            per_point(std::uint32_t(q), x, runs, g.candidate_runs(x, runs));
        }
    }

    /// Traverses all grid points (queries empty) or all query points.
    template <class F>
    void walk(std::span<const T> queries, bool from_queries, std::size_t parts, F&& per_chunk_point) const {
        const std::size_t rows = from_queries ? queries.size() / D : g.size();
        for_each_chunk(rows, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            if (from_queries) {
                walk_queries(queries, b, e, [&](std::uint32_t s, auto& x, auto* runs, std::size_t n) {
                    per_chunk_point(c, s, x, runs, n);
                });
            } else {
                walk_sorted(b, e, [&](std::uint32_t s, auto& x, auto* runs, std::size_t n) {
                    per_chunk_point(c, s, x, runs, n);
                });
            }
        });
    }

    /// Whether the cell sweep (sweep.hpp) serves a query: the grid's own points.
    bool sweeps(bool from_queries) const { return !from_queries; }

    std::vector<std::uint32_t> counts(std::span<const T> queries, bool from_queries, bool self) const {
        const std::size_t rows = from_queries ? queries.size() / D : g.size();
        std::vector<std::uint32_t> out(rows);
        if (sweeps(from_queries)) {
            full_counts(out.data(), self);
            return out;  // at sorted positions
        }
        const distance_kernel<T, D> kern(g);
        const std::uint32_t self_adjust = from_queries || self ? 0 : 1;
        walk(queries, from_queries, chunk_count(rows, threads, 2048),
             [&](std::size_t, std::uint32_t s, const std::array<T, D>& x, const candidate_run* runs, std::size_t n) {
                 out[s] = (kern.periodic ? kern.template count<true>(x, runs, n) : kern.template count<false>(x, runs, n)) -
                          self_adjust;
             });
        return out;  // grid points: at their sorted positions
    }

    /// Neighbor lists of all grid points or of query points; with k_nearest > 0 at most that many
    /// nearest per row. "j > i" of half lists is judged in the numbering `space` asks for.
    csr<T> lists(std::span<const T> queries, bool from_queries, const list_options& o, std::size_t k_nearest) const {
        if (sweeps(from_queries)) {
            csr<T> out;
            swept_lists(out, o, k_nearest);
            return out;
        }
        const std::size_t rows = from_queries ? queries.size() / D : g.size();
        const std::size_t parts = chunk_count(rows, threads, 2048);
        std::vector<chunk_rows<T>> chunks(parts);
        const row_order order = k_nearest > 0 ? row_order::distance : o.order;
        const bool need_d2 = o.distances || order == row_order::distance;
        for (auto& ch : chunks) ch.keep_d2 = need_d2;
        const distance_kernel<T, D> kern(g);
        const auto perm = g.sorted_to_original();
        const bool sorted_space = o.space == index_space::sorted;
        const bool exclude_self = !from_queries && !o.self;
        const bool half = !from_queries && o.half;
        walk(queries, from_queries, parts,
             [&](std::size_t c, std::uint32_t s, const std::array<T, D>& x, const candidate_run* runs, std::size_t n) {
                 auto& ch = chunks[c];
                 const std::size_t start = ch.used;
                 const std::uint32_t skip = exclude_self ? s : no_index;
                 const std::uint32_t ps = from_queries ? 0 : perm[s];
                 const std::uint32_t first = half && sorted_space ? (o.self ? s : s + 1) : 0;
                 auto emit_all = [&](auto periodic_tag) {
                     constexpr bool P = decltype(periodic_tag)::value;
                     for (std::size_t k = 0; k < n; ++k) {
                         const auto& run = runs[k];
                         if (run.end <= first) continue;
                         ch.reserve_more(run.end - std::max(run.begin, first));
                         std::uint32_t* __restrict idx = ch.index.data();
                         T* __restrict dd = ch.d2.data();
                         std::size_t used = ch.used;
                         kern.template run_hits<P>(x, run, first, [&](std::uint32_t j, T d2) {
                             if (j == skip) return;
                             if (half && !sorted_space && !(perm[j] > ps || (o.self && j == s))) return;
                             idx[used] = j;
                             if (need_d2) dd[used] = d2;
                             ++used;
                         });
                         ch.used = used;
                     }
                 };
                 if (kern.periodic) emit_all(std::true_type{});
                 else emit_all(std::false_type{});
                 if (k_nearest > 0) keep_nearest(ch, start, k_nearest, sorted_space ? nullptr : perm.data());
                 ch.row_count.push_back(std::uint32_t(ch.used - start));
             });
        for (auto& ch : chunks) {
            ch.index.resize(ch.used);
            if (need_d2) ch.d2.resize(ch.used);
        }
        row_mapping map;
        if (!from_queries && !sorted_space) map.row_of = perm.data();
        if (!sorted_space) map.index_of = perm.data();
        if (order == row_order::distance && !o.distances) {
            // Sorting by distance needs the distances; drop them afterwards.
            csr<T> out = assemble(chunks, rows, parts, threads, map, true, order);
            out.distances = {};
            return out;
        }
        return assemble(chunks, rows, parts, threads, map, o.distances, order);
    }

    /// Neighbor counts of the grid's own points by sorted index (the point itself included
    /// when `self`). The uniform grid visits each pair of cells once, in two rounds of
    /// alternate slabs of cell layers so that concurrent sweeps never add to the same count.
    void full_counts(std::uint32_t* counts, bool self) const {
        const std::size_t rows = g.size();
        const auto& kernels = sweep_for_cpu<T, D>();
        sweep_job<T> job;
        job.self = self;
        job.counts = counts;
        if (g.periodic()) {
            // The forward half-stencil needs open boundaries: a periodic box counts per point.
            for_each_chunk(rows, chunk_count(rows, threads, 2048), threads,
                           [&](std::size_t, std::size_t b, std::size_t e) { kernels.count(g, job, b, e); });
            return;
        }
        const std::uint32_t start = self ? 1 : 0;
        std::fill(counts, counts + rows, start);
        if (g.kind() != grid_kind::uniform) {
            // Hashed: the partners of a cell lie anywhere in memory, so each thread adds their
            // counts into its own array, summed at the end (integers: the same for any order).
            const std::size_t parts = chunk_count(rows, threads, 2048);
            const int workers = int(std::min<std::size_t>(parts, std::size_t(threads)));
            std::vector<std::vector<std::uint32_t>> partners(std::size_t(workers), std::vector<std::uint32_t>(rows, 0));
            for_each_chunk(rows, parts, workers, [&](std::size_t, std::size_t b, std::size_t e) {
                sweep_job<T> own = job;
                own.partner_counts = partners[std::size_t(omp_get_thread_num())].data();
                kernels.count_pairs(g, own, b, e);
            });
            for_each_chunk(rows, chunk_count(rows, threads, 1 << 15), threads, [&](std::size_t, std::size_t b, std::size_t e) {
                for (const auto& p : partners)
                    for (std::size_t i = b; i < e; ++i) counts[i] += p[i];
            });
            return;
        }
        const auto dims = g.cells_per_axis();
        const std::size_t layers = std::size_t(dims[D - 1]);
        const std::size_t per_layer = D == 3 ? std::size_t(dims[0] * dims[1]) : std::size_t(dims[0]);
        // Slabs at least `reach` layers thick, so that a sweep only reaches into the next slab.
        const std::size_t want = std::max<std::size_t>(1, std::size_t(threads) * 32);
        const std::size_t thick = std::max<std::size_t>(std::size_t(g.reach()), (layers + want - 1) / want);
        const std::size_t slabs = (layers + thick - 1) / thick;
        const auto starts = g.cell_starts();
        for (std::size_t round = 0; round < 2; ++round) {
            const std::size_t n = (slabs + 1 - round) / 2;
            for_each_chunk(n, n, threads, [&](std::size_t c, std::size_t, std::size_t) {
                const std::size_t slab = 2 * c + round;
                const std::size_t z0 = slab * thick, z1 = std::min(layers, z0 + thick);
                kernels.count_pairs(g, job, starts[z0 * per_layer], starts[z1 * per_layer]);
            });
        }
    }

    /// Lists of the grid's own points by two cell sweeps: row sizes, then rows in place.
    void swept_lists(csr<T>& out, const list_options& o, std::size_t k_nearest) const {
        const std::size_t rows = g.size();
        const auto perm = g.sorted_to_original();
        const bool sorted_space = o.space == index_space::sorted;
        sweep_job<T> job;
        job.ids = sorted_space ? nullptr : perm.data();
        job.half = o.half;
        job.self = o.self;
        job.k_nearest = k_nearest;
        job.order = k_nearest > 0 ? row_order::distance : o.order;
        std::vector<std::uint32_t, uninitialized_allocator<std::uint32_t>> sizes(rows);
        job.counts = sizes.data();
        const auto& kernels = sweep_for_cpu<T, D>();
        const std::size_t parts = chunk_count(rows, threads, 2048);
        if (o.half) {
            for_each_chunk(rows, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) { kernels.count(g, job, b, e); });
        } else {
            full_counts(sizes.data(), o.self);
            if (k_nearest > 0) {
                for (auto& c : sizes) c = std::uint32_t(std::min<std::size_t>(c, k_nearest));
            }
        }

        resize_discarding(out.offsets, rows + 1);
        out.offsets[rows] = 0;
        for_each_chunk(rows, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t s = b; s < e; ++s) out.offsets[sorted_space ? s : perm[s]] = sizes[s];
        });
        const std::uint64_t total = exclusive_scan(out.offsets.data(), rows + 1, threads);
        resize_discarding(out.indices, total);
        resize_discarding(out.distances, o.distances ? total : 0);
        job.offsets = out.offsets.data();
        job.indices = out.indices.data();
        job.distances = o.distances ? out.distances.data() : nullptr;
        for_each_chunk(rows, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) { kernels.fill(g, job, b, e); });
    }

    /// Resizes an array whose contents will all be overwritten: growing it allocates afresh
    /// (with a little slack for the next time step) instead of copying the old contents.
    template <class U>
    static void resize_discarding(buffer<U>& v, std::size_t n) {
        if (n > v.capacity()) {
            v = buffer<U>();
            v.reserve(n + n / 16);
        }
        v.resize(n);
    }

    /// Keeps the k nearest of the entries [start, used) of a chunk, ties broken by output index.
    static void keep_nearest(chunk_rows<T>& ch, std::size_t start, std::size_t k, const std::uint32_t* index_of) {
        const std::size_t m = ch.used - start;
        if (m <= k) return;
        std::vector<std::pair<T, std::uint32_t>> tmp(m);
        for (std::size_t i = 0; i < m; ++i) tmp[i] = {ch.d2[start + i], ch.index[start + i]};
        auto key = [&](const std::pair<T, std::uint32_t>& v) {
            return std::pair<T, std::uint32_t>(v.first, index_of ? index_of[v.second] : v.second);
        };
        std::nth_element(tmp.begin(), tmp.begin() + std::ptrdiff_t(k - 1), tmp.end(),
                         [&](auto& l, auto& r) { return key(l) < key(r); });
        for (std::size_t i = 0; i < k; ++i) ch.d2[start + i] = tmp[i].first, ch.index[start + i] = tmp[i].second;
        ch.used = start + k;
    }
};

}  // namespace detail

template <class T, int D>
std::vector<std::uint32_t> grid<T, D>::count_neighbors(index_space space) const {
    detail::query_engine<T, D> q(*this);
    std::vector<std::uint32_t> sorted = q.counts({}, false, false);
    if (space == index_space::sorted) return sorted;
    // Scattered to the caller's order (a permutation: threads write distinct elements).
    std::vector<std::uint32_t> out(size());
    const int threads = q.threads;
    detail::for_each_chunk(size(), detail::chunk_count(size(), threads, 1 << 15), threads,
                           [&](std::size_t, std::size_t b, std::size_t e) {
                               for (std::size_t s = b; s < e; ++s) out[perm_[s]] = sorted[s];
                           });
    return out;
}

template <class T, int D>
csr<T> grid<T, D>::neighbor_lists(const list_options& options) const {
    return detail::query_engine<T, D>(*this).lists({}, false, options, 0);
}

template <class T, int D>
void grid<T, D>::neighbor_lists(csr<T>& out, const list_options& options) const {
    detail::query_engine<T, D> q(*this);
    if (q.sweeps(false)) q.swept_lists(out, options, 0);
    else out = q.lists({}, false, options, 0);
}

template <class T, int D>
csr<T> grid<T, D>::nearest(std::size_t k, const list_options& options) const {
    if (k == 0) throw error("nearest: k must be at least 1");
    return detail::query_engine<T, D>(*this).lists({}, false, options, k);
}

template <class T, int D>
csr<T> grid<T, D>::query(std::span<const T> queries, const list_options& options) const {
    detail::query_engine<T, D> q(*this);
    validate_queries(queries);
    return q.lists(queries, true, options, 0);
}

template <class T, int D>
std::vector<std::uint32_t> grid<T, D>::query_counts(std::span<const T> queries) const {
    detail::query_engine<T, D> q(*this);
    validate_queries(queries);
    return q.counts(queries, true, false);
}

template <class T, int D>
csr<T> grid<T, D>::query_nearest(std::span<const T> queries, std::size_t k, const list_options& options) const {
    if (k == 0) throw error("query_nearest: k must be at least 1");
    detail::query_engine<T, D> q(*this);
    validate_queries(queries);
    return q.lists(queries, true, options, k);
}

template <class T, int D>
void grid<T, D>::validate_queries(std::span<const T> queries) const {
    if (queries.size() % D != 0)
        throw error("query array has " + std::to_string(queries.size()) +
                    " values, not a multiple of the dimension " + std::to_string(D));
    for (std::size_t q = 0; q < queries.size() / D; ++q) {
        point x;
        for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
        check_query_point(x, q);
    }
}

// The class itself is instantiated in grid_build.cpp; these are the members defined here.
#define FRNN_INSTANTIATE_QUERIES(T, D)                                                              \
    template std::vector<std::uint32_t> grid<T, D>::count_neighbors(index_space) const;            \
    template csr<T> grid<T, D>::neighbor_lists(const list_options&) const;                         \
    template void grid<T, D>::neighbor_lists(csr<T>&, const list_options&) const;                  \
    template csr<T> grid<T, D>::nearest(std::size_t, const list_options&) const;                   \
    template csr<T> grid<T, D>::query(std::span<const T>, const list_options&) const;              \
    template std::vector<std::uint32_t> grid<T, D>::query_counts(std::span<const T>) const;        \
    template csr<T> grid<T, D>::query_nearest(std::span<const T>, std::size_t, const list_options&) \
        const;                                                                                      \
    template void grid<T, D>::validate_queries(std::span<const T>) const;
FRNN_INSTANTIATE_QUERIES(float, 2)
FRNN_INSTANTIATE_QUERIES(float, 3)
FRNN_INSTANTIATE_QUERIES(double, 2)
FRNN_INSTANTIATE_QUERIES(double, 3)

}  // namespace frnn
