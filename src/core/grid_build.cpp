// Grid construction: the counting sort (per-chunk cell counts, exclusive prefix sum, stable
// scatter) over the geometry that grid_plan.cpp chooses. The cell index that follows is in
// grid_cell_index.cpp, the stencils' runs in grid_stencils.cpp.
#include <algorithm>
#include <cmath>
#include <memory>

#include "core/grid_plan.hpp"
#include "core/sweep.hpp"
#include "cpu/page_release.hpp"
#include "cpu/parallel.hpp"
#include "frnn/grid.hpp"

namespace frnn {

namespace {

// Input in random order whose records take at most this many bytes is scattered in one
// pass: they stay in the last-level cache (measured with 32 MiB: at 4 MiB the one pass takes
// two thirds of the time of the two-pass scatter by buckets, at 8 MiB and more longer).
constexpr std::size_t cached_scatter_bytes = std::size_t(6) << 20;
// Points per bucket of the two-pass scatter: a bucket's records and its range of the arrays
// (32 bytes per point in float 3D) stay in the L2 cache, and the first pass writes to few
// enough buckets at a time.
constexpr std::size_t bucket_points = 8192;

// A point on its way through a scatter: one write instead of D + 1.
template <class T, int D>
struct point_record {
    T x[D];
    std::uint32_t index;
};


}  // namespace

template <class T, int D>
int grid<T, D>::threads() const {
    return resolve_thread_count(options_.threads);
}

template <class T, int D>
void grid<T, D>::throw_bad_index(std::size_t i) const {
    throw error("point index " + std::to_string(i) + " out of range (grid has " +
                std::to_string(size()) + " points)");
}

template <class T, int D>
void grid<T, D>::check_query_point(const point& x, std::size_t index) const {
    for (int a = 0; a < D; ++a) {
        if (!std::isfinite(x[a]))
            throw error("query point " + std::to_string(index) + " has a non-finite coordinate (axis " +
                        std::to_string(a) + ")");
    }
}

template <class T, int D>
std::size_t grid<T, D>::memory_bytes() const {
    std::size_t bytes = 0;
    for (const auto& p : pos_) bytes += p.capacity() * sizeof(T);
    for (const auto& p : input_pos_) bytes += p.capacity() * sizeof(T);
    bytes += (point_r2_.capacity() + radii_.capacity()) * sizeof(T);
    bytes += (perm_.capacity() + offsets_.capacity()) * sizeof(std::uint32_t) + inverse_.capacity_bytes();
    bytes += shared_slots_.capacity() * sizeof(std::uint64_t) + occupied_.capacity() * sizeof(detail::occupied_slot_word);
    return bytes;
}

// The empty grid a failed allocation leaves: a grid built over no points with the same radius
// and options (valid, since they were), after the memory of the failed build is let go.
template <class T, int D>
void grid<T, D>::clear() noexcept {
    for (auto& p : pos_) p = buffer<T>();
    for (auto& p : input_pos_) p = buffer<T>();
    perm_ = buffer<std::uint32_t>();
    point_r2_ = buffer<T>();
    radii_ = {};
    thread_counts_ = {};
    scratch_.values = buffer<std::byte>();
    search_input_.values = buffer<T>();
    occupied_ = {};
    shared_slots_ = {};
    try {
        geometry_ = detail::plan_geometry<T, D>({}, radius_, options_, search_input_.values);
        sort_into_cells({});
    } catch (...) {
        // Not even an empty grid's few bytes: size() is 0 already (perm_ is empty).
    }
}

// 1. Plan the geometry (checks everything, changes nothing), 2. take it, 3. sort the points
// into cells and index them, 4. keep the caller's coordinates when the search ones differ (scaled or wrapped)
// (5. and the points' radii in cell order). A failure after step 1 leaves the grid empty.
template <class T, int D>
void grid<T, D>::build(std::span<const T> coords, T radius, const grid_options& options) {
    build_planned(coords, radius, options, false, {});
}

template <class T, int D>
void grid<T, D>::build(std::span<const T> coords, std::span<const T> radii, const grid_options& options) {
    const std::size_t n = coords.size() / D;
    if (coords.size() % D == 0 && radii.size() != n)
        throw error("radius array has " + std::to_string(radii.size()) + " values for " + std::to_string(n) + " points");
    T largest = n == 0 ? T(1) : T(0);
    for (std::size_t i = 0; i < radii.size(); ++i) {
        if (!std::isfinite(radii[i]) || !(radii[i] > 0))
            throw error("radius " + std::to_string(i) + " is " + std::to_string(double(radii[i])) +
                        " (each must be finite and > 0)");
        largest = std::max(largest, radii[i]);
    }
    build_planned(coords, largest, options, true, std::vector<T>(radii.begin(), radii.end()));
}

template <class T, int D>
void grid<T, D>::build_planned(std::span<const T> coords, T radius, const grid_options& options, bool per_point,
                               std::vector<T> radii) {
    buffer<T>& search_input = search_input_.values;
    const grid_geometry<T> planned = detail::plan_geometry<T, D>(coords, radius, options, search_input);
    if (&options != &options_) options_ = options;
    radius_ = radius;
    geometry_ = planned;
    point_radii_ = per_point;
    try {
        radii_ = std::move(radii);
        const bool differ = !search_input.empty();
        sort_into_cells(differ ? std::span<const T>(search_input) : coords);
        keep_input_coordinates(coords, differ);
        auto* const input_bytes = reinterpret_cast<std::byte*>(search_input.data());
        detail::free_lazily(input_bytes, input_bytes + search_input.size() * sizeof(T));
        keep_point_radii();
    } catch (...) {
        clear();
        throw;
    }
}

// The points' radii, squared in search space, in cell order (padded for whole-vector copies).
template <class T, int D>
void grid<T, D>::keep_point_radii() {
    if (!point_radii_) {
        point_r2_ = buffer<T>();
        return;
    }
    point_r2_.resize(size() + detail::coordinate_padding);
    const int t = threads();
    detail::for_each_chunk(size(), detail::chunk_count(size(), t, 1 << 15), t, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t s = b; s < e; ++s) {
            const T r = radii_[perm_[s]] * geometry_.scale;
            point_r2_[s] = r * r;
        }
    });
    std::fill(point_r2_.begin() + std::ptrdiff_t(size()), point_r2_.end(), T(0));
}

