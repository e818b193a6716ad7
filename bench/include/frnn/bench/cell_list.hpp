// Baseline: the textbook single-threaded cell list. Cells of edge r over the bounding box; each
// cell holds a vector of its point indices in input order, with no sorting of the particles; a
// query walks the 3^D cells around its point. Build O(N + cells), memory 24 bytes per cell plus
// 4 per point. This is the floor any real implementation must beat. (Per-cell vectors rather
// than head/next linked lists: the list walk is a chain of dependent loads, measured 2x slower
// on W2's random order and no faster on W1, which would flatter frnn.)
// Semantics as frnn: |x_i - x_j| <= r, j != i. Thread safety: const members may run
// concurrently.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "frnn/csr.hpp"

namespace frnn::bench {

template <class T, int D>
class cell_list {
public:
    /// The cell count the bounding box needs, or nullopt when it exceeds the limit of a
    /// textbook dense cell list (max(8 N, 2^20) cells; e.g. W3's or W5's empty space).
    static std::optional<std::size_t> cells_needed(std::span<const T> coords, T radius);

    /// Throws frnn::error when cells_needed() is nullopt; `coords` must outlive the object.
    cell_list(std::span<const T> coords, T radius);

    std::size_t size() const { return coords_.size() / D; }
    std::vector<std::uint32_t> count_neighbors() const;
    /// Rows in the caller's point order; entries in the order the walk finds them.
    csr<T> neighbor_lists() const;
    std::size_t memory_bytes() const;

private:
    template <class Emit>
    void for_each_neighbor(std::size_t i, Emit&& emit) const;
    std::array<std::int64_t, D> cell_of(const T* x) const;

    std::span<const T> coords_;
    T radius_;
    std::array<double, D> lower_{};
    std::array<std::int64_t, D> dims_{};
    std::vector<std::vector<std::uint32_t>> cells_;  // point indices of each cell, x fastest
};

extern template class cell_list<float, 2>;
extern template class cell_list<float, 3>;
extern template class cell_list<double, 2>;
extern template class cell_list<double, 3>;

}  // namespace frnn::bench
