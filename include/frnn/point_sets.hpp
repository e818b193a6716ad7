// frnn::point_sets: neighbor search between several point sets (fluid, boundary, ...), with an
// activation table saying which set searches which, as SPH codes with boundary particles need.
//
// Each set gets its own grid; neighbors(i, j) holds, for every point of set i, its neighbors in
// set j (for i == j the point itself is excluded). find_neighbors() costs one grid build per
// set plus one query per active pair. Thread safety: const functions may run concurrently;
// add/update/set_active/find_neighbors may not.
#pragma once
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "frnn/grid.hpp"

namespace frnn {

template <class T, int D>
class point_sets {
public:
    explicit point_sets(T radius, grid_options options = {}) : radius_(radius), options_(std::move(options)) {}

    /// Adds a set (N*D interleaved coordinates, copied) and returns its id. New sets search and
    /// are searched by every set, including themselves.
    std::size_t add(std::span<const T> coords) {
        sets_.push_back({std::vector<T>(coords.begin(), coords.end()), {}});
        const std::size_t n = sets_.size();
        std::vector<std::vector<char>> active(n, std::vector<char>(n, 1));
        for (std::size_t i = 0; i + 1 < n; ++i)
            for (std::size_t j = 0; j + 1 < n; ++j) active[i][j] = active_[i][j];
        active_ = std::move(active);
        results_.assign(n * n, csr<T>{});
        return n - 1;
    }
    /// Replaces the coordinates of set `id` (for the next time step).
    void update(std::size_t id, std::span<const T> coords) {
        check(id);
        sets_[id].coords.assign(coords.begin(), coords.end());
    }
    /// Whether the points of set i look for neighbors in set j.
    void set_active(std::size_t i, std::size_t j, bool active) {
        check(i), check(j);
        active_[i][j] = active;
    }
    bool is_active(std::size_t i, std::size_t j) const {
        check(i), check(j);
        return active_[i][j];
    }
    std::size_t size() const { return sets_.size(); }
    /// The number of points of set `id`.
    std::size_t points(std::size_t id) const {
        check(id);
        return sets_[id].coords.size() / D;
    }

    /// Rebuilds the grids of the sets that are searched, then every active pair's lists.
    void find_neighbors(const list_options& options = {}) {
        const std::size_t n = sets_.size();
        for (std::size_t j = 0; j < n; ++j) {
            bool searched = false;
            for (std::size_t i = 0; i < n; ++i) searched = searched || active_[i][j];
            if (searched) sets_[j].index.build(sets_[j].coords, radius_, options_);
        }
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) {
                csr<T>& out = results_[i * n + j];
                if (!active_[i][j]) {
                    out = csr<T>{};
                    out.offsets.assign(points(i) + 1, 0);
                } else if (i == j) {
                    list_options o = options;
                    o.space = index_space::original;
                    out = sets_[j].index.neighbor_lists(o);
                } else {
                    list_options o = options;
                    o.space = index_space::original;
                    out = sets_[j].index.query(sets_[i].coords, o);
                }
            }
    }
    /// Row p: the neighbors in set j of point p of set i (empty rows when inactive).
    const csr<T>& neighbors(std::size_t i, std::size_t j) const {
        check(i), check(j);
        return results_[i * sets_.size() + j];
    }

private:
    struct set {
        std::vector<T> coords;
        grid<T, D> index;
    };
    void check(std::size_t id) const {
        if (id >= sets_.size())
            throw error("point set " + std::to_string(id) + " does not exist (" + std::to_string(sets_.size()) +
                        " sets)");
    }
    T radius_;
    grid_options options_;
    std::vector<set> sets_;
    std::vector<std::vector<char>> active_;
    std::vector<csr<T>> results_;
};

}  // namespace frnn