template <class T, int D>
T grid<T, D>::check_query_radius(T radius, std::size_t index) const {
    if (!std::isfinite(radius) || !(radius > 0) || radius > radius_)
        throw error("query radius " + std::to_string(index) + " is " + std::to_string(double(radius)) +
                    " (each must be finite, > 0 and at most the grid's " +
                    (point_radii_ ? "largest radius " : "radius ") + std::to_string(double(radius_)) + ")");
    return radius * geometry_.scale;
}

template <class T, int D>
std::vector<T> grid<T, D>::query_limits(std::span<const T> query_radii, std::size_t queries) const {
    if (query_radii.size() != queries)
        throw error("query radius array has " + std::to_string(query_radii.size()) + " values for " +
                    std::to_string(queries) + " query points");
    std::vector<T> out(queries);
    for (std::size_t q = 0; q < queries; ++q) {
        const T r = check_query_radius(query_radii[q], q);
        out[q] = r * r;
    }
    return out;
}

template <class T, int D>
void grid<T, D>::require_one_radius(const char* what) const {
    if (point_radii_)
        throw error(std::string(what) + ": this grid has a radius per point; give the query points radii too");
}

// A grid whose search coordinates differ from the caller's (scaled, which may round tiny ones,
// or wrapped into the periodic box) keeps the caller's too, in cell order.
template <class T, int D>
void grid<T, D>::keep_input_coordinates(std::span<const T> coords, bool differ) {
    for (int a = 0; a < D; ++a) {
        if (!differ) input_pos_[a] = buffer<T>();
        else input_pos_[a].resize(size());
    }
    if (!differ) return;
    const int t = threads();
    detail::for_each_chunk(size(), detail::chunk_count(size(), t, 1 << 14), t, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t s = b; s < e; ++s) {
            const T* x = &coords[std::size_t(perm_[s]) * D];
            for (int a = 0; a < D; ++a) input_pos_[a][s] = x[a];
        }
    });
}

template <class T, int D>
void grid<T, D>::rebuild(std::span<const T> coords) {
    if (!point_radii_) return build(coords, radius_, options_);
    const std::vector<T> radii = radii_;  // build takes a fresh copy, kept only on success
    build(coords, radii, options_);
}

