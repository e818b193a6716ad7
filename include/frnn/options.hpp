// Options of grid construction and neighbor-list queries.
// Plain value types; safe to copy and share between threads.
#pragma once
#include <cstddef>
#include <string_view>
#include <vector>

namespace frnn {

/// Which spatial structure a grid uses.
enum class grid_kind {
    automatic,  ///< uniform when its cell count is reasonable for N (over the points' bulk
                ///< when at most 1 in 1024 lie far outside it, or any number beyond the
                ///< hashed grid's keys), hashed otherwise
    uniform,    ///< dense cells over a bounded box (the points' bounding box or `domain_*`),
                ///< at most max(2^24, 64 N) of them (4 bytes each; more throws frnn::error)
    hashed,     ///< cells keyed by integer coordinates in a table sized from N: unbounded domains
};

/// "auto", "uniform" or "hash".
std::string_view to_string(grid_kind kind);
/// Parses "auto", "uniform", "hash"/"hashed"; throws frnn::error otherwise.
grid_kind parse_grid_kind(std::string_view text);

/// Which pairs are neighbors when every point has a radius of its own (grid::build with radii).
enum class radius_rule {
    gather,     ///< j is a neighbor of i when |x_i - x_j| <= r_i (i's ball; rows differ from columns)
    symmetric,  ///< when |x_i - x_j| <= max(r_i, r_j) (either ball; j in i's row iff i in j's)
};

/// "gather" or "symmetric".
std::string_view to_string(radius_rule rule);
/// Parses "gather" or "symmetric"; throws frnn::error otherwise.
radius_rule parse_radius_rule(std::string_view text);

struct grid_options {
    grid_kind kind = grid_kind::automatic;
    /// With a radius per point: which pairs are neighbors (ignored with one radius).
    radius_rule rule = radius_rule::gather;
    /// Cell edge length; 0 means the radius (the largest, with a radius per point). Smaller cells (r/2, r/3, r/4) visit
    /// (2*ceil(r/cell)+1)^d cells but test fewer candidates. Must lie in [r/4, r]. In a hashed
    /// grid every one of those cells is a table lookup, so small cells are slow there (W3
    /// counts at 1M points, 1 thread: 0.3 s with cells of r, 1.5 s with r/2, 18 s with r/4).
    double cell_size = 0;
    /// Empty: open boundaries. Otherwise one value per axis: a box length L > 0 makes that
    /// axis periodic, [0, L) with minimum-image distances, and must be >= 2 r; 0 leaves the
    /// axis open (a channel periodic in x only is {Lx, 0, 0}). Points and query points
    /// outside [0, L), any number of boxes out, are wrapped into it exactly
    /// (frnn/periodic_wrap.hpp) and have the neighbors of their image. A box with a periodic axis
    /// always uses the uniform grid (`kind` is then ignored): its open axes span the points, or
    /// their bulk with far outliers in the border cells as the automatic kind does; very
    /// sparse boxes get larger cells instead of more of them.
    std::vector<double> periodic;
    /// Optional bounds of the uniform grid (one value per axis, both or neither). Points
    /// outside are still handled exactly (they share the border cells). Default: bounding box.
    /// With periodic axes they bound the open axes only (a periodic axis spans its box).
    std::vector<double> domain_min, domain_max;
    /// Lay the cells out as for this many points (0: as many as are given): the sparse-box
    /// rule above, the uniform grid's cell budget and the hashed grid's table then do not
    /// depend on the points given, so that grids over parts of one point set (the ranks of a
    /// domain decomposition, with `domain_min`/`domain_max`) share one layout of cells.
    std::size_t layout_points = 0;
    /// Threads for build and bulk queries, the calling one included; 0 means
    /// frnn::default_thread_count() (FRNN_NUM_THREADS, else OMP_NUM_THREADS, else every CPU).
    int threads = 0;
};

/// Order of the entries inside each row of a neighbor list.
enum class row_order {
    none,      ///< traversal order: deterministic, cheapest
    index,     ///< increasing neighbor index
    distance,  ///< increasing distance, ties by index
};

/// Which numbering rows and neighbor indices use.
enum class index_space {
    original,  ///< the caller's point order
    sorted,    ///< the grid's cell order (see grid::reorder): fastest, best locality
};

struct list_options {
    bool half = false;        ///< only pairs with j > i (in the chosen index space)
    bool distances = false;   ///< also return distances (not squared)
    bool self = false;        ///< include i itself, at distance 0
    row_order order = row_order::none;
    index_space space = index_space::original;
    /// Rows for points [0, rows) of the chosen numbering only, and the lists have that many
    /// rows; the other points are neighbors but get no row of their own (a domain's ghost
    /// particles, numbered after the particles it owns). At most the number of points; for
    /// the lists of a grid's own points only (not queries). Default: a row for every point.
    static constexpr std::size_t all_rows = std::size_t(-1);
    std::size_t rows = all_rows;
};

}  // namespace frnn
