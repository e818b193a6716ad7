// frnn::grid: fixed-radius neighbor search over one point set.
//
// Two points i != j are neighbors when |x_i - x_j| <= r (the real radius, never its square),
// with minimum-image distances when the grid is periodic. On a periodic axis every point, and
// every query point, is first wrapped into [0, L) in its own precision (exactly, see
// frnn/periodic_wrap.hpp): distances are those of the wrapped points, so a point any number
// of boxes out has exactly the neighbors of its image in the box.
//
// With a radius per point (build with `radii`), j is a neighbor of i when |x_i - x_j| <= r_i
// (radius_rule::gather) or <= max(r_i, r_j) (radius_rule::symmetric), as grid_options::rule
// says. Cells are sized from the largest radius, and every row tests the candidates of that
// stencil against its own limit (docs/DESIGN.md says what else was measured). Query points
// then come with radii of their own.
//
// Construction is a counting sort of the points by cell (per-cell counts with an index inside
// the cell, exclusive prefix sum, stable scatter), so the grid keeps a copy of the points in
// cell order plus the map between that order and the caller's. Build is O(N + cells); a query
// visits the (2*ceil(r/cell)+1)^d cells around a point. Cells are ordered row by row (x
// fastest), so the cells of one stencil row are one contiguous run of sorted points.
//
// The uniform grid covers a bounded box; the hashed grid keys cells by integer coordinates in a
// table sized from N, so far outliers cost nothing. Hash collisions are verified by cell
// coordinates and never change a result.
//
// Extreme radii (r^2 beyond T's range, see frnn/search_scale.hpp) are searched with every
// coordinate, the radius and the box multiplied by a power of two, so that no square overflows
// or underflows; the answer is exact and the same as for ordinary radii.
//
// A build that throws leaves the grid as it was when the input was invalid (every check runs
// before anything changes), and empty (size() == 0) after std::bad_alloc.
//
// Results are deterministic: identical, bit for bit, for any thread count.
// Thread safety: const member functions may be called concurrently; build/rebuild may not run
// concurrently with anything else on the same grid.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "frnn/buffer.hpp"
#include "frnn/csr.hpp"
#include "frnn/detail/candidate_runs.hpp"
#include "frnn/detail/grid_storage.hpp"
#include "frnn/error.hpp"
#include "frnn/grid_geometry.hpp"
#include "frnn/options.hpp"
#include "frnn/search_scale.hpp"

namespace frnn {

namespace detail {
struct grid_access;
}

template <class T, int D>
class grid {
    static_assert(D == 2 || D == 3, "frnn supports 2D and 3D points");
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);

public:
    using point = std::array<T, D>;

    grid() = default;
    /// Builds over `coords`, N*D interleaved values (x0 y0 [z0] x1 ...).
    grid(std::span<const T> coords, T radius, const grid_options& options = {}) {
        build(coords, radius, options);
    }
    void build(std::span<const T> coords, T radius, const grid_options& options = {});
    /// Builds with a radius per point: radii[i] (finite, > 0) for point i, pairs by
    /// options.rule. radius() is then the largest radius (1 for no points). A bad radius
    /// throws frnn::error naming its index.
    grid(std::span<const T> coords, std::span<const T> radii, const grid_options& options = {}) {
        build(coords, radii, options);
    }
    void build(std::span<const T> coords, std::span<const T> radii, const grid_options& options = {});
    /// Builds again over new coordinates with the same radius (or radii) and options, reusing
    /// memory.
    void rebuild(std::span<const T> coords);
    /// Whether the grid has a radius per point; point_radii() gives them in the caller's order.
    bool has_point_radii() const { return point_radii_; }
    std::span<const T> point_radii() const { return radii_; }

    std::size_t size() const { return perm_.size(); }
    /// Where the cells are and how they are numbered (frnn/grid_geometry.hpp): the cells a
    /// query visits, the cell of a point, a cell's corners.
    const grid_geometry<T>& geometry() const { return geometry_; }
    T radius() const { return radius_; }
    grid_kind kind() const { return geometry_.kind; }          ///< uniform or hashed, never automatic
    double cell_size(int axis = 0) const { return geometry_.cell[axis] / double(geometry_.scale); }
    int reach() const { return geometry_.reach; }              ///< cells visited on each side
    /// Slots of the cell index: one per cell of a uniform grid, the hash table's size for a
    /// hashed one (cells that hash alike share a slot).
    std::size_t slot_count() const { return geometry_.slots; }
    std::size_t occupied_slots() const { return occupied_slots_; }  ///< slots holding at least one point
    std::size_t memory_bytes() const;                 ///< bytes held by the structure
    bool periodic() const { return geometry_.periodic; }  ///< some axis is periodic
    const grid_options& options() const { return options_; }
    int threads() const;
    void set_threads(int threads) { options_.threads = threads; }