template <class T, int D>
void grid<T, D>::input_slots(const T* coords, std::size_t b, std::size_t e, std::uint32_t* out) const {
    if (geometry_.kind == grid_kind::uniform && !geometry_.periodic) {
        // The common case in vector code (cells within 2^31 per axis: checked in configure).
        detail::uniform_frame f{};
        for (int a = 0; a < D; ++a) f.lo[a] = geometry_.origin[a], f.inv[a] = geometry_.inv_cell[a], f.top[a] = double(geometry_.dims[a] - 1);
        f.stride1 = std::uint32_t(geometry_.dims[0]);
        f.stride2 = std::uint32_t(geometry_.dims[0] * geometry_.dims[1]);
        detail::sweep_for_cpu<T, D>().uniform_slots(coords, b, e, f, out);
        return;
    }
    if (geometry_.kind == grid_kind::hashed) {
        detail::hashed_frame f{};
        for (int a = 0; a < D; ++a) f.inv[a] = geometry_.inv_cell[a];
        f.mask = geometry_.slots - 1;
        detail::sweep_for_cpu<T, D>().hashed_slots(coords, b, e, f, out);
        return;
    }
    for (std::size_t i = b; i < e; ++i) {
        point p;
        for (int a = 0; a < D; ++a) p[a] = coords[i * D + a];
        out[i - b] = slot_of_cell(cell_of(p));
    }
}

// Splits count records into the arrays from position begin on.
template <class T, int D>
template <class Record>
void grid<T, D>::store_records(const Record* records, std::size_t begin, std::size_t count) {
    for (std::size_t j = 0; j < count; ++j) {
        for (int a = 0; a < D; ++a) pos_[a][begin + j] = records[j].x[a];
        perm_[begin + j] = records[j].index;
    }
}

// A stable counting sort by slot, in fixed chunks of the input: chunk c's points go after
// chunk c-1's in every cell, which keeps the order the same for any number of threads.
// 1. slot and count, 2. each chunk's start within each cell, 3. each cell's start,
// 4. scatter, 5. index the cells.
template <class T, int D>
void grid<T, D>::sort_into_cells(std::span<const T> coords) {
    const std::size_t n = coords.size() / D;
    const int threads = resolve_thread_count(options_.threads);
    const std::size_t parts = std::max<std::size_t>(1, std::min<std::size_t>(threads, n / 4096));
    size_sort_arrays(n, parts);
    std::uint32_t* const slot_of = reinterpret_cast<std::uint32_t*>(scratch_.values.data());
    const bool nearly_sorted = count_slots(coords, slot_of, parts);
    start_chunks_in_cells(parts);
    detail::exclusive_scan(offsets_.data(), geometry_.slots + 1, threads);
    scatter_into_cells(coords, slot_of, nearly_sorted, parts);
    detail::free_lazily(scratch_.values.data(), scratch_.values.data() + scratch_.values.size());
    index_cells();
}

namespace {
// The build scratch: the slot of every input point (written by the count, read by the
// scatter: cheaper than computing it twice), then room for a scatter of input in random order:
// the records of input that fits the cache, or the slots of larger input in bucket order.
template <class T, int D>
struct scratch_layout {
    std::size_t slot_bytes, record_bytes, extra_bytes;
    explicit scratch_layout(std::size_t n)
        : slot_bytes((n * sizeof(std::uint32_t) + 63) / 64 * 64),
          record_bytes(n * sizeof(point_record<T, D>) <= cached_scatter_bytes ? n * sizeof(point_record<T, D>) : 0),
          extra_bytes(record_bytes > 0 ? record_bytes : n * sizeof(std::uint32_t)) {}
};
}  // namespace

// The arrays of n points and the scratch. The scratch is kept for the next rebuild, which
// saves the system's zeroing of fresh pages (only pages used are touched); after the build the
// system may take it back when short of memory.
template <class T, int D>
void grid<T, D>::size_sort_arrays(std::size_t n, std::size_t parts) {
    // Padding: the SIMD kernels may load a few values past the last point (and mask them off).
    for (auto& p : pos_) {
        p.resize(n + detail::coordinate_padding);
        std::fill(p.begin() + std::ptrdiff_t(n), p.end(), T(0));
    }
    perm_.resize(n);
    inverse_.invalidate();
    offsets_.assign(geometry_.slots + 1, 0);
    thread_counts_.assign(parts * geometry_.slots, 0);
    const scratch_layout<T, D> layout(n);
    buffer<std::byte>& scratch = scratch_.values;
    if (scratch.capacity() < layout.slot_bytes + layout.extra_bytes) scratch = buffer<std::byte>();  // no copy
    scratch.resize(layout.slot_bytes + layout.extra_bytes);
}

