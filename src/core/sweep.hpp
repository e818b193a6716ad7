// Bulk queries of a grid (its own points, or query points grouped by cell, against all
// points), swept cell by cell: the candidates of a cell's stencil are gathered once into one
// contiguous block padded to whole vectors, and every point of the cell is tested against
// that block, by the minimum image in a periodic box. Lists take two sweeps: row sizes, then
// the rows written straight into the final CSR arrays, so each point only writes its own row
// and the output does not depend on the thread count. Where they fit in a small budget, the
// first sweep keeps the hit bits of every distance test, and the second writes the rows from
// them instead of testing again.
//
// The kernels are compiled once per instruction-set level (sweep_base.cpp, sweep_avx2.cpp,
// sweep_avx512.cpp) and chosen at run time.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>

#include "core/grid_access.hpp"
#include "frnn/grid.hpp"
#include "frnn/grid_geometry.hpp"

namespace frnn::detail {

/// What a sweep computes. Neighbors of a point with id `me` are candidates within r whose id
/// passes the list options: all but `me`, or only ids > me (half), with `me` itself if `self`.
template <class T>
struct sweep_job {
    /// Whose rows a sweep computes: the grid's own points, or the points of another set.
    enum class row_source { grid_points, query_points };
    row_source rows = row_source::grid_points;
    bool of_queries() const { return rows == row_source::query_points; }

    /// Id of each sorted point in the output, which is also its output row; null: the sorted
    /// index itself.
    const std::uint32_t* ids = nullptr;
    bool half = false;
    bool self = false;
    std::size_t k_nearest = 0;  ///< > 0: keep that many nearest per row (rows by distance)
    row_order order = row_order::none;
    /// Grid points whose id is at least this get an empty row (list_options::rows): no test,
    /// count 0, nothing written.
    std::uint32_t row_limit = std::numeric_limits<std::uint32_t>::max();

    std::uint32_t* counts = nullptr;          ///< count sweep: row sizes by sorted index
    /// count_pairs: where the counts of the partner points go; null: into counts as well.
    std::uint32_t* partner_counts = nullptr;
    /// count_pairs of [b, e): non-null, the counts of partners after e go to
    /// spill_after[j - e] instead, and those before b (a periodic box's wrap) to
    /// spill_before[j], so that sweeps of neighboring slabs may run at the same time.
    std::uint32_t* spill_after = nullptr;
    std::uint32_t* spill_before = nullptr;
    const std::uint64_t* offsets = nullptr;   ///< fill sweep: row starts by output row
    std::uint32_t* indices = nullptr;
    T* distances = nullptr;                   ///< null: not wanted

    /// Query sweeps (row_source::query_points): points of another set (interleaved
    /// coordinates) instead of the grid's own, swept in `query_order` (query indices grouped by cell, see query_engine). Rows and
    /// counts are then by query index; sweep ranges [b, e) are positions in query_order.
    const T* queries = nullptr;
    const std::uint32_t* query_order = nullptr;
    /// Query sweeps with a radius per query point: their squares in search space, by query
    /// index; null: the grid's radius.
    const T* query_r2 = nullptr;

    /// count_keeping_masks writes and fill_from_masks reads the hit masks of [b, e) here (the
    /// distance test's bits, one per candidate), as many bytes as hit_mask_bytes gives.
    std::byte* hits = nullptr;
};

/// Uniform grid with open boundaries: cell (x, y, z) of a point holds
/// clamp((x - lo) * inv, 0, top) on every axis, its slot x + stride1 y + stride2 z
/// (grid_geometry::cell_of and slot_of_cell).
struct uniform_frame {
    double lo[3], inv[3], top[3];
    std::uint32_t stride1, stride2;
};

/// Hashed grid: cell (x, y, z) of a point holds floor(x * inv) on every axis, its slot
/// hashed_slot(x, y, z, mask) (grid_geometry::cell_of and slot_of_cell).
struct hashed_frame {
    double inv[3];
    std::uint64_t mask;
};

template <class T, int D>
struct sweep_kernels {
    /// Row sizes of the sorted points [b, e) into job.counts (or of the queries, see sweep_job).
    void (*count)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e);
    /// Adds to job.counts (zero before the first sweep) the neighbors of all points, meeting
    /// each pair once from the cells of [b, e) (grid::forward_runs): the points of [b, e)
    /// get their own count, the partner points found in later cells theirs in
    /// job.partner_counts (or job.counts, or the spills). On the uniform grid those lie up to
    /// `reach` cell layers after e (in a periodic box, wrapping to the first layers). With
    /// job.half, a pair counts only for the point of the smaller id (job.ids, or the sorted
    /// index): the sizes of half rows.
    void (*count_pairs)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e);
    /// Rows of the sorted points [b, e) (or of the queries), at job.offsets of their output rows.
    void (*fill)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e);
    /// The bytes that count_keeping_masks keeps for the sorted points [b, e) (one bit per
    /// candidate, whole vectors per point), or some number above `limit` once they exceed it.
    std::size_t (*hit_mask_bytes)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e,
                                  std::size_t limit);
    /// count for rows without k nearest (full or half), keeping the hit bits in job.hits.
    void (*count_keeping_masks)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e);
    /// fill from the hit bits that count_keeping_masks kept for the same [b, e); rows without
    /// distances.
    void (*fill_from_masks)(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e);
    /// Not a sweep, but vector code of the build: the slots of the input points [b, e) of
    /// `coords` (interleaved) into out[0, e - b).
    void (*uniform_slots)(const T* coords, std::size_t b, std::size_t e, const uniform_frame& f, std::uint32_t* out);
    /// The same for the hashed grid.
    void (*hashed_slots)(const T* coords, std::size_t b, std::size_t e, const hashed_frame& f, std::uint32_t* out);
    /// Per axis, the least and greatest coordinate of the input points [b, e) of `coords`
    /// (interleaved) into lo and hi, and into nonfinite a sum that is 0 when every coordinate
    /// is finite and NaN otherwise.
    void (*bounds)(const T* coords, std::size_t b, std::size_t e, T* lo, T* hi, T* nonfinite);
};

/// The kernels of the level in use (see frnn/simd.hpp).
template <class T, int D>
const sweep_kernels<T, D>& sweep_for_cpu();

// One table per compiled level.
namespace base { template <class T, int D> const sweep_kernels<T, D>& table(); }
namespace avx2 { template <class T, int D> const sweep_kernels<T, D>& table(); }
namespace avx512 { template <class T, int D> const sweep_kernels<T, D>& table(); }

}  // namespace frnn::detail
