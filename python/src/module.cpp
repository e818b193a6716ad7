// frnn._frnn: the compiled part of the `frnn` Python package (python/frnn re-exports it).
// Docstrings live here so that help() and editors show them; python/frnn/__init__.pyi repeats
// the signatures with types.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "frnn/error.hpp"
#include "grid_object.hpp"
#include "lattice_list.hpp"

namespace py = pybind11;
using frnn::python::grid_args;
using frnn::python::grid_object;

namespace {

constexpr const char* grid_doc = R"(Fixed-radius neighbor search over one point set.

Grid(points, radius, *, grid="auto", cell_size=None, periodic=None, threads=None, rule="gather")

Two points i != j are neighbors when |x_i - x_j| <= radius (the real radius, not its square),
with minimum-image distances when ``periodic`` is given. With a radius per point, j is a
neighbor of i when |x_i - x_j| <= radius[i] (rule "gather") or <= max(radius[i], radius[j])
(rule "symmetric").

Parameters
----------
points : array_like, shape (N, 2) or (N, 3)
    float32 and float64 arrays that are C-contiguous are read in place (no copy); the grid
    works in their precision. Other layouts are copied; integer and other real dtypes are
    converted to float64. bool, complex, object and string arrays raise TypeError. NaN or
    infinite coordinates raise ValueError. The grid keeps its own sorted copy of the points,
    so the array may be changed or freed afterwards.
radius : float or array_like, shape (N,)
    Search radius, > 0, or one per point (finite, > 0; a bad one raises ValueError naming its
    index). With radii, ``radius`` reads the largest and ``radii`` gives them all.
grid : {"auto", "uniform", "hash"}
    Dense cells over the bounding box, or a hash table of cells (unbounded domains, far
    outliers); "auto" picks by the cell count.
cell_size : float, optional
    Cell edge in [radius/4, radius]; default radius.
periodic : float or sequence of float or None, optional
    Box length(s) L: the box is [0, L) on each axis and distances use the minimum image.
    Every length must be >= 2 * radius; 0 or None on an axis leaves it open, as in
    cKDTree's boxsize: periodic=(Lx, None, Lz).
threads : int, optional
    Threads for build and queries (default: FRNN_NUM_THREADS, else OMP_NUM_THREADS, else
    every CPU the process may use). Results are identical for any thread count.

Raises
------
ValueError (frnn.Error)
    Bad shapes, values or options; the message says what and where.
TypeError
    Unsupported dtype.

Notes
-----
Build and queries release the GIL. Several threads may query one Grid at once; update()
waits for running queries and blocks new ones until it is done.
)";

constexpr const char* query_pairs_doc = R"(All pairs within the radius.

Returns
-------
pairs : ndarray of int64, shape (M, 2)
    Every pair (i, j) with i < j and |x_i - x_j| <= radius, sorted lexicographically: the
    content of ``cKDTree(points).query_pairs(r, output_type='ndarray')`` after sorting. With
    a radius per point, the pairs within max(radius[i], radius[j]) (rule "symmetric"; a
    "gather" grid raises ValueError: its neighbors are not mutual).
)";

constexpr const char* neighbors_doc = R"(Neighbor lists of every point, as CSR arrays.

Parameters
----------
return_distances : bool
    Also return the distances (not squared), in the grid's precision.
sort : {"index", "distance", None}
    Order inside each row: increasing index, increasing distance (ties by index), or the
    traversal order (deterministic and cheapest).
half : bool
    Keep only j > i: each pair once.
rows : int, optional
    Rows for points 0 .. rows - 1 only (every point may still be their neighbor): offsets
    then has rows + 1 entries. At most N; default N.

Returns
-------
offsets : ndarray of int64, shape (N + 1,)
indices : ndarray of uint32
    Row i is ``indices[offsets[i]:offsets[i + 1]]``; i itself is never included.
distances : ndarray of float32 or float64, when return_distances
    The arrays own the C++ result buffers: nothing is copied.
)";

constexpr const char* count_doc = R"(Number of neighbors of every point (itself excluded).

