// The cell index that follows the scatter: the hashed grid's starts of occupied slots, shared
// slots marked and ordered by cell, non-empty cells counted; and where a point's cell ends.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "cpu/parallel.hpp"
#include "frnn/grid.hpp"

namespace frnn {

// After the scatter: the hashed grid's table keeps starts for its occupied slots only; then
// shared slots are marked and cells counted.
template <class T, int D>
void grid<T, D>::index_cells() {
    if (geometry_.kind == grid_kind::hashed) index_occupied_slots();
    else occupied_ = {};
    mark_shared_slots();
}

// Hashed grid: the bits of occupied slots with their counts, and the starts of those slots
// only, in slot order (the scatter's starts of every slot are freed).
template <class T, int D>
void grid<T, D>::index_occupied_slots() {
    const int threads = resolve_thread_count(options_.threads);
    const std::size_t words = geometry_.slots / 32;  // geometry_.slots is a power of 2, at least 64
    occupied_.resize(words);
    const std::size_t parts = detail::chunk_count(words, threads, 1 << 10);
    std::vector<std::uint32_t> before(parts + 1, 0);
    detail::for_each_chunk(words, parts, threads, [&](std::size_t c, std::size_t wb, std::size_t we) {
        std::uint32_t count = 0;
        for (std::size_t w = wb; w < we; ++w) {
            const std::uint32_t* start = offsets_.data() + w * 32;
            std::uint32_t bits = 0;
            for (int k = 0; k < 32; ++k) bits |= std::uint32_t(start[k + 1] > start[k]) << k;
            occupied_[w] = {bits, count};  // counted within the chunk; the chunk's base follows
            count += bit_count(bits);
        }
        before[c + 1] = count;
    });
    for (std::size_t c = 0; c < parts; ++c) before[c + 1] += before[c];
    std::vector<std::uint32_t> starts(before[parts] + 1);
    detail::for_each_chunk(words, parts, threads, [&](std::size_t c, std::size_t wb, std::size_t we) {
        for (std::size_t w = wb; w < we; ++w) {
            occupied_[w].before += before[c];
            std::uint32_t k = occupied_[w].before;
            for (std::uint32_t bits = occupied_[w].bits; bits; bits &= bits - 1)
                starts[k++] = offsets_[w * 32 + std::size_t(std::countr_zero(bits))];
        }
    });
    starts[before[parts]] = std::uint32_t(size());
    offsets_.swap(starts);
}

// Orders the points of a hash slot shared by several cells by cell (stable).
template <class T, int D>
void grid<T, D>::group_cells(std::uint32_t b, std::uint32_t e) {
    // (cell, old position - b), sorted by cell; then both arrays are rewritten in that order.
    std::vector<std::pair<std::array<std::int64_t, 3>, std::uint32_t>> keyed;
    for (std::uint32_t j = b; j < e; ++j) keyed.push_back({cell_of(sorted_point(j)), j - b});
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
    std::vector<point> points;
    std::vector<std::uint32_t> ids(perm_.begin() + b, perm_.begin() + e);
    for (std::uint32_t j = b; j < e; ++j) points.push_back(sorted_point(j));
    for (std::uint32_t j = b; j < e; ++j) {
        const std::uint32_t from = keyed[j - b].second;
        for (int a = 0; a < D; ++a) pos_[a][j] = points[from][a];
        perm_[j] = ids[from];
    }
}

// Whether the points [b, e) of a hash slot are ordered by cell already (input in cell order).
template <class T, int D>
bool grid<T, D>::cells_sorted(std::uint32_t b, std::uint32_t e) const {
    auto cell = cell_of(sorted_point(b));
    for (std::uint32_t j = b + 1; j < e; ++j) {
        if (hashed_point_in_cell(j, cell)) continue;
        const auto next = cell_of(sorted_point(j));
        if (next < cell) return false;
        cell = next;
    }
    return true;
}

// Counts non-empty cells; in the hashed grid, also flags slots shared by several cells and
// orders their points by cell, so that a cell is always one run of points, found by binary search.
template <class T, int D>
void grid<T, D>::mark_shared_slots() {
    const int threads = resolve_thread_count(options_.threads);
    const bool hashed = geometry_.kind == grid_kind::hashed;
    const std::size_t runs = offsets_.size() - 1;  // cells, or occupied slots (hashed)
    shared_slots_.assign(hashed ? (runs + 63) / 64 : 0, 0);
    const std::size_t words = (runs + 63) / 64;
    // Hashed runs are occupied slots, some of them shared and sorted here: smaller chunks.
    const std::size_t parts = detail::chunk_count(words, threads, hashed ? 4 : 1 << 10);
    std::vector<std::size_t> nonempty(parts, 0);
    detail::for_each_chunk(words, parts, threads, [&](std::size_t c, std::size_t wb, std::size_t we) {
        std::size_t count = 0;
        for (std::size_t s = wb * 64; s < std::min(we * 64, runs); ++s) {
            const std::uint32_t b = offsets_[s], e = offsets_[s + 1];
            if (b == e) continue;
            if (!hashed) {
                ++count;
                continue;
            }
            const auto first = cell_of(sorted_point(b));
            std::uint32_t j = b + 1;
            while (j < e && hashed_point_in_cell(j, first)) ++j;
            if (j == e) {
                ++count;
                continue;
            }
            shared_slots_[s / 64] |= std::uint64_t(1) << (s % 64);
            if (!cells_sorted(b, e)) group_cells(b, e);
            for (j = b; j < e; ++count) {  // one piece per cell now
                const auto cell = cell_of(sorted_point(j));
                while (j < e && hashed_point_in_cell(j, cell)) ++j;
            }
        }
        nonempty[c] = count;
    });
    occupied_slots_ = 0;
    for (auto v : nonempty) occupied_slots_ += v;
}

template <class T, int D>
std::uint32_t grid<T, D>::cell_group_end(std::uint32_t s) const {
    const auto cell = cell_of(sorted_point(s));
    const std::uint32_t slot = slot_of_cell(cell);
    if (geometry_.kind != grid_kind::hashed) return offsets_[slot + 1];
    const std::uint32_t k = occupied_index(slot);  // occupied: point s lies in it
    if (shared_slots_[k / 64] >> (k % 64) & 1) {
        // A shared slot holds its cells one after the other (see group_cells).
        std::uint32_t e = s + 1;
        while (e < offsets_[k + 1] && hashed_point_in_cell(e, cell)) ++e;
        return e;
    }
    return offsets_[k + 1];
}

// The class itself is instantiated in grid_build.cpp (grid.hpp declares it extern, so nothing
// here is instantiated implicitly); these are the members defined here.
#define FRNN_INSTANTIATE_CELL_INDEX(T, D)                                            \
    template void grid<T, D>::index_cells();                                       \
    template void grid<T, D>::index_occupied_slots();                              \
    template void grid<T, D>::group_cells(std::uint32_t, std::uint32_t);           \
    template bool grid<T, D>::cells_sorted(std::uint32_t, std::uint32_t) const;    \
    template void grid<T, D>::mark_shared_slots();                                  \
    template std::uint32_t grid<T, D>::cell_group_end(std::uint32_t) const;
FRNN_INSTANTIATE_CELL_INDEX(float, 2)
FRNN_INSTANTIATE_CELL_INDEX(float, 3)
FRNN_INSTANTIATE_CELL_INDEX(double, 2)
FRNN_INSTANTIATE_CELL_INDEX(double, 3)

}  // namespace frnn