// 1. The slot of every point (in vector code, a batch at a time) and each chunk's count of
// every slot. True when most points fall in the slot of the point before them or the next one
// (input already in cell order, or nearly).
template <class T, int D>
bool grid<T, D>::count_slots(std::span<const T> coords, std::uint32_t* slot_of, std::size_t parts) {
    const std::size_t n = coords.size() / D;
    std::vector<std::size_t> local(parts, 0);
    detail::for_each_chunk(n, parts, resolve_thread_count(options_.threads), [&](std::size_t c, std::size_t b, std::size_t e) {
        constexpr std::size_t batch = 256;
        for (std::size_t i = b; i < e; i += batch) input_slots(coords.data(), i, std::min(e, i + batch), slot_of + i);
        std::uint32_t* counts = thread_counts_.data() + c * geometry_.slots;
        std::uint32_t prev = 0;
        std::size_t near = 0;
        for (std::size_t i = b; i < e; ++i) {
            const std::uint32_t s = slot_of[i];
            near += s - prev <= 1;
            prev = s;
            ++counts[s];
        }
        local[c] = near;
    });
    std::size_t near = 0;
    for (auto v : local) near += v;
    return 2 * near >= n;
}

// 2. Per slot: the start of each chunk's points inside the slot, and the slot's total.
template <class T, int D>
void grid<T, D>::start_chunks_in_cells(std::size_t parts) {
    const int threads = resolve_thread_count(options_.threads);
    const std::size_t slot_parts = detail::chunk_count(geometry_.slots, threads, 1 << 14);
    detail::for_each_chunk(geometry_.slots, slot_parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
        for (std::size_t s = b; s < e; ++s) {
            std::uint32_t sum = 0;
            for (std::size_t c = 0; c < parts; ++c) {
                const std::uint32_t v = thread_counts_[c * geometry_.slots + s];
                thread_counts_[c * geometry_.slots + s] = sum;
                sum += v;
            }
            offsets_[s] = sum;
        }
    });
}

// 4. Stable scatter into cell order. Input in cell order (or nearly) is written straight into
// the arrays: its writes stay within a few cells. Other input would miss the cache on its
// D + 1 scattered writes per point. When its records fit the cache, each point goes as one
// record to a scratch array, which a streaming pass splits into the arrays; larger input goes
// through buckets first.
template <class T, int D>
void grid<T, D>::scatter_into_cells(std::span<const T> coords, const std::uint32_t* slot_of, bool nearly_sorted,
                                     std::size_t parts) {
    const std::size_t n = coords.size() / D;
    const int threads = resolve_thread_count(options_.threads);
    using record = point_record<T, D>;
    const scratch_layout<T, D> layout(n);
    std::byte* const extra = scratch_.values.data() + layout.slot_bytes;
    if (nearly_sorted) {
        detail::for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            std::uint32_t* next = thread_counts_.data() + c * geometry_.slots;
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t s = slot_of[i];
                const std::uint32_t dst = offsets_[s] + next[s]++;
                for (int a = 0; a < D; ++a) pos_[a][dst] = coords[i * D + a];
                perm_[dst] = std::uint32_t(i);
            }
        });
    } else if (layout.record_bytes > 0) {
        record* const records = reinterpret_cast<record*>(extra);
        detail::for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            std::uint32_t* next = thread_counts_.data() + c * geometry_.slots;
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t s = slot_of[i];
                record& r = records[offsets_[s] + next[s]++];
                for (int a = 0; a < D; ++a) r.x[a] = coords[i * D + a];
                r.index = std::uint32_t(i);
            }
        });
        detail::for_each_chunk(n, detail::chunk_count(n, threads, 1 << 15), threads,
                               [&](std::size_t, std::size_t b, std::size_t e) { store_records(records + b, b, e - b); });
    } else {
        scatter_by_buckets(coords, slot_of, reinterpret_cast<std::uint32_t*>(extra), parts);
    }
}

