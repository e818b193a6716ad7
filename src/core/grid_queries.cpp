// Bulk queries: neighbor counts, CSR lists, k nearest within r, and queries from other points,
// all by cell sweeps (sweep.hpp): row sizes first, then every row written in place, so the
// output does not depend on the thread count.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>

#include "core/grid_access.hpp"
#include "core/hit_masks.hpp"
#include "core/slab_schedule.hpp"
#include "core/sweep.hpp"
#include "cpu/parallel.hpp"
#include "frnn/grid.hpp"

namespace frnn {

namespace {

/// Leaves new elements of a resized vector uninitialized: the count sweep writes every row
/// size, and zero-filling them first would cost a pass over the array.
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

}  // namespace

namespace detail {

/// Runs the traversals of one grid; a friend-free home for the query code.
template <class T, int D>
struct query_engine {
    const grid<T, D>& g;
    int threads;

    explicit query_engine(const grid<T, D>& gr) : g(gr), threads(gr.threads()) {}

    /// Query indices ordered by the grid slot of their cell (stable), so that the queries of a
    /// cell are consecutive and share one candidate block.
    std::vector<std::uint32_t> queries_by_cell(std::span<const T> queries) const {
        const std::size_t n = queries.size() / D, slots = g.slot_count();
        std::vector<std::uint32_t> slot(n);
        for_each_chunk(n, chunk_count(n, threads, 1 << 14), threads, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t q = b; q < e; ++q) {
                std::array<T, D> x;
                for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
                slot[q] = std::uint32_t(g.geometry().slot_of_cell(g.geometry().cell_of(x)));
            }
        });
        std::vector<std::uint32_t> start(slots + 1, 0);
        for (auto v : slot) ++start[v];
        exclusive_scan(start.data(), slots + 1, threads);
        std::vector<std::uint32_t> order(n);
        for (std::size_t q = 0; q < n; ++q) order[start[slot[q]]++] = std::uint32_t(q);
        return order;
    }

    /// Rows of query points: sizes by a sweep over the queries in cell order, then the rows in
    /// place, as swept_lists does for the grid's own points.
    void swept_query_lists(csr<T>& out, std::span<const T> queries, const list_options& o, std::size_t k_nearest,
                           const T* query_r2) const {
        if (o.rows != list_options::all_rows)
            throw error("list_options.rows applies to the lists of a grid's own points, not to queries");
        const std::size_t rows = queries.size() / D;
        const auto order = queries_by_cell(queries);
        const auto perm = g.sorted_to_original();
        sweep_job<T> job;
        job.ids = o.space == index_space::sorted ? nullptr : perm.data();
        job.self = true;  // no point of the grid is the query itself: keep every candidate
        job.k_nearest = k_nearest;
        job.order = k_nearest > 0 ? row_order::distance : o.order;
        job.rows = sweep_job<T>::row_source::query_points;
        job.queries = queries.data();
        job.query_order = order.data();
        job.query_r2 = query_r2;
        resize_discarding(out.offsets, rows + 1);
        out.offsets[rows] = 0;
        std::vector<std::uint32_t, uninitialized_allocator<std::uint32_t>> sizes(rows);
        job.counts = sizes.data();
        std::size_t parts = chunk_count(rows, threads, 2048);
        const auto kept = keeps_hit_masks(o, k_nearest) ? plan_hit_masks(job, rows, parts) : nullptr;
        count_rows(job, rows, parts, kept.get());
        std::copy(sizes.begin(), sizes.end(), out.offsets.begin());
        fill_rows(out, job, o.distances, parts, kept.get());
    }

    /// Neighbor counts of query points by query index.
    std::vector<std::uint32_t> query_counts(std::span<const T> queries, const T* query_r2) const {
        const std::size_t rows = queries.size() / D;
        std::vector<std::uint32_t> out(rows);
        const auto order = queries_by_cell(queries);
        sweep_job<T> job;
        job.self = true;
        job.rows = sweep_job<T>::row_source::query_points;
        job.queries = queries.data();
        job.query_order = order.data();
        job.query_r2 = query_r2;
        job.counts = out.data();
        const auto& kernels = sweep_for_cpu<T, D>();
        for_each_chunk(rows, chunk_count(rows, threads, 2048), threads,
                       [&](std::size_t, std::size_t b, std::size_t e) { kernels.count(g, job, b, e); });
        return out;
    }

