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

// The parts, each building on those before it.
#include "core/sort_ids_impl.hpp"       // sorting a row's ids
#include "core/simd_lanes_impl.hpp"     // this level's vectors
#include "core/point_kernel_impl.hpp"   // one point against a candidate block
#include "core/pair_counter_impl.hpp"   // each pair once, with partner counts
#include "core/sweeper_impl.hpp"        // the sweeps over a range of cells
#include "core/build_kernels_impl.hpp"  // the build's per-level kernels

// The entry points of sweep.hpp's table.

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
std::size_t hit_mask_bytes(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e, std::size_t limit) {
    return with_sweeper(g, job, [&](auto& s) { return s.hit_mask_bytes(b, e, limit); });
}
template <class T, int D>
void count_keeping_masks(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.count_keeping_masks(b, e); });
}
template <class T, int D>
void fill_from_masks(const grid<T, D>& g, const sweep_job<T>& job, std::size_t b, std::size_t e) {
    with_sweeper(g, job, [&](auto& s) { s.fill_from_masks(b, e); });
}

template <class T, int D>
const sweep_kernels<T, D>& table() {
    static const sweep_kernels<T, D> t{&count<T, D>,          &count_pairs<T, D>,         &fill<T, D>,
                                       &hit_mask_bytes<T, D>, &count_keeping_masks<T, D>, &fill_from_masks<T, D>,
                                       &uniform_slots<T, D>,  &hashed_slots<T, D>,        &bounds<T, D>};
    return t;
}

template const sweep_kernels<float, 2>& table<float, 2>();
template const sweep_kernels<float, 3>& table<float, 3>();
template const sweep_kernels<double, 2>& table<double, 2>();
template const sweep_kernels<double, 3>& table<double, 3>();

}  // namespace frnn::detail::FRNN_SWEEP_NS
