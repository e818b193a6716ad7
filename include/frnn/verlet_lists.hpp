// frnn::verlet_lists: neighbor lists with a skin, kept across time steps until some point has
// moved more than skin/2 since they were built (then no pair can have come within r unseen).
//
// update() is O(N) when the lists are still valid and a grid build plus a list query (radius
// r + skin) otherwise; it reports whether it rebuilt. for_each_neighbor() filters the stored
// candidates by their current distance, so callers see exactly the pairs within r.
// Thread safety: const functions may run concurrently; update may not.
#pragma once
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "frnn/grid.hpp"

namespace frnn {

template <class T, int D>
class verlet_lists {
public:
    verlet_lists(T radius, T skin, grid_options options = {}) : radius_(radius), skin_(skin), options_(std::move(options)) {
        if (!std::isfinite(double(skin)) || skin < 0)
            throw error("skin must be finite and >= 0 (got " + std::to_string(double(skin)) + ")");
    }

    /// Takes the current coordinates (copied); returns true when the lists were rebuilt.
    bool update(std::span<const T> coords) {
        current_.assign(coords.begin(), coords.end());
        test_ = distance_test<T, D>(radius_, search_scale<T>(radius_, largest_magnitude<T>(current_, options_.periodic)),
                                    options_.periodic);
        if (built_ && coords.size() == reference_.size() && max_displacement() <= skin_ / 2) return false;
        grid_options o = options_;
        if (o.cell_size > 0) o.cell_size *= double(radius_ + skin_) / double(radius_);
        index_.build(coords, radius_ + skin_, o);
        list_options lo;
        lo.order = row_order::index;
        lists_ = index_.neighbor_lists(lo);
        reference_ = current_;
        built_ = true;
        ++rebuilds_;
        return true;
    }

    /// Calls f(j, distance_squared) for every j within r of point i, at the last update's positions.
    template <class F>
    void for_each_neighbor(std::size_t i, F&& f) const {
        for (std::uint32_t j : lists_.row(i)) {
            T d2;
            if (test_.within(&current_[i * D], &current_[std::size_t(j) * D], d2)) f(j, test_.distance_squared(d2));
        }
    }
    /// Candidates within r + skin at the last rebuild (caller's indices, rows sorted).
    const csr<T>& candidates() const { return lists_; }
    std::size_t rebuilds() const { return rebuilds_; }
    const grid<T, D>& index() const { return index_; }

private:
    T distance_squared(const T* a, const T* b) const {
        T d2 = 0;
        for (int k = 0; k < D; ++k) {
            T d = b[k] - a[k];
            if (!options_.periodic.empty() && options_.periodic[k] > 0)  // 0: an open axis
                d -= T(options_.periodic[k]) * std::nearbyint(d / T(options_.periodic[k]));
            d2 += d * d;
        }
        return d2;
    }
    T max_displacement() const {
        T worst = 0;
        for (std::size_t i = 0; i < current_.size() / D; ++i)
            worst = std::max(worst, distance_squared(&reference_[i * D], &current_[i * D]));
        return std::sqrt(worst);
    }

    T radius_, skin_;
    grid_options options_;
    distance_test<T, D> test_{T(1), T(1)};  // the test within r at the current positions
    grid<T, D> index_;
    csr<T> lists_;
    std::vector<T> current_, reference_;
    bool built_ = false;
    std::size_t rebuilds_ = 0;
};

}  // namespace frnn