    /// Neighbor lists of all grid points or of query points; with k_nearest > 0 at most that many
    /// nearest per row.
    csr<T> lists(std::span<const T> queries, bool from_queries, const list_options& o, std::size_t k_nearest,
                 const T* query_r2 = nullptr) const {
        csr<T> out;
        if (from_queries) swept_query_lists(out, queries, o, k_nearest, query_r2);
        else swept_lists(out, o, k_nearest);
        return out;
    }

    /// Neighbor counts of the grid's own points by sorted index (the point itself included
    /// when `self`), visiting each pair of cells once (slab_schedule.hpp on the uniform grid).
    /// With `half`, the sizes of half rows: each pair counts for the point of the smaller id,
    /// ids[sorted point] or, without ids, the sorted index.
    void full_counts(std::uint32_t* counts, bool self, bool half = false, const std::uint32_t* ids = nullptr) const {
        const std::size_t rows = g.size();
        const auto& kernels = sweep_for_cpu<T, D>();
        sweep_job<T> job;
        job.self = self;
        job.half = half;
        job.ids = ids;
        job.counts = counts;
        const auto dims = g.geometry().dims;
        if (g.has_point_radii()) {
            // Pairs within r_i of i are not pairs within r_j of j (gather): counted per point.
            for_each_chunk(rows, chunk_count(rows, threads, 2048), threads,
                           [&](std::size_t, std::size_t b, std::size_t e) { kernels.count(g, job, b, e); });
            return;
        }
        if (g.periodic()) {
            // The wrapped forward half-stencil meets each pair of cells once only when every
            // periodic axis has 2 reach + 1 cells or more; smaller boxes count per point.
            bool fits = true;
            for (int a = 0; a < D; ++a) fits = fits && (!g.geometry().wraps[a] || dims[a] >= 2 * g.reach() + 1);
            if (!fits) {
                for_each_chunk(rows, chunk_count(rows, threads, 2048), threads,
                               [&](std::size_t, std::size_t b, std::size_t e) { kernels.count(g, job, b, e); });
                return;
            }
        }
        const std::uint32_t start = self ? 1 : 0;
        // In parallel: the array may be fresh memory, whose page faults take longer than the fill.
        for_each_chunk(rows, chunk_count(rows, threads, 1 << 15), threads,
                       [&](std::size_t, std::size_t b, std::size_t e) { std::fill(counts + b, counts + e, start); });
        if (g.kind() != grid_kind::uniform) {
            // Hashed: the partners of a cell lie anywhere in memory, so each thread adds their
            // counts into its own array, summed at the end (integers: the same for any order).
            const std::size_t parts = chunk_count(rows, threads, 2048);
            const int workers = int(std::min<std::size_t>(parts, std::size_t(threads)));
            std::vector<std::vector<std::uint32_t>> partners(std::size_t(workers), std::vector<std::uint32_t>(rows, 0));
            parallel_chunks(parts, workers, [&](std::size_t c, int worker) {
                sweep_job<T> own = job;
                own.partner_counts = partners[std::size_t(worker)].data();
                kernels.count_pairs(g, own, chunk_bound(rows, parts, c), chunk_bound(rows, parts, c + 1));
            });
            for_each_chunk(rows, chunk_count(rows, threads, 1 << 15), threads, [&](std::size_t, std::size_t b, std::size_t e) {
                for (const auto& p : partners)
                    for (std::size_t i = b; i < e; ++i) counts[i] += p[i];
            });
            return;
        }
        // Uniform: slabs of cell layers swept at the same time, each keeping what it adds to
        // the next slab's points in a spill of its own, added in after all sweeps.
        const auto slabs = layer_slabs(std::size_t(dims[D - 1]), std::size_t(g.reach()), threads);
        const std::size_t n = slabs.size();
        const std::size_t per_layer = D == 3 ? std::size_t(dims[0] * dims[1]) : std::size_t(dims[0]);
        const auto starts = grid_access::cell_starts(g);
        auto first_point = [&](std::size_t layer) { return std::size_t(starts[layer * per_layer]); };
        // Slab k spills into the points [into[k], into[k] + size) at spill[at[k]...): the
        // `reach` layers after it, or the last slab of a periodic box the first `reach` layers.
        const bool wraps = g.geometry().wraps[D - 1] && n > 1;
        std::vector<std::size_t> into(n, 0), at(n + 1, 0);
        for (std::size_t k = 0; k < n; ++k) {
            const bool last = k + 1 == n;
            const std::size_t spill_layers = last ? (wraps ? std::size_t(g.reach()) : 0) : std::size_t(g.reach());
            const std::size_t from = last ? 0 : slabs[k].end;
            into[k] = first_point(from);
            at[k + 1] = at[k] + first_point(from + spill_layers) - into[k];
        }
        buffer<std::uint32_t> spill(at[n]);
        parallel_chunks(n, threads, [&](std::size_t k, int) {
            std::fill(spill.data() + at[k], spill.data() + at[k + 1], 0u);
            sweep_job<T> own = job;
            if (k + 1 < n) own.spill_after = spill.data() + at[k];
            else if (wraps) own.spill_before = spill.data() + at[k];
            kernels.count_pairs(g, own, first_point(slabs[k].begin), first_point(slabs[k].end));
        });
        parallel_chunks(n, threads, [&](std::size_t k, int) {
            for (std::size_t i = at[k]; i < at[k + 1]; ++i) counts[into[k] + i - at[k]] += spill[i];
        });
    }

