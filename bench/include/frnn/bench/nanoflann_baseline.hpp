// Baseline: nanoflann's kd-tree (Debian libnanoflann-dev), built over the points, then one
// radius search per point. Build O(N log N), single-threaded; the searches run in parallel
// over contiguous blocks of points.
//
// Same semantics as frnn: j is a neighbor of i when |x_i - x_j| <= r and j != i. nanoflann
// takes the SQUARED radius and keeps only d^2 < bound (strict), and finds the point itself; so
// the search bound is the next float above r*r, the result set keeps d^2 <= r*r, and the point
// itself is skipped by index (an exact duplicate of it elsewhere still counts).
// Thread safety: const members may be called concurrently; the object is not copyable.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "frnn/csr.hpp"

namespace frnn::bench {

template <class T, int D>
class nanoflann_baseline {
public:
    /// Builds the kd-tree over N*D interleaved coordinates; `coords` must outlive the object.
    nanoflann_baseline(std::span<const T> coords, T radius);
    ~nanoflann_baseline();
    nanoflann_baseline(nanoflann_baseline&&) noexcept;
    nanoflann_baseline& operator=(nanoflann_baseline&&) noexcept;

    std::size_t size() const;
    std::vector<std::uint32_t> count_neighbors(int threads) const;
    /// Rows in the caller's point order; entries in the order nanoflann finds them.
    csr<T> neighbor_lists(int threads) const;
    /// The tree's nodes and index array (nanoflann's usedMemory()).
    std::size_t memory_bytes() const;

private:
    struct impl;
    std::unique_ptr<impl> impl_;
};

extern template class nanoflann_baseline<float, 2>;
extern template class nanoflann_baseline<float, 3>;
extern template class nanoflann_baseline<double, 2>;
extern template class nanoflann_baseline<double, 3>;

}  // namespace frnn::bench