    /// The power of two by which coordinates, radius and box are multiplied for the search: 1
    /// except for extreme radii (frnn/search_scale.hpp). "Search space" below means the
    /// caller's coordinates times this.
    T search_scale() const { return geometry_.scale; }
    T search_radius() const { return geometry_.search_radius; }  ///< radius() * search_scale()

    /// sorted_to_original()[s] is the caller's index of the s-th point in cell order.
    std::span<const std::uint32_t> sorted_to_original() const { return perm_; }
    /// original_to_sorted()[i] is the position in cell order of the caller's point i. Computed
    /// on the first call after a build (4 bytes per point from then on).
    std::span<const std::uint32_t> original_to_sorted() const { return inverse_.get(perm_, threads()); }
    /// Coordinate `axis` of the s-th point in cell order, as the caller gave it (not wrapped).
    T sorted_coord(std::size_t s, int axis) const {
        return input_pos_[axis].empty() ? pos_[axis][s] : input_pos_[axis][s];
    }

    /// Calls f(j, distance_squared) for every neighbor j of point i (caller's indices).
    /// Squared distances beyond T's range (extreme radii only) read +infinity.
    template <class F>
    void for_each_neighbor(std::size_t i, F&& f) const {
        check_index(i);
        const std::uint32_t s = original_to_sorted()[i];
        for_each_near_sorted(sorted_point(s), own_limit(s), [&](std::uint32_t j, T d2) {
            if (j != s) f(perm_[j], d2);
        });
    }
    /// Same in cell order: s and the j passed to f index the sorted points. After the caller has
    /// permuted its arrays with reorder(), these are the caller's indices too.
    template <class F>
    void for_each_neighbor_sorted(std::size_t s, F&& f) const {
        if (s >= size()) throw_bad_index(s);
        for_each_near_sorted(sorted_point(s), own_limit(std::uint32_t(s)), [&](std::uint32_t j, T d2) {
            if (j != s) f(j, d2);
        });
    }
    /// Calls f(j, distance_squared) for every grid point j (caller's index) within r of x.
    /// Not on a grid with a radius per point: give x a radius then.
    template <class F>
    void for_each_neighbor_of(const point& x, F&& f) const {
        require_one_radius("for_each_neighbor_of");
        for_each_near_sorted(search_point(x, 0), geometry_.search_radius * geometry_.search_radius,
                             [&](std::uint32_t j, T d2) { f(perm_[j], d2); });
    }
    /// The same for a query point x of radius `radius` (finite, > 0, at most radius()):
    /// within `radius` of x (gather) or within max(radius, r_j) (symmetric).
    template <class F>
    void for_each_neighbor_of(const point& x, T radius, F&& f) const {
        const T r = check_query_radius(radius, 0);
        for_each_near_sorted(search_point(x, 0), r * r, [&](std::uint32_t j, T d2) { f(perm_[j], d2); });
    }

    /// Number of neighbors of every point.
    std::vector<std::uint32_t> count_neighbors(index_space space = index_space::original) const;
    /// Neighbor lists of every point.
    csr<T> neighbor_lists(const list_options& options = {}) const;
    /// The same into `out`, reusing its memory: in a time-step loop the arrays are allocated
    /// once (with a little slack) instead of every step, which saves the page faults of
    /// fresh memory. `out`'s previous contents are discarded.
    void neighbor_lists(csr<T>& out, const list_options& options = {}) const;
    /// At most k nearest neighbors within r of every point, sorted by distance (ties by index).
    csr<T> nearest(std::size_t k, const list_options& options = {}) const;
    /// Points of this grid within r of each query point (N_q*D interleaved values): row q holds
    /// grid indices. `half` and `self` do not apply; `space` numbers the grid's points. Not on
    /// a grid with a radius per point (those take the queries' radii, below).
    csr<T> query(std::span<const T> queries, const list_options& options = {}) const;
    std::vector<std::uint32_t> query_counts(std::span<const T> queries) const;
    csr<T> query_nearest(std::span<const T> queries, std::size_t k,
                         const list_options& options = {}) const;
    /// The same with a radius per query point (query_radii[q]: finite, > 0, at most radius();
    /// an error names the first that is not): row q holds the grid points within
    /// query_radii[q] of query q (gather, and every grid with one radius), or within
    /// max(query_radii[q], r_j) (symmetric).
    csr<T> query(std::span<const T> queries, std::span<const T> query_radii, const list_options& options = {}) const;
    std::vector<std::uint32_t> query_counts(std::span<const T> queries, std::span<const T> query_radii) const;
    csr<T> query_nearest(std::span<const T> queries, std::span<const T> query_radii, std::size_t k,
                         const list_options& options = {}) const;

