// The automatic choice of grid kind, one policy for every backend (the CPU grid's plan and the
// Vulkan grid's configure call it): a uniform grid when its box needs few enough cells for N,
// else a uniform grid over the bulk of the points with far outliers folded into its border
// cells, else the hashed grid.
#pragma once
#include <cstddef>
#include <span>

#include "frnn/options.hpp"

namespace frnn::detail {

/// What the choice looks at, in search space (see frnn/search_scale.hpp).
struct kind_question {
    grid_kind asked = grid_kind::automatic;
    std::size_t n = 0;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  ///< the points' bounding box, or the domain
    bool explicit_domain = false;                 ///< lo/hi are the caller's domain: kept
    double cell = 1, radius = 1;
    /// The farthest cell coordinate the backend's hashed grid keys (infinity: it has no limit);
    /// points beyond it are folded into a uniform grid over the bulk, however many.
    double hashed_key_limit = 0;
    /// The most cells a uniform grid of the backend may have.
    double uniform_cell_limit = 0;
    /// Axes the caller lays out itself (the periodic axes of a box with open ones): their
    /// lo/hi are kept, they count as `fixed_cells` cells in all, and no bulk is taken on them.
    bool fixed[3] = {false, false, false};
    double fixed_cells = 1;
};

/// The answer: the kind (never automatic) and, for a uniform grid, its box and cell count.
struct kind_answer {
    grid_kind kind = grid_kind::uniform;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    double cells = 0;
};

/// The choice for points `coords` (N*D interleaved, search space). `coords` may be empty when
/// the points are not at hand (a device buffer): then no bulk box is tried. `asked` other than
/// automatic is kept; the caller checks a uniform grid against its cell limit.
template <class T, int D>
kind_answer choose_kind(const kind_question& q, std::span<const T> coords, int threads);

/// The span of the open axes of a box with periodic ones (wraps[a], lengths box[a]), in lo/hi
/// (given: the points' box): the points' box, or their bulk with far outliers in the border
/// cells when the whole span needs too many cells, as choose_kind decides for `q` (its n,
/// cell, radius and limits set). A hashed grid does not wrap, so a uniform one takes the
/// outliers however many.
template <class T, int D>
void span_open_axes(kind_question q, const bool* wraps, const double* box, std::span<const T> coords, int threads,
                    double* lo, double* hi);

}  // namespace frnn::detail
