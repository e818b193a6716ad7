// frnn::verlet_lists: neighbor lists with a skin, kept across time steps until some point has
// moved more than skin/2 since they were built (then no pair can have come within r unseen).
//
// update() is O(N) when the lists are still valid and a grid build plus a list query (radius
// r + skin) otherwise; it reports whether it rebuilt. for_each_neighbor() filters the stored
// candidates by their current distance, so callers see exactly the pairs within r. Distances
// and displacements are the grid's: in a periodic box between the points wrapped into it, with
// the minimum image. An update that throws (a non-finite coordinate, a bad size) leaves the
// lists as they were.
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
        if (!std::isfinite(double(radius)) || !(radius > 0))
            throw error("radius must be finite and > 0 (got " + std::to_string(double(radius)) + ")");
        if (!std::isfinite(double(skin)) || skin < 0)
            throw error("skin must be finite and >= 0 (got " + std::to_string(double(skin)) + ")");
    }

    /// Takes the current coordinates (copied); returns true when the lists were rebuilt.
    bool update(std::span<const T> coords) {
        if (coords.size() % D != 0)
            throw error("verlet_lists: coordinate array has " + std::to_string(coords.size()) +
                        " values, not a multiple of the dimension " + std::to_string(D));
        for (std::size_t i = 0; i < coords.size(); ++i)
            if (!std::isfinite(coords[i]))
                throw error("verlet_lists: point " + std::to_string(i / D) + " has a non-finite coordinate");
        const distance_test<T, D> test(radius_, search_scale<T>(radius_, largest_magnitude<T>(coords, options_.periodic)),
                                       options_.periodic);
        if (built_ && coords.size() == reference_.size() && still_valid(coords, test)) {
            current_.assign(coords.begin(), coords.end());
            test_ = test;
            return false;
        }
        // Candidates within (r + skin) (1 + 2^-16): the margin covers the rounding of the
        // distances and displacements that the skin argument adds up.
        const T reach = (radius_ + skin_) * (T(1) + T(0x1p-16));
        grid_options o = options_;
        if (o.cell_size > 0) o.cell_size *= double(reach) / double(radius_);
        index_.build(coords, reach, o);  // throws before changing anything
        list_options lo;
        lo.order = row_order::index;
        lists_ = index_.neighbor_lists(lo);
        current_.assign(coords.begin(), coords.end());
        test_ = test;
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
    /// Candidates within (r + skin) (1 + 2^-16) at the last rebuild (caller's indices, rows sorted).
    const csr<T>& candidates() const { return lists_; }
    std::size_t rebuilds() const { return rebuilds_; }
    const grid<T, D>& index() const { return index_; }

private:
    /// Whether no point has moved more than skin/2 since the last rebuild. Moves are measured
    /// in the test's scaled units (wrapped, minimum image) by their square where it and the
    /// half-skin's are normal numbers, else with hypot, which neither underflows nor overflows
    /// (a move of 1e-200 squares to 0 in double); a half-skin beyond T's range in those units
    /// lets any finite move pass.
    bool still_valid(std::span<const T> coords, const distance_test<T, D>& test) const {
        const T half_skin = skin_ / 2 * test.scale, half_skin2 = half_skin * half_skin;
        const bool squares = std::isnormal(half_skin2);
        for (std::size_t i = 0; i < coords.size() / D; ++i) {
            T d[3] = {0, 0, 0};
            T d2 = 0;
            for (int a = 0; a < D; ++a) {
                d[a] = test.scaled_difference(&reference_[i * D], &coords[i * D], a);
                d2 += d[a] * d[a];
            }
            if (squares && (std::isnormal(d2) || (d[0] == 0 && d[1] == 0 && d[2] == 0))) {
                if (!(d2 <= half_skin2)) return false;
                continue;
            }
            const T moved = D == 2 ? std::hypot(d[0], d[1]) : std::hypot(d[0], d[1], d[2]);
            if (!(moved <= half_skin) || std::isinf(moved)) return false;
        }
        return true;
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