    /// Permutes the caller's array into cell order: data[s] <- old data[sorted_to_original[s]],
    /// with `components` consecutive values per point (e.g. 3 for a velocity).
    template <class U>
    void reorder(std::span<U> data, std::size_t components = 1) const;
    /// The inverse: brings an array in cell order back to the caller's order.
    template <class U>
    void restore_order(std::span<U> data, std::size_t components = 1) const;

private:
    friend struct detail::grid_access;  // frnn's sweeps, queries and tests (src/core/grid_access.hpp)

    // Traversal, for frnn's own sweeps and backends through detail::grid_access.
    /// All coordinates on `axis` in cell order, in search space (size() values, then
    /// detail::coordinate_padding zeros): wrapped into a periodic box, then scaled.
    const T* search_coords(int axis) const { return pos_[axis].data(); }
    T search_coord(std::size_t s, int axis) const { return pos_[axis][s]; }
    /// Sorted points [s, end) lie in one cell and share their candidate runs.
    std::uint32_t cell_group_end(std::uint32_t s) const;
    /// The runs of sorted points whose cells lie within reach of x, in search space.
    std::size_t candidate_runs(const point& x, detail::candidate_run* out) const {
        return size() == 0 ? 0 : stencil_runs(cell_of(x), out);
    }
    /// The same around a cell given by its integer coordinates (as cell_of gives them). On the
    /// uniform grid with open boundaries, `width` > 1 takes the union of the stencils of that
    /// many cells along x from `cell` on (which must lie in the grid). Periodic boxes: the
    /// runs come in increasing order of sorted index, and with `images` each run's image
    /// (runs of different images are not merged).
    std::size_t stencil_runs(const std::array<std::int64_t, 3>& cell, detail::candidate_run* out,
                             std::int64_t width = 1, detail::run_image* images = nullptr) const;
    /// The forward half of that stencil: the cells after `cell` in row-major order of cell
    /// coordinates (itself included, first), so that visiting these from every cell meets each
    /// pair of cells once (pairs inside the first run once by index order). `width` as for
    /// stencil_runs, uniform grid only. Periodic boxes: wrapped, and only for boxes of at least
    /// 2 reach + 1 cells on each periodic axis (smaller ones would meet some pairs of cells
    /// twice).
    std::size_t forward_runs(const std::array<std::int64_t, 3>& cell, detail::candidate_run* out,
                             std::int64_t width = 1, detail::run_image* images = nullptr) const;
    /// Periodic box: whether the run images of stencil_runs and forward_runs are the minimum
    /// image of every pair within r of grid points: at least 2 reach + 3 cells on each periodic
    /// axis (the points lie in the box, wrapped; another image then lies more than r away).
    bool images_exact() const;
    /// Uniform grid: cell c (geometry().slot_of_cell) holds the sorted points
    /// [cell_starts()[c], cell_starts()[c + 1]). Hashed grid: the starts of the occupied table
    /// slots only, in slot order, then size().
    std::span<const std::uint32_t> cell_starts() const { return offsets_; }
    /// Distance squared between x and sorted point j, in search space, with the minimum image
    /// on the periodic axes.
    T distance_squared_sorted(const point& x, std::uint32_t j) const {
        T d2 = 0;
        for (int a = 0; a < D; ++a) {
            T d = pos_[a][j] - x[a];
            if (geometry_.wraps[a]) d -= geometry_.box[a] * std::nearbyint(d / geometry_.box[a]);
            d2 += d * d;
        }
        return d2;
    }
    /// Integer cell coordinates of x, in search space (clamped to the uniform grid, wrapped
    /// when periodic).
    cell_index cell_of(const point& x) const { return geometry_.cell_of(x); }
    /// The caller's query point x in search space, checked (index: for the message): wrapped
    /// into a periodic box, then scaled. On the hashed grid a coordinate beyond every point by
    /// more than the stencil is brought back to that distance (rounded outwards, so that it
    /// stays beyond in T), where it still has no neighbors: cell keys stay in range.
    point search_point(const point& x, std::size_t index) const {
        check_query_point(x, index);
        point y;
        for (int a = 0; a < D; ++a) {
            const T v = geometry_.wraps[a] ? wrap_into_box(x[a], caller_box(a)) : x[a];
            const double s = double(v * geometry_.scale);
            if (std::abs(s) <= geometry_.far_bound) {
                y[a] = T(s);
                continue;
            }
            T bound = T(geometry_.far_bound);
            if (double(bound) < geometry_.far_bound) bound = std::nextafter(bound, std::numeric_limits<T>::infinity());
            y[a] = s < 0 ? -bound : bound;
        }
        return y;
    }
    /// The periodic box's length on `axis` in the caller's units (0 on an open axis).
    T caller_box(int axis) const { return geometry_.wraps[axis] ? T(options_.periodic[axis]) : T(0); }
    /// Hashed grid: whether sorted point j lies in `cell` (equals cell_of(point j) == cell, but
    /// inline: every cell lookup calls it, several times in slots shared by several cells).
    bool hashed_point_in_cell(std::uint32_t j, const std::array<std::int64_t, 3>& cell) const {
        for (int a = 0; a < D; ++a)  // |v| < 2^52 cells is checked at build
            if (detail::floor_to_int(double(pos_[a][j]) * geometry_.inv_cell[a]) != cell[a]) return false;
        return true;
    }