    /// Lists of the grid's own points by two cell sweeps: row sizes, then rows in place.
    void swept_lists(csr<T>& out, const list_options& o, std::size_t k_nearest) const {
        const std::size_t rows = g.size();
        if (o.rows != list_options::all_rows && o.rows > rows)
            throw error("list_options.rows is " + std::to_string(o.rows) + ", more than the grid's " +
                        std::to_string(rows) + " points");
        const std::size_t with_rows = std::min(o.rows, rows);  // the others' rows stay empty
        const auto perm = g.sorted_to_original();
        const bool sorted_space = o.space == index_space::sorted;
        sweep_job<T> job;
        job.row_limit = std::uint32_t(with_rows);
        job.ids = sorted_space ? nullptr : perm.data();
        job.half = o.half;
        job.self = o.self;
        job.k_nearest = k_nearest;
        job.order = k_nearest > 0 ? row_order::distance : o.order;
        std::vector<std::uint32_t, uninitialized_allocator<std::uint32_t>> sizes(rows);
        job.counts = sizes.data();
        std::size_t parts = chunk_count(rows, threads, 2048);
        const auto kept = keeps_hit_masks(o, k_nearest) ? plan_hit_masks(job, rows, parts) : nullptr;
        // Half rows count each pair once, for the row that holds it, unless a point's sweep
        // skips the candidates before it anyway: an open uniform grid in its own numbering
        // (W8 half lists in the caller's numbering, 32,000 atoms, 1 thread: 42 -> 23 ms).
        const bool half_by_point = o.half && (k_nearest > 0 || (!job.ids && !g.periodic() && g.kind() == grid_kind::uniform));
        if (kept || half_by_point) {
            count_rows(job, rows, parts, kept.get());
        } else {
            full_counts(sizes.data(), o.self, o.half, job.ids);
            if (k_nearest > 0) {
                for (auto& c : sizes) c = std::uint32_t(std::min<std::size_t>(c, k_nearest));
            }
        }

        resize_discarding(out.offsets, rows + 1);
        out.offsets[rows] = 0;
        for_each_chunk(rows, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t s = b; s < e; ++s) {
                if (!sorted_space && s + 16 < e) __builtin_prefetch(&out.offsets[perm[s + 16]], 1);
                const std::size_t row = sorted_space ? s : perm[s];
                out.offsets[row] = row < with_rows ? sizes[s] : 0;  // the pair counts count every point
            }
        });
        fill_rows(out, job, o.distances, parts, kept.get());
        out.offsets.resize(with_rows + 1);  // the rows after are empty: their offsets are all the total
    }

    /// Whether the rows of a list are ones whose hit bits the count sweep can keep: rows (full
    /// or half, not the k nearest) in block order or sorted by index, without distances.
    static bool keeps_hit_masks(const list_options& o, std::size_t k_nearest) {
        return k_nearest == 0 && !o.distances && o.order != row_order::distance;
    }

    /// The count sweep of a list: row sizes into job.counts, keeping the hit bits if `kept`.
    void count_rows(const sweep_job<T>& job, std::size_t rows, std::size_t parts, hit_masks* kept) const {
        const auto& kernels = sweep_for_cpu<T, D>();
        for_each_chunk(rows, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            if (!kept) return kernels.count(g, job, b, e);
            sweep_job<T> own = job;
            own.hits = kept->chunk(c);
            kernels.count_keeping_masks(g, own, b, e);
        });
    }

    /// Rows without distances can skip the second round of distance tests: the count
    /// sweep keeps the hit bits and the fill writes the ids they select (W1 lists at 1M points,
    /// 2 threads: 114 -> 96 ms, into a reused output 99 -> 77). Returns their store, cut into
    /// chunks of at most 32,768 points (`parts` becomes their number), when the bits take at
    /// most 32 bytes per point (W1 on AVX-512 takes 28); null otherwise (dense or clustered
    /// points), leaving `parts` alone.
    std::unique_ptr<hit_masks> plan_hit_masks(const sweep_job<T>& job, std::size_t rows, std::size_t& parts) const {
        constexpr std::size_t budget_per_point = 32, max_chunk = 32768;
        if (rows == 0) return nullptr;
        // Small chunks even on one thread: the memory of each goes back once it is filled.
        const std::size_t chunks = std::max(parts, (rows + max_chunk - 1) / max_chunk);
        std::vector<std::size_t> bytes(chunks);
        const auto& kernels = sweep_for_cpu<T, D>();
        // Sizing looks up every stencil (a hashed grid's lookups cost as much as a count of
        // sparse cells), so it stops where the bits cannot fit: a chunk at twice its share.
        std::atomic<bool> over{false};
        for_each_chunk(rows, chunks, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            if (over.load(std::memory_order_relaxed)) return;
            const std::size_t limit = 2 * budget_per_point * (e - b);
            bytes[c] = kernels.hit_mask_bytes(g, job, b, e, limit);
            if (bytes[c] > limit) over = true;
        });
        if (over || std::accumulate(bytes.begin(), bytes.end(), std::size_t(0)) > budget_per_point * rows) return nullptr;
        parts = chunks;
        return std::make_unique<hit_masks>(bytes);
    }

    /// The second sweep of a list: out.offsets[0, rows) hold the row sizes; makes them offsets,
    /// sizes the rows and lets every point write its own, from the kept hit bits if given.
    void fill_rows(csr<T>& out, sweep_job<T>& job, bool distances, std::size_t parts, hit_masks* kept = nullptr) const {
        const std::size_t rows = out.offsets.size() - 1;
        const std::uint64_t total = exclusive_scan(out.offsets.data(), rows + 1, threads);
        resize_discarding(out.indices, total);
        resize_discarding(out.distances, distances ? total : 0);
        job.offsets = out.offsets.data();
        job.indices = out.indices.data();
        job.distances = distances ? out.distances.data() : nullptr;
        const auto& kernels = sweep_for_cpu<T, D>();
        for_each_chunk(rows, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            if (!kept) return kernels.fill(g, job, b, e);
            sweep_job<T> own = job;
            own.hits = kept->chunk(c);
            kernels.fill_from_masks(g, own, b, e);
            kept->done(c);
        });
        // The distances of a scaled search, back in the caller's units.
        const T inv = T(1) / g.search_scale();
        if (distances && inv != 1) {
            for_each_chunk(total, chunk_count(total, threads, 1 << 15), threads, [&](std::size_t, std::size_t b, std::size_t e) {
                for (std::size_t k = b; k < e; ++k) out.distances[k] *= inv;
            });
        }
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

};

}  // namespace detail

