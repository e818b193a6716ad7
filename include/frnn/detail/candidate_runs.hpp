// Runs of sorted points: what a grid traversal hands to the distance kernels. Internal to frnn
// (its grids, sweeps and backends); included by frnn/grid.hpp for the declarations it needs.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

namespace frnn::detail {

/// A run [begin, end) of sorted points to test: the points of one or more whole cells.
struct candidate_run {
    std::uint32_t begin, end;
};

/// Appends run [b, e) to out[0, n), merging it into the last run when they touch.
inline void append_run(candidate_run* out, std::size_t& n, std::uint32_t b, std::uint32_t e) {
    if (b == e) return;
    if (n > 0 && out[n - 1].end == b) out[n - 1].end = e;
    else out[n++] = {b, e};
}

/// A run of a periodic stencil: per axis, the multiple of the box length that the minimum
/// image subtracts from d = candidate - point for every candidate of the run and every point
/// of the stencil's cell (-1, 0 or 1; exact only where the grid says so, see
/// grid_access::images_exact).
using run_image = std::array<std::int8_t, 3>;

/// Upper bound of runs around one point: (2k+1)^d with k <= 4.
inline constexpr std::size_t max_runs = 729;

}  // namespace frnn::detail