    // Queries and building.
    point sorted_point(std::uint32_t s) const {
        point p;
        for (int a = 0; a < D; ++a) p[a] = pos_[a][s];
        return p;
    }
    /// f(j, distance squared) for the sorted points j within the limit of x: r2 (search
    /// space, squared), or max(r2, r_j^2) on a symmetric grid with a radius per point.
    template <class F>
    void for_each_near_sorted(const point& x, T r2, F&& f) const {
        detail::candidate_run runs[detail::max_runs];
        const std::size_t n = candidate_runs(x, runs);
        const T inv = T(1) / geometry_.scale;
        const bool symmetric = point_radii_ && options_.rule == radius_rule::symmetric;
        for (std::size_t k = 0; k < n; ++k) {
            const auto& run = runs[k];
            for (std::uint32_t j = run.begin; j < run.end; ++j) {
                const T d2 = distance_squared_sorted(x, j);
                if (d2 <= (symmetric ? std::max(r2, point_r2_[j]) : r2)) f(j, unscale_squared(d2, inv));
            }
        }
    }
    /// The squared search radius of sorted point s (search space): its own or the grid's.
    T own_limit(std::uint32_t s) const {
        return point_radii_ ? point_r2_[s] : geometry_.search_radius * geometry_.search_radius;
    }
    /// A query radius checked (index: for the message) and in search space.
    T check_query_radius(T radius, std::size_t index) const;
    /// Throws for a query without radii on a grid with a radius per point.
    void require_one_radius(const char* what) const;
    /// Query radii checked, squared in search space.
    std::vector<T> query_limits(std::span<const T> query_radii, std::size_t queries) const;
    void check_index(std::size_t i) const {
        if (i >= size()) throw_bad_index(i);
    }
    [[noreturn]] void throw_bad_index(std::size_t i) const;
    void check_query_point(const point& x, std::size_t index) const;
    /// Checks the queries and gives them in search space: `queries` itself, or a copy in
    /// `storage` when they need scaling or bringing back (see search_point).
    std::span<const T> search_queries(std::span<const T> queries, std::vector<T>& storage) const;
    void clear() noexcept;
    // The build's steps (grid_build.cpp).
    void build_planned(std::span<const T> coords, T radius, const grid_options& options, bool per_point,
                       std::vector<T> radii);
    void keep_point_radii();
    void keep_input_coordinates(std::span<const T> coords, bool differ);
    void sort_into_cells(std::span<const T> coords);
    void size_sort_arrays(std::size_t n, std::size_t parts);
    bool count_slots(std::span<const T> coords, std::uint32_t* slot_of, std::size_t parts);
    void start_chunks_in_cells(std::size_t parts);
    void scatter_into_cells(std::span<const T> coords, const std::uint32_t* slot_of, bool nearly_sorted,
                            std::size_t parts);
    void scatter_by_buckets(std::span<const T> coords, const std::uint32_t* slot_of, std::uint32_t* bucket_slots,
                            std::size_t parts);
    template <class Record>
    void store_records(const Record* records, std::size_t begin, std::size_t count);
    /// Slots of the input points [b, e) of `coords` into out[0, e - b).
    void input_slots(const T* coords, std::size_t b, std::size_t e, std::uint32_t* out) const;
    void index_cells();
    void index_occupied_slots();
    void mark_shared_slots();
    /// Hashed grid: the index of table slot s among the occupied slots, or empty_slot.
    std::uint32_t occupied_index(std::size_t s) const {
        const detail::occupied_slot_word w = occupied_[s / 32];
        const std::uint32_t bit = 1u << (s % 32);
        if (!(w.bits & bit)) return empty_slot;
        return w.before + bit_count(w.bits & (bit - 1));
    }
    /// Set bits of v, inline: std::popcount is a library call on CPUs without popcnt.
    static std::uint32_t bit_count(std::uint32_t v) {
        v -= (v >> 1) & 0x55555555u;
        v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
        return (((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
    }
    static constexpr std::uint32_t empty_slot = 0xFFFFFFFFu;
    bool cells_sorted(std::uint32_t begin, std::uint32_t end) const;
    void group_cells(std::uint32_t begin, std::uint32_t end);
    std::uint32_t slot_of_cell(const std::array<std::int64_t, 3>& c) const {
        return std::uint32_t(geometry_.slot_of_cell(c));
    }
    /// Hashed grid: the sorted points [first, second) of a cell (an empty range if it has none).
    std::pair<std::uint32_t, std::uint32_t> hashed_cell_points(const std::array<std::int64_t, 3>& cell) const;
    /// Hashed grid: the runs of the stencil of a cell, or of its forward half.
    std::size_t hashed_runs(const std::array<std::int64_t, 3>& cell, bool forward, detail::candidate_run* out) const;

    // Configuration.
    grid_options options_;
    T radius_ = 0;
    bool point_radii_ = false;              // a radius per point
    std::vector<T> radii_;                  // point radii: the caller's, in the caller's order
    grid_geometry<T> geometry_;  // kind, cells, box, search scale
    std::size_t occupied_slots_ = 0;

    // Structure.
    std::array<buffer<T>, D> pos_;          // points in cell order, one array per axis, search space
    std::array<buffer<T>, D> input_pos_;    // scaled or wrapped: the caller's coordinates in cell order
    buffer<std::uint32_t> perm_;            // sorted -> original
    buffer<T> point_r2_;                    // point radii: squared, search space, cell order, padded
    detail::lazy_inverse inverse_;          // original -> sorted, on first use
    std::vector<std::uint32_t> offsets_;    // run starts: of the cells, or of the occupied slots (hashed); then size()
    std::vector<detail::occupied_slot_word> occupied_;  // hashed: geometry_.slots / 32 words
    std::vector<std::uint64_t> shared_slots_;      // hashed: bit per occupied slot holding points of several cells

    // Build scratch, kept for rebuilds.
    std::vector<std::uint32_t> thread_counts_;
    detail::build_scratch<> scratch_;  // the build's slots of the input points, then records or slots by bucket
    detail::build_scratch<T> search_input_;  // the input points in search space when they differ from the caller's
};

template <class T, int D>
template <class U>
void grid<T, D>::reorder(std::span<U> data, std::size_t components) const {
    if (data.size() != size() * components)
        throw error("reorder: array has " + std::to_string(data.size()) + " values, expected " +
                    std::to_string(size() * components));
    std::vector<U> copy(data.begin(), data.end());
    for (std::size_t s = 0; s < size(); ++s)
        for (std::size_t c = 0; c < components; ++c)
            data[s * components + c] = copy[std::size_t(perm_[s]) * components + c];
}

template <class T, int D>
template <class U>
void grid<T, D>::restore_order(std::span<U> data, std::size_t components) const {
    if (data.size() != size() * components)
        throw error("restore_order: array has " + std::to_string(data.size()) +
                    " values, expected " + std::to_string(size() * components));
    std::vector<U> copy(data.begin(), data.end());
    for (std::size_t s = 0; s < size(); ++s)
        for (std::size_t c = 0; c < components; ++c)
            data[std::size_t(perm_[s]) * components + c] = copy[s * components + c];
}

extern template class grid<float, 2>;
extern template class grid<float, 3>;
extern template class grid<double, 2>;
extern template class grid<double, 3>;

}  // namespace frnn
