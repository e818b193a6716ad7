#include "grid_object.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "frnn/parallel.hpp"
#include "numpy_io.hpp"

namespace frnn::python {

namespace {

/// The four precision x dimension cases as a value, for a run-time dispatch.
template <class T, int D>
struct case_tag {
    using type = T;
    static constexpr int dim = D;
};
template <class F>
decltype(auto) dispatch(bool float32, int dim, F&& f) {
    if (float32) return dim == 2 ? f(case_tag<float, 2>{}) : f(case_tag<float, 3>{});
    return dim == 2 ? f(case_tag<double, 2>{}) : f(case_tag<double, 3>{});
}

row_order parse_sort(const py::object& sort) {
    if (sort.is_none()) return row_order::none;
    if (py::isinstance<py::str>(sort)) {
        const auto s = sort.cast<std::string>();
        if (s == "index") return row_order::index;
        if (s == "distance") return row_order::distance;
    }
    throw py::value_error("sort must be 'index', 'distance' or None; got " +
                          std::string(py::repr(sort)));
}

/// None, one box length for every axis, or one length per axis.
/// A radius argument: nothing for one number, else its values, one per point (`count`).
std::optional<std::vector<double>> radii_of(const py::object& radius, std::size_t count, const char* what) {
    if (py::isinstance<py::float_>(radius) || py::isinstance<py::int_>(radius)) return std::nullopt;
    const py::array a = as_array(radius);
    const char kind = a.dtype().kind();
    if (!(kind == 'f' || kind == 'i' || kind == 'u'))
        throw py::value_error(std::string(what) + " must be a number or an array of numbers; got " +
                              std::string(py::repr(radius)));
    if (a.ndim() == 0) return std::nullopt;
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != count)
        throw py::value_error(std::string(what) + " must be one number or " + std::to_string(count) +
                              " (one per point); got an array of shape " + std::string(py::str(py::tuple(a.attr("shape")))));
    const auto v = as_contiguous<double>(a);
    return std::vector<double>(v.data(), v.data() + count);
}

std::vector<double> parse_periodic(const py::object& periodic, int dim) {
    if (periodic.is_none()) return {};
    if ((py::isinstance<py::tuple>(periodic) || py::isinstance<py::list>(periodic)) && py::len(periodic) == std::size_t(dim)) {
        // None on an axis leaves it open, as 0 does (cKDTree's boxsize takes 0 there).
        py::list lengths;
        for (const py::handle v : periodic) lengths.append(v.is_none() ? py::float_(0.0) : py::reinterpret_borrow<py::object>(v));
        return parse_periodic(as_array(lengths), dim);
    }
    const py::array a = as_array(periodic);
    const char kind = a.dtype().kind();
    const bool numeric = kind == 'f' || kind == 'i' || kind == 'u';
    if (!numeric || !(a.ndim() == 0 || (a.ndim() == 1 && a.shape(0) == dim)))
        throw py::value_error("periodic must be None, one box length, or " + std::to_string(dim) +
                              " box lengths (one per axis, 0 or None for an open axis); got " +
                              std::string(py::repr(periodic)));
    const auto v = as_contiguous<double>(a);
    return a.ndim() == 0 ? std::vector<double>(std::size_t(dim), v.data()[0])
                         : std::vector<double>(v.data(), v.data() + dim);
}

grid_options make_options(const grid_args& args, int dim) {
    grid_options o;
    o.kind = parse_grid_kind(args.grid);
    o.cell_size = args.cell_size.value_or(0.0);
    o.periodic = parse_periodic(args.periodic, dim);
    o.rule = parse_radius_rule(args.rule);
    // The upper bound only stops typos from asking for a million threads.
    if (args.threads && (*args.threads < 1 || *args.threads > 1024))
        throw py::value_error("threads must be in [1, 1024] (None: FRNN_NUM_THREADS, else OMP_NUM_THREADS, else every CPU); got " +
                              std::to_string(*args.threads));
    o.threads = args.threads.value_or(0);
    return o;
}

/// Coordinates of `points` as a C-contiguous (N, D) array of T, checked and converted.
template <class T, int D>
py::array_t<T, py::array::c_style> typed_points(py::handle points, const char* what,
                                                bool allow_single) {
    const py::array a = check_points_shape(as_array(points), what, D, allow_single);
    is_float32_input(a, what);  // rejects non-numeric dtypes
    return as_contiguous<T>(a);
}

template <class T>
std::span<const T> coords_of(const py::array_t<T, py::array::c_style>& a) {
    return {a.data(), std::size_t(a.size())};
}

std::vector<std::int64_t> widen(const std::vector<std::uint32_t>& v) {
    return {v.begin(), v.end()};
}

/// (offsets int64, indices uint32[, distances]) without copying the vectors.
template <class T>
py::tuple csr_to_numpy(csr<T>&& c, bool distances) {
    py::array offsets = to_numpy<std::int64_t>(std::move(c.offsets));
    py::array indices = to_numpy(std::move(c.indices));
    if (!distances) return py::make_tuple(offsets, indices);
    return py::make_tuple(offsets, indices, to_numpy(std::move(c.distances)));
}

template <class T>
bool all_finite(std::span<const T> v) {
    for (const T x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

}  // namespace

template <class F>
auto grid_object::under_read_lock(F&& f) const {
    py::gil_scoped_release nogil;
    std::shared_lock lock(mutex_);
    if (!valid_) throw error("frnn.Grid: a previous update() failed; call update() again");
    return f();
}

void grid_object::build_into(any_grid& target, py::handle points, const py::object& radius,
                             const grid_options& options) {
    const py::array a = check_points_shape(as_array(points), "points", 0, false);
    const auto per_point = radii_of(radius, std::size_t(a.shape(0)), "radius");
    dispatch(is_float32_input(a, "points"), int(a.shape(1)), [&](auto tag) {
        using T = typename decltype(tag)::type;
        constexpr int D = decltype(tag)::dim;
        const auto c = as_contiguous<T>(a);
        auto& g = target.template emplace<grid<T, D>>();
        if (!per_point) {
            const T r = T(radius.cast<double>());
            py::gil_scoped_release nogil;
            return g.build(coords_of(c), r, options);
        }
        const std::vector<T> radii(per_point->begin(), per_point->end());
        py::gil_scoped_release nogil;
        g.build(coords_of(c), std::span<const T>(radii), options);
    });
}

grid_object::grid_object(const py::object& points, const py::object& radius, const grid_args& args) {
    const py::array a = check_points_shape(as_array(points), "points", 0, false);
    options_ = make_options(args, int(a.shape(1)));
    build_into(g_, a, radius, options_);
}

/// Pairs i < j (caller's indices) sorted lexicographically, as 2*M int64 values. The half lists
/// in the caller's numbering (row i holds the j > i) with rows sorted by index are already in
/// that order: no sort of the pairs, only a copy into the (M, 2) layout, rows in parallel.
template <class T, int D>
static buffer<std::int64_t> sorted_pairs(const grid<T, D>& g) {
    list_options o;
    o.half = true;
    o.order = row_order::index;
    const csr<T> c = g.neighbor_lists(o);
    buffer<std::int64_t> p(2 * c.size());  // not zero-filled: every value is written once
    constexpr std::size_t block = 4096;
    const std::size_t rows = g.size();
    parallel_chunks((rows + block - 1) / block, g.threads(), [&](std::size_t b, int) {
        for (std::size_t i = b * block; i < std::min(rows, (b + 1) * block); ++i)
            for (auto k = c.offsets[i]; k < c.offsets[i + 1]; ++k) {
                p[2 * k] = std::int64_t(i);
                p[2 * k + 1] = c.indices[k];
            }
    });
    return p;
}

py::array grid_object::query_pairs() const {
    return std::visit(
        [&](auto& g) {
            if (g.has_point_radii() && g.options().rule == radius_rule::gather)
                throw error("query_pairs: gather neighbors are not mutual (j within r_i of i, not i within r_j of j); "
                            "build with rule='symmetric' for pairs, or use neighbors()");
            auto pairs = under_read_lock([&] { return sorted_pairs(g); });
            const auto m = py::ssize_t(pairs.size() / 2);
            return to_numpy(std::move(pairs), {m, 2});
        },
        g_);
}

py::tuple grid_object::neighbors(bool return_distances, const py::object& sort, bool half, const py::object& rows) const {
    list_options o;
    o.half = half;
    if (!rows.is_none()) {
        if (!PyIndex_Check(rows.ptr()))
            throw py::type_error("rows must be an integer, got " + std::string(py::str(py::repr(rows))));
        const long long m = py::reinterpret_steal<py::int_>(PyNumber_Index(rows.ptr())).cast<long long>();
        // A count above the number of points is the core's error, which names both.
        if (m < 0) throw py::value_error("rows must be >= 0, got " + std::to_string(m));
        o.rows = std::size_t(m);
    }
    o.distances = return_distances;
    o.order = parse_sort(sort);
    return std::visit(
        [&](auto& g) {
            auto c = under_read_lock([&] { return g.neighbor_lists(o); });
            return csr_to_numpy(std::move(c), return_distances);
        },
        g_);
}

py::array grid_object::count_neighbors() const {
    return std::visit(
        [&](auto& g) { return to_numpy(under_read_lock([&] { return widen(g.count_neighbors()); })); }, g_);
}

py::object grid_object::query_ball_point(const py::object& x, const py::object& r_arg,
                                         bool return_distances, const py::object& sort,
                                         bool return_length) const {
    const row_order order = parse_sort(sort);
    return std::visit(
        [&](auto& g) -> py::object {
            using T = typename grid_traits<std::decay_t<decltype(g)>>::type;
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            const auto q = typed_points<T, D>(x, "x", true);
            const std::size_t nq = std::size_t(q.size()) / D;
            const auto per_query = r_arg.is_none() ? std::nullopt : radii_of(r_arg, nq, "r");
            std::optional<double> r;
            if (!r_arg.is_none() && !per_query) r = r_arg.cast<double>();
            if (per_query || (r && g.has_point_radii())) {
                // Radii of the queries' own (cKDTree's r array): the grid's own search when none
                // exceeds its radius, else a grid of one radius, the largest, over the same points.
                std::vector<T> radii(nq, r ? T(*r) : T(0));
                if (per_query) std::transform(per_query->begin(), per_query->end(), radii.begin(), [](double v) { return T(v); });
                T largest = 0;
                for (T v : radii) largest = std::isfinite(v) ? std::max(largest, v) : largest;
                if (!g.has_point_radii() && largest > g.radius()) {
                    grid_object other;
                    other.options_ = options_;
                    other.options_.cell_size = 0;
                    build_into(other.g_, original_points(), py::float_(double(largest)), other.options_);
                    return other.query_ball_point(q, to_numpy(std::move(radii)), return_distances, sort, return_length);
                }
                if (return_length)
                    return to_numpy(under_read_lock([&] { return widen(g.query_counts(coords_of(q), radii)); }));
                list_options o;
                o.distances = return_distances;
                o.order = order;
                auto c = under_read_lock([&] { return g.query(coords_of(q), radii, o); });
                return csr_to_numpy(std::move(c), return_distances);
            }
            if (r && T(*r) != g.radius()) {
                // Another radius needs another grid: build one over the same points.
                grid_object other;
                other.options_ = options_;
                if (options_.cell_size != 0 &&
                    (options_.cell_size > *r || options_.cell_size < *r / 4))
                    other.options_.cell_size = 0;
                build_into(other.g_, original_points(), py::float_(*r), other.options_);
                return other.query_ball_point(q, py::none(), return_distances, sort, return_length);
            }
            if (return_length)
                return to_numpy(under_read_lock([&] { return widen(g.query_counts(coords_of(q))); }));
            list_options o;
            o.distances = return_distances;
            o.order = order;
            auto c = under_read_lock([&] { return g.query(coords_of(q), o); });
            return csr_to_numpy(std::move(c), return_distances);
        },
        g_);
}

py::tuple grid_object::query_knn(std::int64_t k, const py::object& x) const {
    // Signed, so that a negative k reaches this check rather than pybind11's TypeError.
    if (k < 1) throw py::value_error("query_knn: k must be >= 1, got " + std::to_string(k));
    list_options o;
    o.distances = true;
    o.order = row_order::distance;
    return std::visit(
        [&](auto& g) {
            using T = typename grid_traits<std::decay_t<decltype(g)>>::type;
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            if (x.is_none()) return csr_to_numpy(under_read_lock([&] { return g.nearest(std::size_t(k), o); }), true);
            const auto q = typed_points<T, D>(x, "x", true);
            return csr_to_numpy(under_read_lock([&] { return g.query_nearest(coords_of(q), std::size_t(k), o); }), true);
        },
        g_);
}

void grid_object::update(const py::object& points) {
    std::visit(
        [&](auto& g) {
            using T = typename grid_traits<std::decay_t<decltype(g)>>::type;
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            const auto c = typed_points<T, D>(points, "points", false);
            py::gil_scoped_release nogil;
            std::unique_lock lock(mutex_);
            // Checked here so that a bad array leaves the grid as it was.
            if (!all_finite(coords_of(c)))
                throw error("update: points contain NaN or infinite coordinates");
            valid_ = false;
            g.rebuild(coords_of(c));
            valid_ = true;
        },
        g_);
}

py::array grid_object::original_points() const {
    return std::visit(
        [&](auto& g) {
            using T = typename grid_traits<std::decay_t<decltype(g)>>::type;
            constexpr int D = grid_traits<std::decay_t<decltype(g)>>::dim;
            std::vector<T> out = under_read_lock([&] {
                std::vector<T> p(g.size() * D);
                const auto perm = g.sorted_to_original();
                for (std::size_t s = 0; s < g.size(); ++s)
                    for (int a = 0; a < D; ++a) p[std::size_t(perm[s]) * D + a] = g.sorted_coord(s, a);
                return p;
            });
            const auto n = py::ssize_t(out.size() / D);
            return to_numpy(std::move(out), {n, py::ssize_t(D)});
        },
        g_);
}

/// Indices as int64 numpy array: sorted -> original (or the inverse).
static py::array index_array(const auto& g, bool inverse) {
    std::vector<std::int64_t> v;
    const auto src = inverse ? g.original_to_sorted() : g.sorted_to_original();
    v.assign(src.begin(), src.end());
    return to_numpy(std::move(v));
}

py::array grid_object::permutation() const {
    std::shared_lock lock(mutex_);
    return std::visit([&](auto& g) { return index_array(g, false); }, g_);
}

/// array.take(rows, axis=0), after checking that array has one row per point.
static py::array take_rows(py::handle array, const py::array& rows, const char* what) {
    const py::array a = as_array(array);
    const auto n = rows.shape(0);
    if (a.ndim() < 1 || a.shape(0) != n)
        throw py::value_error(std::string(what) + ": array must have " + std::to_string(n) +
                              " rows (one per point); got shape " + shape_text(a));
    return a.attr("take")(rows, py::arg("axis") = 0);
}

py::array grid_object::reorder(const py::object& array) const {
    return take_rows(array, permutation(), "reorder");
}

py::array grid_object::restore_order(const py::object& array) const {
    std::shared_lock lock(mutex_);
    const py::array inverse = std::visit([&](auto& g) { return index_array(g, true); }, g_);
    lock.unlock();
    return take_rows(array, inverse, "restore_order");
}

std::size_t grid_object::size() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.size(); }, g_);
}
double grid_object::radius() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return double(g.radius()); }, g_);
}
py::object grid_object::radii() const {
    std::shared_lock lock(mutex_);
    return std::visit(
        [](auto& g) -> py::object {
            if (!g.has_point_radii()) return py::none();
            using T = typename grid_traits<std::decay_t<decltype(g)>>::type;
            std::vector<T> r(g.point_radii().begin(), g.point_radii().end());
            return to_numpy(std::move(r));
        },
        g_);
}
py::object grid_object::rule() const {
    std::shared_lock lock(mutex_);
    return std::visit(
        [](auto& g) -> py::object {
            if (!g.has_point_radii()) return py::none();
            return py::str(std::string(to_string(g.options().rule)));
        },
        g_);
}
int grid_object::dim() const {
    return std::visit([](auto& g) { return grid_traits<std::decay_t<decltype(g)>>::dim; }, g_);
}
py::dtype grid_object::dtype() const {
    return is_float32() ? py::dtype::of<float>() : py::dtype::of<double>();
}
std::string grid_object::kind() const {
    std::shared_lock lock(mutex_);
    return std::string(to_string(std::visit([](auto& g) { return g.kind(); }, g_)));
}
std::size_t grid_object::slots() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.slot_count(); }, g_);
}
std::size_t grid_object::occupied_slots() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.occupied_slots(); }, g_);
}
double grid_object::cell_size() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.cell_size(0); }, g_);
}
py::object grid_object::periodic() const {
    if (options_.periodic.empty()) return py::none();
    py::tuple out(options_.periodic.size());
    for (std::size_t a = 0; a < options_.periodic.size(); ++a) out[a] = options_.periodic[a];
    return out;
}
int grid_object::threads() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.threads(); }, g_);
}
std::size_t grid_object::memory_bytes() const {
    std::shared_lock lock(mutex_);
    return std::visit([](auto& g) { return g.memory_bytes(); }, g_);
}
std::string grid_object::repr() const {
    return "frnn.Grid(n=" + std::to_string(size()) + ", dim=" + std::to_string(dim()) +
           ", radius=" + std::string(py::repr(py::float_(radius()))) + ", kind='" + kind() +
           "', dtype=" + std::string(py::str(py::handle(dtype()))) + ")";
}

}  // namespace frnn::python