Returns
-------
counts : ndarray of int64, shape (N,)
    Equal to ``numpy.diff(offsets)`` of neighbors().
)";

constexpr const char* ball_doc = R"(Grid points within r of other points.

Parameters
----------
x : array_like, shape (M, dim) or (dim,)
    Query points, converted to the grid's precision. A single point gives one row.
r : float or array_like of shape (M,), optional
    Radius; default the grid's. Another radius builds a temporary grid over the same points
    with that radius (O(N) extra work per call): build a Grid with that radius to query it
    often. An array gives each query point its own radius, as cKDTree's does: row q holds the
    points within r[q] (the grid's own search when no r[q] exceeds its radius). A grid with a
    radius per point needs r (one value for every query, or an array); under the symmetric
    rule row q holds the points j within max(r[q], radius[j]).
return_distances : bool
    Also return distances.
sort : {"index", "distance", None}
    Order inside each row.
return_length : bool
    Return only the number of points in each row (int64, shape (M,)).

Returns
-------
(offsets, indices[, distances]) as in neighbors(): row q holds the grid points within r of
x[q] (a query point equal to a grid point finds that point, at distance 0).
)";

constexpr const char* knn_doc = R"(At most k nearest neighbors within the radius.

Parameters
----------
k : int
    Maximum neighbors per row, >= 1.
x : array_like, shape (M, dim) or (dim,), optional
    Query points; default the grid's own points (each point then excludes itself).

Returns
-------
offsets, indices, distances : CSR arrays as in neighbors()
    Each row is sorted by distance, ties by index, and holds min(k, neighbors within r)
    entries. ``cKDTree.query(x, k, distance_upper_bound=b)`` keeps only distances < b
    (strict): with b = r it drops the neighbors at exactly r that this keeps, with
    b = numpy.nextafter(r, inf) it finds the same ones, padded with inf (docs/PYTHON.md).
)";

constexpr const char* cell_of_doc = R"(The cell of point x: its integer coordinates, one per axis.

On a uniform grid points beyond its domain share its border cells; in a periodic box x is
wrapped into the box first. Cell (0, 0[, 0]) starts at the grid's origin (cell_bounds).
)";

constexpr const char* cells_within_doc = R"(The cells a query at x visits, as (first, last).

Every cell whose coordinates lie in [first[a], last[a]] on each axis a: the cell of x and
the grid's reach (1 at the default cell size) on each side, within a uniform grid's cells.
Every point within the radius of x lies in one of them. In a periodic box the coordinates
may leave the box's range: such a cell is the one at the coordinate modulo the cells per
axis, in the neighboring image of the box.
)";

constexpr const char* cell_bounds_doc = R"(Lower and upper corner of a cell, in the points' units.

The border cells of a uniform grid also hold the points beyond it.
)";

constexpr const char* update_doc = R"(Rebuild over new positions (the next time step).

The radius and options stay; the number of points may change. ``points`` must have the
grid's dimension; other dtypes are converted to the grid's precision (a copy). On error the
grid is unchanged.
)";

constexpr const char* reorder_doc = R"(The array permuted into the grid's cell order.

Returns ``array.take(permutation, axis=0)``: row s of the result is row permutation[s] of
the input. Per-particle data in cell order is read with better locality. ``array`` must have
N rows; any dtype and trailing shape.
)";

constexpr const char* restore_doc = R"(The inverse of reorder(): an array in cell order back in the caller's order.)";

constexpr const char* one_shot_doc = R"(All pairs within radius: Grid(points, radius, **kw).query_pairs().

Returns an (M, 2) int64 array of pairs i < j, sorted lexicographically. Keyword arguments are
those of Grid; with a radius per point the rule is "symmetric" (pairs within the larger radius).
)";

}  // namespace