template <class T, int D>
std::vector<std::uint32_t> grid<T, D>::count_neighbors(index_space space) const {
    detail::query_engine<T, D> q(*this);
    if (space == index_space::sorted) {
        std::vector<std::uint32_t> out(size());
        q.full_counts(out.data(), false);
        return out;
    }
    // Counted into an uninitialized array (the result's own zero-fill is serial), then
    // scattered to the caller's order (a permutation: threads write distinct elements).
    buffer<std::uint32_t> sorted(size());
    q.full_counts(sorted.data(), false);
    std::vector<std::uint32_t> out(size());
    const int threads = q.threads;
    detail::for_each_chunk(size(), detail::chunk_count(size(), threads, 1 << 15), threads,
                           [&](std::size_t, std::size_t b, std::size_t e) {
                               for (std::size_t s = b; s < e; ++s) {
                                   if (s + 16 < e) __builtin_prefetch(&out[perm_[s + 16]], 1);
                                   out[perm_[s]] = sorted[s];
                               }
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
    q.swept_lists(out, options, 0);
}

template <class T, int D>
csr<T> grid<T, D>::nearest(std::size_t k, const list_options& options) const {
    if (k == 0) throw error("nearest: k must be at least 1");
    return detail::query_engine<T, D>(*this).lists({}, false, options, k);
}

template <class T, int D>
csr<T> grid<T, D>::query(std::span<const T> queries, const list_options& options) const {
    require_one_radius("query");
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    return q.lists(queries, true, options, 0);
}

template <class T, int D>
std::vector<std::uint32_t> grid<T, D>::query_counts(std::span<const T> queries) const {
    require_one_radius("query_counts");
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    return q.query_counts(queries, nullptr);
}

template <class T, int D>
csr<T> grid<T, D>::query_nearest(std::span<const T> queries, std::size_t k, const list_options& options) const {
    if (k == 0) throw error("query_nearest: k must be at least 1");
    require_one_radius("query_nearest");
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    return q.lists(queries, true, options, k);
}

template <class T, int D>
csr<T> grid<T, D>::query(std::span<const T> queries, std::span<const T> query_radii, const list_options& options) const {
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    const std::vector<T> limits = query_limits(query_radii, queries.size() / D);
    return q.lists(queries, true, options, 0, limits.data());
}

template <class T, int D>
std::vector<std::uint32_t> grid<T, D>::query_counts(std::span<const T> queries, std::span<const T> query_radii) const {
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    const std::vector<T> limits = query_limits(query_radii, queries.size() / D);
    return q.query_counts(queries, limits.data());
}

template <class T, int D>
csr<T> grid<T, D>::query_nearest(std::span<const T> queries, std::span<const T> query_radii, std::size_t k,
                                 const list_options& options) const {
    if (k == 0) throw error("query_nearest: k must be at least 1");
    detail::query_engine<T, D> q(*this);
    std::vector<T> storage;
    queries = search_queries(queries, storage);
    const std::vector<T> limits = query_limits(query_radii, queries.size() / D);
    return q.lists(queries, true, options, k, limits.data());
}

template <class T, int D>
std::span<const T> grid<T, D>::search_queries(std::span<const T> queries, std::vector<T>& storage) const {
    if (queries.size() % D != 0)
        throw error("query array has " + std::to_string(queries.size()) +
                    " values, not a multiple of the dimension " + std::to_string(D));
    bool as_given = geometry_.scale == 1;
    for (std::size_t q = 0; q < queries.size() / D; ++q) {
        point x;
        for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
        check_query_point(x, q);
        for (int a = 0; a < D; ++a)
            as_given = as_given && std::abs(double(x[a])) <= geometry_.far_bound &&
                       (!geometry_.wraps[a] || (x[a] >= 0 && x[a] < caller_box(a)));
    }
    if (as_given) return queries;
    storage.resize(queries.size());
    for (std::size_t q = 0; q < queries.size() / D; ++q) {
        point x;
        for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
        const point y = search_point(x, q);
        for (int a = 0; a < D; ++a) storage[q * D + a] = y[a];
    }
    return storage;
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
    template csr<T> grid<T, D>::query(std::span<const T>, std::span<const T>, const list_options&) const; \
    template std::vector<std::uint32_t> grid<T, D>::query_counts(std::span<const T>, std::span<const T>) \
        const;                                                                                      \
    template csr<T> grid<T, D>::query_nearest(std::span<const T>, std::span<const T>, std::size_t,  \
                                              const list_options&) const;                           \
    template std::span<const T> grid<T, D>::search_queries(std::span<const T>, std::vector<T>&) const;
FRNN_INSTANTIATE_QUERIES(float, 2)
FRNN_INSTANTIATE_QUERIES(float, 3)
FRNN_INSTANTIATE_QUERIES(double, 2)
FRNN_INSTANTIATE_QUERIES(double, 3)

}  // namespace frnn
