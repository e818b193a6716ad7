#include "frnn/bench/nanoflann_baseline.hpp"

#include <nanoflann.hpp>

#include <cmath>
#include <limits>

#include "frnn/bench/row_builder.hpp"
#include "frnn/error.hpp"

namespace frnn::bench {
namespace {

// nanoflann's dataset adaptor over interleaved coordinates.
template <class T, int D>
struct point_cloud {
    std::span<const T> coords;
    std::size_t kdtree_get_point_count() const { return coords.size() / D; }
    T kdtree_get_pt(std::uint32_t i, std::size_t axis) const {
        return coords[std::size_t(i) * D + axis];
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }  // let nanoflann compute it
};

// A nanoflann result set with frnn's semantics: d^2 <= r^2 (nanoflann's own test is strict
// against worstDist(), hence the next representable value above r^2), and i itself skipped.
template <class T, class Emit>
struct within_radius {
    T r2, bound;
    std::uint32_t self;
    Emit& emit;
    bool full() const { return true; }
    T worstDist() const { return bound; }
    bool addPoint(T d2, std::uint32_t j) {
        if (j != self && d2 <= r2) emit(j);
        return true;  // keep searching
    }
};

}  // namespace

template <class T, int D>
struct nanoflann_baseline<T, D>::impl {
    using cloud = point_cloud<T, D>;
    using tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<T, cloud, T>,
                                                     cloud, D, std::uint32_t>;
    cloud points;
    T radius;
    tree index;  // built by its constructor (nanoflann's default leaf size, 10)

    impl(std::span<const T> coords, T r)
        : points{coords}, radius(r), index(D, points, nanoflann::KDTreeSingleIndexAdaptorParams()) {}

    template <class Emit>
    void visit(std::size_t i, Emit&& emit) const {
        const T r2 = radius * radius;  // the same r^2 as frnn and the brute-force oracle
        within_radius<T, Emit> result{r2, std::nextafter(r2, std::numeric_limits<T>::infinity()),
                                      std::uint32_t(i), emit};
        index.findNeighbors(result, &points.coords[i * D], nanoflann::SearchParams());
    }
};

template <class T, int D>
nanoflann_baseline<T, D>::nanoflann_baseline(std::span<const T> coords, T radius) {
    if (coords.size() % D != 0)
        throw error("nanoflann baseline: " + std::to_string(coords.size()) +
                    " coordinates is not a multiple of " + std::to_string(D));
    if (!(radius > 0)) throw error("nanoflann baseline: radius must be > 0");
    if (coords.empty()) throw error("nanoflann baseline: no points");
    impl_ = std::make_unique<impl>(coords, radius);
}

template <class T, int D>
nanoflann_baseline<T, D>::~nanoflann_baseline() = default;
template <class T, int D>
nanoflann_baseline<T, D>::nanoflann_baseline(nanoflann_baseline&&) noexcept = default;
template <class T, int D>
nanoflann_baseline<T, D>& nanoflann_baseline<T, D>::operator=(nanoflann_baseline&&) noexcept =
    default;

template <class T, int D>
std::size_t nanoflann_baseline<T, D>::size() const {
    return impl_->points.kdtree_get_point_count();
}

template <class T, int D>
std::vector<std::uint32_t> nanoflann_baseline<T, D>::count_neighbors(int threads) const {
    return detail::counts_from_rows(size(), threads,
                                    [this](std::size_t i, auto&& emit) { impl_->visit(i, emit); });
}

template <class T, int D>
csr<T> nanoflann_baseline<T, D>::neighbor_lists(int threads) const {
    return detail::lists_from_rows<T>(size(), threads,
                                      [this](std::size_t i, auto&& emit) { impl_->visit(i, emit); });
}

template <class T, int D>
std::size_t nanoflann_baseline<T, D>::memory_bytes() const {
    return impl_->index.usedMemory(impl_->index);
}

template class nanoflann_baseline<float, 2>;
template class nanoflann_baseline<float, 3>;
template class nanoflann_baseline<double, 2>;
template class nanoflann_baseline<double, 3>;

}  // namespace frnn::bench