// The scatter of input in random order, in two passes whose writes stay in cache:
// (a) each chunk of the input scatters its points by bucket (a range of consecutive cells
// with about bucket_points points) straight into the arrays, and their slots to
// bucket_slots, a few hundred write streams, stably: chunk c's points after chunk c-1's in
// every bucket; (b) each bucket is sorted by cell, within its own range of the arrays.
template <class T, int D>
void grid<T, D>::scatter_by_buckets(std::span<const T> coords, const std::uint32_t* slot_of, std::uint32_t* bucket_slots,
                                     std::size_t parts) {
    const std::size_t n = coords.size() / D;
    const int threads = resolve_thread_count(options_.threads);
    // Buckets are cut between groups of 2^shift slots, small groups (a sixteenth of a bucket
    // on average) so that uneven density still gives buckets of about the same size.
    int shift = 0;
    while (shift < 24 && double(std::size_t(2) << shift) * double(n) <= double(geometry_.slots) * (bucket_points / 16)) ++shift;
    const std::size_t groups = ((geometry_.slots - 1) >> shift) + 1;
    std::vector<std::uint32_t> bucket_of(groups);
    std::vector<std::size_t> first_slot;  // of each bucket, then geometry_.slots
    std::size_t largest = 0;              // points of the largest bucket
    for (std::size_t q = 0; q < groups; ++q) {
        const std::size_t s = q << shift;
        if (first_slot.empty() || offsets_[s] - offsets_[first_slot.back()] >= bucket_points) {
            if (!first_slot.empty()) largest = std::max<std::size_t>(largest, offsets_[s] - offsets_[first_slot.back()]);
            first_slot.push_back(s);
        }
        bucket_of[q] = std::uint32_t(first_slot.size() - 1);
    }
    largest = std::max<std::size_t>(largest, n - offsets_[first_slot.back()]);
    first_slot.push_back(geometry_.slots);
    const std::size_t buckets = first_slot.size() - 1;

    // (a) By bucket. Chunk c's points of a bucket start after those of the earlier chunks,
    // which are the sum of their counts in the bucket's cells (step 2 left them per cell).
    detail::for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
        const std::uint32_t* earlier = thread_counts_.data() + c * geometry_.slots;
        std::vector<std::uint32_t> next(buckets);
        for (std::size_t k = 0; k < buckets; ++k) {
            std::uint32_t start = offsets_[first_slot[k]];
            for (std::size_t s = first_slot[k]; s < first_slot[k + 1]; ++s) start += earlier[s];
            next[k] = start;
        }
        for (std::size_t i = b; i < e; ++i) {
            const std::uint32_t slot = slot_of[i];
            const std::uint32_t dst = next[bucket_of[slot >> shift]]++;
            for (int a = 0; a < D; ++a) pos_[a][dst] = coords[i * D + a];
            perm_[dst] = std::uint32_t(i);
            bucket_slots[dst] = slot;
        }
    });
    // (b) By cell, within each bucket: each point goes as one record to its place in a local
    // array, which is then split into the bucket's range of the arrays.
    using record = point_record<T, D>;
    const std::size_t bucket_parts = detail::chunk_count(buckets, threads, 1);
    detail::for_each_chunk(buckets, bucket_parts, threads, [&](std::size_t, std::size_t kb, std::size_t ke) {
        // Uninitialized: every element used is written first.
        const auto sorted = std::make_unique_for_overwrite<record[]>(largest);
        std::vector<std::uint32_t> next;
        for (std::size_t k = kb; k < ke; ++k) {
            const std::size_t s0 = first_slot[k], s1 = first_slot[k + 1];
            const std::uint32_t b = offsets_[s0], m = offsets_[s1] - b;
            // Points of one cell only are in order already: pass (a) kept the input's order.
            std::size_t filled = 0;
            for (std::size_t s = s0; s < s1 && filled < 2; ++s) filled += offsets_[s + 1] > offsets_[s];
            if (filled < 2) continue;
            next.resize(s1 - s0);
            for (std::size_t s = s0; s < s1; ++s) next[s - s0] = offsets_[s] - b;
            for (std::uint32_t j = b; j < b + m; ++j) {
                record& r = sorted[next[bucket_slots[j] - s0]++];
                for (int a = 0; a < D; ++a) r.x[a] = pos_[a][j];
                r.index = perm_[j];
            }
            store_records(sorted.get(), b, m);
        }
    });
}

template class grid<float, 2>;
template class grid<float, 3>;
template class grid<double, 2>;
template class grid<double, 3>;

}  // namespace frnn