PYBIND11_MODULE(_frnn, m) {
    m.doc() = "frnn: fast fixed-radius neighbor search (compiled module)";
    m.attr("__version__") = FRNN_VERSION;
    py::register_exception<frnn::error>(m, "Error", PyExc_ValueError);
    frnn::python::add_lattice_pairs(m);

    py::class_<grid_object>(m, "Grid", grid_doc)
        .def(py::init([](const py::object& points, const py::object& radius, std::string grid,
                         std::optional<double> cell_size, py::object periodic,
                         std::optional<int> threads, std::string rule) {
                 return new grid_object(points, radius,
                                        grid_args{std::move(grid), cell_size, periodic, threads, std::move(rule)});
             }),
             py::arg("points"), py::arg("radius"), py::kw_only(), py::arg("grid") = "auto",
             py::arg("cell_size") = py::none(), py::arg("periodic") = py::none(),
             py::arg("threads") = py::none(), py::arg("rule") = "gather")
        .def("query_pairs", &grid_object::query_pairs, query_pairs_doc)
        .def("neighbors", &grid_object::neighbors, neighbors_doc,
             py::arg("return_distances") = false, py::arg("sort") = "index",
             py::arg("half") = false, py::kw_only(), py::arg("rows") = py::none())
        .def("count_neighbors", &grid_object::count_neighbors, count_doc)
        .def("query_ball_point", &grid_object::query_ball_point, ball_doc, py::arg("x"),
             py::arg("r") = py::none(), py::kw_only(), py::arg("return_distances") = false,
             py::arg("sort") = "index", py::arg("return_length") = false)
        .def("query_knn", &grid_object::query_knn, knn_doc, py::arg("k"),
             py::arg("x") = py::none())
        .def("cell_of", &grid_object::cell_of, cell_of_doc, py::arg("x"))
        .def("cells_within", &grid_object::cells_within, cells_within_doc, py::arg("x"))
        .def("cell_bounds", &grid_object::cell_bounds, cell_bounds_doc, py::arg("cell"))
        .def("update", &grid_object::update, update_doc, py::arg("points"))
        .def("reorder", &grid_object::reorder, reorder_doc, py::arg("array"))
        .def("restore_order", &grid_object::restore_order, restore_doc, py::arg("array"))
        .def_property_readonly("permutation", &grid_object::permutation,
                               "int64 array: permutation[s] is the caller's index of the s-th "
                               "point in cell order")
        .def_property_readonly("n", &grid_object::size, "Number of points")
        .def_property_readonly("radius", &grid_object::radius, "Search radius (the largest, with a radius per point)")
        .def_property_readonly("radii", &grid_object::radii, "The radius of each point (caller's order), or None")
        .def_property_readonly("rule", &grid_object::rule,
                               "'gather' or 'symmetric' with a radius per point, else None")
        .def_property_readonly("dim", &grid_object::dim, "Dimension: 2 or 3")
        .def_property_readonly("dtype", &grid_object::dtype, "float32 or float64")
        .def_property_readonly("kind", &grid_object::kind, "'uniform' or 'hash'")
        .def_property_readonly("slots", &grid_object::slots,
                               "Slots of the cell index: the cells of a uniform grid, the size of a "
                               "hashed grid's table")
        .def_property_readonly("occupied_slots", &grid_object::occupied_slots,
                               "Slots holding at least one point")
        .def_property_readonly("cell_size", &grid_object::cell_size, "Cell edge length in use (the grid may round the requested one up to fit the domain)")
        .def_property_readonly("periodic", &grid_object::periodic,
                               "Box lengths per axis, or None for open boundaries")
        .def_property_readonly("threads", &grid_object::threads, "Worker threads used")
        .def_property_readonly("memory_bytes", &grid_object::memory_bytes,
                               "Bytes held by the structure")
        .def("__len__", &grid_object::size)
        .def("__repr__", &grid_object::repr);

    m.def(
        "query_pairs",
        [](const py::object& points, const py::object& radius, std::string grid, std::optional<double> cell_size,
           py::object periodic, std::optional<int> threads, std::string rule) {
            return grid_object(points, radius,
                               grid_args{std::move(grid), cell_size, periodic, threads, std::move(rule)})
                .query_pairs();
        },
        one_shot_doc, py::arg("points"), py::arg("radius"), py::kw_only(),
        py::arg("grid") = "auto", py::arg("cell_size") = py::none(),
        py::arg("periodic") = py::none(), py::arg("threads") = py::none(), py::arg("rule") = "symmetric");
}
